//! The per-wingbeat hover controller: its design about a trim (the averaged model
//! linearised there, discretised over one wingbeat, with integral action on the position
//! error), and its law (the sensor delay, a past state predicted forward, saturation at the
//! design excursions and at an actuator's voltage limit).

use std::collections::VecDeque;

use nalgebra::{DMatrix, DVector, UnitQuaternion, Vector3};

use super::lqr::{LqrWeights, discretize, dlqr};
use crate::error::{Error, Result};
use crate::linear::{AveragedModel, N_CONTROLS, N_STATES};
use crate::model::{Controls, Vehicle};
use crate::sim::State;
use crate::trim::Trim;

/// A per-wingbeat hover controller.
#[derive(Debug, Clone)]
pub struct HoverController {
    gain: DMatrix<f64>,
    trim_controls: Controls,
    q_trim: UnitQuaternion<f64>,
    reference_m: Vector3<f64>,
    /// The trim's velocity through the air, world, m/s (zero in hover).
    velocity_ref_m_s: Vector3<f64>,
    delay_wingbeats: usize,
    history: VecDeque<DVector<f64>>,
    /// Saturation of each channel: three times its design excursion.
    limits: [f64; N_CONTROLS],
    /// The channels are drive parameters.
    drive: bool,
    /// An actuated vehicle's actuation: its commands also stay within the actuator's voltage
    /// limit.
    actuation: Option<crate::actuated::Actuation>,
    /// Integral of the position error, m s.
    integral: Vector3<f64>,
    period_s: f64,
    /// The design model discretised over one wingbeat (x+ = A_d x + B_d u), for predicting
    /// a past state forward ([`HoverController::update_from_past`]).
    ad: DMatrix<f64>,
    bd: DMatrix<f64>,
    /// The control channels' deviations from trim applied in the last wingbeats, newest
    /// last (at most [`MAX_PREDICTION_WINGBEATS`]).
    applied: VecDeque<[f64; N_CONTROLS]>,
}

/// The longest a past state is predicted forward by [`HoverController::update_from_past`],
/// wingbeats.
pub const MAX_PREDICTION_WINGBEATS: usize = 16;

impl HoverController {
    /// Designs the controller for a trimmed `vehicle` (controls and attitude at `trim`).
    pub fn design(
        vehicle: &Vehicle,
        trim: &Trim,
        weights: &LqrWeights,
        delay_wingbeats: usize,
    ) -> Result<Self> {
        let model = AveragedModel::new(vehicle, trim.attitude(), trim.controls, 100);
        let (a, b) = model.linearize(&crate::stability::trim_state(trim))?;
        let period = 1.0 / vehicle.freq_hz();
        let (ad, bd) = discretize(&a, &b, period);
        let l = vehicle.length_m;
        let w = weights;
        let qd = [
            l * w.position_body_lengths,
            l * w.position_body_lengths,
            l * w.position_body_lengths,
            l * w.velocity_body_lengths_per_wingbeat / period,
            l * w.velocity_body_lengths_per_wingbeat / period,
            l * w.velocity_body_lengths_per_wingbeat / period,
            w.attitude_rad,
            w.attitude_rad,
            w.attitude_rad,
            w.rate_rad_per_wingbeat / period,
            w.rate_rad_per_wingbeat / period,
            w.rate_rad_per_wingbeat / period,
        ];
        // Integral action on the position error (3 extra states z += T p) removes the
        // steady offset left by the small difference between the averaged trim and the
        // time-stepped periodic hover.
        let n = N_STATES + 3;
        let mut a_aug = DMatrix::zeros(n, n);
        a_aug.view_mut((0, 0), (N_STATES, N_STATES)).copy_from(&ad);
        for i in 0..3 {
            a_aug[(N_STATES + i, i)] = period;
            a_aug[(N_STATES + i, N_STATES + i)] = 1.0;
        }
        let mut b_aug = DMatrix::zeros(n, N_CONTROLS);
        b_aug
            .view_mut((0, 0), (N_STATES, N_CONTROLS))
            .copy_from(&bd);
        let zmax = l * w.position_body_lengths * w.integral_time_s;
        let q = DMatrix::from_diagonal(&DVector::from_iterator(
            n,
            qd.iter()
                .map(|x| 1.0 / (x * x))
                .chain(std::iter::repeat_n(1.0 / (zmax * zmax), 3)),
        ));
        let umax = w.control_max(vehicle);
        let r = DMatrix::from_diagonal(&DVector::from_iterator(
            N_CONTROLS,
            umax.iter().map(|u| 1.0 / (u * u)),
        ));
        let gain = dlqr(&a_aug, &b_aug, &q, &r)?;
        Ok(Self {
            gain,
            trim_controls: trim.controls,
            q_trim: trim.attitude(),
            reference_m: vehicle.initial_position_m,
            velocity_ref_m_s: trim.condition.velocity_world_m_s(),
            delay_wingbeats,
            history: VecDeque::new(),
            limits: umax.map(|u| 3.0 * u),
            drive: vehicle.drive_controlled(),
            actuation: vehicle.actuation.clone(),
            integral: Vector3::zeros(),
            period_s: period,
            ad,
            bd,
            applied: VecDeque::new(),
        })
    }

    /// The LQR gain (controls x (states + 3 position integrals)).
    pub fn gain(&self) -> &DMatrix<f64> {
        &self.gain
    }

