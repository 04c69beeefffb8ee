//! Trim: the stroke amplitude (weight support), mean stroke angle (pitch-moment balance) and
//! body pitch (no net horizontal force) at which the cycle-averaged forces and moments
//! balance, found by Newton's method with finite-difference Jacobians, in hover or at a
//! flight condition ([`crate::flight`]: forward speed and climb rate, with the body's drag
//! and the induced inflow of that condition). An actuated
//! vehicle trims the same way on its drive: amplitude and bias voltage in place of stroke
//! amplitude and mean stroke angle ([`Vehicle::control_channels`]), with its wings run into
//! their periodic motion at every evaluation ([`crate::actuated::periodic`]).

use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};
use wingforce::Wing;

use crate::actuated::{Actuator, Stroke};
use crate::averaged::{FrozenState, mean_loads};
use crate::error::{Error, Result};
use crate::flight::condition::FlightCondition;
use crate::model::{Controls, Vehicle};

pub mod spec;

/// Phases averaged per evaluation under the step-start sampling (a rectangle rule over the
/// wingbeat; see [`trim_samples`]).
pub const TRIM_SAMPLES: usize = 200;

/// The steps of the wingbeat whose loads a trim of `vehicle` balances: under a second-order
/// load sampling (`[sim] load_sampling`, `midpoint` or `step_mean`), the vehicle's own
/// `steps_per_wingbeat`, so that the trim balances exactly the loads its simulation steps
/// with at the trim state (each step's loads are already a quadrature over the step, so
/// their mean is the wingbeat's to the quadrature's accuracy); under the step-start
/// sampling, [`TRIM_SAMPLES`] samples (one per step would balance a rectangle rule's error).
pub fn trim_samples(vehicle: &Vehicle) -> usize {
    match vehicle.load_sampling().step_rule() {
        Some(_) => vehicle.sim.steps_per_wingbeat,
        None => TRIM_SAMPLES,
    }
}

pub use spec::{LiftVariable, TrimSpec};

/// A trim (in hover unless `condition` says otherwise).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Trim {
    /// The flight condition trimmed at.
    #[serde(default)]
    pub condition: FlightCondition,
    /// Controls at trim (amplitude and mean stroke offsets from the model's base kinematics).
    pub controls: Controls,
    /// Body pitch at trim, rad (positive nose up).
    pub pitch_rad: f64,
    /// Residual horizontal force over weight.
    pub residual_fx_over_weight: f64,
    /// Residual vertical force minus weight, over weight.
    pub residual_fz_over_weight: f64,
    /// Residual pitch moment over (weight x wing length).
    pub residual_my_over_weight_length: f64,
    /// Newton iterations used.
    pub iterations: usize,
    /// What the trim varied to carry the weight.
    #[serde(default)]
    pub lift_variable: LiftVariable,
}

impl Trim {
    /// world_from_body at trim.
    pub fn attitude(&self) -> UnitQuaternion<f64> {
        attitude_for_pitch(self.pitch_rad)
    }
    /// The body's velocity through the air at trim, body frame, m/s.
    pub fn velocity_body_m_s(&self) -> Vector3<f64> {
        self.attitude().inverse() * self.condition.velocity_world_m_s()
    }
    /// Largest residual (all non-dimensional).
    pub fn max_residual(&self) -> f64 {
        self.residual_fx_over_weight
            .abs()
            .max(self.residual_fz_over_weight.abs())
            .max(self.residual_my_over_weight_length.abs())
    }
}

/// world_from_body for a body pitched up by `pitch_rad` (no roll or yaw).
pub fn attitude_for_pitch(pitch_rad: f64) -> UnitQuaternion<f64> {
    UnitQuaternion::from_euler_angles(0.0, -pitch_rad, 0.0)
}

/// The trim variables' offsets as controls: x[0] on the lift variable, x[1] on the
/// mean-stroke (or bias) channel.
fn trim_controls(vehicle: &Vehicle, lift: LiftVariable, x: &Vector3<f64>) -> Controls {
    let mut c = vehicle.controls_with(&vehicle.controls, &[x[1], 0.0, 0.0, 0.0]);
    match lift {
        LiftVariable::Amplitude => c = vehicle.controls_with(&c, &[0.0, x[0], 0.0, 0.0]),
        LiftVariable::AngleOfAttack => c.aoa_rad += x[0],
        LiftVariable::Frequency => c.freq_hz += x[0],
    }
    c
}

