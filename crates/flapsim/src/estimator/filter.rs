//! The filter itself: [`Estimator`] (the error-state Kalman filter fed by the IMU and the
//! motion capture, with the history its latencies need) and its [`Prior`]; the equations are
//! in the module documentation of [`crate::estimator`].

use std::collections::VecDeque;

use nalgebra::{UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::model::Vehicle;
use crate::sensor_run::Reading;
use crate::sensors::{ImuSample, MocapParams, MocapSample, SensorParams};
use crate::sim::State;

use super::eskf::{Covariance, IAB, IP, ITH, IV, IWB, ImuNoise, Nominal, predict, update_pose};

/// The filter's starting point: a nominal pose and velocity and their standard deviations
/// (the biases start at zero with the turn-on standard deviations of `[sensors.imu]`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Prior {
    /// Position, world, m.
    pub position_world_m: [f64; 3],
    /// Velocity, world, m/s.
    pub velocity_world_m_s: [f64; 3],
    /// Attitude, world from body.
    pub world_from_body: UnitQuaternion<f64>,
    /// Standard deviation of the position, each axis, m.
    pub position_std_m: f64,
    /// Standard deviation of the velocity, each axis, m/s.
    pub velocity_std_m_s: f64,
    /// Standard deviation of the attitude, each axis of a rotation vector, rad.
    pub attitude_std_rad: f64,
}

impl Prior {
    /// The hover point of `vehicle` at attitude `world_from_body`, at rest, with standard
    /// deviations of one body length, 0.1 body length per wingbeat and 10 degrees: wide
    /// enough for the disturbances `flapwing hover` takes (a few degrees, velocities well
    /// under a body length per wingbeat), which the first motion-capture frames correct.
    pub fn hover(vehicle: &Vehicle, world_from_body: UnitQuaternion<f64>) -> Self {
        let p = vehicle.initial_position_m;
        Self {
            position_world_m: [p.x, p.y, p.z],
            velocity_world_m_s: [0.0; 3],
            world_from_body,
            position_std_m: vehicle.length_m,
            velocity_std_m_s: 0.1 * vehicle.length_m * vehicle.freq_hz(),
            attitude_std_rad: 10f64.to_radians(),
        }
    }

    fn check(&self) -> Result<()> {
        let finite = self
            .position_world_m
            .iter()
            .chain(&self.velocity_world_m_s)
            .all(|x| x.is_finite());
        if !finite {
            return Err(Error::Input(format!(
                "estimator prior: position {:?} m and velocity {:?} m/s must be finite",
                self.position_world_m, self.velocity_world_m_s
            )));
        }
        for (name, x) in [
            ("position_std_m", self.position_std_m),
            ("velocity_std_m_s", self.velocity_std_m_s),
            ("attitude_std_rad", self.attitude_std_rad),
        ] {
            if !(x.is_finite() && x >= 0.0) {
                return Err(Error::Input(format!(
                    "estimator prior: {name} = {x} is not allowed: a finite number >= 0"
                )));
            }
        }
        Ok(())
    }
}

#[derive(Debug, Clone, Copy)]
struct Entry {
    t_s: f64,
    x: Nominal,
    p: Covariance,
    gyro_rad_s: Vector3<f64>,
    accel_m_s2: Vector3<f64>,
}

/// Counts of what the filter did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct EstimatorStats {
    /// IMU samples applied.
    pub imu_samples: u64,
    /// IMU samples ignored because not after the previous one.
    pub imu_out_of_order: u64,
    /// Motion-capture frames fused.
    pub mocap_frames: u64,
    /// Motion-capture frames older than the history, dropped.
    pub mocap_dropped: u64,
    /// Sum of the frames' normalised innovation squared (6 degrees of freedom each).
    pub nis_sum: f64,
}

/// The error-state Kalman filter with its history for late measurements (see the module
/// documentation).
#[derive(Debug, Clone)]
pub struct Estimator {
    noise: ImuNoise,
    mocap: MocapParams,
    imu_period_s: f64,
    horizon_s: f64,
    prior: (Nominal, Covariance),
    history: VecDeque<Entry>,
    pending: VecDeque<MocapSample>,
    stats: EstimatorStats,
}

