//! Actuated wings: the stroke driven by an actuator through a transmission, the pitch
//! passive about a compliant hinge, both integrated in time with the aerodynamic loads of
//! wingforce's four terms at the wing's actual angles, rates and accelerations.
//!
//! - [`actuator`]: piezoelectric bimorph (RoboBee) and DC motor with gearbox (Purdue
//!   hummingbird robot), each reduced to the stroke axis;
//! - [`drive`]: the periodic drive voltage;
//! - [`dynamics`]: the wing's two-degree-of-freedom equations and their sub-stepped
//!   integrator (the module doc states both);
//! - [`stop`]: hinge stops as a stiff unilateral contact with damping (the module doc
//!   derives the contact law and its restitution);
//! - [`spec`]: the `[actuation]` section of a vehicle model file;
//! - [`driven`]: both wings driven together with the body held in one motion, with their
//!   pair's dynamic inflow when the wake answers (the run the next two share);
//! - [`periodic`]: the wings run into their periodic motion at a frozen body state (what
//!   trim, the averaged model and a hover start need);
//! - [`motion`]: the wing motion measured from a record of whole drive periods (stroke and
//!   pitch amplitude, pitch-stroke phase, mid-stroke angle of attack, drive), one measurement
//!   for `simulate`, the frequency response and `validate`;
//! - [`response`]: the frequency response of the tethered vehicle (what a MAV builder reads
//!   the resonance from).
//!
//! The wing's dynamics ([`actuator`], [`drive`], [`dynamics`], [`stop`]) are part of the
//! force element and live with it in crate `wingset` (no engine, no I/O; re-exported here);
//! the model file's section, the periodic motion, the measurement and the response, which
//! need the vehicle model, are flapsim's. Neither is wingforce: the hinge and actuator are
//! structure and time integration, while wingforce stays a pure map from a wing's motion to
//! its loads (it gained the pieces this needs: loads about the joint axes, the added-mass
//! inertia and a measured stroke reference).

pub use wingset::actuated::{actuator, drive, dynamics, stop};
pub mod driven;
pub mod motion;
pub mod periodic;
pub mod response;
pub mod spec;

pub use actuator::{Actuator, ActuatorState, DcMotor, Piezo, Reflected};
pub use drive::Drive;
pub use driven::DrivenPair;
pub use dynamics::{
    ActuatedWingOutput, DynamicWing, Hinge, Stroke, WingDynamics, WingInertia, WingState, WingStep,
};
pub use motion::{MotionRecorder, MotionSample, RecordedMotion, WingMotion};
pub use periodic::{ActuatedWings, PERIODIC_TOLERANCE_RAD, PeriodicWings, settle};
pub use response::{
    FrequencyResponse, ResponseOptions, ResponsePoint, TetheredRun, frequency_response,
    run_tethered,
};
pub use spec::{Actuation, ActuationSpec, StopSpec};
pub use stop::StopContact;
