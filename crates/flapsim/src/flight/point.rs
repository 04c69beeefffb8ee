//! What a trim at a flight condition looks like and costs: the stroke-plane angle, the
//! amplitude, the power, the downwash, and the margin to the limit of the drive.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::flight::power::{Power, power_at};
use crate::model::Vehicle;

/// What a trim at a flight condition costs and looks like.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TrimPoint {
    /// The (first) stroke plane's angle to the horizontal, rad, positive with its normal
    /// tilted forward (Dudley & Ellington 1990a's beta).
    pub stroke_plane_angle_rad: f64,
    /// The wings' stroke amplitude at trim (wing 0), rad.
    pub stroke_amplitude_rad: f64,
    /// The wings' power at trim.
    pub power: Power,
    /// The body's parasite power |D| |V|, W (part of `power`, which pays it).
    pub parasite_power_w: f64,
    /// The induced downwash through the (first) stroke plane at trim, m/s (0 without
    /// `[aero] induced_inflow`).
    pub induced_downwash_m_s: f64,
}

pub use crate::trim::stroke_plane_angle_rad;

/// The stroke-plane angle, amplitude, power and downwash of `vehicle` trimmed at `t`.
pub fn trim_point(vehicle: &Vehicle, t: &crate::trim::Trim) -> Result<TrimPoint> {
    let v = crate::trim::trimmed_vehicle(vehicle, t)?;
    let q = t.attitude();
    let state = crate::averaged::FrozenState {
        world_from_body: q,
        velocity_body_m_s: t.velocity_body_m_s(),
        angular_velocity_body_rad_s: Vector3::zeros(),
    };
    let vel_w = t.condition.velocity_world_m_s();
    let amplitude = match &v.actuation {
        // An actuated wing's amplitude is an output of its dynamics: half the peak-to-peak
        // stroke of its periodic motion.
        Some(_) => {
            let p = crate::actuated::periodic::settle(
                &v,
                &wingforce::BodyMotion {
                    velocity_m_s: state.velocity_body_m_s,
                    angular_velocity_rad_s: Vector3::zeros(),
                },
            )?;
            let (lo, hi) = p.samples.iter().fold((f64::MAX, f64::MIN), |(lo, hi), s| {
                (lo.min(s[0].angles.phi), hi.max(s[0].angles.phi))
            });
            hi - lo
        }
        None => v.wings[0].kinematics().amplitude_rad,
    };
    Ok(TrimPoint {
        stroke_plane_angle_rad: stroke_plane_angle_rad(&v.wings[0], &q),
        stroke_amplitude_rad: amplitude,
        power: power_at(&v, &state, crate::trim::TRIM_SAMPLES)?,
        parasite_power_w: -v.body_drag_world_n(&vel_w).dot(&vel_w),
        induced_downwash_m_s: v.wings[0].induced_downwash_m_s(),
    })
}

/// How far a trim is from the limit of what drives the wings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LimitMargin {
    /// What is limited: `stroke amplitude` (prescribed kinematics, at most 180 deg) or
    /// `drive peak voltage` (an actuated vehicle, the actuator's voltage limit).
    pub quantity: String,
    /// Its value at trim (rad or V).
    pub value: f64,
    /// The limit (rad or V).
    pub limit: f64,
    /// (limit - value) / limit: 0 at the limit, negative beyond it.
    pub fraction: f64,
}

/// The margin of `vehicle` trimmed at `t` (its amplitude from [`TrimPoint`]) to its limit.
pub fn limit_margin(vehicle: &Vehicle, t: &crate::trim::Trim, point: &TrimPoint) -> LimitMargin {
    match &vehicle.actuation {
        Some(a) => {
            let limit = a.dynamics.stroke.voltage_limit_v();
            let value = a
                .controlled_drives(&t.controls)
                .map(|d| d.iter().map(|d| d.peak_bound_v()).fold(0.0, f64::max))
                .unwrap_or(f64::INFINITY);
            LimitMargin {
                quantity: "drive peak voltage".into(),
                value,
                limit,
                fraction: (limit - value) / limit,
            }
        }
        None => {
            let limit = std::f64::consts::PI;
            LimitMargin {
                quantity: "stroke amplitude".into(),
                value: point.stroke_amplitude_rad,
                limit,
                fraction: (limit - point.stroke_amplitude_rad) / limit,
            }
        }
    }
}
