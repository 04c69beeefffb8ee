//! The host's step relative to the wingbeat: at most 1/10 of it ([`check_dt`]), checked where
//! it enters (building the set, a frequency change), so every host (flapsim, the C ABI and on
//! it MuJoCo and the FMU, Python) refuses the same steps with the same message.

use crate::error::{Error, Result};

/// Fewest steps per wingbeat a set accepts: its step `dt_s` is at most 1/10 of the wingbeat
/// period, `dt_s <= 1 / (10 f)`, the coarsest count of issue 37's error-cost frontier
/// (docs/speed.md). How coarse a step may be is a question of accuracy, which each built-in
/// vehicle's model states (`sim.accurate_steps_per_wingbeat`, the fewest counts of the
/// frontier that hold its bound: 20 for the fly and the bumblebee, whose hover alone held
/// from 12 and its forward flight from 20; a coarser run warns); the step-start sampling, which holds one sample of the kinematic pulses per step,
/// aliases them well above this minimum. 10 is also the smallest `sim.steps_per_wingbeat` a
/// vehicle model accepts (flapsim's own host steps the same loads).
pub const MIN_STEPS_PER_WINGBEAT: f64 = 10.0;

/// The longest step a set accepts at wingbeat frequency `freq_hz`: `1 / (10 f)`, s.
pub fn max_dt_s(freq_hz: f64) -> f64 {
    1.0 / (MIN_STEPS_PER_WINGBEAT * freq_hz)
}

/// Checks a host's step against the wingbeat: finite, > 0 and at most `max_dt_s(freq_hz)`
/// (within a relative 1e-12, so that `1 / (10 f)` itself passes), or an error naming the step,
/// the wingbeat and what is allowed.
pub fn check_dt(dt_s: f64, freq_hz: f64) -> Result<()> {
    if !(dt_s > 0.0 && dt_s.is_finite()) {
        return Err(Error::Input(format!(
            "wing set: time step dt_s = {dt_s}; allowed: a finite step > 0 s of at most 1/{MIN_STEPS_PER_WINGBEAT} of the wingbeat period"
        )));
    }
    let per_beat = 1.0 / (freq_hz * dt_s);
    if per_beat < MIN_STEPS_PER_WINGBEAT * (1.0 - 1e-12) {
        // Debug: 1e300 as "1e300", not 301 digits.
        let per = if per_beat >= 1e-3 {
            format!("{per_beat:.4}")
        } else {
            format!("{per_beat:.3e}")
        };
        return Err(Error::Input(format!(
            "wing set: time step dt_s = {dt_s:?} s is {per} steps per wingbeat at {freq_hz} Hz; allowed: a finite step > 0 s of at most 1/{MIN_STEPS_PER_WINGBEAT} of the wingbeat period (dt_s <= {:.6e} s at {freq_hz} Hz)",
            max_dt_s(freq_hz)
        )));
    }
    Ok(())
}
