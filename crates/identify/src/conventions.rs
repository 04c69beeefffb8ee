//! Frame conventions of recorded flights, and the one place where a recording's frames
//! become flapwing's.
//!
//! flapwing's world frame is right-handed with z up (x and y horizontal; the flight dynamics
//! do not depend on the heading), its body frame FLU (x forward, y left, z up, origin at the
//! centre of mass), and an attitude is the unit quaternion world_from_body. Recordings use
//! other conventions (REP 103 and REP 105 for ROS; PX4 and most aerospace code NED/FRD):
//!
//! - world **ENU** (x east, y north, z up) is already z up: `world_from_enu` is the identity;
//!   world **NED** (x north, y east, z down): `world_from_ned` swaps x and y and flips z
//!   (a proper rotation, half a turn about the horizontal axis (1, 1, 0) / sqrt 2);
//! - body **FLU** is flapwing's; body **FRD** (x forward, y right, z down):
//!   `flu_from_frd` = diag(1, -1, -1), half a turn about x;
//! - the quaternion's storage: **xyzw**, the message's `x, y, z, w` fields mean what they say
//!   (ROS's `geometry_msgs/Quaternion`); **wxyz**, a scalar-first quaternion was written
//!   into them in order (the `x` field holds w), as some motion-capture bridges do.
//!
//! So `world_from_body = world_from_rec * rec_world_from_rec_body * rec_body_from_body`,
//! a position `world_from_rec * p`, and a body vector (a gyroscope's rate, an
//! accelerometer's specific force) `body_from_rec_body * v`.

use nalgebra::{Matrix3, Quaternion, Rotation3, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

/// A recording's world frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum WorldConvention {
    /// x east, y north, z up (ROS REP 103).
    #[default]
    Enu,
    /// x north, y east, z down.
    Ned,
}

/// A recording's body frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BodyConvention {
    /// x forward, y left, z up (ROS REP 103; flapwing's).
    #[default]
    Flu,
    /// x forward, y right, z down.
    Frd,
}

/// How a quaternion's four numbers sit in a message's `x, y, z, w` fields.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum QuaternionOrder {
    /// The fields mean what they say (ROS).
    #[default]
    Xyzw,
    /// A scalar-first quaternion written into the fields in order: `x` holds w, `y` x,
    /// `z` y and `w` z.
    Wxyz,
}

impl WorldConvention {
    /// The name used in roles files and flags.
    pub fn name(self) -> &'static str {
        match self {
            WorldConvention::Enu => "enu",
            WorldConvention::Ned => "ned",
        }
    }

    /// flapwing's world from this world.
    pub fn world_from_rec(self) -> Rotation3<f64> {
        match self {
            WorldConvention::Enu => Rotation3::identity(),
            WorldConvention::Ned => Rotation3::from_matrix_unchecked(Matrix3::new(
                0.0, 1.0, 0.0, //
                1.0, 0.0, 0.0, //
                0.0, 0.0, -1.0,
            )),
        }
    }
}

impl BodyConvention {
    /// The name used in roles files and flags.
    pub fn name(self) -> &'static str {
        match self {
            BodyConvention::Flu => "flu",
            BodyConvention::Frd => "frd",
        }
    }

    /// flapwing's body (FLU) from this body frame (its own inverse).
    pub fn body_from_rec(self) -> Rotation3<f64> {
        match self {
            BodyConvention::Flu => Rotation3::identity(),
            BodyConvention::Frd => Rotation3::from_matrix_unchecked(Matrix3::from_diagonal(
                &Vector3::new(1.0, -1.0, -1.0),
            )),
        }
    }
}

impl QuaternionOrder {
    /// The name used in roles files.
    pub fn name(self) -> &'static str {
        match self {
            QuaternionOrder::Xyzw => "xyzw",
            QuaternionOrder::Wxyz => "wxyz",
        }
    }

    /// The quaternion held by the fields `[x, y, z, w]`.
    pub fn quaternion(self, fields_xyzw: [f64; 4]) -> Quaternion<f64> {
        let [a, b, c, d] = fields_xyzw;
        match self {
            QuaternionOrder::Xyzw => Quaternion::new(d, a, b, c),
            QuaternionOrder::Wxyz => Quaternion::new(a, b, c, d),
        }
    }
}

