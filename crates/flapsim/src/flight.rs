//! Flight conditions beyond hover: forward flight and climb.
//!
//! A [`FlightCondition`] is the body's steady velocity through still air, world frame: a
//! forward speed U along world x (the vehicle flies nose first, no sideslip: a left-right
//! symmetric vehicle trims in its plane of symmetry) and a climb rate W along world z (up).
//! Hover is U = W = 0. At a condition three things change from hover:
//!
//! - The wings see the body's velocity: the cycle-averaged loads are taken at the frozen
//!   state with that velocity ([`crate::averaged::FrozenState`]).
//! - The body feels parasite drag, 0.5 rho |V| V C_D S against its velocity V, at the centre
//!   of mass, with C_D S the model's `[body] drag_area_m2` (0: none).
//! - The induced inflow (`[aero] induced_inflow`) follows Glauert's momentum theory
//!   ([`wingforce::inflow`]): the wake shed at the condition, frozen there like the hover
//!   downwash, for the force the wings must carry (weight plus body drag).
//!
//! Power ([`Power`]) is what the wings' drive spends against the air: the cycle mean of
//! P(t) = - sum over wings of M_hinge(t) . omega_wing(t) (the aerodynamic moment about each
//! hinge and the wing's angular velocity relative to the body). In steady flight it includes
//! the body's parasite power: the wings push the body against its drag and the drive pays.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use wingforce::wing::WingFrame;
use wingforce::{Wing, WingForces};

use crate::error::{Error, Result};
use crate::model::Vehicle;

/// A steady flight condition: see the module documentation.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct FlightCondition {
    /// Forward speed through the air along world x, m/s (>= 0).
    pub forward_speed_m_s: f64,
    /// Climb rate along world z (up), m/s (negative: descent).
    pub climb_rate_m_s: f64,
}

impl FlightCondition {
    /// Hover.
    pub const HOVER: FlightCondition = FlightCondition {
        forward_speed_m_s: 0.0,
        climb_rate_m_s: 0.0,
    };

    /// A condition, or an error naming the value and what is allowed (a forward speed finite
    /// and >= 0, at most 100 m/s; a finite climb rate within +-100 m/s).
    pub fn new(forward_speed_m_s: f64, climb_rate_m_s: f64) -> Result<Self> {
        if !(forward_speed_m_s.is_finite() && (0.0..=100.0).contains(&forward_speed_m_s)) {
            return Err(Error::Input(format!(
                "forward speed {forward_speed_m_s} m/s; allowed: a finite speed in [0, 100] m/s (the vehicle flies nose first along world x)"
            )));
        }
        if !(climb_rate_m_s.is_finite() && climb_rate_m_s.abs() <= 100.0) {
            return Err(Error::Input(format!(
                "climb rate {climb_rate_m_s} m/s; allowed: a finite rate in [-100, 100] m/s (negative descends)"
            )));
        }
        Ok(Self {
            forward_speed_m_s,
            climb_rate_m_s,
        })
    }

    /// Hover (both velocities zero).
    pub fn is_hover(&self) -> bool {
        self.forward_speed_m_s == 0.0 && self.climb_rate_m_s == 0.0
    }

    /// The body's velocity through the air, world frame, m/s.
    pub fn velocity_world_m_s(&self) -> Vector3<f64> {
        Vector3::new(self.forward_speed_m_s, 0.0, self.climb_rate_m_s)
    }

    /// "hover" or "3.00 m/s forward, 0.50 m/s climb" for messages.
    pub fn describe(&self) -> String {
        if self.is_hover() {
            "hover".into()
        } else {
            format!(
                "{:.2} m/s forward, {:.2} m/s climb",
                self.forward_speed_m_s, self.climb_rate_m_s
            )
        }
    }
}

impl Vehicle {
    /// The body's parasite drag for a velocity `velocity_world_m_s` through the air, world
    /// frame, N (zero without `[body] drag_area_m2`).
    pub fn body_drag_world_n(&self, velocity_world_m_s: &Vector3<f64>) -> Vector3<f64> {
        if self.body_drag_area_m2 == 0.0 {
            return Vector3::zeros();
        }
        let rho = self.wings[0].fluid().density_kg_m3;
        -0.5 * rho * self.body_drag_area_m2 * velocity_world_m_s.norm() * velocity_world_m_s
    }

    /// Whether the wings carry an induced inflow (`[aero] induced_inflow`).
    pub fn has_induced_inflow(&self) -> bool {
        self.wings
            .iter()
            .any(|w| w.options().induced_inflow.is_some())
    }