/// The vehicle with trim variables `x` applied at `condition`: controls, and the induced
/// inflow frozen at the condition for the force the wings must carry (weight and body drag).
fn at_condition(
    vehicle: &Vehicle,
    lift: LiftVariable,
    x: &Vector3<f64>,
    condition: &FlightCondition,
) -> Result<Vehicle> {
    let mut v = vehicle.clone();
    v.apply_controls(&trim_controls(vehicle, lift, x))?;
    v.freeze_inflow_at(condition, &attitude_for_pitch(x[2]));
    Ok(v)
}

fn residual(
    vehicle: &Vehicle,
    lift: LiftVariable,
    x: &Vector3<f64>,
    condition: &FlightCondition,
) -> Result<Vector3<f64>> {
    let v = at_condition(vehicle, lift, x, condition)?;
    let q = attitude_for_pitch(x[2]);
    let vel_w = condition.velocity_world_m_s();
    let m = mean_loads(
        &v,
        &FrozenState {
            world_from_body: q,
            velocity_body_m_s: q.inverse() * vel_w,
            angular_velocity_body_rad_s: Vector3::zeros(),
        },
        trim_samples(&v),
    )?;
    let f = q * m.total.force_n + v.body_drag_world_n(&vel_w);
    let w = v.weight_n();
    let r_wing = v.wings[0].geometry().r_tip_m;
    Ok(Vector3::new(
        f.x / w,
        f.z / w - 1.0,
        m.total.moment_nm.y / (w * r_wing),
    ))
}

/// `vehicle` as a host stepping it every `dt_s` steps it: where `dt_s` divides the wingbeat
/// (to 1e-9), its `steps_per_wingbeat` is the host's, so that a trim of it balances the
/// loads that host's steps apply ([`trim_samples`]: a C, FMI or MuJoCo host whose step is
/// not the model's); otherwise unchanged (the steps then fall on other phases every
/// wingbeat and no stepped wingbeat is the one to balance).
pub fn at_host_step(vehicle: &Vehicle, dt_s: f64) -> Vehicle {
    let mut v = vehicle.clone();
    let per_wingbeat = 1.0 / (vehicle.freq_hz() * dt_s);
    let n = per_wingbeat.round();
    if n >= 1.0 && (per_wingbeat - n).abs() <= 1e-9 * n {
        v.sim.steps_per_wingbeat = n as usize;
    }
    v
}

/// Finds the hover trim of `vehicle` on the lift variable its model file names (`[trim]`),
/// starting from its current controls and initial pitch.
pub fn trim(vehicle: &Vehicle) -> Result<Trim> {
    trim_on(vehicle, vehicle.trim_lift)
}

/// Finds the hover trim of `vehicle` varying `lift` to carry the weight.
pub fn trim_on(vehicle: &Vehicle, lift: LiftVariable) -> Result<Trim> {
    trim_at(vehicle, lift, &FlightCondition::HOVER)
}

/// Finds the trim of `vehicle` at `condition` varying `lift` to carry the weight, starting
/// from its current controls and initial pitch. Away from hover, when Newton's method does
/// not converge from there, it continues from the hover trim along the straight path of
/// conditions to `condition` ([`CONTINUATION_STEPS`] steps, each starting from the last
/// trim), and reports the first attempt's failure if that does not reach it either.
pub fn trim_at(vehicle: &Vehicle, lift: LiftVariable, condition: &FlightCondition) -> Result<Trim> {
    let (_, p0, _) = vehicle.initial_attitude.euler_angles();
    let start = Vector3::new(0.0, 0.0, -p0);
    if condition.is_hover() {
        return hover_from(vehicle, lift, start);
    }
    let direct = trim_from(vehicle, lift, condition, start);
    if !matches!(direct, Err(Error::Analysis(_))) {
        return direct;
    }
    let continued = (|| {
        let mut x = trim_variables(vehicle, &hover_from(vehicle, lift, start)?);
        let mut last = None;
        for k in 1..=CONTINUATION_STEPS {
            let f = k as f64 / CONTINUATION_STEPS as f64;
            let c = FlightCondition {
                forward_speed_m_s: f * condition.forward_speed_m_s,
                climb_rate_m_s: f * condition.climb_rate_m_s,
            };
            let t = trim_from(vehicle, lift, &c, x)?;
            x = trim_variables(vehicle, &t);
            last = Some(t);
        }
        last.ok_or_else(|| Error::Analysis("no continuation steps".into()))
    })();
    match continued {
        Ok(mut t) => {
            t.condition = *condition;
            Ok(t)
        }
        Err(_) => direct,
    }
}

