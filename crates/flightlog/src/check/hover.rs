//! Re-running a `hover` log: `flapwing hover`'s run from its logged settings. The settings
//! hold the trim the run flew from (its controls, attitude and flight condition: the logged
//! numbers are read back exactly, `serde_json`'s `float_roundtrip`), the disturbance, open or
//! closed loop, the controller's delay and the wind field; the controller is the LQR of the
//! default weights designed at that trim, as the command designs it
//! ([`flapsim::control::HoverController::design`]), and the run is
//! [`flapsim::control::run_hover_with`] on the true state. A run flown on the state estimate
//! (`--feedback estimated`) is not re-run: its controller flew on noisy sensors whose noise
//! the log does not hold.

use serde::Deserialize;

use super::CheckOutcome;
use super::compare::Comparer;
use crate::error::{Error, Result};

/// The settings `flapwing hover` writes into its log's metadata.
#[derive(Debug, Clone, Deserialize)]
pub(super) struct HoverSettings {
    duration_s: f64,
    disturbance: flapsim::control::Disturbance,
    open_loop: bool,
    delay_wingbeats: usize,
    feedback: String,
    trim: flapsim::trim::Trim,
    /// The run's wind field (absent: still air apart from the disturbance's gust).
    #[serde(default)]
    wind: Option<flapsim::WindSpec>,
}

impl HoverSettings {
    /// The settings of a `hover` log: `Ok(Err(reason))` when the run cannot be re-run.
    pub(super) fn from_json(text: &str) -> Result<std::result::Result<Self, String>> {
        let s: Self = serde_json::from_str(text)
            .map_err(|e| Error::Embedded(format!("the log's hover settings do not load: {e}")))?;
        if !(s.duration_s.is_finite() && s.duration_s >= 0.0) {
            return Err(Error::Embedded(format!(
                "the hover settings' duration {} s is not a finite time >= 0",
                s.duration_s
            )));
        }
        if s.feedback != "true" {
            return Ok(Err(format!(
                "the run flew on the state estimate (feedback `{}`), from sensors whose noise the log does not hold; only runs on the true state can be re-run",
                s.feedback
            )));
        }
        Ok(Ok(s))
    }
}

/// Re-runs the hover of `s` with `vehicle` (the embedded model, as the log's metadata
/// built it) and compares it with the log.
pub(super) fn rerun(
    s: &HoverSettings,
    vehicle: flapsim::Vehicle,
    mut comparer: Comparer,
    complete: bool,
) -> Result<CheckOutcome> {
    let mut trimmed = match flapsim::trim::trimmed_vehicle(&vehicle, &s.trim) {
        Ok(v) => v,
        Err(e) => return Ok(comparer.stopped(&format!("the logged trim: {e}"))),
    };
    trimmed.wind = s.wind.clone();
    let controller = match s.open_loop {
        true => None,
        false => match flapsim::control::HoverController::design(
            &trimmed,
            &s.trim,
            &flapsim::control::LqrWeights::default(),
            s.delay_wingbeats,
        ) {
            Ok(c) => Some(c),
            Err(e) => return Ok(comparer.stopped(&format!("the controller's design: {e}"))),
        },
    };
    let mut difference = None;
    let outcome = flapsim::control::run_hover_with(
        &trimmed,
        &s.trim,
        controller,
        &s.disturbance,
        s.duration_s,
        None,
        |step| {
            if comparer.done() {
                return false;
            }
            difference = comparer.step(step.out, step.sim);
            difference.is_none()
        },
    );
    if let Some(m) = difference {
        return Ok(m);
    }
    match outcome {
        Err(e) => Ok(comparer.stopped(&e.to_string())),
        Ok(o) => match o.diverged {
            Some(why) if !comparer.done() => Ok(comparer.stopped(&why)),
            _ => Ok(comparer.finish(s.duration_s, complete)),
        },
    }
}
