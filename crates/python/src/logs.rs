//! Reading flapwing MCAP logs and ROS 2 bags from Python: each channel (topic) as a dict of
//! numpy arrays, through flightlog's own decoding (`flightlog::replay::read_table` and
//! `flightlog::ros2::summary::read_topic_table`, what `flapwing replay --csv` writes), so
//! the bindings follow both formats wherever flightlog takes them.

use std::path::{Path, PathBuf};

use flightlog::ros2::bag::{Bag, read_bag};
use flightlog::ros2::summary::read_topic_table;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::log_err;

/// `path` if it is a regular file (or does not exist: flightlog then says so). Anything else
/// is refused before it is opened: a FIFO with no writer would block the open, ignoring
/// Ctrl-C, and a device read without end.
fn log_file(path: PathBuf) -> PyResult<PathBuf> {
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

/// The ROS 2 bag at `path`, read when flightlog found it is MCAP but not a flapwing log
/// (`not_flapwing`, the error given if it has no ROS 2 channel either): what `flapwing
/// replay` does.
fn ros2_bag(path: &Path, not_flapwing: flightlog::Error) -> PyResult<Bag> {
    let bag = read_bag(path).map_err(log_err)?;
    if !bag.has_ros2() {
        return Err(log_err(not_flapwing));
    }
    Ok(bag)
}

/// The topics of a log (or of a ROS 2 bag), in file order.
#[pyfunction]
pub fn log_topics(py: Python<'_>, path: PathBuf) -> PyResult<Vec<String>> {
    let path = log_file(path)?;
    match py.detach(|| flightlog::replay::read_summary(&path)) {
        Ok(s) => Ok(s.channels.into_iter().map(|c| c.topic).collect()),
        Err(e @ flightlog::Error::NotFlapwing { .. }) => {
            let bag = py.detach(|| ros2_bag(&path, e))?;
            Ok(bag.channels.into_values().map(|c| c.topic).collect())
        }
        Err(e) => Err(log_err(e)),
    }
}

/// What is missing from a flapwing MCAP log (or a ROS 2 bag): `None` for a complete log,
/// else flightlog's note of where it is truncated or damaged and how much was recovered (a
/// killed run's log).
#[pyfunction]
pub fn log_damage(py: Python<'_>, path: PathBuf) -> PyResult<Option<String>> {
    let path = log_file(path)?;
    match py.detach(|| flightlog::replay::read_summary(&path)) {
        Ok(s) => Ok(s.damage),
        Err(e @ flightlog::Error::NotFlapwing { .. }) => {
            Ok(py.detach(|| ros2_bag(&path, e))?.damage)
        }
        Err(e) => Err(log_err(e)),
    }
}

/// One channel of a flapwing MCAP log (or one topic of a ROS 2 bag) as {column: numpy
/// array}: `log_time_ns` (int64) and one column per message field by its dotted path (a ROS 2
/// array element `transforms.0.child_frame_id`: the columns of `flapwing replay --csv`);
/// numeric columns are float64 arrays (NaN where a message lacks the field), others lists
/// of str (None where missing). A bag topic that cannot be decoded is flightlog's error.
#[pyfunction]
pub fn read_channel<'py>(
    py: Python<'py>,
    path: PathBuf,
    topic: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let path = log_file(path)?;
    let (columns, rows) = py.detach(|| match flightlog::replay::read_table(&path, topic) {
        Ok(t) => Ok((t.columns, t.rows)),
        Err(e @ flightlog::Error::NotFlapwing { .. }) => {
            let bag = ros2_bag(&path, e)?;
            let t = read_topic_table(&bag, topic).map_err(log_err)?;
            Ok((t.columns, t.rows))
        }
        Err(e) => Err(log_err(e)),
    })?;
    table_dict(py, &columns, &rows)
}

/// A table (the first column the log time in ns) as {column: numpy array or list}.
fn table_dict<'py>(
    py: Python<'py>,
    columns: &[String],
    rows: &[Vec<Option<String>>],
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (j, name) in columns.iter().enumerate() {
        let cells: Vec<Option<&str>> = rows.iter().map(|r| r[j].as_deref()).collect();
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
