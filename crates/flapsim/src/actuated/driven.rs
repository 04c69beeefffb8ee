//! Both wings of an actuated vehicle driven together with the body held in one motion: the
//! run that the periodic motion ([`super::periodic`]), the bench's tethered runs
//! ([`super::response`]) and every analysis built on them share.
//!
//! Each step takes each wing's dynamics one step on ([`DynamicWing::step`]) in the wings'
//! order, with the loads sampled as the vehicle's wing set samples them
//! ([`Vehicle::load_sampling`]; until issue 37's actuated step mean they were always taken
//! at the step's start here, so that the trim and the averaged model of an actuated vehicle
//! stayed first order under a second-order sampling). When the vehicle's wake answers (`[aero] inflow = "dynamic"`), the pair's
//! dynamic inflow goes with them as the wing set steps it (`wingset::set::inflow`): its
//! field is set on the wings before the step, and its states advance with the step's loads
//! after it; its disc is the stroke the wings swept over their last wingbeat
//! ([`wingset::DiscAmplitude::Measured`]).

use wingforce::{BodyMotion, Wing, WingForces};
use wingset::LoadSampling;
use wingset::PairInflows;
use wingset::actuated::drive::Drive;
use wingset::actuated::dynamics::{DynamicWing, WingStep};

use crate::error::{Error, Result};
use crate::model::Vehicle;

/// Two actuated wings and, when the wake answers, their pair's dynamic inflow.
#[derive(Debug, Clone)]
pub struct DrivenPair {
    /// The wings' dynamics.
    pub dynamic: [DynamicWing; 2],
    /// The wings (stroke reference, inflow field).
    pub wings: [Wing; 2],
    /// The pair's dynamic inflow, if its wake answers.
    pub inflow: Option<PairInflows>,
    /// The last step's forces, in the wings' order (the inflow's loads).
    forces: Vec<WingForces>,
    /// Where in a step the loads are taken: the vehicle's, as its wing set takes them.
    sampling: LoadSampling,
}

impl DrivenPair {
    /// The wings of actuated `vehicle` at rest, driven by `drives` (left, right).
    pub fn new(vehicle: &Vehicle, drives: [Drive; 2]) -> Result<Self> {
        let act = vehicle.actuation.as_ref().ok_or_else(|| {
            Error::Analysis(format!(
                "{} has prescribed kinematics: its wings have no dynamics to drive",
                vehicle.name
            ))
        })?;
        let wings: [Wing; 2] = [vehicle.wings[0].clone(), vehicle.wings[1].clone()];
        let inflow = PairInflows::of(&wings, wingset::DiscAmplitude::Measured)?;
        let sampling = vehicle.load_sampling();
        let wing = |drive: Drive| -> Result<DynamicWing> {
            let mut w = DynamicWing::new(act.dynamics.clone(), drive)?;
            w.set_load_sampling(sampling);
            w.set_strike_share(vehicle.strike_share());
            w.set_stage_loads(vehicle.sim.actuated_stage_loads);
            Ok(w)
        };
        Ok(Self {
            dynamic: [wing(drives[0])?, wing(drives[1])?],
            wings,
            inflow,
            forces: Vec::with_capacity(2),
            sampling,
        })
    }

    /// One step of `dt_s` with the body moving as `motion`: each wing's step (left, right).
    pub fn step(&mut self, motion: &BodyMotion, dt_s: f64) -> Result<[WingStep; 2]> {
        if let Some(i) = &mut self.inflow {
            i.apply(&mut self.wings, self.sampling);
        }
        let left = self.dynamic[0].step(&mut self.wings[0], motion, dt_s)?;
        let right = self.dynamic[1].step(&mut self.wings[1], motion, dt_s)?;
        if let Some(i) = &mut self.inflow {
            self.forces.clear();
            self.forces.extend([left.forces, right.forces]);
            i.advance(&self.wings, &self.forces, motion, dt_s)?;
        }
        Ok([left, right])
    }
}
