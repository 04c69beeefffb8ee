//! The measurements a fit compares with: one motion-capture frame, one IMU sample (below the
//! flight data and the CSV reader, which both make them).

use nalgebra::{UnitQuaternion, Vector3};

/// One motion-capture frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MocapFrame {
    /// Exposure time, s.
    pub t_s: f64,
    /// Position of the centre of mass, world, m.
    pub position_m: Vector3<f64>,
    /// Attitude, world_from_body.
    pub attitude: UnitQuaternion<f64>,
}

/// One IMU sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImuFrame {
    /// Sample time, s.
    pub t_s: f64,
    /// Angular velocity, body frame, rad/s.
    pub gyro_rad_s: Vector3<f64>,
    /// Specific force, body frame, m/s^2.
    pub accel_m_s2: Vector3<f64>,
}
