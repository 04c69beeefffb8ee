//! Conversions between flapwing's Rust values and Python objects: numpy arrays for vectors
//! and matrices, dicts for records (through their serde form), and the model loader.
//!
//! Every argument check of the bindings lives here, so that every method refuses bad input
//! the same way, with a message naming the argument, the value and what is allowed:
//! integers ([`arg_int`], [`int_list`]: `TypeError` for a non-integer, `ValueError` out of
//! range, never an `OverflowError`), real numbers and arrays ([`scalar`], [`float_array`],
//! [`vector`]: any array-like numpy converts, `TypeError` for complex, boolean, text or
//! object values, `ValueError` for a wrong shape or a NaN/infinity) and the size of what a
//! call would allocate ([`MAX_OUTPUT_BYTES`], [`output_cap`], [`try_vec`]).

use nalgebra::{DMatrix, UnitQuaternion, Vector3};
use numpy::{
    PyArray1, PyArray2, PyArrayDescrMethods, PyArrayDyn, PyArrayMethods, PyUntypedArray,
    PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyMemoryError, PyOSError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyBytes, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// The largest output one call builds, in bytes (1 GiB): `Simulation.run` with
/// `record=True`, `Wing.evaluate_many` and `Wing.evaluate_cycle` refuse, before allocating,
/// a request whose output arrays would exceed it (`ValueError` naming the argument and its
/// largest allowed value); run longer simulations in chunks or with `record=False`.
pub const MAX_OUTPUT_BYTES: u64 = 1 << 30;

/// `ValueError` unless `n` items of `bytes_each` bytes of output fit [`MAX_OUTPUT_BYTES`];
/// `hint` ends the message (what to do instead).
pub fn output_cap(name: &str, n: u64, bytes_each: u64, hint: &str) -> PyResult<()> {
    let need = n.checked_mul(bytes_each);
    if need.is_some_and(|b| b <= MAX_OUTPUT_BYTES) {
        return Ok(());
    }
    let need = need.map_or_else(|| "more than 2^64".to_owned(), |b| b.to_string());
    Err(PyValueError::new_err(format!(
        "`{name}` = {n} would need {need} bytes of output arrays ({bytes_each} bytes each); \
         the limit is {MAX_OUTPUT_BYTES} bytes (1 GiB), so `{name}` must be at most {}{hint}",
        MAX_OUTPUT_BYTES / bytes_each.max(1)
    )))
}

/// An empty vector with room for `n` items, or `MemoryError` naming `name` when the system
/// cannot provide it (instead of Rust's abort).
pub fn try_vec<T>(name: &str, n: usize) -> PyResult<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(n).map_err(|_| {
        PyMemoryError::new_err(format!(
            "cannot allocate {} bytes for `{name}` ({n} items)",
            n.saturating_mul(std::mem::size_of::<T>())
        ))
    })?;
    Ok(v)
}

/// A short description of a Python value for messages: its type and repr (cut at 60 chars).
pub fn describe(obj: &Bound<'_, PyAny>) -> String {
    let ty = obj
        .get_type()
        .name()
        .map(|n| n.to_string())
        .unwrap_or_else(|_| "?".to_owned());
    let mut r = obj
        .repr()
        .map(|r| r.to_string())
        .unwrap_or_else(|_| "?".to_owned());
    if r.chars().count() > 60 {
        r = r.chars().take(57).collect::<String>() + "...";
    }
    format!("{ty} {r}")
}

/// An integer argument in `min..=max` (`max` None: no upper bound but 2^64 - 1). Anything
/// with `__index__` (int, numpy integers) is accepted; bool, float, str and the rest are a
/// `TypeError`, an integer out of range a `ValueError`, both naming `name`.
pub fn arg_int(name: &str, obj: &Bound<'_, PyAny>, min: u64, max: Option<u64>) -> PyResult<u64> {
    let range = match max {
        Some(m) => format!("from {min} to {m}"),
        None => format!("at least {min}"),
    };
    if obj.is_instance_of::<PyBool>() {
        return Err(PyTypeError::new_err(format!(
            "`{name}` must be an integer {range}, got {}",
            describe(obj)
        )));
    }
    let index = if obj.is_instance_of::<PyInt>() {
        obj.clone()
    } else {
        obj.py()
            .import("operator")?
            .call_method1("index", (obj,))
            .map_err(|_| {
                PyTypeError::new_err(format!(
                    "`{name}` must be an integer {range}, got {}",
                    describe(obj)
                ))
            })?
    };
    match index.extract::<u64>() {
        Ok(v) if v >= min && max.is_none_or(|m| v <= m) => Ok(v),
        _ => Err(PyValueError::new_err(format!(
            "`{name}` must be an integer {range}, got {index}"
        ))),
    }
}

