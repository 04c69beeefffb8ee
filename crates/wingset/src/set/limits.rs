//! What a host may hand the wing set: its step relative to the wingbeat, and a body state and
//! wind whose loads the model can compute. Checked where they enter (building the set, a
//! frequency change, each step), so every host (flapsim, the C ABI and on it MuJoCo and the
//! FMU, Python) refuses the same inputs with the same message.

use nalgebra::Vector3;
use wingforce::BodyMotion;

use super::WingSet;
use super::body::State;
use crate::error::{Error, LOAD_OVERFLOW, Result};

/// Fewest steps per wingbeat a set accepts: its step `dt_s` is at most 1/20 of the wingbeat
/// period, `dt_s <= 1 / (20 f)`. The set samples each wing's kinematics and forces once per
/// step, at t_k, and holds them over the step; the force of a flapping wing varies at twice
/// the wingbeat frequency and faster (two half strokes, the rotational and wake-capture peaks
/// at each reversal), so fewer samples alias it into a wrong cycle-mean. 20 is the smallest
/// `sim.steps_per_wingbeat` a vehicle model accepts (flapsim's own host steps the same loads).
pub const MIN_STEPS_PER_WINGBEAT: f64 = 20.0;

/// The longest step a set accepts at wingbeat frequency `freq_hz`: `1 / (20 f)`, s.
pub fn max_dt_s(freq_hz: f64) -> f64 {
    1.0 / (MIN_STEPS_PER_WINGBEAT * freq_hz)
}

/// Checks a host's step against the wingbeat: finite, > 0 and at most `max_dt_s(freq_hz)`
/// (within a relative 1e-12, so that `1 / (20 f)` itself passes), or an error naming the step,
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

/// `[x, y, z]` for messages.
fn vec_str(v: &Vector3<f64>) -> String {
    format!("[{:e}, {:e}, {:e}]", v.x, v.y, v.z)
}

impl WingSet {
    /// The body state and the winds in force: every number finite, or an error naming the
    /// first that is not (nothing has changed).
    pub(super) fn check_input(&self, body: &State) -> Result<()> {
        if let Some(field) = body.first_non_finite() {
            return Err(Error::Input(format!(
                "wing set, step {} (t = {:.6} s): the body state's {field} is not finite; allowed: finite numbers",
                self.step,
                self.time_s()
            )));
        }
        let bad_wind = |w: &Vector3<f64>| w.iter().any(|x| !x.is_finite());
        if bad_wind(&self.wind_world_m_s) {
            return Err(Error::Input(format!(
                "wing set, step {}: the wind {} m/s is not finite; allowed: finite numbers",
                self.step,
                vec_str(&self.wind_world_m_s)
            )));
        }
        Ok(())
    }

    /// The error of a step whose loads overflowed: the forces grow with the square of the
    /// speed through the air, and a motion whose forces are not finite is refused, as
    /// wingforce's `Wing::evaluate` callers refuse it (Python's `Wing.evaluate`). Reported as
    /// [`Error::Diverged`] (for a host that integrates the body, flapsim's own, its run has left
    /// every flight), recognised by [`Error::is_load_overflow`] (hosts whose states come from
    /// their user report it as a bad input).
    pub(super) fn overflow_error(&self, body: &State, motion: &BodyMotion) -> Error {
        Error::Diverged {
            t_s: self.time_s(),
            step: self.step,
            reason: format!(
                "{LOAD_OVERFLOW} for the body's velocity through the air {} m/s (body frame; velocity_m_s {} m/s, wind {} m/s, world) and angular velocity {} rad/s; allowed: a body state and wind whose loads are finite (they grow with the square of the speed through the air)",
                vec_str(&motion.velocity_m_s),
                vec_str(&body.velocity_m_s),
                vec_str(&self.body_air_m_s()),
                vec_str(&body.angular_velocity_body_rad_s),
            ),
        }
    }
}
