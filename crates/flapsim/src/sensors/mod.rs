//! Sensors on the body: an IMU (gyroscope and accelerometer) with white noise, a constant
//! turn-on bias and a random-walk bias drift, sampled at a fixed rate and delivered after a
//! latency; and an optional motion-capture pose with noise and delay. Deterministic for a
//! given seed (the noise comes from a SplitMix64 stream and the Box-Muller transform).
//!
//! The accelerometer measures the specific force, body frame: f = R^T (a - g_world), with
//! a the acceleration of the centre of mass and g_world = (0, 0, -g); a body at rest (or
//! held by a tether) reads +g on its z axis when level. The gyroscope measures the body-frame
//! angular velocity. White noise of density `n` (unit/sqrt(Hz)) sampled at `rate_hz` has the
//! standard deviation n sqrt(rate_hz) per sample: the discrete equivalent of continuous white
//! noise, sigma = n / sqrt(dt) (IEEE Std 952 and Kalibr's IMU noise model), and a bias
//! random walk of coefficient `b` (unit sqrt(Hz)) moves by b sqrt(dt) per sample.
//!
//! Parameters come from the model file's `[sensors.imu]` and `[sensors.mocap]` tables,
//! each number with its source there (`models/drosophila.toml`).

use std::collections::VecDeque;

use nalgebra::{UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use wingset::set::State;

pub mod params;
pub use params::{ImuParams, ImuSpec, MocapParams, MocapSpec, SensorParams, SensorSpec};

/// A deterministic normal random stream (SplitMix64, Box-Muller).
#[derive(Debug, Clone)]
pub struct Noise {
    state: u64,
    spare: Option<f64>,
}

impl Noise {
    /// A stream from a seed.
    pub fn new(seed: u64) -> Self {
        Self {
            state: seed ^ 0x9E37_79B9_7F4A_7C15,
            spare: None,
        }
    }
    fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// A seed for another stream.
    pub fn next_seed(&mut self) -> u64 {
        self.next_u64()
    }
    /// Uniform in (0, 1].
    pub fn uniform(&mut self) -> f64 {
        ((self.next_u64() >> 11) + 1) as f64 / (1u64 << 53) as f64
    }
    /// Standard normal.
    pub fn normal(&mut self) -> f64 {
        if let Some(x) = self.spare.take() {
            return x;
        }
        let (u1, u2) = (self.uniform(), self.uniform());
        let r = (-2.0 * u1.ln()).sqrt();
        let a = std::f64::consts::TAU * u2;
        self.spare = Some(r * a.sin());
        r * a.cos()
    }
    /// Three independent normals scaled by `sigma`.
    pub fn vec3(&mut self, sigma: f64) -> Vector3<f64> {
        Vector3::new(self.normal(), self.normal(), self.normal()) * sigma
    }
}

/// One IMU sample.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ImuSample {
    /// When the sample was taken, s.
    pub t_s: f64,
    /// Angular velocity, body frame, rad/s (with bias and noise).
    pub gyro_rad_s: Vector3<f64>,
    /// Specific force, body frame, m/s^2 (with bias and noise).
    pub accel_m_s2: Vector3<f64>,
    /// Truth behind the reading (for estimator evaluation): the body-frame angular
    /// velocity the gyroscope saw, rad/s.
    pub true_angular_velocity_rad_s: Vector3<f64>,
    /// Truth: the specific force the accelerometer saw, body frame, m/s^2.
    pub true_specific_force_m_s2: Vector3<f64>,
    /// Truth: the gyroscope bias in the reading, rad/s.
    pub gyro_bias_rad_s: Vector3<f64>,
    /// Truth: the accelerometer bias in the reading, m/s^2.
    pub accel_bias_m_s2: Vector3<f64>,
}

/// Samples taken at `rate_hz` and delivered `latency_s` later.
#[derive(Debug, Clone)]
struct Schedule<T> {
    period_s: f64,
    latency_s: f64,
    next_k: u64,
    queue: VecDeque<(f64, T)>,
    latest: Option<T>,
}

