//! Cycle-averaged loads at a frozen body state: the averaged model that trim and the
//! stability derivatives of Sun and Xiong (2005) are built on. The body's velocity and
//! attitude are held fixed over one wingbeat while the wings flap; the loads are averaged
//! over `steps` equally spaced phases.

use nalgebra::{UnitQuaternion, Vector3};
use wingforce::{BodyMotion, Term};

use crate::error::Result;
use crate::model::Vehicle;
pub use crate::wings::MeanLoads;

/// A frozen body state for averaging.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrozenState {
    /// Attitude world_from_body.
    pub world_from_body: UnitQuaternion<f64>,
    /// Air-relative velocity of the CoM in the body frame, m/s.
    pub velocity_body_m_s: Vector3<f64>,
    /// Angular velocity, body frame, rad/s.
    pub angular_velocity_body_rad_s: Vector3<f64>,
}

/// Mean loads over one wingbeat at a frozen state: `steps` samples of the prescribed
/// kinematics (with the vehicle's midpoint load sampling, `Vehicle::load_sampling`, the
/// means over `steps` steps that a simulation stepping at that count applies:
/// `wingforce::Wing::kinematic_loads_over_step`, the translational term at each step's
/// midpoint; so a trim balances the loads the simulation steps with), or, for an actuated vehicle, the wings run into their periodic motion at
/// that body state by the dynamics ([`crate::actuated::periodic`], which integrates at the
/// simulation's step and ignores `steps`; its error says when there is no periodic motion).
pub fn mean_loads(vehicle: &Vehicle, state: &FrozenState, steps: usize) -> Result<MeanLoads> {
    crate::cancel::check()?;
    let motion = BodyMotion {
        velocity_m_s: state.velocity_body_m_s,
        angular_velocity_rad_s: state.angular_velocity_body_rad_s,
    };
    if vehicle.actuation.is_some() {
        return Ok(crate::actuated::periodic::settle(vehicle, &motion)?.mean);
    }
    let mut out = MeanLoads::default();
    let w = 1.0 / steps as f64;
    let midpoint = vehicle.load_sampling() == wingset::LoadSampling::Midpoint;
    let dt_s = w / vehicle.freq_hz();
    for k in 0..steps {
        let phase = k as f64 * w;
        for wing in &vehicle.wings {
            let f = if midpoint {
                let s = wing.kinematic_loads_over_step(phase, (k + 1) as f64 * w, dt_s);
                wing.evaluate_with(&s.mean, &motion)
            } else {
                wing.evaluate(phase, &motion)
            };
            let hinge = &wing.mount().hinge_in_body_m;
            for term in Term::ALL {
                let t = f.term(term);
                let m = t.moment_about_com_nm(hinge);
                let slot = &mut out.terms[term as usize];
                slot.force_n += w * t.force_n;
                slot.moment_nm += w * m;
                out.total.force_n += w * t.force_n;
                out.total.moment_nm += w * m;
            }
        }
    }
    Ok(out)
}
