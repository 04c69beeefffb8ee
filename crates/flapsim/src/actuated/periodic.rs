//! The wings' periodic motion at a frozen body state: what the averaged model, trim and the
//! start of a hover need of an actuated vehicle, whose wing motion is not given but comes
//! out of the drive.
//!
//! Both wings are integrated from rest (at their springs' rest angles) with the body held at
//! the frozen velocity and angular velocity for [`super::Actuation::settle_cycles`] drive
//! periods, then for one more period over which the aerodynamic loads are averaged. The run
//! has a fixed length, so the mean loads are a smooth function of the drive and the body
//! state (finite-difference Jacobians stay clean). The motion must have become periodic:
//! the angles (and the rates times the period over 2 pi) at the start and the end of the
//! averaged period agree to [`PERIODIC_TOLERANCE_RAD`], or the analysis stops with an error
//! that says how far the motion still drifts.
//!
//! Only the aerodynamic loads are averaged: the wings' and actuators' inertial reaction is
//! the time derivative of a periodic momentum (and angular momentum about the hinge), so
//! its cycle mean is zero.

use wingforce::{BodyMotion, Term, Wing, WingForces};

use super::driven::DrivenPair;
use crate::error::{Error, Result};
use crate::model::Vehicle;
use crate::wings::MeanLoads;
use wingset::PairInflows;
use wingset::actuated::dynamics::{DynamicWing, WingState};

/// Largest change of a wing angle over the averaged period for the motion to count as
/// periodic, rad (0.06 deg).
pub const PERIODIC_TOLERANCE_RAD: f64 = 1e-3;

/// An actuated vehicle's wings at one step: the hinge and actuator states, the drive, the
/// drive period's bookkeeping and the stroke reference (the wake-capture inputs); what a
/// simulation restarted at that step continues from (`Simulation::wings_now`,
/// `Simulation::continue_wings`).
#[derive(Debug, Clone)]
pub struct ActuatedWings {
    /// The wings' dynamics.
    pub dynamic: Vec<DynamicWing>,
    /// The wings, with their stroke reference.
    pub wings: Vec<Wing>,
    /// The pair's dynamic inflow (states and the stroke its disc was measured from), when
    /// the wake answers.
    pub inflow: Option<PairInflows>,
}

/// Two wings on their periodic motion at a frozen body state.
#[derive(Debug, Clone)]
pub struct PeriodicWings {
    /// The wings' dynamics at the end of the averaged period (a whole number of drive
    /// periods from the start: a simulation can continue from here at phase 0).
    pub dynamic: [DynamicWing; 2],
    /// The wings with the stroke reference (wake-capture inputs) measured on the way.
    pub wings: [Wing; 2],
    /// The pair's dynamic inflow on its periodic motion (with the stroke its disc was
    /// measured from), when the wake answers.
    pub inflow: Option<PairInflows>,
    /// Each pair's inflow states averaged over that period (empty unless the wake answers).
    pub inflow_mean: Vec<wingforce::inflow::InflowState>,
    /// Mean aerodynamic loads over the averaged period (body frame, about the CoM).
    pub mean: MeanLoads,
    /// Each wing's forces at every step of the averaged period (phase k / steps).
    pub samples: Vec<[WingForces; 2]>,
    /// Largest change of an angle (or a rate times period / 2 pi) over that period, rad.
    pub drift_rad: f64,
    /// Drive periods run in all.
    pub cycles: usize,
}

