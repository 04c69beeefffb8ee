//! The body state as Python sees it: a dict of numpy arrays (`position_m`,
//! `world_from_body_wxyz`, `velocity_m_s`, `angular_velocity_body_rad_s`, and the derived
//! `euler_rad`), both ways. Below the simulation and the vehicle, which both take states.

use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use numpy::PyArray1;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use flapsim::State;

use crate::convert::{quat_wxyz, vec3, vector};

/// How far a state's quaternion norm may be from 1 (it is normalised within that).
const MAX_NORM_ERROR: f64 = 1e-6;

const STATE_KEYS: [&str; 4] = [
    "position_m",
    "world_from_body_wxyz",
    "velocity_m_s",
    "angular_velocity_body_rad_s",
];

/// A state as a dict of numpy arrays (the quaternion as w, x, y, z).
pub fn state_dict<'py>(py: Python<'py>, s: &State) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("position_m", vec3(py, &s.position_m))?;
    d.set_item("world_from_body_wxyz", quat_wxyz(py, &s.world_from_body))?;
    d.set_item("velocity_m_s", vec3(py, &s.velocity_m_s))?;
    d.set_item(
        "angular_velocity_body_rad_s",
        vec3(py, &s.angular_velocity_body_rad_s),
    )?;
    let (r, p, y) = s.euler_rad();
    d.set_item("euler_rad", PyArray1::from_slice(py, &[r, p, y]))?;
    Ok(d)
}

/// A state from a dict with the keys of [`state_dict`] (missing keys keep `base`'s values;
/// `euler_rad` is ignored, being derived).
pub fn state_from_dict(d: &Bound<'_, PyDict>, base: State) -> PyResult<State> {
    let mut s = base;
    for (k, v) in d.iter() {
        let k: String = k.extract()?;
        if k == "euler_rad" {
            continue;
        }
        if !STATE_KEYS.contains(&k.as_str()) {
            return Err(PyValueError::new_err(format!(
                "state has no field `{k}` (allowed: {})",
                STATE_KEYS.join(", ")
            )));
        }
        let need = if k == "world_from_body_wxyz" { 4 } else { 3 };
        let a = vector(&k, &v, Some(need))?;
        match k.as_str() {
            "position_m" => s.position_m = Vector3::new(a[0], a[1], a[2]),
            "velocity_m_s" => s.velocity_m_s = Vector3::new(a[0], a[1], a[2]),
            "angular_velocity_body_rad_s" => {
                s.angular_velocity_body_rad_s = Vector3::new(a[0], a[1], a[2])
            }
            _ => {
                let q = Quaternion::new(a[0], a[1], a[2], a[3]);
                let n = q.norm();
                // A unit quaternion, as WingSet.step takes it: a norm far from 1 is not a
                // rounding error but a wrong value (never normalised quietly).
                if !(n.is_finite() && (n - 1.0).abs() <= MAX_NORM_ERROR) {
                    return Err(PyValueError::new_err(format!(
                        "state `world_from_body_wxyz` must be a unit quaternion (w, x, y, z), \
                         got norm {n}; allowed: a norm within {MAX_NORM_ERROR:e} of 1"
                    )));
                }
                s.world_from_body = UnitQuaternion::from_quaternion(q);
            }
        }
    }
    Ok(s)
}
