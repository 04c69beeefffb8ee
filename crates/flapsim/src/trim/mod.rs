//! Hover trim: the stroke amplitude (weight support), mean stroke angle (pitch-moment
//! balance) and body pitch (no net horizontal force) at which the cycle-averaged forces and
//! moments balance, found by Newton's method with finite-difference Jacobians. An actuated
//! vehicle trims the same way on its drive: amplitude and bias voltage in place of stroke
//! amplitude and mean stroke angle ([`Vehicle::control_channels`]), with its wings run into
//! their periodic motion at every evaluation ([`crate::actuated::periodic`]).

use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::averaged::{FrozenState, mean_loads};
use crate::error::{Error, Result};
use crate::model::{Controls, Vehicle};

pub mod spec;

/// Phases averaged per evaluation.
pub const TRIM_SAMPLES: usize = 200;

pub use spec::{LiftVariable, TrimSpec};

/// A hover trim.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Trim {
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

fn residual(vehicle: &Vehicle, lift: LiftVariable, x: &Vector3<f64>) -> Result<Vector3<f64>> {
    let mut v = vehicle.clone();
    v.apply_controls(&trim_controls(vehicle, lift, x))?;
    let q = attitude_for_pitch(x[2]);
    let m = mean_loads(
        &v,
        &FrozenState {
            world_from_body: q,
            velocity_body_m_s: Vector3::zeros(),
            angular_velocity_body_rad_s: Vector3::zeros(),
        },
        TRIM_SAMPLES,
    )?;
    let f = q * m.total.force_n;
    let w = v.weight_n();
    let r_wing = v.wings[0].geometry().r_tip_m;
    Ok(Vector3::new(
        f.x / w,
        f.z / w - 1.0,
        m.total.moment_nm.y / (w * r_wing),
    ))
}

/// Finds the hover trim of `vehicle` on the lift variable its model file names (`[trim]`),
/// starting from its current controls and initial pitch.
pub fn trim(vehicle: &Vehicle) -> Result<Trim> {
    trim_on(vehicle, vehicle.trim_lift)
}

/// Finds the hover trim of `vehicle` varying `lift` to carry the weight.
pub fn trim_on(vehicle: &Vehicle, lift: LiftVariable) -> Result<Trim> {
    if vehicle.drive_controlled() && lift != LiftVariable::Amplitude {
        return Err(Error::Analysis(format!(
            "no hover trim for `{}` on the {}: an actuated vehicle trims its drive amplitude (lift variable `amplitude`)",
            vehicle.name,
            lift.name()
        )));
    }
    let (_, p0, _) = vehicle.initial_attitude.euler_angles();
    let mut x = Vector3::new(0.0, 0.0, -p0);
    let fail =
        |why: String| Error::Analysis(format!("no hover trim for `{}`: {why}", vehicle.name));
    let mut r =
        residual(vehicle, lift, &x).map_err(|e| fail(format!("at the starting controls: {e}")))?;
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
        if r.amax() < 1e-10 {
            return Ok(finish(vehicle, lift, x, r, it));
        }
        let mut jac = Matrix3::zeros();
        for j in 0..3 {
            let mut xp = x;
            let mut xm = x;
            xp[j] += h[j];
            xm[j] -= h[j];
            let rp = residual(vehicle, lift, &xp)
                .map_err(|e| fail(format!("during the search: {e}")))?;
            let rm = residual(vehicle, lift, &xm)
                .map_err(|e| fail(format!("during the search: {e}")))?;
            jac.set_column(j, &((rp - rm) / (2.0 * h[j])));
        }
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
            match residual(vehicle, lift, &cand) {
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
                return Err(fail(match last_error {
                    Some(e) => format!(
                        "Newton stalled with residual {:.3e}; the last step tried was refused: {e}",
                        r.norm()
                    ),
                    None => format!("Newton stalled with residual {:.3e}", r.norm()),
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
        return Ok(finish(vehicle, lift, x, r, 40));
    }
    Err(fail(format!(
        "Newton did not converge in 40 iterations (residual {:.3e})",
        r.amax()
    )))
}

fn finish(
    vehicle: &Vehicle,
    lift: LiftVariable,
    x: Vector3<f64>,
    r: Vector3<f64>,
    iterations: usize,
) -> Trim {
    Trim {
        lift_variable: lift,
        controls: trim_controls(vehicle, lift, &x),
        pitch_rad: x[2],
        residual_fx_over_weight: r[0],
        residual_fz_over_weight: r[1],
        residual_my_over_weight_length: r[2],
        iterations,
    }
}

/// The vehicle at trim: trimmed controls applied and the initial attitude set to the trim pitch.
pub fn trimmed_vehicle(vehicle: &Vehicle, t: &Trim) -> Result<Vehicle> {
    let mut v = vehicle.clone();
    v.apply_controls(&t.controls)?;
    v.initial_attitude = t.attitude();
    v.initial_velocity_m_s = Vector3::zeros();
    v.initial_angular_velocity_rad_s = Vector3::zeros();
    Ok(v)
}
