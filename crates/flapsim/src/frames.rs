//! The one boundary between rapier's glam types and wingforce's nalgebra types.
//!
//! Nothing else in flapsim converts between the two: the simulation reads rapier's state
//! through [`from_glam`] / [`quat_from_glam`] and hands forces back through [`to_glam`].

use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use rapier3d_f64::math::{Matrix, Rotation, Vector};

/// glam vector to nalgebra.
#[inline]
pub fn from_glam(v: Vector) -> Vector3<f64> {
    Vector3::new(v.x, v.y, v.z)
}

/// nalgebra vector to glam.
#[inline]
pub fn to_glam(v: &Vector3<f64>) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

/// glam quaternion (world_from_body) to nalgebra.
#[inline]
pub fn quat_from_glam(q: &Rotation) -> UnitQuaternion<f64> {
    UnitQuaternion::new_unchecked(Quaternion::new(q.w, q.x, q.y, q.z))
}

/// nalgebra quaternion to glam.
#[inline]
pub fn quat_to_glam(q: &UnitQuaternion<f64>) -> Rotation {
    Rotation::from_xyzw(q.i, q.j, q.k, q.w)
}

/// glam 3x3 matrix to nalgebra.
#[inline]
pub fn matrix_from_glam(m: &Matrix) -> nalgebra::Matrix3<f64> {
    let c = m.to_cols_array();
    nalgebra::Matrix3::from_column_slice(&c)
}