impl<T: Copy> Schedule<T> {
    fn new(rate_hz: f64, latency_s: f64) -> Self {
        Self {
            period_s: 1.0 / rate_hz,
            latency_s,
            next_k: 0,
            queue: VecDeque::new(),
            latest: None,
        }
    }
    /// Sample instants due at or before `t_s` (with a tolerance of a millionth of a period
    /// so that a sample time that falls on a step is taken at that step).
    fn due(&mut self, t_s: f64) -> Option<f64> {
        let t_k = self.next_k as f64 * self.period_s;
        (t_k <= t_s + 1e-6 * self.period_s).then(|| {
            self.next_k += 1;
            t_k
        })
    }
    fn push(&mut self, t_k: f64, x: T) {
        self.queue.push_back((t_k + self.latency_s, x));
    }
    /// The oldest sample delivered by `t_s` and not yet taken, with its delivery time
    /// (it also becomes the newest for [`Schedule::read`]).
    fn next_delivered(&mut self, t_s: f64) -> Option<(f64, T)> {
        let (t_avail, x) = self.queue.front().copied()?;
        (t_avail <= t_s + 1e-6 * self.period_s).then(|| {
            self.queue.pop_front();
            self.latest = Some(x);
            (t_avail, x)
        })
    }
    /// The newest sample delivered by `t_s`.
    fn read(&mut self, t_s: f64) -> Option<T> {
        while let Some((t_avail, x)) = self.queue.front().copied() {
            if t_avail <= t_s + 1e-6 * self.period_s {
                self.latest = Some(x);
                self.queue.pop_front();
            } else {
                break;
            }
        }
        self.latest
    }
}

/// A body IMU.
#[derive(Debug, Clone)]
pub struct Imu {
    params: ImuParams,
    gravity_m_s2: f64,
    noise: Noise,
    gyro_bias: Vector3<f64>,
    accel_bias: Vector3<f64>,
    schedule: Schedule<ImuSample>,
}

impl Imu {
    /// An IMU with its turn-on biases drawn from `seed`; `gravity_m_s2` is the world's g.
    pub fn new(params: ImuParams, gravity_m_s2: f64, seed: u64) -> Self {
        let mut noise = Noise::new(seed);
        let gyro_bias = noise.vec3(params.gyro_bias_rad_s);
        let accel_bias = noise.vec3(params.accel_bias_m_s2);
        Self {
            params,
            gravity_m_s2,
            noise,
            gyro_bias,
            accel_bias,
            schedule: Schedule::new(params.rate_hz, params.latency_s),
        }
    }

    /// The parameters.
    pub fn params(&self) -> &ImuParams {
        &self.params
    }
    /// The current biases (gyro rad/s, accelerometer m/s^2).
    pub fn biases(&self) -> (Vector3<f64>, Vector3<f64>) {
        (self.gyro_bias, self.accel_bias)
    }
    /// Per-sample white-noise standard deviations (gyro rad/s, accelerometer m/s^2).
    pub fn noise_std(&self) -> (f64, f64) {
        let s = self.params.rate_hz.sqrt();
        (
            self.params.gyro_noise_density * s,
            self.params.accel_noise_density * s,
        )
    }

    /// Shows the IMU the body at time `t_s` with centre-of-mass acceleration
    /// `accel_world_m_s2`; takes the samples due by then.
    pub fn observe(&mut self, t_s: f64, state: &State, accel_world_m_s2: &Vector3<f64>) {
        let (sg, sa) = self.noise_std();
        let dt = self.schedule.period_s.sqrt();
        while let Some(t_k) = self.schedule.due(t_s) {
            let g = Vector3::new(0.0, 0.0, -self.gravity_m_s2);
            let f = state.world_from_body.inverse() * (accel_world_m_s2 - g);
            let w = state.angular_velocity_body_rad_s;
            let s = ImuSample {
                t_s: t_k,
                gyro_rad_s: w + self.gyro_bias + self.noise.vec3(sg),
                accel_m_s2: f + self.accel_bias + self.noise.vec3(sa),
                true_angular_velocity_rad_s: w,
                true_specific_force_m_s2: f,
                gyro_bias_rad_s: self.gyro_bias,
                accel_bias_m_s2: self.accel_bias,
            };
            self.schedule.push(t_k, s);
            self.gyro_bias += self.noise.vec3(self.params.gyro_bias_walk * dt);
            self.accel_bias += self.noise.vec3(self.params.accel_bias_walk * dt);
        }
    }