/// The hover trim searched from `start`, and, when Newton's method does not converge from
/// there, from the body pitch that levels the wings' mean stroke plane
/// ([`level_stroke_plane_pitch_rad`]): the wings' mean force lies close to the normal of
/// their stroke plane, and most insects hover with that plane nearly horizontal (Weis-Fogh
/// 1973, J Exp Biol 59:169, "normal hovering"), so that pitch is near the balance for a
/// vehicle whose model file holds its body as in forward flight. Measured: the dragonfly
/// (stroke planes 55 and 48 deg to its body) does not converge from its level body, and from
/// 35 to 80 deg of body pitch converges to one trim (55.7 deg; from 0 to 30 deg the search
/// leaves the range). The first attempt's failure is reported, with the second's, if neither
/// converges.
fn hover_from(vehicle: &Vehicle, lift: LiftVariable, start: Vector3<f64>) -> Result<Trim> {
    let direct = trim_from(vehicle, lift, &FlightCondition::HOVER, start);
    let Err(Error::Analysis(first)) = &direct else {
        return direct;
    };
    let level = level_stroke_plane_pitch_rad(vehicle);
    if (level - start[2]).abs() < 1e-3 {
        return direct;
    }
    trim_from(
        vehicle,
        lift,
        &FlightCondition::HOVER,
        Vector3::new(0.0, 0.0, level),
    )
    .map_err(|e| {
        Error::Analysis(format!(
            "{first}; from {:.1} deg of body pitch (the stroke planes level): {e}",
            level.to_degrees()
        ))
    })
}

/// The stroke plane's angle to the horizontal of `wing` on a body at `world_from_body`, rad
/// (positive: its normal tilted forward, towards world x).
pub fn stroke_plane_angle_rad(wing: &Wing, world_from_body: &UnitQuaternion<f64>) -> f64 {
    let n = world_from_body * (wing.body_from_stroke() * Vector3::z());
    n.x.atan2(n.z)
}

/// The body pitch, rad (nose up), at which the mean of the wings' stroke-plane angles
/// ([`stroke_plane_angle_rad`]) is zero: the angles with the body level, averaged (a body
/// pitched up by p turns each by -p).
pub fn level_stroke_plane_pitch_rad(vehicle: &Vehicle) -> f64 {
    let level = UnitQuaternion::identity();
    let n = vehicle.wings.len().max(1) as f64;
    vehicle
        .wings
        .iter()
        .map(|w| stroke_plane_angle_rad(w, &level))
        .sum::<f64>()
        / n
}

/// Steps of the continuation from hover in [`trim_at`].
pub const CONTINUATION_STEPS: usize = 8;

/// Finds the trim of `vehicle` at `condition` from the trim variables `x0` (offsets of the
/// lift variable and the mean stroke angle from the current controls, and the body pitch),
/// as a continuation from a neighbouring condition's trim does.
pub fn trim_from(
    vehicle: &Vehicle,
    lift: LiftVariable,
    condition: &FlightCondition,
    x0: Vector3<f64>,
) -> Result<Trim> {
    search(vehicle, lift, condition, x0, true)
}

