//! What the estimator's tests share: the trimmed fruit fly and a filter prior drawn around
//! the true start from the prior's own distribution (so that the filter's starting error is
//! what its covariance says).
#![allow(dead_code)]

use flapsim::estimator::Prior;
use flapsim::sensors::Noise;
use flapsim::trim::{Trim, trim, trimmed_vehicle};
use flapsim::{State, Vehicle};
use nalgebra::UnitQuaternion;

/// The built-in fruit fly trimmed for hover, and its trim.
pub fn fly() -> (Vehicle, Trim) {
    let mut v = Vehicle::from_toml(flapsim::DROSOPHILA_TOML, "drosophila").unwrap();
    // The estimator's tests pin what issue #27 measured with the loads taken at each step's
    // start (an IMU sample is a step's load; with the midpoint sampling it is the step's
    // mean, and the every-step propagation is no longer rapier's own step).
    v.sim.load_sampling = Some(flapsim::LoadSampling::StepStart);
    // ... at the 100 steps per wingbeat the fly was stepped at then.
    v.sim.steps_per_wingbeat = 100;
    let t = trim(&v).unwrap();
    let tv = trimmed_vehicle(&v, &t).unwrap();
    (tv, t)
}

/// A prior around the true start `s0`: standard deviations of one body length, one body
/// length per wingbeat and 10 degrees, and a start drawn from them with `seed`.
pub fn drawn_prior(v: &Vehicle, s0: &State, seed: u64) -> Prior {
    let mut draw = Noise::new(seed);
    let (sp_m, sv, sth) = (v.length_m, v.length_m * v.freq_hz(), 10f64.to_radians());
    let p0 = s0.position_m + draw.vec3(sp_m);
    let v0 = s0.velocity_m_s + draw.vec3(sv);
    let q0 = s0.world_from_body * UnitQuaternion::from_scaled_axis(draw.vec3(sth));
    Prior {
        position_world_m: [p0.x, p0.y, p0.z],
        velocity_world_m_s: [v0.x, v0.y, v0.z],
        world_from_body: q0,
        position_std_m: sp_m,
        velocity_std_m_s: sv,
        attitude_std_rad: sth,
    }
}
