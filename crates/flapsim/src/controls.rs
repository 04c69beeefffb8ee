//! Control inputs: offsets on a vehicle's base kinematics (angles, frequency) or, for an
//! actuated vehicle, on its drive (volts), and the four channels of each kind that trim, the
//! averaged model and the hover LQR work on. Defined with the wing set (crate `wingset`, the
//! element the controls act on); a vehicle model maps them onto its wings
//! ([`crate::Vehicle::apply_controls`]).

pub use wingset::controls::{Controls, DRIVE_CHANNELS, KINEMATIC_CHANNELS};
