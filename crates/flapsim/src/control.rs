//! Hover control: a linear-quadratic regulator designed on the averaged model, discretised
//! over one wingbeat, that sets the controls once per wingbeat (mean stroke angle for
//! pitch, amplitude for height, left-right amplitude difference for roll, left-right pitch
//! bias difference for yaw; on an actuated vehicle the drive's bias, amplitude, amplitude
//! difference and second-harmonic difference), with an optional sensor delay in whole
//! wingbeats. In hover it holds a point; at a flight condition ([`crate::flight`]) it is
//! designed about that condition's trim and holds a point moving at the condition's velocity
//! (the same regulator: the error dynamics about a steady flight are those of the averaged
//! model linearised there).

use std::collections::VecDeque;

use nalgebra::{DMatrix, DVector, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::estimator::EstimatedFeedback;
use crate::linear::{AveragedModel, N_CONTROLS, N_STATES};
use crate::model::{Controls, Vehicle};
use crate::sim::{Mode, Simulation, State, StepOutput};
use crate::trim::Trim;

/// LQR weights as the largest acceptable excursions (Bryson's rule: weight = 1/max^2).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LqrWeights {
    /// Position error, in body lengths.
    pub position_body_lengths: f64,
    /// Velocity error, body lengths per wingbeat.
    pub velocity_body_lengths_per_wingbeat: f64,
    /// Attitude error, rad.
    pub attitude_rad: f64,
    /// Angular rate, rad per wingbeat.
    pub rate_rad_per_wingbeat: f64,
    /// Control excursion, rad (kinematic controls).
    pub control_rad: f64,
    /// Control excursion of a drive voltage channel, V (actuated vehicles).
    #[serde(default = "default_control_v")]
    pub control_v: f64,
    /// Control excursion of the second-harmonic difference (actuated vehicles).
    #[serde(default = "default_control_second_harmonic")]
    pub control_second_harmonic: f64,
    /// Time scale of the position-error integral, s (its weight is 1/(position x this)^2).
    pub integral_time_s: f64,
}

impl Default for LqrWeights {
    fn default() -> Self {
        Self {
            position_body_lengths: 0.1,
            velocity_body_lengths_per_wingbeat: 0.05,
            attitude_rad: 2f64.to_radians(),
            rate_rad_per_wingbeat: 1f64.to_radians(),
            control_rad: 10f64.to_radians(),
            control_v: default_control_v(),
            control_second_harmonic: default_control_second_harmonic(),
            integral_time_s: 0.1,
        }
    }
}

fn default_control_v() -> f64 {
    10.0
}

fn default_control_second_harmonic() -> f64 {
    0.1
}

impl LqrWeights {
    /// The largest acceptable excursion of each of `vehicle`'s control channels.
    pub fn control_max(&self, vehicle: &Vehicle) -> [f64; N_CONTROLS] {
        if vehicle.drive_controlled() {
            [
                self.control_v,
                self.control_v,
                self.control_v,
                self.control_second_harmonic,
            ]
        } else {
            [self.control_rad; N_CONTROLS]
        }
    }
}

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

/// Discrete-time algebraic Riccati equation by fixed-point iteration; returns the gain K of
/// u = -K x for x+ = A x + B u with costs Q, R.
pub fn dlqr(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    q: &DMatrix<f64>,
    r: &DMatrix<f64>,
) -> Result<DMatrix<f64>> {
    let mut p = q.clone();
    for _ in 0..100_000 {
        let btp = b.transpose() * &p;
        let s = r + &btp * b;
        let Some(s_inv) = s.try_inverse() else {
            return Err(Error::Analysis("LQR: singular R + B'PB".into()));
        };
        let k = &s_inv * &btp * a;
        let next = q + a.transpose() * &p * a - a.transpose() * &p * b * &k;
        let diff = (&next - &p).amax();
        p = next;
        if diff <= 1e-12 * p.amax() {
            return Ok(k);
        }
    }
    Err(Error::Analysis("LQR: the Riccati iteration did not converge (the hover may not be stabilisable with these controls)".into()))
}

/// Zero-order-hold discretisation over `t_s`: (A_d, B_d) = (exp(A t), int_0^t exp(A s) ds B).
pub fn discretize(a: &DMatrix<f64>, b: &DMatrix<f64>, t_s: f64) -> (DMatrix<f64>, DMatrix<f64>) {
    let (n, m) = (a.nrows(), b.ncols());
    let mut aug = DMatrix::zeros(n + m, n + m);
    aug.view_mut((0, 0), (n, n)).copy_from(&(a * t_s));
    aug.view_mut((0, n), (n, m)).copy_from(&(b * t_s));
    let e = aug.exp();
    (
        e.view((0, 0), (n, n)).into_owned(),
        e.view((0, n), (n, m)).into_owned(),
    )
}

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

