//! An actuated vehicle in the [`Simulation`]: the wing states the analyses set and read.

use super::Simulation;

impl Simulation {
    /// Continues an actuated vehicle's wings from a periodic motion found at a frozen body
    /// state ([`crate::actuated::periodic::settle`] on this vehicle), instead of from rest.
    /// The motion spans whole drive periods, so it joins the simulation's phase 0; call it
    /// before the first step. Does nothing for prescribed kinematics.
    pub fn start_wings_from(&mut self, p: &crate::actuated::PeriodicWings) {
        self.wings.start_dynamic_from(&p.dynamic, &p.wings);
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
