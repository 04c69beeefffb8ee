//! Re-running a `hover` log: `flapwing hover`'s run from its logged settings. The settings
//! hold the trim the run flew from (its controls, attitude and flight condition: the logged
//! numbers are read back exactly, `serde_json`'s `float_roundtrip`), the disturbance, open or
//! closed loop, the controller's delay and the wind field; the controller is the LQR of the
//! default weights designed at that trim, as the command designs it
//! ([`flapsim::control::HoverController::design`]), and the run is
//! [`flapsim::control::run_hover_with`] on the true state, or on the state estimate
//! (`--feedback estimated`) of the model's sensors with the logged seed of their noise. A
//! run on the estimate logged before the seed was is not re-run.

use flapsim::estimator::{EstimatedFeedback, Prior};
use serde::Deserialize;

use super::compare::Comparer;
use super::outcome::CheckOutcome;
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
    /// The seed of the sensors' noise a run on the state estimate flew on (absent: a run on
    /// the true state, or one logged before the seed was).
    #[serde(default)]
    sensor_seed: Option<u64>,
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
        match (s.feedback.as_str(), s.sensor_seed) {
            ("true", _) | ("estimated", Some(_)) => Ok(Ok(s)),
            ("estimated", None) => Ok(Err(
                "the run flew on the state estimate, and the log (written before the sensors' seed was logged) does not say which noise its sensors had".into(),
            )),
            (other, _) => Err(Error::Embedded(format!(
                "the hover settings' feedback `{other}` is not a feedback: allowed `true`, `estimated`"
            ))),
        }
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
    // On the estimate: the model's sensors with the logged seed and the filter starting at
    // the trim pose at rest, as the command builds them.
    let mut feedback = match s.sensor_seed.filter(|_| s.feedback == "estimated") {
        None => None,
        Some(seed) => {
            match EstimatedFeedback::new(&trimmed, seed, &Prior::hover(&trimmed, s.trim.attitude()))
            {
                Ok(f) => Some(f),
                Err(e) => return Ok(comparer.stopped(&format!("the sensors and filter: {e}"))),
            }
        }
    };
    let mut difference = None;
    let outcome = flapsim::control::run_hover_with(
        &trimmed,
        &s.trim,
        controller,
        &s.disturbance,
        s.duration_s,
        feedback.as_mut(),
        |step| {
            if comparer.done() {
                return false;
            }
            difference = comparer.step(step.out, step.sim);
            // Stop once the log's last sample has matched: no step beyond it, as the
            // simulate re-run takes none (the logged run may have ended at the next one).
            difference.is_none() && !comparer.done()
        },
    );
    if let Some(m) = difference {
        return Ok(m);
    }
    match outcome {
        Err(e) if !comparer.done() => Ok(comparer.stopped(&e.to_string())),
        Err(_) => Ok(comparer.finish(s.duration_s, complete)),
        Ok(o) => match o.diverged {
            Some(why) if !comparer.done() => Ok(comparer.stopped(&why)),
            _ => Ok(comparer.finish(s.duration_s, complete)),
        },
    }
}
