//! The sensors' parameters: the `[sensors.imu]` and `[sensors.mocap]` tables of a model file
//! (datasheet units) and their validated SI form. Plain data below the vehicle model, which
//! holds them, and the devices of [`crate::sensors`], which use them.

use serde::{Deserialize, Serialize};
use wingforce::Validator;

use crate::error::Result;

/// `[sensors.imu]`: a MEMS IMU.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ImuSpec {
    /// Output data rate, Hz.
    pub rate_hz: f64,
    /// From sampling to delivery, s: 0 to [`MAX_LATENCY_S`] (0.1 s).
    pub latency_s: f64,
    /// Gyroscope white-noise density, deg/s/sqrt(Hz) (datasheets' unit).
    pub gyro_noise_density_deg_s_sqrt_hz: f64,
    /// Standard deviation of the gyroscope's turn-on bias, each axis, deg/s.
    pub gyro_bias_deg_s: f64,
    /// Gyroscope bias random walk, deg/s per sqrt(s).
    pub gyro_bias_walk_deg_s_sqrt_s: f64,
    /// Accelerometer white-noise density, micro-g/sqrt(Hz).
    pub accel_noise_density_ug_sqrt_hz: f64,
    /// Standard deviation of the accelerometer's turn-on bias, each axis, milli-g.
    pub accel_bias_mg: f64,
    /// Accelerometer bias random walk, milli-g per sqrt(s).
    pub accel_bias_walk_mg_sqrt_s: f64,
}

/// `[sensors.mocap]`: a motion-capture system tracking the body's pose.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MocapSpec {
    /// Frame rate, Hz.
    pub rate_hz: f64,
    /// From exposure to delivery, s: 0 to [`MAX_LATENCY_S`] (0.1 s).
    pub latency_s: f64,
    /// Position noise, each axis, standard deviation, m.
    pub position_noise_m: f64,
    /// Attitude noise, each axis of a small rotation, standard deviation, deg.
    pub attitude_noise_deg: f64,
}

/// `[sensors]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorSpec {
    /// The IMU.
    pub imu: ImuSpec,
    /// Motion capture, if the vehicle flies in a tracked volume.
    #[serde(default)]
    pub mocap: Option<MocapSpec>,
}

/// The longest latency of a sensor, s (`latency_s` of `[sensors.imu]` and
/// `[sensors.mocap]`). The slowest device of the built-in models is the hummingbird's Vicon
/// at 30 ms; 0.1 s is 22 fruit-fly wingbeats, 3.4 hummingbird wingbeats (34 Hz) and half of a
/// `flapwing/Hover-v0` episode (0.2 s): a longer delay delivers an episode's readings after
/// it has ended, and a task's sensors run for their latency before every episode starts.
pub const MAX_LATENCY_S: f64 = 0.1;

const G0: f64 = 9.80665; // standard gravity, m/s^2 (the g of datasheets' mg and ug)

/// An IMU's parameters in SI units (rad, m/s^2, s), validated.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ImuParams {
    /// Output data rate, Hz.
    pub rate_hz: f64,
    /// Latency, s.
    pub latency_s: f64,
    /// Gyroscope white-noise density, rad/s/sqrt(Hz).
    pub gyro_noise_density: f64,
    /// Turn-on bias standard deviation, rad/s.
    pub gyro_bias_rad_s: f64,
    /// Bias random walk, rad/s/sqrt(s).
    pub gyro_bias_walk: f64,
    /// Accelerometer white-noise density, m/s^2/sqrt(Hz).
    pub accel_noise_density: f64,
    /// Turn-on bias standard deviation, m/s^2.
    pub accel_bias_m_s2: f64,
    /// Bias random walk, m/s^2/sqrt(s).
    pub accel_bias_walk: f64,
}

/// Motion-capture parameters in SI units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MocapParams {
    /// Frame rate, Hz.
    pub rate_hz: f64,
    /// Latency, s.
    pub latency_s: f64,
    /// Position noise standard deviation, m.
    pub position_noise_m: f64,
    /// Attitude noise standard deviation (each axis of a rotation vector), rad.
    pub attitude_noise_rad: f64,
}

/// The validated `[sensors]` of a vehicle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SensorParams {
    /// The IMU.
    pub imu: ImuParams,
    /// Motion capture.
    pub mocap: Option<MocapParams>,
}

impl SensorSpec {
    /// Validates and converts to SI units (errors name the file and field).
    pub fn build(&self, v: &Validator<'_>) -> Result<SensorParams> {
        let i = &self.imu;
        let imu = ImuParams {
            rate_hz: v.within_open_low("sensors.imu.rate_hz", i.rate_hz, 0.0, 1e6)?,
            latency_s: v.within("sensors.imu.latency_s", i.latency_s, 0.0, MAX_LATENCY_S)?,
            gyro_noise_density: v
                .non_negative(
                    "sensors.imu.gyro_noise_density_deg_s_sqrt_hz",
                    i.gyro_noise_density_deg_s_sqrt_hz,
                )?
                .to_radians(),
            gyro_bias_rad_s: v
                .non_negative("sensors.imu.gyro_bias_deg_s", i.gyro_bias_deg_s)?
                .to_radians(),
            gyro_bias_walk: v
                .non_negative(
                    "sensors.imu.gyro_bias_walk_deg_s_sqrt_s",
                    i.gyro_bias_walk_deg_s_sqrt_s,
                )?
                .to_radians(),
            accel_noise_density: v.non_negative(
                "sensors.imu.accel_noise_density_ug_sqrt_hz",
                i.accel_noise_density_ug_sqrt_hz,
            )? * 1e-6
                * G0,
            accel_bias_m_s2: v.non_negative("sensors.imu.accel_bias_mg", i.accel_bias_mg)?
                * 1e-3
                * G0,
            accel_bias_walk: v.non_negative(
                "sensors.imu.accel_bias_walk_mg_sqrt_s",
                i.accel_bias_walk_mg_sqrt_s,
            )? * 1e-3
                * G0,
        };
        let mocap = match &self.mocap {
            None => None,
            Some(m) => Some(MocapParams {
                rate_hz: v.within_open_low("sensors.mocap.rate_hz", m.rate_hz, 0.0, 1e6)?,
                latency_s: v.within("sensors.mocap.latency_s", m.latency_s, 0.0, MAX_LATENCY_S)?,
                position_noise_m: v
                    .non_negative("sensors.mocap.position_noise_m", m.position_noise_m)?,
                attitude_noise_rad: v
                    .non_negative("sensors.mocap.attitude_noise_deg", m.attitude_noise_deg)?
                    .to_radians(),
            }),
        };
        Ok(SensorParams { imu, mocap })
    }
}
