//! What a host may hand the wing set at each step: a body state and wind whose loads the model
//! can compute (the step's length is bounded in `dt`). Checked in the set's step, so every
//! host (flapsim, the C ABI and on it MuJoCo and the FMU, Python) refuses the same inputs
//! with the same message.

use nalgebra::Vector3;
use wingforce::BodyMotion;

use super::WingSet;
use super::body::State;
use crate::error::{Error, LOAD_OVERFLOW, Result};

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
