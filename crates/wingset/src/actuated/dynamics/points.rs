//! What a step of a [`DynamicWing`] passes and takes at its points: the state, time and
//! stroke phase at a point ([`StepStart`]), the loads the integrator took there ([`Loads`],
//! [`Aero`]), the states it passed ([`Nodes`]) and those of them its mean loads need
//! ([`quadrature_nodes`]); shared by `step` (which takes them) and `mean` (which weighs
//! them).

use smallvec::SmallVec;
use wingforce::{StrokePhase, TermForce, WingFrame};

use super::equations::Held;
#[cfg(doc)]
use super::wing::DynamicWing;
use super::wing::WingState;
#[cfg(doc)]
use wingforce::Wing;

/// What [`DynamicWing::report`] needs of an aerodynamic evaluation besides the held loads:
/// its translational term (the others follow from the motion alone,
/// [`Wing::with_translational`]) and the wing's frame.
pub(super) type Aero = (TermForce, WingFrame);

/// The states a step passed: (time, state, the touch's left-side flag).
pub(in crate::actuated) type Nodes = SmallVec<[(f64, [f64; 4], bool); 8]>;

/// Loads the integrator took: where ([`DynamicWing::aero_at`]'s arguments) and what.
pub(super) type Loads = (StepStart, Held, Option<Aero>);

/// The state, time and stroke phase at a step's start (what its report describes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct StepStart {
    pub(super) state: WingState,
    pub(super) t_s: f64,
    pub(super) phase: StrokePhase,
}

/// Of the states a step passed (time, state, the touch's left-side flag), those its mean
/// loads need: the first and the last, both sides of a touch, and wherever a rate has moved
/// by more than [`NODE_RATE_FRACTION`] of the step's largest rate since the last one kept
/// (with the node before it, so that the loads between two kept nodes vary smoothly and
/// little). A wing resting in a stop passes many contact steps in which little changes;
/// a strike's collapse of the pitch rate keeps every one of them.
pub(super) fn quadrature_nodes(nodes: &[(f64, [f64; 4], bool)], kept: &mut Nodes) {
    let scale = nodes
        .iter()
        .fold(0.0f64, |m, n| m.max(n.1[2].abs()).max(n.1[3].abs()));
    let tol = NODE_RATE_FRACTION * scale;
    for (k, n) in nodes.iter().enumerate() {
        let Some(last) = kept.last().copied() else {
            kept.push(*n);
            continue;
        };
        let touch = n.2 || nodes[k - 1].2;
        let moved = (n.1[2] - last.1[2]).abs() > tol || (n.1[3] - last.1[3]).abs() > tol;
        if touch || moved || k + 1 == nodes.len() {
            if moved && last.0 < nodes[k - 1].0 {
                kept.push(nodes[k - 1]);
            }
            kept.push(*n);
        }
    }
}

/// The largest change of a rate, as a fraction of the step's largest rate, between two
/// nodes of a step's mean loads ([`quadrature_nodes`]).
const NODE_RATE_FRACTION: f64 = 0.001;