    /// The newest sample delivered by `t_s` (None before the first arrives).
    pub fn read(&mut self, t_s: f64) -> Option<ImuSample> {
        self.schedule.read(t_s)
    }
    /// The oldest sample delivered by `t_s` that has not been taken yet, with the time it
    /// was delivered (sample time plus latency), s; call until `None` to take every sample
    /// in order (e.g. to log each one).
    pub fn next_delivered(&mut self, t_s: f64) -> Option<(f64, ImuSample)> {
        self.schedule.next_delivered(t_s)
    }
}

/// One motion-capture frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MocapSample {
    /// Exposure time, s.
    pub t_s: f64,
    /// Position, world, m.
    pub position_m: Vector3<f64>,
    /// Attitude.
    pub world_from_body: UnitQuaternion<f64>,
}

/// A motion-capture system.
#[derive(Debug, Clone)]
pub struct Mocap {
    params: MocapParams,
    noise: Noise,
    schedule: Schedule<MocapSample>,
}

impl Mocap {
    /// A motion-capture system with noise from `seed`.
    pub fn new(params: MocapParams, seed: u64) -> Self {
        Self {
            params,
            noise: Noise::new(seed.wrapping_add(0x5EED_0F_0CA9)),
            schedule: Schedule::new(params.rate_hz, params.latency_s),
        }
    }
    /// Shows the system the body at `t_s`.
    pub fn observe(&mut self, t_s: f64, state: &State) {
        while let Some(t_k) = self.schedule.due(t_s) {
            let d =
                UnitQuaternion::from_scaled_axis(self.noise.vec3(self.params.attitude_noise_rad));
            let s = MocapSample {
                t_s: t_k,
                position_m: state.position_m + self.noise.vec3(self.params.position_noise_m),
                world_from_body: state.world_from_body * d,
            };
            self.schedule.push(t_k, s);
        }
    }
    /// The newest frame delivered by `t_s`.
    pub fn read(&mut self, t_s: f64) -> Option<MocapSample> {
        self.schedule.read(t_s)
    }
    /// The oldest frame delivered by `t_s` not yet taken, with its delivery time, s.
    pub fn next_delivered(&mut self, t_s: f64) -> Option<(f64, MocapSample)> {
        self.schedule.next_delivered(t_s)
    }
    /// The parameters.
    pub fn params(&self) -> &MocapParams {
        &self.params
    }
}

/// A vehicle's sensors, fed from a simulation step by step.
#[derive(Debug, Clone)]
pub struct Sensors {
    /// The IMU.
    pub imu: Imu,
    /// Motion capture.
    pub mocap: Option<Mocap>,
    prev_velocity: Option<(f64, Vector3<f64>)>,
}

impl Sensors {
    /// Sensors with parameters `p` and noise from `seed`.
    pub fn new(p: &SensorParams, gravity_m_s2: f64, seed: u64) -> Self {
        Self {
            imu: Imu::new(p.imu, gravity_m_s2, seed),
            mocap: p.mocap.map(|m| Mocap::new(m, seed)),
            prev_velocity: None,
        }
    }

    /// Shows the sensors the body state at `t_s`. The acceleration comes from the change of
    /// velocity since the previous call (exact for rapier's semi-implicit Euler, whose
    /// velocity changes by a dt over a step); the first call takes it as zero.
    pub fn observe(&mut self, t_s: f64, state: &State) {
        let a = match self.prev_velocity {
            Some((t0, v0)) if t_s > t0 => (state.velocity_m_s - v0) / (t_s - t0),
            _ => Vector3::zeros(),
        };
        self.prev_velocity = Some((t_s, state.velocity_m_s));
        self.imu.observe(t_s, state, &a);
        if let Some(m) = &mut self.mocap {
            m.observe(t_s, state);
        }
    }
}