/// The frame conventions of one recording.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Conventions {
    /// The world frame of poses.
    #[serde(default)]
    pub world: WorldConvention,
    /// The body frame of poses and of the IMU.
    #[serde(default)]
    pub body: BodyConvention,
    /// How quaternions are stored.
    #[serde(default)]
    pub quaternion: QuaternionOrder,
}

impl Conventions {
    /// "world ENU, body FLU, quaternion xyzw".
    pub fn describe(&self) -> String {
        format!(
            "world {}, body {}, quaternion {}",
            self.world.name().to_uppercase(),
            self.body.name().to_uppercase(),
            self.quaternion.name()
        )
    }

    /// A recorded position (world, m) in flapwing's world.
    pub fn position(&self, p_rec: Vector3<f64>) -> Vector3<f64> {
        self.world.world_from_rec() * p_rec
    }

    /// A recorded attitude (the quaternion fields `[x, y, z, w]` of rec_world_from_rec_body)
    /// as flapwing's world_from_body, or the quaternion's norm when it is not within 1e-3
    /// of 1.
    pub fn attitude(&self, fields_xyzw: [f64; 4]) -> Result<UnitQuaternion<f64>, f64> {
        let q = self.quaternion.quaternion(fields_xyzw);
        let norm = q.norm();
        if !(norm - 1.0).abs().le(&1e-3) {
            return Err(norm);
        }
        let rec = UnitQuaternion::from_quaternion(q);
        let world = UnitQuaternion::from_rotation_matrix(&self.world.world_from_rec());
        // The body rotation is its own inverse: rec_body_from_body = body_from_rec_body.
        let body = UnitQuaternion::from_rotation_matrix(&self.body.body_from_rec());
        Ok(world * rec * body)
    }

    /// A vector measured in the recording's body frame (a rate, a specific force) in
    /// flapwing's body frame.
    pub fn body_vector(&self, v_rec: Vector3<f64>) -> Vector3<f64> {
        self.body.body_from_rec() * v_rec
    }
}

#[cfg(test)]
mod tests {
    //! Each convention against an attitude written out by hand: a body facing east, level,
    //! and the same body pitched nose-up by 30 deg, as ENU/FLU and as NED/FRD quaternions.
    use super::*;

    const EPS: f64 = 1e-12;

    fn conv(world: WorldConvention, body: BodyConvention) -> Conventions {
        Conventions {
            world,
            body,
            quaternion: QuaternionOrder::Xyzw,
        }
    }

    /// [x, y, z, w] of a rotation by `angle` about the unit `axis`.
    fn fields(axis: [f64; 3], angle: f64) -> [f64; 4] {
        let s = (angle / 2.0).sin();
        [axis[0] * s, axis[1] * s, axis[2] * s, (angle / 2.0).cos()]
    }

    #[test]
    fn rotations_are_proper() {
        for w in [WorldConvention::Enu, WorldConvention::Ned] {
            let m = w.world_from_rec().into_inner();
            assert!((m.determinant() - 1.0).abs() < EPS);
            assert!((m * m.transpose() - Matrix3::identity()).norm() < EPS);
        }
        let m = BodyConvention::Frd.body_from_rec().into_inner();
        assert!((m.determinant() - 1.0).abs() < EPS);
    }

    #[test]
    fn ned_positions_swap_north_east_and_flip_down() {
        let c = conv(WorldConvention::Ned, BodyConvention::Frd);
        let p = c.position(Vector3::new(1.0, 2.0, 3.0));
        assert!((p - Vector3::new(2.0, 1.0, -3.0)).norm() < EPS);
        let c = conv(WorldConvention::Enu, BodyConvention::Flu);
        assert_eq!(
            c.position(Vector3::new(1.0, 2.0, 3.0)),
            Vector3::new(1.0, 2.0, 3.0)
        );
    }

