//! Where and in what a wing flaps: the side of the body it is on, its mount (hinge and
//! stroke-plane tilt), the fluid, and the body's motion through that fluid.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Which side of the body a wing is on. The right wing is the mirror image of the left in
/// the body's x-z plane.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    /// +y side.
    Left,
    /// -y side.
    Right,
}

impl Side {
    /// +1 for the left wing, -1 for the right.
    pub fn sign(self) -> f64 {
        match self {
            Side::Left => 1.0,
            Side::Right => -1.0,
        }
    }
}

/// Where and how a wing is attached to the body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mount {
    /// Which side.
    pub side: Side,
    /// Hinge position in the body frame, relative to the centre of mass, m.
    pub hinge_in_body_m: Vector3<f64>,
    /// Rotation about body y from the body frame to the stroke-plane frame, rad (positive
    /// tilts the stroke-plane normal forward: a hovering insect whose body is pitched up by
    /// this angle relative to a horizontal stroke plane).
    pub stroke_plane_tilt_rad: f64,
}

impl Mount {
    /// A fixed mount at the origin with the stroke plane on the body x-y plane (robofly).
    pub fn fixed(side: Side) -> Self {
        Self {
            side,
            hinge_in_body_m: Vector3::zeros(),
            stroke_plane_tilt_rad: 0.0,
        }
    }
}

/// Fluid properties.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Fluid {
    /// Density rho, kg/m^3.
    pub density_kg_m3: f64,
    /// Kinematic viscosity nu, m^2/s.
    pub kinematic_viscosity_m2_s: f64,
}

impl Fluid {
    /// Air at 20 C and 101.325 kPa: rho = 1.204 kg/m^3, nu = 1.516e-5 m^2/s
    /// (e.g. Engineering ToolBox / CRC Handbook tables of dry air).
    pub const AIR_20C: Fluid = Fluid {
        density_kg_m3: 1.204,
        kinematic_viscosity_m2_s: 1.516e-5,
    };
}

/// Linear and angular velocity of the body relative to the air, in the body frame.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BodyMotion {
    /// Velocity of the centre of mass relative to the air, body frame, m/s.
    pub velocity_m_s: Vector3<f64>,
    /// Angular velocity, body frame, rad/s.
    pub angular_velocity_rad_s: Vector3<f64>,
}
