//! What evaluating a wing returns: all four terms with their sum ([`WingForces`]), or the
//! part of them the kinematics alone decide ([`KinematicLoads`]), which a simulator can keep
//! and finish later with the body's motion.

use crate::frame::WingFrame;
use crate::kinematics::{StrokePhase, WingAngles};
use crate::terms::{Term, TermForce};

/// Everything one evaluation produces.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WingForces {
    /// Per term, in the order of [`Term::ALL`].
    pub terms: [TermForce; 4],
    /// Sum of the terms.
    pub total: TermForce,
    /// The kinematic state used.
    pub angles: WingAngles,
    /// Half stroke and t*.
    pub phase: StrokePhase,
}

impl WingForces {
    /// One term.
    pub fn term(&self, term: Term) -> &TermForce {
        &self.terms[term as usize]
    }
}

/// What a wing's loads at one wingbeat phase owe to the kinematics alone: the angles, the
/// stroke phase, the wing's frame, and the rotational, added-mass and wake-capture terms.
/// Only the translational term depends on the body's motion, so a simulator whose steps
/// repeat every wingbeat can compute these once per step of the wingbeat and reuse them
/// with [`crate::Wing::evaluate_with`] (the results are the same bit for bit).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KinematicLoads {
    /// The kinematic state.
    pub angles: WingAngles,
    /// Half stroke and t*.
    pub phase: StrokePhase,
    /// The wing's unit vectors and rates, stroke frame.
    pub frame: WingFrame,
    /// In the order of [`Term::ALL`], body frame; the translational entry is zero.
    pub terms: [TermForce; 4],
    /// The wing's spanwise twist at this phase (a tabulated wing that has one), which the
    /// translational term's strips meet the air with; `None`: a rigid wing.
    pub twist: Option<crate::kinematics::TwistAt>,
}

/// The kinematic loads that represent one step ([`crate::Wing::kinematic_loads_over_step`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepKinematicLoads {
    /// The midpoint's state with each kinematic term's mean over the step.
    pub mean: KinematicLoads,
    /// The wing's frame at the step's start.
    pub start: WingFrame,
    /// The wing's frame at the step's end.
    pub end: WingFrame,
}