    /// Facing east, level: ENU/FLU identity; NED/FRD yaw +90 deg about down. Both give a
    /// body whose forward axis is east (flapwing x), left north (y), up up (z).
    #[test]
    fn facing_east_level_in_every_convention() {
        let want = UnitQuaternion::identity();
        let enu_flu = conv(WorldConvention::Enu, BodyConvention::Flu)
            .attitude([0.0, 0.0, 0.0, 1.0])
            .unwrap();
        let ned_frd = conv(WorldConvention::Ned, BodyConvention::Frd)
            .attitude(fields([0.0, 0.0, 1.0], std::f64::consts::FRAC_PI_2))
            .unwrap();
        assert!(enu_flu.angle_to(&want) < EPS);
        assert!(ned_frd.angle_to(&want) < EPS, "{ned_frd:?}");
    }

    /// Nose up 30 deg, facing east. ENU/FLU: a rotation of -30 deg about y (left) lifts the
    /// nose. NED/FRD: yaw 90 deg then pitch +30 deg about the body's y (right), the
    /// aerospace nose-up. ENU/FRD: the ENU attitude times half a turn about x. NED/FLU: the
    /// NED/FRD one times half a turn about x.
    #[test]
    fn nose_up_pitch_in_every_convention() {
        let pitch = 30f64.to_radians();
        let enu_flu = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), -pitch);
        let ned_frd =
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), std::f64::consts::FRAC_PI_2)
                * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), pitch);
        let flip = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI);
        let cases = [
            (WorldConvention::Enu, BodyConvention::Flu, enu_flu),
            (WorldConvention::Ned, BodyConvention::Frd, ned_frd),
            (WorldConvention::Enu, BodyConvention::Frd, enu_flu * flip),
            (WorldConvention::Ned, BodyConvention::Flu, ned_frd * flip),
        ];
        for (w, b, q) in cases {
            let f = [q.i, q.j, q.k, q.w];
            let got = conv(w, b).attitude(f).unwrap();
            let forward = got * Vector3::x();
            assert!(
                (forward - Vector3::new(pitch.cos(), 0.0, pitch.sin())).norm() < EPS,
                "{w:?} {b:?}: {forward}"
            );
            let up = got * Vector3::z();
            assert!(
                (up - Vector3::new(-pitch.sin(), 0.0, pitch.cos())).norm() < EPS,
                "{w:?} {b:?}: {up}"
            );
            // Scalar first in the same fields gives the same attitude.
            let c = Conventions {
                world: w,
                body: b,
                quaternion: QuaternionOrder::Wxyz,
            };
            let again = c.attitude([q.w, q.i, q.j, q.k]).unwrap();
            assert!(again.angle_to(&got) < EPS);
        }
    }

    /// An FRD gyroscope's roll rate is FLU's, its pitch and yaw rates change sign; so does an
    /// FRD accelerometer's z (hovering, it reads -g along its down axis).
    #[test]
    fn frd_body_vectors() {
        let c = conv(WorldConvention::Ned, BodyConvention::Frd);
        assert_eq!(
            c.body_vector(Vector3::new(1.0, 2.0, -9.8)),
            Vector3::new(1.0, -2.0, 9.8)
        );
        let c = conv(WorldConvention::Ned, BodyConvention::Flu);
        assert_eq!(
            c.body_vector(Vector3::new(1.0, 2.0, 3.0)),
            Vector3::new(1.0, 2.0, 3.0)
        );
    }

    #[test]
    fn a_quaternion_off_unit_norm_is_refused_with_its_norm() {
        let c = Conventions::default();
        assert_eq!(c.attitude([0.0, 0.0, 0.0, 2.0]).unwrap_err(), 2.0);
        assert!(c.attitude([0.0, 0.0, 0.0, f64::NAN]).is_err());
    }
}
