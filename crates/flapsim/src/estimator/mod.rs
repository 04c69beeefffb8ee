//! A state estimator for flying on sensors: an error-state extended Kalman filter (ESKF) of
//! attitude, velocity, position and the IMU's biases, predicted by the IMU (gyroscope and
//! accelerometer) and corrected by motion capture (position and attitude), with both
//! sensors' latencies. The formulation follows J. Sola, "Quaternion kinematics for the
//! error-state Kalman filter", arXiv:1711.02508 (2017), sections 5 and 6 (local, body-frame
//! attitude error); equation numbers below are that paper's.
//!
//! # State
//! Nominal state (world z up, body x forward, y left, z up; [`Nominal`]):
//! position p and velocity v of the body origin (the centre of mass), world; attitude q
//! (world from body, rotation R = R(q)); accelerometer bias a_b and gyroscope bias w_b,
//! body. Gravity g = (0, 0, -g) is known. The angular rate is not a state: the feedback
//! rate is the newest gyroscope sample less the estimated bias, w = w_m - w_b.
//!
//! Error state (15): dx = [dp, dv, dtheta, da_b, dw_b], with the true state
//! p_t = p + dp, v_t = v + dv, q_t = q (x) Exp(dtheta) (dtheta a body-frame rotation vector),
//! a_b,t = a_b + da_b, w_b,t = w_b + dw_b.
//!
//! # Prediction (each IMU sample)
//! The IMU model is the one [`crate::sensors`] simulates: w_m = w + w_b + n_w,
//! a_m = R'(a - g) + a_b + n_a, white per-sample noise of standard deviation
//! sigma = density x sqrt(rate) (n_w, n_a), biases walking by walk x sqrt(dt) per sample.
//! A sample taken at t_k moves the state from the previous sample's time over
//! dt = t_k - t_(k-1), with w = w_m - w_b and a = a_m - a_b:
//!
//! q+ = q (x) Exp(w dt),   v+ = v + (R(q+) a + g) dt,   p+ = p + v+ dt,   biases held.
//!
//! This is Sola's nominal kinematics (eq. 260) written semi-implicitly (the attitude and the
//! velocity first, the position with the new velocity): the integrator of the rigid-body
//! engine (rapier, semi-implicit Euler), so that a noiseless IMU sampled every simulation
//! step reproduces the body's motion to rounding, but for the rotation: rapier turns by the
//! normalised first-order quaternion (1, w dt / 2) about the same axis, an angle
//! 2 atan(|w| dt / 2) that differs from the exponential map's |w| dt by (|w| dt)^3 / 12.
//! The error state moves by the same three sub-steps (the linearisation of eq. 269-270):
//!
//! F1: dtheta+ = Exp(w dt)' dtheta - dt dw_b,        Q1 = (sigma_w dt)^2 I on dtheta;
//! F2: dv+ = dv - R+ [a]x dt dtheta+ - R+ dt da_b,    Q2 = (sigma_a dt)^2 I on dv;
//! F3: dp+ = dp + dt dv+;
//! Qb: (walk_w^2 dt) I on dw_b and (walk_a^2 dt) I on da_b (the walk after the sample),
//!
//! P <- F3 (F2 (F1 P F1' + Q1) F2' + Q2) F3' + Qb, each F the identity elsewhere.
//!
//! # Correction (each motion-capture frame)
//! The frame measures y_p = p_t + n_p and q_m = q_t (x) Exp(n_theta) (the model of
//! [`crate::sensors::Mocap`]), so the innovation y = [y_p - p, Log(q' (x) q_m)] has
//! H = [I 0 0 0 0; 0 0 I 0 0] (6 x 15) and R = diag(sigma_p^2 I, sigma_theta^2 I) from
//! `[sensors.mocap]`. S = H P H' + R, K = P H' S^-1, dx = K y, and the Joseph form
//! P <- (I - K H) P (I - K H)' + K R K' (eq. 274-276). Injection (eq. 282): p += dp,
//! v += dv, q <- q (x) Exp(dtheta), biases += their errors; reset (eq. 285-287):
//! P <- G P G' with G = I except I - [dtheta/2]x on the attitude block.
//!
//! # Latency
//! Both sensors deliver late (IMU latency L_i, motion capture L_m). The filter's state
//! lives at the time of the newest IMU sample (t_k = now - L_i) and keeps a short history
//! (each sample's time, nominal state, covariance and reading) covering the motion-capture
//! latency plus two frame periods. A frame of exposure time t_m corrects the history entry
//! at t_m (the newest entry not after t_m: exact when the frame times fall on IMU sample
//! times, as with the rates of the built-in models, else off by less than an IMU period),
//! and the later samples are re-applied from there: the frame is fused at the time it was
//! taken, as if it had arrived without delay. A frame newer than the newest IMU sample
//! waits until the IMU reaches it; one older than the history is dropped (and counted).
//! For the controller the filter's state is predicted forward from t_k to now at constant
//! velocity and angular rate (p + v dt, q (x) Exp(w dt), [`Estimator::state_at`]), not with
//! the newest specific force held: a flapping body's specific force swings by about g
//! within each wingbeat, so one instantaneous sample held across a latency as long as a
//! wingbeat (5 ms against the fruit fly's 4.6 ms) would add an error of that order, while
//! the wingbeat-mean acceleration of a hover is small. This extrapolation's error is not in P.
//!
//! A controller acting once per wingbeat does better across a latency of a wingbeat or more
//! ([`EstimatedFeedback::controller_input`]): it reads the filter's state at the same
//! wingbeat phase d whole wingbeats ago (from the history, corrected by every frame fused
//! since) and predicts it forward on its own design model with the controls it applied
//! since ([`crate::control::HoverController::update_from_past`], a discrete Smith
//! predictor), so that no instant of the in-wingbeat oscillation is held across the latency.
//!
//! # Before the first sample
//! The filter starts from a prior (nominal state and covariance, [`Prior`]); the gyroscope
//! and accelerometer biases' prior standard deviations are the turn-on bias standard
//! deviations of `[sensors.imu]`. Until the first IMU sample arrives the estimate is the
//! prior (angular rate zero).
//!
//! # What the filter does not model
//! The IMU samples are instants of a body that vibrates at the wingbeat frequency and its
//! harmonics; held over an IMU period longer than the simulation step they integrate with
//! an error that is not in the sensor model's noise (aliasing). The filter is consistent
//! when the IMU samples every simulation step (see `tests/estimator.rs`); at the datasheet
//! rates of the built-in models it is a working but not a consistent filter.

