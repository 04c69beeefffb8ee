//! Hover control: a linear-quadratic regulator designed on the averaged model, discretised
//! over one wingbeat, that sets the controls once per wingbeat (mean stroke angle for
//! pitch, amplitude for height, left-right amplitude difference for roll, left-right pitch
//! bias difference for yaw; on an actuated vehicle the drive's bias, amplitude, amplitude
//! difference and second-harmonic difference), with an optional sensor delay in whole
//! wingbeats. In hover it holds a point; at a flight condition ([`crate::flight`]) it is
//! designed about that condition's trim and holds a point moving at the condition's velocity
//! (the same regulator: the error dynamics about a steady flight are those of the averaged
//! model linearised there).
//!
//! The design's parts (`lqr.rs`: the weights, the Riccati solve, the discretisation) are
//! below the controller that applies them (`controller.rs`), which is below the hover run
//! that flies it (`run.rs`).

mod controller;
mod lqr;
mod run;

pub use controller::{HoverController, MAX_PREDICTION_WINGBEATS};
pub use lqr::{LqrWeights, discretize, dlqr};
pub use run::{
    Disturbance, HoverOutcome, HoverStep, run_hover, run_hover_estimated, run_hover_with,
};