/// [`trim_from`]'s Newton search; `explain_limit`: when it stalls on an actuator's voltage
/// limit, say how much the balance needs (a second search with the limit lifted).
fn search(
    vehicle: &Vehicle,
    lift: LiftVariable,
    condition: &FlightCondition,
    x0: Vector3<f64>,
    explain_limit: bool,
) -> Result<Trim> {
    let what = if condition.is_hover() {
        "no hover trim".to_owned()
    } else {
        format!("no trim at {}", condition.describe())
    };
    if vehicle.drive_controlled() && lift != LiftVariable::Amplitude {
        return Err(Error::Analysis(format!(
            "{what} for `{}` on the {}: an actuated vehicle trims its drive amplitude (lift variable `amplitude`)",
            vehicle.name,
            lift.name()
        )));
    }
    vehicle.check_flight_condition(condition)?;
    let mut x = x0;
    let fail = |why: String| Error::Analysis(format!("{what} for `{}`: {why}", vehicle.name));
    let residual = |x: &Vector3<f64>| residual(vehicle, lift, x, condition);
    let mut r = residual(&x).map_err(|e| fail(format!("at the starting controls: {e}")))?;
    // Finite-difference steps: 1e-6 rad of the kinematic channels, 1e-6 of a drive
    // channel's scale (Vehicle::control_scales), 1e-6 rad of body pitch.
    let scales = vehicle.control_scales();
    let h_lift = match lift {
        LiftVariable::Amplitude => 1e-6 * scales[1],
        LiftVariable::AngleOfAttack => 1e-6,
        LiftVariable::Frequency => 1e-6 * vehicle.freq_hz(),
    };
    let h = [h_lift, 1e-6 * scales[0], 1e-6];
    for it in 0..40 {
        crate::cancel::check()?;
        if r.amax() < 1e-10 {
            return Ok(finish(vehicle, lift, condition, x, r, it));
        }
        // The six residuals of the central differences in parallel, bit for bit.
        let columns = crate::cancel::par_in_order(3, |j| {
            let mut xp = x;
            let mut xm = x;
            xp[j] += h[j];
            xm[j] -= h[j];
            let rp = residual(&xp).map_err(|e| fail(format!("during the search: {e}")))?;
            let rm = residual(&xm).map_err(|e| fail(format!("during the search: {e}")))?;
            Ok((rp - rm) / (2.0 * h[j]))
        })?;
        let jac = Matrix3::from_columns(&columns);
        let Some(mut step) = jac.lu().solve(&(-r)) else {
            return Err(fail(
                "the trim Jacobian is singular (the controls do not affect the balance)".into(),
            ));
        };
        // The lift is flat in the angle of attack near 45 deg (C_l goes as sin 2 alpha) and
        // grows smoothly with the frequency, so a Newton step on those variables can be
        // far too long: cap it at 0.1 rad of angle of attack or 5% of the frequency per
        // iteration.
        let cap = match lift {
            LiftVariable::Amplitude => f64::INFINITY,
            LiftVariable::AngleOfAttack => 0.1,
            LiftVariable::Frequency => 0.05 * vehicle.freq_hz(),
        };
        if step[0].abs() > cap {
            step *= cap / step[0].abs();
        }
        // Damped step: halve until the residual falls (or the controls become valid).
        let mut lambda = 1.0;
        let mut last_error = None;
        loop {
            let cand = x + lambda * step;
            match residual(&cand) {
                Ok(rc) if rc.norm() < r.norm() || lambda < 1e-3 => {
                    x = cand;
                    r = rc;
                    break;
                }
                Ok(_) => {}
                Err(e) => last_error = Some(e),
            }
            lambda *= 0.5;
            if lambda < 1e-4 {
                let stalled = match last_error {
                    Some(e) => format!(
                        "Newton stalled with residual {:.3e}; the last step tried was refused: {e}",
                        r.norm()
                    ),
                    None => format!("Newton stalled with residual {:.3e}", r.norm()),
                };
                let at_limit = explain_limit
                    .then(|| drive_at_limit(vehicle, lift, &x))
                    .flatten();
                return Err(fail(match at_limit {
                    Some((peak_v, limit_v)) => {
                        let needs = match needed_peak_v(vehicle, lift, condition, x) {
                            Some(v) => format!("the balance needs a drive peaking at {v:.1} V"),
                            None => "no balance found even past the limit".to_owned(),
                        };
                        format!(
                            "{needs} and the actuator allows {limit_v} V: at its limit (peak {peak_v:.1} V, {:.2} Hz) the wings lift {:.3} of the weight; {stalled}",
                            vehicle.freq_hz(),
                            1.0 + r[1],
                        )
                    }
                    None => stalled,
                }));
            }
        }
        if !vehicle.drive_controlled() {
            let amp = vehicle.base_kinematics[0].amplitude_rad
                + vehicle.controls.amplitude_rad
                + if lift == LiftVariable::Amplitude {
                    x[0]
                } else {
                    0.0
                };
            if lift == LiftVariable::AngleOfAttack && x[0].abs() > 1.0 {
                return Err(fail(format!(
                    "the search left the allowed range (angle-of-attack offset {:.1} deg of [-57, 57])",
                    x[0].to_degrees()
                )));
            }
            if !(0.0..=std::f64::consts::PI).contains(&amp) || x[1].abs() > 1.0 {
                return Err(fail(format!(
                    "the search left the allowed range (amplitude {:.1} deg of (0, 180], mean stroke offset {:.1} deg of [-57, 57])",
                    amp.to_degrees(),
                    x[1].to_degrees(),
                )));
            }
        }
        if x[2].abs() > 1.5 {
            return Err(fail(format!(
                "the search left the allowed range (body pitch {:.1} deg of [-86, 86])",
                x[2].to_degrees()
            )));
        }
        let _ = it;
    }
    if r.amax() < 1e-7 {
        return Ok(finish(vehicle, lift, condition, x, r, 40));
    }
    Err(fail(format!(
        "Newton did not converge in 40 iterations (residual {:.3e})",
        r.amax()
    )))
}

