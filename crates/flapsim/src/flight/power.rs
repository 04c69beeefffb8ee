//! The power the wings' drive spends against the air (see the module above).

use serde::{Deserialize, Serialize};
use wingforce::wing::WingFrame;
use wingforce::{Wing, WingForces};

use crate::error::Result;
use crate::model::Vehicle;

/// Power a set of wings spends against the air over one wingbeat.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Power {
    /// Cycle-mean aerodynamic power, W: negative work stored and returned (perfect elastic
    /// storage).
    pub aero_w: f64,
    /// Cycle mean of the positive part of each wing's power, W: negative work lost (no
    /// elastic storage), the other bound Dudley & Ellington (1990b) report.
    pub aero_positive_w: f64,
}

/// One wing's instantaneous aerodynamic power, W: - M_hinge . omega_wing (the moment of its
/// aerodynamic force about the hinge and its angular velocity relative to the body, body
/// axes).
pub fn wing_power_w(wing: &Wing, forces: &WingForces) -> f64 {
    let omega_body =
        wing.body_from_stroke() * WingFrame::new(&forces.angles, wing.mount().side).omega;
    -forces.total.moment_hinge_nm.dot(&omega_body)
}

/// The power of `wings` over equally weighted samples of a wingbeat, each sample holding
/// every wing's forces in the wings' order.
pub fn cycle_power<'a, S>(wings: &[Wing], samples: impl ExactSizeIterator<Item = &'a S>) -> Power
where
    S: AsRef<[WingForces]> + 'a,
{
    let w = 1.0 / samples.len().max(1) as f64;
    let mut out = Power::default();
    for forces in samples {
        for (wing, f) in wings.iter().zip(forces.as_ref()) {
            let p = wing_power_w(wing, f);
            out.aero_w += w * p;
            out.aero_positive_w += w * p.max(0.0);
        }
    }
    out
}

/// The wings' power over one wingbeat at a frozen body state: `steps` samples of the
/// prescribed kinematics (with a wake that answers, over its periodic motion at that state:
/// [`crate::averaged::periodic_inflow`], as the averaged model's loads), or an actuated
/// vehicle's periodic motion at that state ([`crate::actuated::periodic`], at the
/// simulation's step, its pair's inflow with it).
pub fn power_at(
    vehicle: &Vehicle,
    state: &crate::averaged::FrozenState,
    steps: usize,
) -> Result<Power> {
    let motion = wingforce::BodyMotion {
        velocity_m_s: state.velocity_body_m_s,
        angular_velocity_rad_s: state.angular_velocity_body_rad_s,
    };
    if vehicle.actuation.is_some() {
        let p = crate::actuated::periodic::settle(vehicle, &motion)?;
        return Ok(cycle_power(&p.wings, p.samples.iter()));
    }
    if let Some(p) = crate::averaged::periodic_inflow(vehicle, &motion, steps)? {
        return Ok(cycle_power(&vehicle.wings, p.samples.iter()));
    }
    let samples: Vec<Vec<WingForces>> = (0..steps)
        .map(|k| {
            let phase = k as f64 / steps as f64;
            vehicle
                .wings
                .iter()
                .map(|w| w.evaluate(phase, &motion))
                .collect()
        })
        .collect();
    Ok(cycle_power(&vehicle.wings, samples.iter()))
}