/// A disturbance for a hover run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Disturbance {
    /// Initial pitch perturbation, deg (nose up).
    pub pitch_deg: f64,
    /// Initial roll perturbation, deg.
    pub roll_deg: f64,
    /// Initial velocity, world, m/s.
    pub velocity_m_s: [f64; 3],
    /// Gust (wind) velocity, world, m/s, blowing from `gust_start_s` for `gust_duration_s`.
    pub gust_m_s: [f64; 3],
    /// Gust start, s.
    pub gust_start_s: f64,
    /// Gust duration, s.
    pub gust_duration_s: f64,
}

/// How a hover run went.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HoverOutcome {
    /// Closed loop (true) or open loop.
    pub closed_loop: bool,
    /// Simulated time, s.
    pub duration_s: f64,
    /// Largest distance from the hover point, m.
    pub max_position_error_m: f64,
    /// Same, in body lengths.
    pub max_position_error_body_lengths: f64,
    /// Largest attitude error from trim, deg.
    pub max_attitude_error_deg: f64,
    /// Position error at the end, m.
    pub final_position_error_m: f64,
    /// Attitude error at the end, deg.
    pub final_attitude_error_deg: f64,
    /// First time after which the vehicle stayed within 1 body length and 2 deg to the end, s.
    pub recovery_time_s: Option<f64>,
    /// The run stopped early: attitude error beyond 90 deg, or the simulation diverged.
    pub diverged: Option<String>,
    /// The observer stopped the run early (e.g. Ctrl-C).
    pub interrupted: bool,
}

/// Flies a hover from the trim with a disturbance, closed loop (with `controller`) or open
/// loop (trim controls held), calling `observer` after every step; the run ends early when
/// the observer returns false (e.g. on Ctrl-C). A vehicle with a `[wind]` flies in that wind
/// field (evaluated at each wing's hinge, reference point the start), plus the disturbance's
/// gust.
pub fn run_hover(
    vehicle: &Vehicle,
    trim: &Trim,
    controller: Option<HoverController>,
    disturbance: &Disturbance,
    duration_s: f64,
    mut observer: impl FnMut(&StepOutput) -> bool,
) -> Result<HoverOutcome> {
    run_hover_with(
        vehicle,
        trim,
        controller,
        disturbance,
        duration_s,
        None,
        |step| observer(step.out),
    )
}

/// As [`run_hover`], but the controller flies on the state estimated by `feedback` (the
/// model's sensors and the error-state Kalman filter of [`crate::estimator`]) instead of the
/// true state. Each step the sensors are shown the body at the step's start, before the
/// controller reads the estimate; `observer` receives the step and the feedback (its
/// readings delivered at that step's start, and the filter).
pub fn run_hover_estimated(
    vehicle: &Vehicle,
    trim: &Trim,
    controller: Option<HoverController>,
    disturbance: &Disturbance,
    duration_s: f64,
    feedback: &mut EstimatedFeedback,
    mut observer: impl FnMut(&StepOutput, &EstimatedFeedback) -> bool,
) -> Result<HoverOutcome> {
    run_hover_with(
        vehicle,
        trim,
        controller,
        disturbance,
        duration_s,
        Some(feedback),
        |step| match step.feedback {
            Some(f) => observer(step.out, f),
            None => true,
        },
    )
}

/// What the observer of [`run_hover_with`] sees after each step.
#[derive(Debug, Clone, Copy)]
pub struct HoverStep<'a> {
    /// The step.
    pub out: &'a StepOutput,
    /// The estimated feedback, when the controller flies on it (its readings delivered at
    /// the step's start, and the filter).
    pub feedback: Option<&'a EstimatedFeedback>,
    /// The simulation after the step: e.g. [`Simulation::wing_winds_m_s`] (each wing's wind
    /// in the step) and [`Simulation::uniform_wind_m_s`] (the disturbance's gust).
    pub sim: &'a Simulation,
}

