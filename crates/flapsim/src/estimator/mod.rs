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
//! since, interpolated between the two samples around that instant:
//! [`Estimator::state_in_history`]) and predicts it forward on its own design model with the controls it applied
//! since ([`crate::control::HoverController::update_from_past`], a discrete Smith
//! predictor), so that no instant of the in-wingbeat oscillation is held across the latency.
//!
//! # Before the first sample
//! The filter starts from a prior (nominal state and covariance, [`Prior`]); the gyroscope
//! and accelerometer biases' prior standard deviations are the turn-on bias standard
//! deviations of `[sensors.imu]`. Until the first IMU sample arrives the estimate is the
//! prior (angular rate zero).
//!
//! # What the filter does not model: the IMU's rate (issue #27)
//! The filter holds each IMU sample over the interval before it (zero-order hold), the
//! standard ESKF discretisation, right when the sampled signal changes little within an
//! IMU period. A hovering flapping body's does not: its rate and specific force carry the
//! wingbeat and its harmonics, and the model's IMU ([`crate::sensors::Imu`]) takes
//! instants of them. On the fruit fly (`models/drosophila.toml`; all numbers from
//! `tests/estimator_rates.rs`, whose ignored tests print them) the hover on the true state
//! has, over 20 wingbeats, a pitch rate of 26.8 rad/s at the wingbeat frequency f = 218 Hz,
//! 8.8 rad/s at 3f (654 Hz), 3.3 at 5f (1090 Hz), 0.7 at 7f, and a specific force of
//! 16.2 m/s^2 fore-aft at f and 7.4, 5.8, 2.9 m/s^2 vertically at 2f, 4f (872 Hz), 6f.
//! The fundamental is below the 500 Hz Nyquist frequency of the model's 1 kHz IMU, but
//! the harmonics above it alias (3f to 346 Hz, 5f to 90 Hz, 4f to 128 Hz, 6f to 308 Hz),
//! and the fundamental itself, at 4.6 samples a wingbeat, is integrated by the hold with
//! a gain of (w dt/2)/sin(w dt/2) = 1.08 and half a sample (39 degrees) of phase error.
//!
//! The propagation's own error (noiseless, unbiased samples propagated by [`propagate`]
//! from the true state over one 5 ms motion-capture interval, rms; the filter's Q carries
//! 1.2e-4 m/s and 8.6e-6 rad of IMU noise over the same interval):
//!
//! | IMU | point samples: velocity, attitude | same samples, trapezoid | integrating IMU |
//! |---|---|---|---|
//! | 1 kHz | 1.3e-2 m/s, 1.1e-2 rad | 1.2e-2, 8.3e-3 | 3.9e-4, 1.2e-9 |
//! | 2 kHz | 4.0e-3, 3.7e-3 | 2.8e-3, 1.6e-3 | 2.3e-4, 1.2e-9 |
//! | 4 kHz | 2.0e-3, 1.7e-3 | 1.2e-3, 3.9e-4 | 1.1e-4, 1.2e-9 |
//! | 8 kHz | 8.7e-4, 8.7e-4 | 4.6e-4, 2.7e-4 | 4.5e-5, 1.2e-9 |
//! | every step (21.8 kHz) | 8.7e-11, 1.2e-9 | | |
//!
//! At 1 kHz the error is 100 times the velocity noise and 1300 times the attitude noise
//! the filter's Q carries; it stays bounded (attitude 1.7e-2 rad over 20 ms, 1.5e-2 over
//! 50 ms: an in-wingbeat oscillation the estimate cannot follow) while the position error
//! grows with the velocity error's offset (5.2e-5 m over 5 ms, 3.6e-4 m over 50 ms). A
//! better use of the same samples does little at 1 kHz (the trapezoid: 8.3e-3 rad against
//! 1.1e-2): the aliased harmonics are lost to point sampling. An integrating IMU at the same
//! 1 kHz (each sample the mean rate and specific force over its period: delta-angle and
//! delta-velocity outputs, or an anti-aliasing filter that averages over the output period)
//! propagates the attitude to the rigid-body integrator's rounding and the velocity to
//! 3.2 times the IMU noise (sculling: the body-frame mean ignores the rotation within the
//! period). The error at 8 kHz is partly the samples' time stamps: a sample due at t_k is
//! taken at the first simulation step not before it (up to a step, 46 us, late) and stamped
//! t_k, which at 20 rad/s rms of in-wingbeat rate is of order 20 rad/s x 23 us = 5e-4 rad.
//!
//! In the filter, per error-state block (mean NEES over the samples from 0.1 to 0.3 s, 3
//! expected for each block; 30 seeds; the filter run on the true-state hover from a 5
//! degree pitch, the model's latencies): 1 kHz position 4.2, velocity 40.5, attitude 4.0,
//! NIS 6.07 (6 expected); 2 kHz 3.5, 9.5, 2.8; 4 kHz 3.1, 4.3, 2.5; 8 kHz 3.0, 3.1, 2.4;
//! every step 3.0, 2.9, 2.4, NIS 5.93. Flying on the estimate (`flapwing hover --feedback
//! estimated`, 1 s, sensor seeds 0-2, the model's latencies) the loop's larger motion makes
//! it worse. At 1 kHz: NEES position 27-34, velocity 310-322, attitude 8.7-10.9, NIS
//! 9.0-9.3; the controller's input (the state it flies on, against the truth at the time it
//! stands for) errs by 1.1-1.3 degrees and 1.0-1.1e-2 m/s rms, and the fly swings by 11-20
//! degrees without settling inside 2 degrees. At 2 kHz 0.54-0.66 degrees, NEES velocity
//! 57-67, no settling. At 4 kHz, 8 kHz and every step 0.49-0.59 degrees (NEES position
//! 2.3-5.5, velocity 2.7-15, attitude 1.3-2.0, NIS 5.9-6.3) and recovery in 0.56-1.0 s in
//! all 9 runs. Before [`Estimator::state_in_history`] interpolated (it carried the sample
//! before the controller's instant forward at constant rates, up to an IMU period) the
//! 1 kHz input erred by 1.8-2.0 degrees, NEES velocity 344-365, attitude 19-25, NIS
//! 10.3-11.3 (the CLI's 11.25: seed 0), swings of 20-25 degrees, and 4 kHz recovered in 2 of
//! 3 runs.
//!
//! An integrating IMU at the model's 1 kHz (a measurement with the sensor model changed to
//! output each period's mean, not committed: [`crate::sensors`] is left as it is) makes the
//! filter consistent (3 seeds on the true-state hover: NEES 3.3, 3.7, 2.5; NIS 6.3) and the
//! loop recover (seeds 0-2: 0.97-0.99 s, controller input 0.48-0.61 degrees, NEES position
//! 2.2-2.9, velocity 3.4-4.4, attitude 1.4-2.1, NIS 5.9-6.2).
//!
//! What is not the cause, measured:
//! - the latencies: with both latencies zero the 1 kHz filter is as inconsistent (one seed,
//!   open loop: NEES velocity 47.3 against 45.5 with the latencies, attitude 4.9 against
//!   4.9; in the loop, seed 0, the look-back carried forward as before: velocity 325
//!   against 365, attitude 9.3 against 22.7, NIS 9.4 against 11.3, the smaller numbers
//!   following the calmer flight, 10.9 degrees at most and settled at 1.0 s, where the
//!   controller's prediction across the latencies lets the fly swing to 25 degrees);
//! - the motion-capture noise model: the sensor draws q_m = q_t (x) Exp(n_theta) with n_theta
//!   of 3.4 degrees per body axis and the filter's H and R are that model; the NIS is 5.9-6.2
//!   at 4 kHz and above;
//! - the innovation statistics: with the filter on the true-state hover the mean NIS is
//!   6.07 even at 1 kHz, because S is dominated by R (3.4 degrees of motion-capture attitude
//!   noise against a 0.6 degree propagation error): the NIS hides the velocity error that the
//!   NEES shows, and the larger NIS of the CLI's run (9.34; 11.25 before the
//!   interpolation) is the swinging loop's.
//!
//! So the filter's algebra and its latency handling are right (consistent when the IMU
//! samples every step, nearly so from 4 kHz), and the inconsistency at the model's 1 kHz is
//! the sensor's: point samples at 4.6 a wingbeat cannot carry the body's in-wingbeat motion.
//! A process noise covering the error would restore the NEES but not the estimate (the
//! error is lost information, not misweighted information), and it would have to come from
//! the vehicle's wingbeat spectrum, which the filter does not know; it is not added. The
//! remedies are the IMU's: a faster output rate (4 kHz and above, measured above), or
//! samples that integrate over their period, as an anti-aliasing filter ahead of the
//! output rate would (a sensor-model change in [`crate::sensors`], measured above).

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