impl Estimator {
    /// A filter for sensors `params` (which must include motion capture: without a position
    /// measurement the position drifts unbounded) under gravity `gravity_m_s2`, starting
    /// from `prior`.
    pub fn new(params: &SensorParams, gravity_m_s2: f64, prior: &Prior) -> Result<Self> {
        let mocap = params.mocap.ok_or_else(|| {
            Error::Input(
                "the estimator needs motion capture ([sensors.mocap]) to observe position and attitude; the model's [sensors] has only an IMU".into(),
            )
        })?;
        prior.check()?;
        let imu = &params.imu;
        let noise = ImuNoise {
            gyro_noise_std_rad_s: imu.gyro_noise_density * imu.rate_hz.sqrt(),
            accel_noise_std_m_s2: imu.accel_noise_density * imu.rate_hz.sqrt(),
            gyro_bias_walk_rad_s_sqrt_s: imu.gyro_bias_walk,
            accel_bias_walk_m_s2_sqrt_s: imu.accel_bias_walk,
            gravity_m_s2,
        };
        let x = Nominal {
            position_world_m: Vector3::from(prior.position_world_m),
            velocity_world_m_s: Vector3::from(prior.velocity_world_m_s),
            world_from_body: prior.world_from_body,
            accel_bias_body_m_s2: Vector3::zeros(),
            gyro_bias_body_rad_s: Vector3::zeros(),
        };
        let mut p = Covariance::zeros();
        for k in 0..3 {
            p[(IP + k, IP + k)] = prior.position_std_m.powi(2);
            p[(IV + k, IV + k)] = prior.velocity_std_m_s.powi(2);
            p[(ITH + k, ITH + k)] = prior.attitude_std_rad.powi(2);
            p[(IAB + k, IAB + k)] = imu.accel_bias_m_s2.powi(2);
            p[(IWB + k, IWB + k)] = imu.gyro_bias_rad_s.powi(2);
        }
        let imu_period_s = 1.0 / imu.rate_hz;
        Ok(Self {
            noise,
            mocap,
            imu_period_s,
            horizon_s: mocap.latency_s + 2.0 / mocap.rate_hz + 2.0 * imu_period_s,
            prior: (x, p),
            history: VecDeque::new(),
            pending: VecDeque::new(),
            stats: EstimatorStats::default(),
        })
    }

    /// A filter for `vehicle`'s `[sensors]`; an error names the model and the missing table.
    pub fn for_vehicle(vehicle: &Vehicle, prior: &Prior) -> Result<Self> {
        let params = vehicle.sensors.ok_or_else(|| {
            Error::Input(format!(
                "the model `{}` has no [sensors] table: the estimator needs [sensors.imu] and [sensors.mocap] (see models/drosophila.toml)",
                vehicle.name
            ))
        })?;
        Self::new(&params, vehicle.gravity_m_s2, prior)
            .map_err(|e| Error::Input(format!("model `{}`: {e}", vehicle.name)))
    }

    fn tol_s(&self) -> f64 {
        1e-6 * self.imu_period_s
    }

    /// Applies a delivered reading.
    pub fn reading(&mut self, r: &Reading) {
        match r {
            Reading::Imu { sample, .. } => self.imu(sample),
            Reading::Mocap { sample, .. } => self.mocap(sample),
        }
    }

    /// Predicts with an IMU sample (samples must come in time order).
    pub fn imu(&mut self, s: &ImuSample) {
        let next = match self.history.back() {
            None => Entry {
                t_s: s.t_s,
                x: self.prior.0,
                p: self.prior.1,
                gyro_rad_s: s.gyro_rad_s,
                accel_m_s2: s.accel_m_s2,
            },
            Some(last) => {
                let dt = s.t_s - last.t_s;
                if dt <= self.tol_s() {
                    self.stats.imu_out_of_order += 1;
                    return;
                }
                let (x, p) = predict(
                    &last.x,
                    &last.p,
                    &s.gyro_rad_s,
                    &s.accel_m_s2,
                    dt,
                    &self.noise,
                );
                Entry {
                    t_s: s.t_s,
                    x,
                    p,
                    gyro_rad_s: s.gyro_rad_s,
                    accel_m_s2: s.accel_m_s2,
                }
            }
        };
        self.stats.imu_samples += 1;
        self.history.push_back(next);
        let oldest = s.t_s - self.horizon_s;
        while self.history.len() > 1 && self.history[0].t_s < oldest {
            self.history.pop_front();
        }
        while let Some(m) = self.pending.front().copied() {
            if m.t_s > s.t_s + self.tol_s() {
                break;
            }
            self.pending.pop_front();
            self.fuse(&m);
        }
    }

    /// Corrects with a motion-capture frame (at its exposure time, see the module
    /// documentation).
    pub fn mocap(&mut self, m: &MocapSample) {
        match self.history.back() {
            Some(last) if m.t_s <= last.t_s + self.tol_s() => self.fuse(m),
            _ => self.pending.push_back(*m),
        }
    }

    fn fuse(&mut self, m: &MocapSample) {
        let tol = self.tol_s();
        let Some(j) = self.history.iter().rposition(|e| e.t_s <= m.t_s + tol) else {
            self.stats.mocap_dropped += 1;
            return;
        };
        let e = &mut self.history[j];
        let u = update_pose(
            &mut e.x,
            &mut e.p,
            &m.position_m,
            &m.world_from_body,
            self.mocap.position_noise_m,
            self.mocap.attitude_noise_rad,
        );
        self.stats.mocap_frames += 1;
        self.stats.nis_sum += u.nis;
        for i in j + 1..self.history.len() {
            let prev = self.history[i - 1];
            let cur = &mut self.history[i];
            let (x, p) = predict(
                &prev.x,
                &prev.p,
                &cur.gyro_rad_s,
                &cur.accel_m_s2,
                cur.t_s - prev.t_s,
                &self.noise,
            );
            cur.x = x;
            cur.p = p;
        }
    }

