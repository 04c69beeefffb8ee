//! An actuated vehicle in the [`Simulation`]: the wing states the analyses set and read.

use super::Simulation;
use crate::actuated::ActuatedWings;

impl Simulation {
    /// Continues an actuated vehicle's wings from a periodic motion found at a frozen body
    /// state ([`crate::actuated::periodic::settle`] on this vehicle), instead of from rest.
    /// The motion spans whole drive periods, so it joins the simulation's phase 0; call it
    /// before the first step. Does nothing for prescribed kinematics.
    pub fn start_wings_from(&mut self, p: &crate::actuated::PeriodicWings) {
        self.wings
            .start_dynamic_from(&p.dynamic, &p.wings, p.inflow.as_ref());
    }

    /// An actuated vehicle's wings now (their dynamics, and the wings with the stroke
    /// reference measured on the way): what a simulation restarted here continues from
    /// ([`Simulation::continue_wings`]); `None` for prescribed kinematics.
    pub fn wings_now(&self) -> Option<ActuatedWings> {
        Some(ActuatedWings {
            dynamic: self.wings.dynamic_wings()?.to_vec(),
            wings: self.wings.wings().to_vec(),
            inflow: self.wings.pair_inflows().cloned(),
        })
    }

    /// Continues an actuated vehicle's wings from another simulation's
    /// ([`Simulation::wings_now`]), at a step of the same drive phase; call it before the
    /// first step. Does nothing for prescribed kinematics.
    pub fn continue_wings(&mut self, w: &ActuatedWings) {
        self.wings
            .start_dynamic_from(&w.dynamic, &w.wings, w.inflow.as_ref());
    }

    /// The wings' dynamic states (left, right) of an actuated vehicle.
    pub fn wing_states(&self) -> Option<[crate::actuated::WingState; 2]> {
        match self.wings.dynamic_wings()? {
            [l, r, ..] => Some([l.state(), r.state()]),
            _ => None,
        }
    }

    /// Overwrites the wings' dynamic states of an actuated vehicle (Floquet perturbations);
    /// does nothing for prescribed kinematics.
    pub fn set_wing_states(&mut self, states: [crate::actuated::WingState; 2]) {
        self.wings.set_wing_states(&states);
    }
}