/// A sequence of integers (list, tuple, numpy integer array), each checked by [`arg_int`]
/// as `name[i]`; `None` items are kept as `None` when `allow_none`.
pub fn int_list(
    name: &str,
    obj: &Bound<'_, PyAny>,
    min: u64,
    max: Option<u64>,
    allow_none: bool,
) -> PyResult<Vec<Option<u64>>> {
    let not_seq = || {
        PyTypeError::new_err(format!(
            "`{name}` must be a sequence of integers, got {}",
            describe(obj)
        ))
    };
    if obj.is_instance_of::<PyString>() || obj.is_instance_of::<PyBytes>() {
        return Err(not_seq());
    }
    let mut out = Vec::new();
    for (i, item) in obj.try_iter().map_err(|_| not_seq())?.enumerate() {
        let item = item?;
        if allow_none && item.is_none() {
            out.push(None);
        } else {
            out.push(Some(arg_int(&format!("{name}[{i}]"), &item, min, max)?));
        }
    }
    Ok(out)
}

/// Any array-like of real numbers (list, tuple, scalar, numpy array of a float or integer
/// dtype) as a numpy array, not yet converted nor copied (see [`float_array`]); complex,
/// boolean, text, object and ragged input is refused naming `name` (`TypeError`; a ragged
/// list `ValueError`).
pub fn real_array<'py>(
    name: &str,
    obj: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyUntypedArray>> {
    let np = obj.py().import("numpy")?;
    let a = np.call_method1("asarray", (obj,)).map_err(|e| {
        PyValueError::new_err(format!(
            "`{name}` must be an array of real numbers, got {}: {e}",
            describe(obj)
        ))
    })?;
    let a = a.cast_into::<PyUntypedArray>().map_err(|_| {
        PyTypeError::new_err(format!(
            "`{name}` must be an array of real numbers, got {}",
            describe(obj)
        ))
    })?;
    let dtype = a.dtype();
    let kind = dtype.kind();
    // numpy turns booleans mixed with numbers ([True, 0, 0]) into numbers: refused too.
    if matches!(kind, b'f' | b'i' | b'u') && holds_a_bool(obj) {
        return Err(PyTypeError::new_err(format!(
            "`{name}` must be real numbers (float or int), got a boolean value among them: {}",
            describe(obj)
        )));
    }
    if !matches!(kind, b'f' | b'i' | b'u') {
        let what = match kind {
            b'c' => "a complex value",
            b'b' => "a boolean value",
            _ => "a non-numeric value",
        };
        return Err(PyTypeError::new_err(format!(
            "`{name}` must be real numbers (float or int), got {what} (dtype {dtype}): {}",
            describe(obj)
        )));
    }
    Ok(a)
}

/// A Python bool (or numpy bool) in a list or tuple, at any depth (numpy arrays are judged
/// by their dtype).
fn holds_a_bool(obj: &Bound<'_, PyAny>) -> bool {
    let is_bool = |x: &Bound<'_, PyAny>| {
        x.is_instance_of::<PyBool>() || x.get_type().name().is_ok_and(|n| n == "bool")
    };
    if let Ok(l) = obj.cast::<PyList>() {
        return l.iter().any(|x| is_bool(&x) || holds_a_bool(&x));
    }
    if let Ok(t) = obj.cast::<PyTuple>() {
        return t.iter().any(|x| is_bool(&x) || holds_a_bool(&x));
    }
    false
}

