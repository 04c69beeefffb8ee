//! The wing's dynamic model: its mass properties, the pitch hinge, what moves the stroke,
//! and the stroke system's stiffness, inertia and natural frequencies (the parameters the
//! equations in [`super`] are written in).

use serde::{Deserialize, Serialize};
use wingforce::Kinematics;

use super::super::actuator::Actuator;
use super::super::stop::StopContact;

/// The wing's mass properties about its hinge.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WingInertia {
    /// Mass m, kg.
    pub mass_kg: f64,
    /// J = int r^2 dm about the stroke axis with the wing normal to the stroke plane
    /// (wing and spar), kg m^2.
    pub stroke_inertia_kg_m2: f64,
    /// B = int x^2 dm about the pitch axis, kg m^2.
    pub pitch_inertia_kg_m2: f64,
    /// Spanwise position of the centre of mass from the stroke axis r_c, m.
    pub com_span_m: f64,
    /// Chordwise position of the centre of mass from the pitch axis x_c, positive towards
    /// the leading edge (negative: behind the axis, which makes pitch lag the stroke), m.
    pub com_chord_m: f64,
}

impl WingInertia {
    /// The product of inertia C = int r x dm, lumped as m r_c x_c, kg m^2.
    pub fn product_kg_m2(&self) -> f64 {
        self.mass_kg * self.com_span_m * self.com_chord_m
    }
}

/// The pitch hinge: a torsional spring and damper (either may be zero), optional contact
/// stops ([`StopContact`]) and a break limit.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Hinge {
    /// Torsional stiffness k_h, N m/rad (zero: the wing swings freely between its stops).
    pub stiffness_nm_rad: f64,
    /// Torsional damping c_h, N m s/rad.
    pub damping_nm_s_rad: f64,
    /// Rest angle theta_r (pi/2: the wing normal to the stroke plane), rad.
    pub rest_rad: f64,
    /// Where the hinge breaks (a flexure past its limit): |theta - theta_r| beyond this
    /// ends the run with an error, rad (infinite: no such limit).
    pub break_rad: f64,
    /// Mechanical stops the wing strikes (none: the hinge has no stops, only its break
    /// limit).
    pub contact: Option<StopContact>,
}

impl Hinge {
    /// The hinge's moment on the wing about the pitch axis, N m: spring, damper and, when
    /// the wing presses into a stop, the stop (`m_eff`: the effective pitch inertia that
    /// sets the stop's damping, see [`super::stop`]).
    ///
    /// [`super::stop`]: crate::actuated::stop
    pub fn moment_nm(&self, theta_rad: f64, theta_dot_rad_s: f64, m_eff_kg_m2: f64) -> f64 {
        let d = theta_rad - self.rest_rad;
        let stop = self
            .contact
            .map_or(0.0, |c| c.moment_nm(d, theta_dot_rad_s, m_eff_kg_m2));
        -self.stiffness_nm_rad * d - self.damping_nm_s_rad * theta_dot_rad_s + stop
    }
}

/// What moves the stroke.
#[derive(Debug, Clone, PartialEq)]
pub enum Stroke {
    /// An actuator through a transmission with a flexure (or stroke spring).
    Driven {
        /// The actuator.
        actuator: Actuator,
        /// Transmission flexure / stroke spring stiffness about the stroke axis k_t, N m/rad.
        flexure_nm_rad: f64,
        /// Extra viscous damping about the stroke axis (bearings, flexure), N m s/rad.
        damping_nm_s_rad: f64,
        /// Stroke angle where the springs are relaxed phi_0, rad.
        rest_rad: f64,
    },
    /// Stroke prescribed by kinematics (pitch still passive), as in passive-pitch
    /// experiments and CFD studies that drive the stroke and let the wing pitch.
    Prescribed(Kinematics),
}

impl Stroke {
    /// The actuator's voltage limit (infinite for a prescribed stroke), V.
    pub fn voltage_limit_v(&self) -> f64 {
        match self {
            Stroke::Driven { actuator, .. } => actuator.voltage_limit_v(),
            Stroke::Prescribed(_) => f64::INFINITY,
        }
    }
}

/// A wing's dynamic model.
#[derive(Debug, Clone, PartialEq)]
pub struct WingDynamics {
    /// Mass properties.
    pub inertia: WingInertia,
    /// The pitch hinge.
    pub hinge: Hinge,
    /// The stroke's drive.
    pub stroke: Stroke,
    /// Sub-steps per body step (>= 1).
    pub substeps: usize,
    /// Couple the aerodynamic loads (off for structural tests).
    pub aero: bool,
}

impl WingDynamics {
    /// Stroke-axis inertia with the wing normal to the stroke plane, J + J_a, kg m^2.
    pub fn stroke_inertia_kg_m2(&self) -> f64 {
        let ja = match &self.stroke {
            Stroke::Driven { actuator, .. } => actuator.reflected().inertia_kg_m2,
            Stroke::Prescribed(_) => 0.0,
        };
        self.inertia.stroke_inertia_kg_m2 + ja
    }

    /// Stroke-axis stiffness k_a + k_t, N m/rad (zero for a prescribed stroke).
    pub fn stroke_stiffness_nm_rad(&self) -> f64 {
        match &self.stroke {
            Stroke::Driven {
                actuator,
                flexure_nm_rad,
                ..
            } => actuator.reflected().stiffness_nm_rad + flexure_nm_rad,
            Stroke::Prescribed(_) => 0.0,
        }
    }

    /// Undamped natural frequency of the stroke system,
    /// f_n = (1/2 pi) sqrt((k_a + T^2 k_t) / (m_a + T^2 J)) for a piezo (the same as
    /// sqrt(k / J) about the stroke axis), Hz.
    pub fn stroke_natural_freq_hz(&self) -> f64 {
        (self.stroke_stiffness_nm_rad() / self.stroke_inertia_kg_m2()).sqrt()
            / (2.0 * std::f64::consts::PI)
    }

    /// Natural frequency of the pitch mode with the stroke held, sqrt(k_h / B) / 2 pi, Hz.
    pub fn pitch_natural_freq_hz(&self) -> f64 {
        (self.hinge.stiffness_nm_rad / self.inertia.pitch_inertia_kg_m2).sqrt()
            / (2.0 * std::f64::consts::PI)
    }
}
