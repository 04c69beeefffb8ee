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
//!   derives the contact law and its restitution).
//!
//! The model file's `[actuation]` section, the periodic motion at a frozen body state, the
//! motion measurement and the frequency response are flapsim's (`flapsim::actuated`, which
//! re-exports these modules). This is not wingforce: the hinge and actuator are structure
//! and time integration, while wingforce stays a pure map from a wing's motion to its loads
//! (it gained the pieces this needs: loads about the joint axes, the added-mass inertia and
//! a measured stroke reference).

pub mod actuator;
mod contact;
pub mod drive;
pub mod dynamics;
pub mod stop;

pub use actuator::{Actuator, ActuatorState, DcMotor, Piezo, Reflected};
pub use drive::Drive;
pub use dynamics::{
    ActuatedWingOutput, DynamicWing, Hinge, StageLoads, StrikeShare, Stroke, WingDynamics,
    WingInertia, WingState, WingStep,
};
pub use stop::StopContact;