/// [`real_array`] as a C-contiguous float64 numpy array (no copy when it already is one).
/// The values are not checked (see [`vector`] and [`finite`]).
pub fn float_array<'py>(
    name: &str,
    obj: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    if let Ok(a) = obj.cast::<PyArrayDyn<f64>>()
        && a.is_c_contiguous()
    {
        return Ok(a.clone());
    }
    contiguous(&real_array(name, obj)?)
}

/// A real numpy array as a C-contiguous float64 one.
pub fn contiguous<'py>(a: &Bound<'py, PyUntypedArray>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let np = a.py().import("numpy")?;
    // Not ascontiguousarray: it turns a 0-d array (a scalar) into shape (1,).
    let kw = PyDict::new(a.py());
    kw.set_item("dtype", "float64")?;
    kw.set_item("order", "C")?;
    let f = np.call_method("asarray", (a,), Some(&kw))?;
    Ok(f.cast_into::<PyArrayDyn<f64>>()?)
}

/// The shape of an array as "(a, b)" (Python's spelling).
pub fn shape_str(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        s => format!(
            "({})",
            s.iter()
                .map(|x| x.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// A real scalar argument (int, float, numpy scalar or 0-d array), finite.
pub fn scalar(name: &str, obj: &Bound<'_, PyAny>) -> PyResult<f64> {
    let x = if (obj.is_instance_of::<PyFloat>() || obj.is_instance_of::<PyInt>())
        && !obj.is_instance_of::<PyBool>()
    {
        obj.extract::<f64>().map_err(|_| {
            PyValueError::new_err(format!(
                "`{name}` must be a finite real number, got {}",
                describe(obj)
            ))
        })?
    } else {
        let a = float_array(name, obj)?;
        if a.ndim() != 0 {
            return Err(PyValueError::new_err(format!(
                "`{name}` must be a number, got an array of shape {}",
                shape_str(a.shape())
            )));
        }
        a.readonly().as_slice()?[0]
    };
    finite(name, &[x])?;
    Ok(x)
}

/// A 1-D array-like of finite reals with `len` items (None: any length).
pub fn vector(name: &str, obj: &Bound<'_, PyAny>, len: Option<usize>) -> PyResult<Vec<f64>> {
    let a = float_array(name, obj)?;
    let ok = a.ndim() == 1 && len.is_none_or(|n| a.len() == n);
    if !ok {
        let want = len.map_or_else(
            || "(n,)".to_owned(),
            |n| format!("{} ({n} components)", shape_str(&[n])),
        );
        return Err(PyValueError::new_err(format!(
            "`{name}` must have shape {want}, got shape {}",
            shape_str(a.shape())
        )));
    }
    let v = a.readonly().as_slice()?.to_vec();
    finite(name, &v)?;
    Ok(v)
}

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

/// A 3-vector argument: any array-like of 3 finite reals; None is zero.
pub fn arg_vec3(name: &str, v: Option<&Bound<'_, PyAny>>) -> PyResult<Vector3<f64>> {
    let Some(v) = v else {
        return Ok(Vector3::zeros());
    };
    let s = vector(name, v, Some(3))?;
    Ok(Vector3::new(s[0], s[1], s[2]))
}

/// Rejects NaN and infinities, naming the argument (and the index in an array).
pub fn finite(name: &str, v: &[f64]) -> PyResult<()> {
    if let Some((i, x)) = v.iter().enumerate().find(|(_, x)| !x.is_finite()) {
        let at = if v.len() > 1 {
            format!("{name}[{i}]")
        } else {
            name.to_owned()
        };
        return Err(PyValueError::new_err(format!(
            "`{at}` must be finite, got {x}"
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
    // Bounded: regular files of at most 1 MiB (flapsim::model::MAX_MODEL_FILE_BYTES).
    let text =
        flapsim::model::read_model_file(path).map_err(|e| PyOSError::new_err(e.to_string()))?;
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
        let x = scalar(&format!("{what}.{k}"), &v)?;
        obj.insert(k, serde_json::json!(x));
    }
    serde_json::from_value(j).map_err(|e| bad(format!("{what}: {e}")))
}
