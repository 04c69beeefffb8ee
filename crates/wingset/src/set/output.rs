//! What one step of the wing set reports ([`WingSetOutput`]): plain data below the set,
//! which keeps the last one, and its step, which fills it.

use wingforce::WingForces;

use super::body::BodyLoad;
use crate::actuated::ActuatedWingOutput;
use crate::controls::Controls;

/// What one step of a [`WingSet`](super::WingSet) computed.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct WingSetOutput {
    /// Step index k.
    pub step: u64,
    /// t_k, s.
    pub t_s: f64,
    /// Wingbeat phase at which the loads were taken (cycles): at t_k, or at t_k + dt/2 with
    /// [`LoadSampling::Midpoint`](crate::LoadSampling::Midpoint).
    pub phase: f64,
    /// Each wing's forces, in the set's order.
    pub wings: Vec<WingForces>,
    /// Each actuated wing's hinge and actuator state (empty for prescribed kinematics).
    pub actuated: Vec<ActuatedWingOutput>,
    /// Aerodynamic load of each term ([`wingforce::Term::ALL`] order), all wings, about the CoM.
    pub terms: [BodyLoad; 4],
    /// Inertial reaction of the wings' (and actuators') masses.
    pub wing_inertia: BodyLoad,
    /// The body's parasite drag at its centre of mass (no moment), when the host turned it on
    /// ([`WingSet::set_body_drag_area_m2`](super::WingSet::set_body_drag_area_m2)); zero
    /// otherwise.
    pub body_drag: BodyLoad,
    /// Everything the set applies to the body: the four terms, the wings' inertia and the body
    /// drag.
    pub total: BodyLoad,
    /// Controls in force during this step.
    pub controls: Controls,
    /// Each wing pair's dynamic inflow states the step's loads were taken at (empty unless
    /// the wake answers: `wingforce::inflow::dynamic`).
    pub inflow: Vec<wingforce::inflow::InflowState>,
}

/// A wing's forces before any step: all zero (what a host reports before its first step).
pub fn zero_forces() -> WingForces {
    WingForces {
        terms: Default::default(),
        total: Default::default(),
        angles: Default::default(),
        phase: wingforce::StrokePhase {
            half_stroke: 0,
            t_star: 0.0,
            downstroke: true,
        },
    }
}

impl WingSetOutput {
    pub(super) fn empty(n: usize) -> Self {
        let wing = zero_forces();
        Self {
            step: 0,
            t_s: 0.0,
            phase: 0.0,
            wings: vec![wing; n],
            actuated: Vec::new(),
            terms: Default::default(),
            wing_inertia: BodyLoad::default(),
            body_drag: BodyLoad::default(),
            total: BodyLoad::default(),
            controls: Controls::default(),
            inflow: Vec::new(),
        }
    }
}