    /// Freezes the wings' induced inflow at a flight condition: the body moving at
    /// `velocity_body_m_s` (body frame) through the air while the wings carry
    /// `required_force_n` in all (shared equally). Hover (zero velocity) keeps the model's
    /// own hover inflow untouched.
    pub fn set_flight_inflow(&mut self, velocity_body_m_s: &Vector3<f64>, required_force_n: f64) {
        if *velocity_body_m_s == Vector3::zeros() {
            return;
        }
        let n = self.wings.len() as f64;
        for w in self.wings.iter_mut() {
            let Some(mut inflow) = w.options().induced_inflow else {
                continue;
            };
            inflow.thrust_n = required_force_n / n;
            inflow.flight_velocity_body_m_s = (*velocity_body_m_s).into();
            let mut options = w.options().clone();
            options.induced_inflow = Some(inflow);
            w.set_options(options);
        }
    }

    /// Refuses conditions outside momentum theory: an axial descent faster than half the
    /// hover downwash w_h enters the vortex-ring state (Johnson 1980, *Helicopter Theory*,
    /// section 4.2: momentum theory has no valid solution for -2 w_h < V_c < 0 and is unreliable
    /// from about -0.5 w_h), unless the forward speed exceeds w_h and carries the wake away.
    pub fn check_flight_condition(&self, condition: &FlightCondition) -> Result<()> {
        if !self.has_induced_inflow() || condition.climb_rate_m_s >= 0.0 {
            return Ok(());
        }
        let w_h = self.wings[0].induced_downwash_m_s();
        if -condition.climb_rate_m_s > 0.5 * w_h && condition.forward_speed_m_s < w_h {
            return Err(Error::Input(format!(
                "`{}` at {}: a descent faster than half the hover downwash ({:.3} m/s) at a forward speed below it ({w_h:.3} m/s) is the vortex-ring state, outside the momentum theory of the induced inflow; allowed: climb rate >= {:.3} m/s here, or a forward speed >= {w_h:.3} m/s",
                self.name,
                condition.describe(),
                0.5 * w_h,
                -0.5 * w_h,
            )));
        }
        Ok(())
    }
}

/// Power a set of wings spends against the air over one wingbeat.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Power {
    /// Cycle-mean aerodynamic power, W: negative work stored and returned (perfect elastic
    /// storage).
    pub aero_w: f64,
    /// Cycle mean of the positive part of each wing's power, W: negative work lost (no
    /// elastic storage), the other bound Dudley & Ellington (1990b) report.
    pub aero_positive_w: f64,
}

/// One wing's instantaneous aerodynamic power, W: - M_hinge . omega_wing (the moment of its
/// aerodynamic force about the hinge and its angular velocity relative to the body, body
/// axes).
pub fn wing_power_w(wing: &Wing, forces: &WingForces) -> f64 {
    let omega_body =
        wing.body_from_stroke() * WingFrame::new(&forces.angles, wing.mount().side).omega;
    -forces.total.moment_hinge_nm.dot(&omega_body)
}

/// The power of `wings` over equally weighted samples of a wingbeat, each sample holding
/// every wing's forces in the wings' order.
pub fn cycle_power<'a, S>(wings: &[Wing], samples: impl ExactSizeIterator<Item = &'a S>) -> Power
where
    S: AsRef<[WingForces]> + 'a,
{
    let w = 1.0 / samples.len().max(1) as f64;
    let mut out = Power::default();
    for forces in samples {
        for (wing, f) in wings.iter().zip(forces.as_ref()) {
            let p = wing_power_w(wing, f);
            out.aero_w += w * p;
            out.aero_positive_w += w * p.max(0.0);
        }
    }
    out
}

/// The wings' power over one wingbeat at a frozen body state: `steps` samples of the
/// prescribed kinematics, or an actuated vehicle's periodic motion at that state
/// ([`crate::actuated::periodic`], at the simulation's step).
pub fn power_at(
    vehicle: &Vehicle,
    state: &crate::averaged::FrozenState,
    steps: usize,
) -> Result<Power> {
    let motion = wingforce::BodyMotion {
        velocity_m_s: state.velocity_body_m_s,
        angular_velocity_rad_s: state.angular_velocity_body_rad_s,
    };
    if vehicle.actuation.is_some() {
        let p = crate::actuated::periodic::settle(vehicle, &motion)?;
        return Ok(cycle_power(&p.wings, p.samples.iter()));
    }
    let samples: Vec<Vec<WingForces>> = (0..steps)
        .map(|k| {
            let phase = k as f64 / steps as f64;
            vehicle
                .wings
                .iter()
                .map(|w| w.evaluate(phase, &motion))
                .collect()
        })
        .collect();
    Ok(cycle_power(&vehicle.wings, samples.iter()))
}

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

/// The stroke plane's angle to the horizontal of `wing` on a body at `world_from_body`, rad
/// (positive: its normal tilted forward, towards world x).
pub fn stroke_plane_angle_rad(wing: &Wing, world_from_body: &nalgebra::UnitQuaternion<f64>) -> f64 {
    let n = world_from_body * (wing.body_from_stroke() * Vector3::z());
    n.x.atan2(n.z)
}

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