/// For an actuated vehicle whose drive at trim variables `x` peaks within 0.1% of its
/// actuator's voltage limit: (the largest peak of its wings' drives, the limit), V. A
/// search that stalls there is stopped by the actuator, and its residual there is the
/// balance at the most the actuator can give.
fn drive_at_limit(vehicle: &Vehicle, lift: LiftVariable, x: &Vector3<f64>) -> Option<(f64, f64)> {
    let limit_v = vehicle
        .actuation
        .as_ref()?
        .dynamics
        .stroke
        .voltage_limit_v();
    let peak_v = peak_drive_v(vehicle, &trim_controls(vehicle, lift, x))?;
    (peak_v >= (1.0 - 1e-3) * limit_v).then_some((peak_v, limit_v))
}

/// The largest peak voltage of an actuated vehicle's drives under `controls`, V (`None`
/// for prescribed kinematics or controls its actuator refuses).
fn peak_drive_v(vehicle: &Vehicle, controls: &Controls) -> Option<f64> {
    let drives = vehicle
        .actuation
        .as_ref()?
        .controlled_drives(controls)
        .ok()?;
    Some(drives.iter().map(|d| d.peak_bound_v()).fold(0.0, f64::max))
}

/// The largest peak voltage of the drives at the trim of `vehicle` with its actuator's
/// voltage limit lifted tenfold (searched from `x`), V: what a stalled search's balance
/// needs. `None` when that search fails too.
fn needed_peak_v(
    vehicle: &Vehicle,
    lift: LiftVariable,
    condition: &FlightCondition,
    x: Vector3<f64>,
) -> Option<f64> {
    let mut lifted = vehicle.clone();
    if let Some(a) = lifted.actuation.as_mut()
        && let Stroke::Driven { actuator, .. } = &mut a.dynamics.stroke
    {
        match actuator {
            Actuator::Piezo(p) => p.voltage_limit_v *= 10.0,
            Actuator::DcMotor(m) => m.voltage_limit_v *= 10.0,
        }
    }
    let t = search(&lifted, lift, condition, x, false).ok()?;
    peak_drive_v(&lifted, &t.controls)
}

fn finish(
    vehicle: &Vehicle,
    lift: LiftVariable,
    condition: &FlightCondition,
    x: Vector3<f64>,
    r: Vector3<f64>,
    iterations: usize,
) -> Trim {
    Trim {
        condition: *condition,
        lift_variable: lift,
        controls: trim_controls(vehicle, lift, &x),
        pitch_rad: x[2],
        residual_fx_over_weight: r[0],
        residual_fz_over_weight: r[1],
        residual_my_over_weight_length: r[2],
        iterations,
    }
}

/// The trim variables of `t` as [`trim_from`] takes them (for a vehicle whose controls are
/// those `t` started from).
pub fn trim_variables(vehicle: &Vehicle, t: &Trim) -> Vector3<f64> {
    let lift = match t.lift_variable {
        LiftVariable::Amplitude => {
            (t.controls.amplitude_rad - vehicle.controls.amplitude_rad)
                + (t.controls.amplitude_v - vehicle.controls.amplitude_v)
        }
        LiftVariable::AngleOfAttack => t.controls.aoa_rad - vehicle.controls.aoa_rad,
        LiftVariable::Frequency => t.controls.freq_hz - vehicle.controls.freq_hz,
    };
    let mean = (t.controls.mean_stroke_rad - vehicle.controls.mean_stroke_rad)
        + (t.controls.bias_v - vehicle.controls.bias_v);
    Vector3::new(lift, mean, t.pitch_rad)
}

/// The vehicle at trim: trimmed controls applied, the induced inflow frozen at the trim's
/// flight condition, and the initial attitude and velocity those of the trim.
pub fn trimmed_vehicle(vehicle: &Vehicle, t: &Trim) -> Result<Vehicle> {
    let mut v = vehicle.clone();
    v.apply_controls(&t.controls)?;
    v.freeze_inflow_at(&t.condition, &t.attitude());
    v.initial_attitude = t.attitude();
    v.initial_velocity_m_s = t.condition.velocity_world_m_s();
    v.initial_angular_velocity_rad_s = Vector3::zeros();
    Ok(v)
}