fn largest_change(a: &[WingState; 2], b: &[WingState; 2], period_s: f64) -> f64 {
    let k = period_s / (2.0 * std::f64::consts::PI);
    a.iter()
        .zip(b)
        .map(|(a, b)| {
            [
                (a.phi_rad - b.phi_rad).abs(),
                (a.theta_rad - b.theta_rad).abs(),
                k * (a.phi_dot_rad_s - b.phi_dot_rad_s).abs(),
                k * (a.theta_dot_rad_s - b.theta_dot_rad_s).abs(),
            ]
            .into_iter()
            .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max)
}

/// For an actuated vehicle, its wings settled at a body at rest (how a hover that has been
/// going on starts); `None` for prescribed kinematics.
pub fn settle_at_rest(vehicle: &Vehicle) -> Result<Option<PeriodicWings>> {
    if vehicle.actuation.is_some() {
        settle(vehicle, &BodyMotion::default()).map(Some)
    } else {
        Ok(None)
    }
}

/// Runs the wings of actuated `vehicle` into their periodic motion with the body moving as
/// `motion` (held fixed), and averages their aerodynamic loads over one period.
pub fn settle(vehicle: &Vehicle, motion: &BodyMotion) -> Result<PeriodicWings> {
    let Some(act) = &vehicle.actuation else {
        return Err(Error::Analysis(format!(
            "{} has prescribed kinematics: its wings have no dynamics to settle",
            vehicle.name
        )));
    };
    let n = vehicle.sim.steps_per_wingbeat;
    let freq_hz = act.drives[0].freq_hz;
    let period_s = 1.0 / freq_hz;
    let dt_s = period_s / n as f64;
    let mut pair = DrivenPair::new(vehicle, [act.drives[0], act.drives[1]])?;
    let what = |e: Error| match e {
        Error::Diverged { t_s, reason, .. } => Error::Analysis(format!(
            "the wings of {} have no periodic motion at this drive and body state: {reason} (t = {t_s:.5} s after the start from rest)",
            vehicle.name
        )),
        e => e,
    };
    for _ in 0..act.settle_cycles * n {
        pair.step(motion, dt_s).map_err(what)?;
    }
    let states = |p: &DrivenPair| [p.dynamic[0].state(), p.dynamic[1].state()];
    let start = states(&pair);
    let inflow_start = pair.inflow.as_ref().map(PairInflows::states);
    let mut mean = MeanLoads::default();
    let mut samples = Vec::with_capacity(n);
    let mut inflow_mean = Vec::new();
    let w = 1.0 / n as f64;
    for _ in 0..n {
        let s = pair.step(motion, dt_s).map_err(what)?;
        for (i, s) in s.iter().enumerate() {
            let hinge = pair.wings[i].mount().hinge_in_body_m;
            for term in Term::ALL {
                let t = s.forces.term(term);
                let m = t.moment_about_com_nm(&hinge);
                mean.terms[term as usize].add(w * t.force_n, w * m);
                mean.total.add(w * t.force_n, w * m);
            }
        }
        samples.push([s[0].forces, s[1].forces]);
        if let Some(i) = &pair.inflow {
            i.add_states_to(&mut inflow_mean, w);
        }
    }
    let end = states(&pair);
    let mut drift_rad = largest_change(&start, &end, period_s);
    if let (Some(a), Some(i)) = (inflow_start, &pair.inflow) {
        // The inflow's drift over the period, as an angle: its change relative to the mean
        // inflow, which [`PERIODIC_TOLERANCE_RAD`] bounds like the wings' angles.
        for (a, b) in a.iter().zip(i.states()) {
            let scale = b.mean_m_s.abs().max(f64::MIN_POSITIVE);
            let (a, b) = (a.to_array(), b.to_array());
            for k in 0..3 {
                drift_rad = drift_rad.max((a[k] - b[k]).abs() / scale);
            }
        }
    }
    if !(drift_rad <= PERIODIC_TOLERANCE_RAD) {
        return Err(Error::Analysis(format!(
            "the wings of {} did not settle into a periodic motion in {} drive periods: an angle{} still changes by {:.3} deg per period (allowed: {:.3} deg); raise [actuation] settle_cycles",
            vehicle.name,
            act.settle_cycles,
            if pair.inflow.is_some() {
                " (or the dynamic inflow, relative to its mean, in radians)"
            } else {
                ""
            },
            drift_rad.to_degrees(),
            PERIODIC_TOLERANCE_RAD.to_degrees()
        )));
    }
    let DrivenPair {
        dynamic,
        wings,
        inflow,
        ..
    } = pair;
    Ok(PeriodicWings {
        dynamic,
        wings,
        inflow,
        inflow_mean,
        mean,
        samples,
        drift_rad,
        cycles: act.settle_cycles + 1,
    })
}
