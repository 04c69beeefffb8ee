//! Wing kinematics: stroke (flapping) angle phi, pitch angle theta and deviation eta as
//! periodic functions of the wingbeat phase, with analytic first and second derivatives.
//!
//! Conventions (see MODEL.md section 1 and 3):
//! - phase is measured in wingbeats (cycles); phase 0 is the stroke reversal that starts the
//!   first downstroke, during which phi increases (the wing moves forward).
//! - theta is the angle between the leading-edge chord direction and the forward stroke
//!   tangent, rotating towards the stroke-plane normal: mid-downstroke theta = alpha_m,
//!   mid-upstroke theta = pi - alpha_m, so the geometric angle of attack is alpha_m in both.
//! - A pitch bias adds to theta in both half strokes (raising the downstroke angle of attack
//!   and lowering the upstroke one).
//!
//! The files, each one family: `wingbeat` (the [`Kinematics`] a wing flaps with and what they
//! give at any phase: [`WingAngles`], [`StrokePhase`]), `shape` (each family's [`Shape`]),
//! `spec` (the [`KinematicsSpec`] of a model file, validated into kinematics), `twist` (a
//! measured wing's spanwise twist) and
//! `acceleration` (the half-peak rule for dtau_A and dtau_D of any stroke-rate profile).

mod acceleration;
mod shape;
mod spec;
mod twist;
mod wingbeat;

pub use crate::kinematics::acceleration::{
    measure_acceleration_fractions, sampled_acceleration_fractions,
};
pub use crate::kinematics::shape::{Shape, TableShape};
pub use crate::kinematics::spec::{FrequencySpec, KinematicsSpec};
pub use crate::kinematics::twist::{MAX_TWIST_STATIONS, TableTwist, TwistAt, TwistSpec};
pub use crate::kinematics::wingbeat::{Kinematics, StrokePhase, WingAngles};
pub use crate::spline::PeriodicSpline;