mod eskf;

pub use eskf::{
    Covariance, ErrorState, IAB, IP, ITH, IV, IWB, ImuNoise, N_ERR, Nominal, PoseUpdate, inject,
    predict, propagate, skew, update_pose,
};

use std::collections::VecDeque;

use nalgebra::{UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::model::Vehicle;
use crate::sensor_run::{Reading, SensorRun, SensorSummary};
use crate::sensors::{ImuSample, MocapParams, MocapSample, SensorParams};
use crate::sim::State;

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

    /// The estimated body state at a past time `t_s` within the filter's history: the
    /// newest history entry not after `t_s` (its samples since corrected by every frame
    /// fused so far) carried to `t_s` at constant velocity and angular rate (less than an
    /// IMU period). `None` when `t_s` is after the newest sample or before the history.
    pub fn state_in_history(&self, t_s: f64) -> Option<State> {
        let tol = self.tol_s();
        let last = self.history.back()?;
        if t_s > last.t_s + tol {
            return None;
        }
        let j = self.history.iter().rposition(|e| e.t_s <= t_s + tol)?;
        Some(self.extrapolated(&self.history[j], t_s))
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

/// A vehicle's sensors feeding the estimator, for flying on the estimate: shown the body
/// each step, it samples the model's `[sensors]` and hands every delivered reading to the
/// filter.
#[derive(Debug, Clone)]
pub struct EstimatedFeedback {
    sensors: SensorRun,
    filter: Estimator,
    readings: Vec<Reading>,
}

impl EstimatedFeedback {
    /// The sensors of `vehicle` (every random draw from `seed`) and a filter from `prior`;
    /// an error names the model and what its `[sensors]` lacks.
    pub fn new(vehicle: &Vehicle, seed: u64, prior: &Prior) -> Result<Self> {
        let mut filter = Estimator::for_vehicle(vehicle, prior)?;
        // Room for the controller's look-back (see EstimatedFeedback::controller_input):
        // the IMU latency plus a wingbeat and two IMU periods.
        if let Some(p) = &vehicle.sensors {
            filter.keep_history_s(
                p.imu.latency_s + 1.0 / vehicle.freq_hz() + 2.0 * filter.imu_period_s(),
            );
        }
        Ok(Self {
            sensors: SensorRun::new(vehicle, seed)?,
            filter,
            readings: Vec::new(),
        })
    }

    /// Shows the sensors the body `state` at `t_s` (once per step, in time order) and
    /// applies what they deliver to the filter.
    pub fn observe(&mut self, t_s: f64, state: &State) {
        self.readings.clear();
        let (readings, filter) = (&mut self.readings, &mut self.filter);
        self.sensors.observe(t_s, state, |r| {
            filter.reading(&r);
            readings.push(r);
        });
    }

    /// The readings delivered at the last [`EstimatedFeedback::observe`].
    pub fn readings(&self) -> &[Reading] {
        &self.readings
    }

    /// The estimated state at `t_s` (see [`Estimator::state_at`]).
    pub fn estimate(&self, t_s: f64) -> State {
        self.filter.state_at(t_s)
    }

    /// What a controller acting once per wingbeat of `period_s` at `t_s` should fly on:
    /// the estimate and how many whole wingbeats before `t_s` it is. A filter within one
    /// IMU period of `t_s` (no IMU latency) gives its state carried to `t_s` (0 wingbeats;
    /// [`Estimator::state_at`]). A filter behind by more (the IMU's latency) gives its state
    /// at t_s - d period, the same wingbeat phase d wingbeats ago, for the smallest d that
    /// reaches into its history: the controller predicts it forward with the controls it
    /// applied since ([`crate::control::HoverController::update_from_past`]). Carrying the
    /// newest state across a latency of a wingbeat at constant rates instead would hold an
    /// instant of the in-wingbeat oscillation for the whole latency: measured, the fruit
    /// fly's loop with its 5 ms IMU latency then diverges within 7 wingbeats.
    pub fn controller_input(&self, t_s: f64, period_s: f64) -> (State, usize) {
        let f = &self.filter;
        let Some(t_filter) = f.time_s() else {
            return (f.state_at(t_s), 0);
        };
        let lag = t_s - t_filter;
        if lag <= f.imu_period_s() * (1.0 + 1e-6) {
            return (f.state_at(t_s), 0);
        }
        let d = ((lag / period_s) - 1e-9).ceil().max(1.0) as usize;
        match f.state_in_history(t_s - d as f64 * period_s) {
            Some(s) => (s, d),
            None => (f.state_at(t_s), 0),
        }
    }

    /// The filter.
    pub fn filter(&self) -> &Estimator {
        &self.filter
    }

    /// What the sensors sampled.
    pub fn summary(&self) -> &SensorSummary {
        self.sensors.summary()
    }
}
