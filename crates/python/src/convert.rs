//! Conversions between flapwing's Rust values and Python objects: numpy arrays for vectors
//! and matrices, dicts for records (through their serde form), and the model loader.

use nalgebra::{DMatrix, UnitQuaternion, Vector3};
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

/// A 3-vector as a numpy array of shape (3,).
pub fn vec3<'py>(py: Python<'py>, v: &Vector3<f64>) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, v.as_slice())
}

/// A quaternion as (w, x, y, z), MuJoCo's order.
pub fn quat_wxyz<'py>(py: Python<'py>, q: &UnitQuaternion<f64>) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, &[q.w, q.i, q.j, q.k])
}

/// A matrix as a 2-D numpy array.
pub fn matrix<'py>(py: Python<'py>, m: &DMatrix<f64>) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let rows: Vec<Vec<f64>> = (0..m.nrows())
        .map(|i| m.row(i).iter().copied().collect())
        .collect();
    rows2(py, &rows, m.ncols())
}

/// Rows as a 2-D numpy array (an empty list gives shape (0, ncols)).
pub fn rows2<'py>(
    py: Python<'py>,
    rows: &[Vec<f64>],
    ncols: usize,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    if rows.is_empty() {
        return Ok(PyArray1::<f64>::zeros(py, 0, false).reshape([0, ncols])?);
    }
    Ok(PyArray2::from_vec2(py, rows)?)
}

/// A flat buffer as a numpy array of the given shape.
pub fn shaped<'py>(
    py: Python<'py>,
    data: Vec<f64>,
    shape: &[usize],
) -> PyResult<Bound<'py, PyAny>> {
    let a = PyArray1::from_vec(py, data);
    Ok(a.reshape(shape)?.into_any())
}

/// A serde value as plain Python objects (dict, list, float, int, str, bool, None).
pub fn json_to_py<'py>(py: Python<'py>, v: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    use serde_json::Value;
    Ok(match v {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => b.into_pyobject(py)?.to_owned().into_any(),
        Value::Number(n) => match (n.as_i64(), n.as_f64()) {
            (Some(i), _) if !n.is_f64() => i.into_pyobject(py)?.into_any(),
            (_, Some(f)) => f.into_pyobject(py)?.into_any(),
            _ => n.to_string().into_pyobject(py)?.into_any(),
        },
        Value::String(s) => s.into_pyobject(py)?.into_any(),
        Value::Array(a) => {
            let l = PyList::empty(py);
            for x in a {
                l.append(json_to_py(py, x)?)?;
            }
            l.into_any()
        }
        Value::Object(o) => {
            let d = PyDict::new(py);
            for (k, x) in o {
                d.set_item(k, json_to_py(py, x)?)?;
            }
            d.into_any()
        }
    })
}

/// Any serializable record as a Python dict.
pub fn record<'py, T: serde::Serialize>(py: Python<'py>, v: &T) -> PyResult<Bound<'py, PyAny>> {
    let j = serde_json::to_value(v).map_err(|e| PyValueError::new_err(e.to_string()))?;
    json_to_py(py, &j)
}

/// A 3-vector argument: any sequence or array of 3 floats.
pub fn arg_vec3(name: &str, v: Option<PyReadonlyArray1<'_, f64>>) -> PyResult<Vector3<f64>> {
    let Some(v) = v else {
        return Ok(Vector3::zeros());
    };
    let s = v.as_slice()?;
    if s.len() != 3 {
        return Err(PyValueError::new_err(format!(
            "`{name}` must have 3 components (x, y, z), got {}",
            s.len()
        )));
    }
    let out = Vector3::new(s[0], s[1], s[2]);
    finite(name, out.as_slice())?;
    Ok(out)
}

/// Rejects NaN and infinities, naming the argument.
pub fn finite(name: &str, v: &[f64]) -> PyResult<()> {
    if let Some(x) = v.iter().find(|x| !x.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "`{name}` must be finite, got {x}"
        )));
    }
    Ok(())
}

/// A model's TOML text and origin from a built-in name or a file path.
pub fn model_text(model: &str, builtins: &[(&str, &'static str)]) -> PyResult<(String, String)> {
    if let Some((n, t)) = builtins.iter().find(|(n, _)| *n == model) {
        return Ok(((*t).to_owned(), format!("<built-in {n}>")));
    }
    let path = std::path::Path::new(model);
    if !path.exists() {
        let names: Vec<&str> = builtins.iter().map(|(n, _)| *n).collect();
        return Err(PyValueError::new_err(format!(
            "model `{model}` is neither a built-in name ({}) nor an existing file",
            names.join(", ")
        )));
    }
    let text = std::fs::read_to_string(path)
        .map_err(|e| PyOSError::new_err(format!("cannot read model file {model}: {e}")))?;
    Ok((text, model.to_owned()))
}

/// `base` with the numeric fields named in `kw` replaced; an unknown name or a non-finite
/// value is a `ValueError` naming `what`, the field and the allowed names.
pub fn merge_record<T>(base: &T, kw: Option<&Bound<'_, PyDict>>, what: &str) -> PyResult<T>
where
    T: serde::Serialize + serde::de::DeserializeOwned,
{
    let bad = |e: String| PyValueError::new_err(e);
    let mut j = serde_json::to_value(base).map_err(|e| bad(e.to_string()))?;
    let Some(kw) = kw else {
        return serde_json::from_value(j).map_err(|e| bad(e.to_string()));
    };
    let obj = j
        .as_object_mut()
        .ok_or_else(|| bad(format!("{what} is not a record")))?;
    for (k, v) in kw.iter() {
        let k: String = k.extract()?;
        if !obj.contains_key(&k) {
            let allowed: Vec<&str> = obj.keys().map(String::as_str).collect();
            return Err(bad(format!(
                "{what} has no field `{k}` (allowed: {})",
                allowed.join(", ")
            )));
        }
        let x: f64 = v
            .extract()
            .map_err(|_| bad(format!("{what} field `{k}` must be a number, got {v}")))?;
        finite(&format!("{what}.{k}"), &[x])?;
        obj.insert(k, serde_json::json!(x));
    }
    serde_json::from_value(j).map_err(|e| bad(format!("{what}: {e}")))
}
