//! Actuated wings: the stroke driven by an actuator through a transmission, the pitch
//! passive about a compliant hinge, both integrated in time with the aerodynamic loads of
//! wingforce's four terms at the wing's actual angles, rates and accelerations.
//!
//! - [`actuator`]: piezoelectric bimorph (RoboBee) and DC motor with gearbox (Purdue
//!   hummingbird robot), each reduced to the stroke axis;
//! - [`drive`]: the periodic drive voltage;
//! - [`dynamics`]: the wing's two-degree-of-freedom equations and their sub-stepped
//!   integrator (the module doc states both);
//! - [`spec`]: the `[actuation]` section of a vehicle model file;
//! - [`response`]: the frequency response of the tethered vehicle (what a MAV builder reads
//!   the resonance from).
//!
//! This lives in flapsim, not wingforce: the hinge and actuator are structure and time
//! integration, while wingforce stays a pure map from a wing's motion to its loads (it
//! gained the pieces this needs: loads about the joint axes, the added-mass inertia and a
//! measured stroke reference).

pub mod actuator;
pub mod drive;
pub mod dynamics;
pub mod response;
pub mod spec;

pub use actuator::{Actuator, ActuatorState, DcMotor, Piezo, Reflected};
pub use drive::Drive;
pub use dynamics::{
    ActuatedWingOutput, DynamicWing, Hinge, Stroke, WingDynamics, WingInertia, WingState, WingStep,
};
pub use response::{FrequencyResponse, ResponseOptions, ResponsePoint, frequency_response};
pub use spec::{Actuation, ActuationSpec};

/// Refuses an analysis that is built on prescribed kinematics (cycle averages of the wings'
/// kinematic loads) for an actuated vehicle, whose wing motion those kinematics do not
/// describe: an error rather than a silently wrong answer.
pub(crate) fn require_prescribed(vehicle: &crate::Vehicle, what: &str) -> crate::Result<()> {
    if vehicle.actuation.is_some() {
        return Err(crate::Error::Analysis(format!(
            "{what} of {}: not available for actuated vehicles yet (their controls are drive parameters, and this analysis averages prescribed kinematics); use `simulate` or `frequency-response`",
            vehicle.name
        )));
    }
    Ok(())
}
