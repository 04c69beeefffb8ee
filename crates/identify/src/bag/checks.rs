//! Frame conventions that do not match the bag, refused: the attitudes against the
//! vehicle's hover attitude, the IMU's specific force against gravity.

use flapsim::Vehicle;
use nalgebra::Vector3;

use crate::conventions::Conventions;
use crate::error::Result;
use crate::frames::{ImuFrame, MocapFrame};

use super::topics::Topic;

/// The largest mean tilt from the hover attitude a recorded flight is taken to have, deg
/// (an estimate: wide enough for manoeuvres about hover, below what misread frames give:
/// the synthetic fruit-fly hover's NED/FRD bag of tests/python/test_ros2_identify.py read
/// as ENU/FLU or NED/FLU averages 90 deg, as ENU/FRD 179 deg, with its quaternions taken
/// scalar-first 120 deg); a mean beyond this says the frames are misread. A mismatch of both the world's and the body's vertical
/// (NED/FRD read as ENU/FLU) leaves the body's z axis up, so the check is against the
/// model's own hover attitude, not only the body's z axis.
pub const MAX_MEAN_TILT_DEG: f64 = 60.0;

/// The recorded attitudes, on average, lie within [`MAX_MEAN_TILT_DEG`] of the vehicle's
/// hover attitude (its trim; the body's z axis up when the vehicle has no hover trim).
pub(super) fn check_attitudes(
    topic: &Topic<'_>,
    mocap: &[MocapFrame],
    frames: &Conventions,
    vehicle: &Vehicle,
) -> Result<()> {
    let (up_in_body, hover) = match flapsim::trim::trim(vehicle) {
        Ok(t) => (
            t.attitude().inverse() * Vector3::z(),
            format!(
                "`{}`'s hover attitude (body pitch {:.1} deg)",
                vehicle.name,
                t.pitch_rad.to_degrees()
            ),
        ),
        Err(_) => (Vector3::z(), "upright (body z axis up)".to_owned()),
    };
    if mocap.is_empty() {
        return Ok(());
    }
    let mean_cos = mocap
        .iter()
        .map(|f| (f.attitude * up_in_body).z)
        .sum::<f64>()
        / mocap.len() as f64;
    let tilt_deg = mean_cos.clamp(-1.0, 1.0).acos().to_degrees();
    if tilt_deg <= MAX_MEAN_TILT_DEG {
        return Ok(());
    }
    Err(topic.err(format!(
        "with {} the body is on average {tilt_deg:.0} deg from {hover} over {} frames (a flight stays within about {MAX_MEAN_TILT_DEG:.0} deg of it): the frame conventions given do not match the bag's; check [frames] world (--world-frame enu|ned), body (--body-frame flu|frd) and quaternion (--quaternion-order xyzw|wxyz)",
        frames.describe(),
        mocap.len()
    )))
}

/// Hovering or flying slowly, the mean specific force an IMU reads points up (about g):
/// when it points down in flapwing's world the world convention (or the IMU's axes) given
/// is not the bag's.
pub(super) fn check_gravity(
    topic: &Topic<'_>,
    imu: &[ImuFrame],
    mocap: &[MocapFrame],
) -> Result<()> {
    let mut sum = Vector3::zeros();
    let mut n = 0usize;
    for s in imu {
        let i = mocap
            .partition_point(|f| f.t_s < s.t_s)
            .min(mocap.len() - 1);
        sum += mocap[i].attitude * s.accel_m_s2;
        n += 1;
    }
    if n == 0 || sum.z / n as f64 > 0.0 {
        return Ok(());
    }
    Err(topic.err(format!(
        "the mean specific force, turned into the world by the poses' attitudes, is {:.3} m/s^2 up: it points down, so the IMU's axes or the world convention given do not match the bag's (a flight's mean specific force is about +g, up); check [frames] world (--world-frame enu|ned) and [imu] body",
        sum.z / n as f64
    )))
}
