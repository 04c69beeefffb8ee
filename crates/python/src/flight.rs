//! `flapwing.envelope`: the flight envelope of flapstudy::envelope from Python, its points
//! in parallel with the GIL released, Ctrl-C stopping the points within a second (those in
//! flight at their next `flapsim::cancel` checkpoint).

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::sync::atomic::Ordering;

use crate::convert::{record, vector};
use crate::vehicle::Vehicle;

/// The envelope of `vehicle` over every forward speed of `speeds_m_s` with every climb rate
/// of `climbs_m_s` (default `[0.0]`): a list of dicts, one per condition in that order
/// (climb rates outermost), each with `condition`, `point` (the trim, the stroke-plane angle,
/// amplitude, power and downwash, the limit margin and the modes; `None` when the point does
/// not trim) and `no_trim_reason`. Raises `ValueError` for an empty or non-finite grid and
/// `TypeError` for values that are not real numbers (booleans included), and
/// `KeyboardInterrupt` on Ctrl-C.
#[pyfunction]
#[pyo3(signature = (vehicle, speeds_m_s, climbs_m_s = None))]
pub fn envelope<'py>(
    py: Python<'py>,
    vehicle: &Vehicle,
    speeds_m_s: &Bound<'py, PyAny>,
    climbs_m_s: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    // Real numbers only: booleans, complex and text are a TypeError naming the argument.
    let speeds = vector("speeds_m_s", speeds_m_s, None)?;
    let climbs = match climbs_m_s {
        Some(c) => vector("climbs_m_s", c, None)?,
        None => vec![0.0],
    };
    let grid = flapstudy::envelope::EnvelopeGrid::new(speeds, climbs, "speeds_m_s / climbs_m_s")
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let v = &vehicle.vehicle;
    let rows = crate::interrupt::watch_token(py, |stop| {
        let run =
            || flapstudy::envelope::envelope(v, &grid, &|_| {}, &|| stop.load(Ordering::Relaxed));
        // The points run on a pool of their own whose threads carry the cancel token, so
        // that Ctrl-C stops the trims and analyses in flight, not only the points to come.
        let token = stop.clone();
        match rayon::ThreadPoolBuilder::new()
            .num_threads(rayon::current_num_threads())
            .start_handler(move |_| flapsim::cancel::install(token.clone()))
            .build()
        {
            Ok(pool) => pool.install(run),
            Err(_) => run(),
        }
    })?;
    record(py, &rows)
}
