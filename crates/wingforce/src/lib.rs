//! # wingforce
//!
//! Quasi-steady blade-element aerodynamics of insect-scale flapping wings: translational
//! (Lee et al. 2016, or Dickinson et al. 1999), rotational (Van Veen et al.), added-mass and
//! the wake-capture term of the seed paper (eq 17-19, 23-24), each reported separately and
//! summed, with the body's own motion included so a vehicle simulator gets damping right.
//!
//! Pure computation: no physics engine, no file or network I/O. Model files are parsed from
//! text the caller has read. The frames, formulas and reference numbers follow
//! `shared/reference/MODEL.md`.
//!
//! ```
//! use wingforce::{BodyMotion, WingModelSpec};
//! let text = include_str!("../../../models/robofly.toml");
//! let wing = WingModelSpec::from_toml(text, "robofly.toml")?.build("robofly.toml")?;
//! let forces = wing.evaluate(0.25, &BodyMotion::default()); // mid-downstroke
//! assert!(forces.total.c_l > 1.0);
//! # Ok::<(), wingforce::Error>(())
//! ```

pub mod added_mass;
pub mod axes;
mod cache;
pub mod coefficients;
pub mod cycle;
mod error;
mod forces;
mod frame;
pub mod inflow;
pub mod kinematics;
pub mod model;
mod mount;
pub mod pitch_flip;
pub mod planform;
pub mod quad;
pub mod reproduction;
mod spline;
mod strips;
mod terms;
pub mod wing;

pub use added_mass::AddedMassForm;
pub use axes::AxisMoments;
pub use coefficients::{RangeFlags, TranslationalModel, WakeCaptureModel, WakeCaptureParams};
pub use error::{Error, Result, Validator};
pub use inflow::{InducedInflow, InflowModel};
pub use kinematics::{Kinematics, KinematicsSpec, StrokePhase, TwistAt, TwistSpec, WingAngles};
pub use model::{AeroSpec, FluidSpec, WingModelSpec, WingSpec};
pub use planform::{Geometry, GeometryOverrides, PlanformSpec};
pub use wing::step_mean::{MAX_PIECE_PHASE, StepRule};
pub use wing::{
    AeroOptions, BodyMotion, Fluid, KinematicLoads, Mount, Side, StepKinematicLoads,
    StrokeReference, Term, TermForce, Wing, WingForces, WingFrame,
};