/// [`run_hover`] and [`run_hover_estimated`] in one: flies on the estimate of `feedback`
/// when given, else on the true state; `observer` sees each step with the feedback and the
/// simulation ([`HoverStep`]).
pub fn run_hover_with(
    vehicle: &Vehicle,
    trim: &Trim,
    mut controller: Option<HoverController>,
    disturbance: &Disturbance,
    duration_s: f64,
    mut feedback: Option<&mut EstimatedFeedback>,
    mut observer: impl FnMut(&HoverStep<'_>) -> bool,
) -> Result<HoverOutcome> {
    // At a flight condition the induced inflow is frozen there (trimmed_vehicle).
    let mut v = crate::trim::trimmed_vehicle(vehicle, trim)?;
    // An actuated vehicle starts with its wings on their periodic motion at the trim (as a
    // flight that has been going on), not from rest.
    let velocity_ref = trim.condition.velocity_world_m_s();
    let periodic = match &v.actuation {
        Some(_) => Some(crate::actuated::periodic::settle(
            &v,
            &wingforce::BodyMotion {
                velocity_m_s: trim.velocity_body_m_s(),
                angular_velocity_rad_s: Vector3::zeros(),
            },
        )?),
        None => None,
    };
    let q_trim = trim.attitude();
    let start_q = q_trim
        * UnitQuaternion::from_scaled_axis(Vector3::new(
            disturbance.roll_deg.to_radians(),
            -disturbance.pitch_deg.to_radians(),
            0.0,
        ));
    v.initial_attitude = start_q;
    v.initial_velocity_m_s = velocity_ref + Vector3::from(disturbance.velocity_m_s);
    v.initial_angular_velocity_rad_s = Vector3::zeros();
    let reference = v.initial_position_m;
    let length = v.length_m;
    let wind = vehicle
        .wind
        .as_ref()
        .map(|w| crate::wind::Wind::from_spec(w, &vehicle.name, reference))
        .transpose()?;
    let mut sim = Simulation::new(v, Mode::Free);
    // The model's `[wind]` (field at each hinge) adds to the disturbance's uniform gust.
    sim.set_wind_model(wind);
    if let Some(p) = &periodic {
        sim.start_wings_from(p);
    }
    let n = (duration_s / sim.dt_s()).round() as u64;
    let period_s = 1.0 / vehicle.freq_hz();
    let mut max_p: f64 = 0.0;
    let mut max_a: f64 = 0.0;
    let mut last_bad_t = 0.0;
    let mut diverged = None;
    let mut interrupted = false;
    let mut last_cycle = -1i64;
    let closed = controller.is_some();
    let (mut final_p, mut final_a) = (0.0, 0.0);
    for _ in 0..n {
        let t = sim.time_s();
        let gust_on = t >= disturbance.gust_start_s
            && t < disturbance.gust_start_s + disturbance.gust_duration_s;
        sim.set_wind(if gust_on {
            Vector3::from(disturbance.gust_m_s)
        } else {
            Vector3::zeros()
        });
        if let Some(f) = feedback.as_deref_mut() {
            f.observe(t, &sim.state());
        }
        let cycle = sim.phase().floor() as i64;
        if cycle != last_cycle {
            last_cycle = cycle;
            if let Some(c) = controller.as_mut() {
                let u = match feedback.as_deref() {
                    Some(f) => {
                        let (s, wingbeats_ago) = f.controller_input(t, period_s);
                        let t_s = t - wingbeats_ago as f64 * period_s;
                        c.set_reference(reference + velocity_ref * t_s);
                        c.update_from_past(&s, wingbeats_ago)?
                    }
                    None => {
                        c.set_reference(reference + velocity_ref * t);
                        c.update(&sim.state())
                    }
                };
                sim.set_controls(u);
            }
        }
        let out = match sim.step() {
            Ok(o) => *o,
            Err(e) => {
                diverged = Some(e.to_string());
                break;
            }
        };
        let step = HoverStep {
            out: &out,
            feedback: feedback.as_deref(),
            sim: &sim,
        };
        if !observer(&step) {
            interrupted = true;
            break;
        }
        let s = out.state;
        let pe = (s.position_m - (reference + velocity_ref * out.t_s)).norm();
        let ae = (q_trim.inverse() * s.world_from_body).angle().to_degrees();
        max_p = max_p.max(pe);
        max_a = max_a.max(ae);
        (final_p, final_a) = (pe, ae);
        if pe > length || ae > 2.0 {
            last_bad_t = out.t_s + sim.dt_s();
        }
        if ae > 90.0 {
            diverged = Some(format!(
                "attitude error {ae:.1} deg exceeds 90 deg at t = {:.4} s",
                out.t_s
            ));
            break;
        }
    }
    let end = sim.time_s();
    Ok(HoverOutcome {
        closed_loop: closed,
        duration_s: end,
        max_position_error_m: max_p,
        max_position_error_body_lengths: max_p / length,
        max_attitude_error_deg: max_a,
        final_position_error_m: final_p,
        final_attitude_error_deg: final_a,
        recovery_time_s: (diverged.is_none() && !interrupted && last_bad_t < end)
            .then_some(last_bad_t),
        diverged,
        interrupted,
    })
}