    /// Sets the position to hold, world, m (at a flight condition: where the reference
    /// point, moving at the trim's velocity, is at the time of the state the next update
    /// reads).
    pub fn set_reference(&mut self, p: Vector3<f64>) {
        self.reference_m = p;
    }

    /// The trim's velocity the controller holds, world, m/s (zero in hover).
    pub fn velocity_reference_m_s(&self) -> Vector3<f64> {
        self.velocity_ref_m_s
    }

    /// The state the controller holds: at the reference position, the trim's velocity and
    /// attitude, not rotating (its error state is zero).
    pub fn reference_state(&self) -> State {
        State {
            position_m: self.reference_m,
            world_from_body: self.q_trim,
            velocity_m_s: self.velocity_ref_m_s,
            angular_velocity_body_rad_s: Vector3::zeros(),
        }
    }

    /// The error state of `s` (see [`crate::linear`]).
    pub fn error_state(&self, s: &State) -> DVector<f64> {
        let d = (self.q_trim.inverse() * s.world_from_body).scaled_axis();
        let p = s.position_m - self.reference_m;
        let v = s.velocity_m_s - self.velocity_ref_m_s;
        DVector::from_iterator(
            N_STATES,
            p.iter()
                .chain(v.iter())
                .chain(d.iter())
                .chain(s.angular_velocity_body_rad_s.iter())
                .copied(),
        )
    }

    /// Controls for the next wingbeat given the state measured now (delayed by the sensor
    /// delay), saturated at three times the design excursion and, for an actuated vehicle,
    /// at its actuator's voltage limit: a command past the limit is scaled back towards the
    /// trim along its own direction (bisection on the scale, to 1e-9 of it) until the drive
    /// fits, as a real drive amplifier saturates. The sensor delay of
    /// [`HoverController::design`] is not compensated (it shows what a delay does to a loop
    /// designed without it); [`HoverController::update_from_past`] compensates one.
    pub fn update(&mut self, s: &State) -> Controls {
        self.history.push_back(self.error_state(s));
        while self.history.len() > self.delay_wingbeats.saturating_add(1) {
            self.history.pop_front();
        }
        let x = self.history[0].clone();
        self.law(&x)
    }

    /// Controls for the next wingbeat from a state `s_past` measured `wingbeats_ago` whole
    /// wingbeats before now (at the same wingbeat phase: a late sensor's state), predicted
    /// forward to now on the design model with the controls applied since,
    /// x_n = A_d^d x_(n-d) + sum_j A_d^(d-1-j) B_d u_(n-d+j) (a discrete Smith predictor:
    /// K. J. Astrom & B. Wittenmark, "Computer-Controlled Systems", 3rd ed. 1997, section
    /// 5.8 on time delays), then the law of [`HoverController::update`] without its delay.
    /// Before the first update the controls applied were the trim's (deviation 0). An error
    /// for `wingbeats_ago` > [`MAX_PREDICTION_WINGBEATS`].
    pub fn update_from_past(&mut self, s_past: &State, wingbeats_ago: usize) -> Result<Controls> {
        if wingbeats_ago > MAX_PREDICTION_WINGBEATS {
            return Err(Error::Input(format!(
                "hover controller: a state {wingbeats_ago} wingbeats old; allowed: at most {MAX_PREDICTION_WINGBEATS} wingbeats of prediction"
            )));
        }
        let mut x = self.error_state(s_past);
        let n = self.applied.len();
        for k in (0..wingbeats_ago).rev() {
            // The control applied k + 1 wingbeats before the one about to be set.
            let u = match n.checked_sub(k + 1) {
                Some(i) => DVector::from_row_slice(&self.applied[i]),
                None => DVector::zeros(N_CONTROLS),
            };
            x = &self.ad * x + &self.bd * u;
        }
        Ok(self.law(&x))
    }

    /// The control law on the error state `x` (see [`HoverController::update`]).
    fn law(&mut self, x: &DVector<f64>) -> Controls {
        let p = Vector3::new(x[0], x[1], x[2]);
        let aug = DVector::from_iterator(
            N_STATES + 3,
            x.iter().copied().chain(self.integral.iter().copied()),
        );
        self.integral += self.period_s * p;
        let u = -(&self.gain * aug);
        let u: Vec<f64> = u
            .iter()
            .zip(&self.limits)
            .map(|(v, lim)| v.clamp(-lim, *lim))
            .collect();
        let scale = self.drive_scale(&u);
        let applied: [f64; N_CONTROLS] = std::array::from_fn(|i| scale * u[i]);
        self.applied.push_back(applied);
        while self.applied.len() > MAX_PREDICTION_WINGBEATS {
            self.applied.pop_front();
        }
        self.trim_controls.with_channels(self.drive, &applied)
    }

    /// The factor in [0, 1] the channel deviations `u` are scaled by so that an actuated
    /// vehicle's drive fits its voltage limit (1 when it fits or for kinematic controls).
    fn drive_scale(&self, u: &[f64]) -> f64 {
        let Some(act) = &self.actuation else {
            return 1.0;
        };
        let fits = |c: &Controls| act.controlled_drives(c).is_ok();
        let scaled = |k: f64| {
            let v: Vec<f64> = u.iter().map(|x| k * x).collect();
            self.trim_controls.with_channels(self.drive, &v)
        };
        if fits(&scaled(1.0)) || !fits(&self.trim_controls) {
            return 1.0;
        }
        let (mut lo, mut hi) = (0.0, 1.0);
        while hi - lo > 1e-9 {
            let mid = 0.5 * (lo + hi);
            if fits(&scaled(mid)) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    }
}
