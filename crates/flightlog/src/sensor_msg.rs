//! The sensor messages of `/sensors/imu` and `/sensors/mocap` ([`crate::schema::SENSOR_CHANNELS`])
//! from flapsim's delivered readings ([`flapsim::sensor_run::Reading`]).

use flapsim::sensor_run::Reading;
use nalgebra::UnitQuaternion;

use crate::proto;
use crate::sample::timestamp;

/// One reading's message.
pub(crate) enum SensorMessage {
    Imu(proto::ImuReading),
    Mocap(proto::MocapReading),
}

pub(crate) fn quaternion(q: &UnitQuaternion<f64>) -> proto::Quaternion {
    q.into()
}

/// Roll, pitch (nose up positive) and yaw in degrees, as `/vehicle/state` gives them
/// ([`flapsim::State::euler_rad`]).
pub(crate) fn euler_deg(q: &UnitQuaternion<f64>) -> proto::Euler {
    let (r, p, y) = q.euler_angles();
    proto::Euler {
        roll: r.to_degrees(),
        pitch: (-p).to_degrees(),
        yaw: y.to_degrees(),
    }
}

impl SensorMessage {
    /// The message of `reading`, stamped with the log time `t_ns`.
    pub fn of(reading: &Reading, t_ns: u64) -> Self {
        let ts = Some(timestamp(t_ns));
        match reading {
            Reading::Imu {
                t_delivered_s,
                sample: s,
            } => Self::Imu(proto::ImuReading {
                timestamp: ts,
                t_sample_s: s.t_s,
                t_delivered_s: *t_delivered_s,
                gyro_rad_s: Some((&s.gyro_rad_s).into()),
                accel_m_s2: Some((&s.accel_m_s2).into()),
                true_angular_velocity_rad_s: Some((&s.true_angular_velocity_rad_s).into()),
                true_specific_force_m_s2: Some((&s.true_specific_force_m_s2).into()),
                gyro_bias_rad_s: Some((&s.gyro_bias_rad_s).into()),
                accel_bias_m_s2: Some((&s.accel_bias_m_s2).into()),
            }),
            Reading::Mocap {
                t_delivered_s,
                sample: s,
            } => Self::Mocap(proto::MocapReading {
                timestamp: ts,
                t_sample_s: s.t_s,
                t_delivered_s: *t_delivered_s,
                position_m: Some((&s.position_m).into()),
                attitude: Some(quaternion(&s.world_from_body)),
                euler_deg: Some(euler_deg(&s.world_from_body)),
            }),
        }
    }

    /// The index of its channel in [`crate::schema::SENSOR_CHANNELS`].
    pub fn channel(&self) -> usize {
        match self {
            Self::Imu(_) => 0,
            Self::Mocap(_) => 1,
        }
    }

    /// The message as the MCAP writer takes it.
    pub fn encoded(&self) -> &dyn crate::sample::Encoded {
        match self {
            Self::Imu(m) => m,
            Self::Mocap(m) => m,
        }
    }
}
