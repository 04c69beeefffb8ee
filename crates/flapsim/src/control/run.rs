//! A hover run: the vehicle started from its trim with a disturbance (an initial attitude
//! and velocity, a gust), flown closed loop on the true or the estimated state, or open loop,
//! and how it went (largest and final errors, recovery time, divergence).

use nalgebra::{UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use super::controller::HoverController;
use crate::error::Result;
use crate::estimator::EstimatedFeedback;
use crate::model::Vehicle;
use crate::sim::{Mode, Simulation, StepOutput};
use crate::trim::Trim;

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
