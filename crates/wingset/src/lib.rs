//! The wing set: flapping wings as a force element on one rigid body, for any host.
//!
//! A [`WingSet`] holds any number of wings (each with its own hinge position, stroke plane,
//! planform and kinematics, or actuation) and their own state: the wingbeat phase, the
//! actuated wings' stroke and pitch dynamics and the table of kinematic loads. The host
//! gives it the body's state at t_k ([`State`]) and its fixed time step; each
//! [`WingSet::step`] returns the loads on the body over [t_k, t_k + dt] about its centre of
//! mass, body frame ([`WingSetOutput`]: the aerodynamic load of each of wingforce's four
//! terms, the inertial reaction of the wings and actuators, the total, and each wing's
//! forces, angles and hinge state). The host integrates the body.
//!
//! No engine and no I/O: this crate depends on wingforce and nalgebra only (with serde's
//! derives on its plain types and thiserror for [`Error`]). Controls ([`Controls`]) reach
//! the wings through a [`ControlMap`], which a vehicle model implements (flapsim's
//! `Vehicle`); a set built wing by wing ([`WingSet::builder`]) takes each wing's kinematics
//! instead. Its hosts: flapsim's own `Simulation` (a private rapier world) and
//! `host::RapierWings` (a body in the user's rapier world), the C ABI, the MuJoCo plugin,
//! the FMU and the Python module (crates `flapwing-ffi`, `flapwing-mujoco`, `flapwing-fmu`,
//! `flapwing-python`). The layers: wingforce (aerodynamics) <- wingset (this element) <-
//! hosts <- the CLI.
//!
//! - [`set`]: the set, its step and what the step reports;
//! - [`actuated`]: the actuated wings' dynamics (actuator, drive, hinge, stops);
//! - [`controls`]: the control inputs;
//! - [`sampling`]: where in a step the loads are taken (second-order stepping).

pub mod actuated;
pub mod controls;
mod error;
pub mod sampling;
pub mod set;

pub use controls::Controls;
pub use error::{Error, Result};
pub use sampling::LoadSampling;
pub use set::{
    BodyLoad, ControlMap, DiscAmplitude, MIN_STEPS_PER_WINGBEAT, MeanLoads, PairInflows, State,
    StepMemory, WingSet, WingSetBuilder, WingSetOutput, check_dt, max_dt_s, zero_forces,
};