    /// The filter's newest estimate: its time (the newest IMU sample's), nominal state and
    /// error-state covariance; the prior before the first sample (time `None`).
    pub fn latest(&self) -> (Option<f64>, &Nominal, &Covariance) {
        match self.history.back() {
            Some(e) => (Some(e.t_s), &e.x, &e.p),
            None => (None, &self.prior.0, &self.prior.1),
        }
    }

    /// The estimated body state at time `t_s`: the newest estimate predicted forward at
    /// constant velocity and angular rate (see the module documentation); the angular rate
    /// is the newest gyroscope sample less the estimated bias. The prior (at rest) before the
    /// first IMU sample.
    pub fn state_at(&self, t_s: f64) -> State {
        match self.history.back() {
            Some(e) => self.extrapolated(e, t_s),
            None => {
                let x = &self.prior.0;
                State {
                    position_m: x.position_world_m,
                    world_from_body: x.world_from_body,
                    velocity_m_s: x.velocity_world_m_s,
                    angular_velocity_body_rad_s: Vector3::zeros(),
                }
            }
        }
    }

    /// The estimated body state at a past time `t_s` within the filter's history (its
    /// samples corrected by every frame fused so far): interpolated between the two entries
    /// around `t_s` (position, velocity and the rate, less the estimated bias, linearly;
    /// the attitude by slerp), or the entry at `t_s` itself. Interpolating, rather than
    /// carrying the older entry forward at constant velocity and rate, matters when the IMU
    /// period is a sizeable part of a wingbeat: measured on the fruit fly's 1 kHz IMU
    /// (module documentation, "What the filter does not model"), the controller's input
    /// erred by 1.8-2.0 degrees rms carried forward and by 1.1-1.3 degrees interpolated.
    /// `None` when `t_s` is after the newest sample or before the history.
    pub fn state_in_history(&self, t_s: f64) -> Option<State> {
        let tol = self.tol_s();
        let last = self.history.back()?;
        if t_s > last.t_s + tol {
            return None;
        }
        let j = self.history.iter().rposition(|e| e.t_s <= t_s + tol)?;
        let a = &self.history[j];
        match self.history.get(j + 1) {
            Some(b) if t_s > a.t_s + tol => {
                let u = (t_s - a.t_s) / (b.t_s - a.t_s);
                let wa = a.gyro_rad_s - a.x.gyro_bias_body_rad_s;
                let wb = b.gyro_rad_s - b.x.gyro_bias_body_rad_s;
                Some(State {
                    position_m: a.x.position_world_m.lerp(&b.x.position_world_m, u),
                    world_from_body: a.x.world_from_body.slerp(&b.x.world_from_body, u),
                    velocity_m_s: a.x.velocity_world_m_s.lerp(&b.x.velocity_world_m_s, u),
                    angular_velocity_body_rad_s: wa.lerp(&wb, u),
                })
            }
            _ => Some(self.extrapolated(a, t_s)),
        }
    }

    /// Entry `e` carried to `t_s` at constant velocity and angular rate.
    fn extrapolated(&self, e: &Entry, t_s: f64) -> State {
        let x = &e.x;
        let w = e.gyro_rad_s - x.gyro_bias_body_rad_s;
        let dt = t_s - e.t_s;
        let (p, q) = if dt > self.tol_s() {
            (
                x.position_world_m + x.velocity_world_m_s * dt,
                x.world_from_body * UnitQuaternion::from_scaled_axis(w * dt),
            )
        } else {
            (x.position_world_m, x.world_from_body)
        };
        State {
            position_m: p,
            world_from_body: q,
            velocity_m_s: x.velocity_world_m_s,
            angular_velocity_body_rad_s: w,
        }
    }

    /// The time of the newest IMU sample applied (`None` before the first).
    pub fn time_s(&self) -> Option<f64> {
        self.history.back().map(|e| e.t_s)
    }

    /// The IMU's sample period, s.
    pub fn imu_period_s(&self) -> f64 {
        self.imu_period_s
    }

    /// Keeps at least `span_s` of history behind the newest sample (for states read back
    /// by [`Estimator::state_in_history`]); the filter keeps the motion-capture latency plus
    /// two frame and two IMU periods in any case.
    pub fn keep_history_s(&mut self, span_s: f64) {
        if span_s.is_finite() {
            self.horizon_s = self.horizon_s.max(span_s);
        }
    }

    /// What the filter has done so far.
    pub fn stats(&self) -> &EstimatorStats {
        &self.stats
    }
}
