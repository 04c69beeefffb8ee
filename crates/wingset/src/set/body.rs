//! What a host and the wing set exchange: the body's state going in, loads on the body
//! coming out. Plain nalgebra types, body frame for loads (x forward, y left, z up, origin
//! at the centre of mass), world z up (MODEL.md section 1).

use nalgebra::{UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

/// Force and moment about the centre of mass, body frame.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct BodyLoad {
    /// Force, body frame, N.
    pub force_n: Vector3<f64>,
    /// Moment about the centre of mass, body frame, N m.
    pub moment_nm: Vector3<f64>,
}

impl BodyLoad {
    /// Adds force `f` and moment `m`.
    pub fn add(&mut self, f: Vector3<f64>, m: Vector3<f64>) {
        self.force_n += f;
        self.moment_nm += m;
    }

    /// Whether every component is finite.
    pub fn is_finite(&self) -> bool {
        self.force_n
            .iter()
            .chain(self.moment_nm.iter())
            .all(|x| x.is_finite())
    }
}

/// The body's state.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct State {
    /// Position of the centre of mass, world (z up), m.
    pub position_m: Vector3<f64>,
    /// Attitude: world_from_body.
    pub world_from_body: UnitQuaternion<f64>,
    /// Velocity of the centre of mass, world frame, m/s.
    pub velocity_m_s: Vector3<f64>,
    /// Angular velocity, body frame, rad/s.
    pub angular_velocity_body_rad_s: Vector3<f64>,
}

impl State {
    /// At rest at the origin, level.
    pub fn at_rest() -> Self {
        Self {
            position_m: Vector3::zeros(),
            world_from_body: UnitQuaternion::identity(),
            velocity_m_s: Vector3::zeros(),
            angular_velocity_body_rad_s: Vector3::zeros(),
        }
    }

    /// Roll, pitch (positive nose up) and yaw, rad.
    pub fn euler_rad(&self) -> (f64, f64, f64) {
        let (r, p, y) = self.world_from_body.euler_angles();
        (r, -p, y)
    }

    /// The name of the first component that is not finite (a host's NaN), if any.
    pub fn first_non_finite(&self) -> Option<&'static str> {
        let q = self.world_from_body.quaternion();
        let parts: [(&'static str, &[f64]); 4] = [
            ("position_m", self.position_m.as_slice()),
            ("world_from_body", q.coords.as_slice()),
            ("velocity_m_s", self.velocity_m_s.as_slice()),
            (
                "angular_velocity_body_rad_s",
                self.angular_velocity_body_rad_s.as_slice(),
            ),
        ];
        parts
            .into_iter()
            .find(|(_, v)| v.iter().any(|x| !x.is_finite()))
            .map(|(name, _)| name)
    }
}

/// Cycle-mean aerodynamic load per term and in total (body frame, about the CoM).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct MeanLoads {
    /// Per term, in the order of [`wingforce::Term::ALL`].
    pub terms: [BodyLoad; 4],
    /// Sum.
    pub total: BodyLoad,
}

impl MeanLoads {
    /// Total force in the world frame for the given attitude, N.
    pub fn force_world_n(&self, world_from_body: &UnitQuaternion<f64>) -> Vector3<f64> {
        world_from_body * self.total.force_n
    }
}
