//! Reading flapwing MCAP logs from Python: each channel as a dict of numpy arrays, through
//! flightlog's own decoding (`flightlog::replay::read_table`), so the bindings follow the
//! log format wherever flightlog takes it.

use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::log_err;

/// `path` if it is a regular file (or does not exist: flightlog then says so). Anything else
/// is refused before it is opened: a FIFO with no writer would block the open, ignoring
/// Ctrl-C, and a device read without end.
fn log_file(path: std::path::PathBuf) -> PyResult<std::path::PathBuf> {
    match std::fs::metadata(&path) {
        Ok(m) if !m.is_file() => Err(pyo3::exceptions::PyOSError::new_err(format!(
            "{} is not a regular file ({}): a flapwing log is an MCAP file",
            path.display(),
            if m.is_dir() {
                "a directory"
            } else {
                "a FIFO, device or socket"
            }
        ))),
        _ => Ok(path),
    }
}

/// The topics of a log, in file order.
#[pyfunction]
pub fn log_topics(path: std::path::PathBuf) -> PyResult<Vec<String>> {
    let path = log_file(path)?;
    let s = flightlog::replay::read_summary(&path).map_err(log_err)?;
    Ok(s.channels.into_iter().map(|c| c.topic).collect())
}

/// What is missing from a flapwing MCAP log: `None` for a complete log, else flightlog's
/// note of where it is truncated or damaged and how much was recovered (a killed run's log).
#[pyfunction]
pub fn log_damage(path: std::path::PathBuf) -> PyResult<Option<String>> {
    let path = log_file(path)?;
    let s = flightlog::replay::read_summary(&path).map_err(log_err)?;
    Ok(s.damage)
}

/// One channel of a flapwing MCAP log as {column: numpy array}: `log_time_ns` (int64) and
/// one column per message field by its dotted path; numeric columns are float64 arrays (NaN
/// where a message lacks the field), others lists of str (None where missing).
#[pyfunction]
pub fn read_channel<'py>(
    py: Python<'py>,
    path: std::path::PathBuf,
    topic: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let path = log_file(path)?;
    let t = py
        .detach(|| flightlog::replay::read_table(&path, topic))
        .map_err(log_err)?;
    let d = PyDict::new(py);
    for (j, name) in t.columns.iter().enumerate() {
        let cells: Vec<Option<&str>> = t.rows.iter().map(|r| r[j].as_deref()).collect();
        if j == 0 {
            let v: Vec<i64> = cells
                .iter()
                .map(|c| c.and_then(|s| s.parse().ok()).unwrap_or(-1))
                .collect();
            d.set_item(name, PyArray1::from_vec(py, v))?;
            continue;
        }
        let nums: Option<Vec<f64>> = cells
            .iter()
            .map(|c| match c {
                None => Some(f64::NAN),
                Some(s) => s.parse::<f64>().ok(),
            })
            .collect();
        match nums {
            Some(v) => d.set_item(name, PyArray1::from_vec(py, v))?,
            None => d.set_item(name, PyList::new(py, cells)?)?,
        }
    }
    Ok(d)
}
