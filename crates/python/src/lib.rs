//! The `flapwing` Python package's native module, `flapwing._flapwing` (pyo3, abi3).
//!
//! Glue only: every number comes from wingforce, flapsim and flightlog; this crate converts
//! arguments and results (numpy arrays, dicts) and maps flapwing's errors to Python
//! exceptions (`ValueError` for bad models and arguments, [`DivergedError`] and
//! [`AnalysisError`] for runs and analyses that fail, `OSError` for files). The Python
//! package in `python/flapwing/` re-exports these classes, documents them (`.pyi` stubs) and
//! adds the Gymnasium environments.

mod convert;
mod env;
mod flight;
mod interrupt;
mod logs;
mod sim;
mod state;
mod vehicle;
mod wing;
mod wings;

use pyo3::create_exception;
use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;

create_exception!(
    flapwing,
    DivergedError,
    PyRuntimeError,
    "A simulation left the physically meaningful region (flapsim's Error::Diverged)."
);
create_exception!(
    flapwing,
    AnalysisError,
    PyRuntimeError,
    "Trim or a stability analysis could not find what it looked for (flapsim's Error::Analysis)."
);

/// flapsim's error as the matching Python exception, with flapsim's message.
pub(crate) fn sim_err(e: impl Into<flapsim::Error>) -> PyErr {
    match e.into() {
        flapsim::Error::Model(m) => PyValueError::new_err(m.to_string()),
        flapsim::Error::Input(m) => PyValueError::new_err(m),
        e @ flapsim::Error::Diverged { .. } => DivergedError::new_err(e.to_string()),
        e @ flapsim::Error::Analysis(_) => AnalysisError::new_err(e.to_string()),
    }
}

/// wingforce's error (a bad model file or value) as a `ValueError`.
pub(crate) fn wing_err(e: wingforce::Error) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// flightlog's error: `OSError` for files that cannot be read or written, `ValueError` for
/// the rest (not an MCAP file, unknown topic, bad metadata).
pub(crate) fn log_err(e: flightlog::Error) -> PyErr {
    match e {
        flightlog::Error::Io { .. } => PyOSError::new_err(e.to_string()),
        e => PyValueError::new_err(e.to_string()),
    }
}

/// The names of the built-in vehicles: what `Vehicle`, `Simulation`, `HoverTask` and the
/// Gymnasium environments take (each has a `[sensors]` table).
#[pyfunction]
fn builtin_models() -> Vec<&'static str> {
    vehicle::BUILTIN_VEHICLES.to_vec()
}

/// The names of the built-in wing-only models (`robofly`): `Wing` takes these and every
/// vehicle of `builtin_models()`.
#[pyfunction]
fn builtin_wings() -> Vec<&'static str> {
    vec!["robofly"]
}

#[pymodule]
fn _flapwing(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("DivergedError", py.get_type::<DivergedError>())?;
    m.add("AnalysisError", py.get_type::<AnalysisError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(builtin_models, m)?)?;
    m.add_function(wrap_pyfunction!(builtin_wings, m)?)?;
    m.add_function(wrap_pyfunction!(flight::envelope, m)?)?;
    m.add_class::<wing::Wing>()?;
    m.add_class::<vehicle::Vehicle>()?;
    m.add_class::<vehicle::HoverController>()?;
    m.add_class::<sim::Simulation>()?;
    m.add_class::<wings::WingSet>()?;
    m.add_class::<env::HoverTask>()?;
    m.add_class::<env::VecHoverTask>()?;
    m.add_function(wrap_pyfunction!(logs::log_topics, m)?)?;
    m.add_function(wrap_pyfunction!(logs::log_damage, m)?)?;
    m.add_function(wrap_pyfunction!(logs::read_channel, m)?)?;
    Ok(())
}
