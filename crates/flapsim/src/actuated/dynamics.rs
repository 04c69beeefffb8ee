//! One wing as a two-degree-of-freedom system: stroke phi driven by an actuator (or
//! prescribed), pitch theta free about a compliant hinge, deviation prescribed at zero.
//!
//! # Equations of motion
//! The wing is a thin rigid plate with mass m, centre of mass at span r_c and chordwise x_c
//! (towards the leading edge) from the hinge, inertia J = int r^2 dm about the stroke axis
//! with the wing normal to the stroke plane, B = int x^2 dm about the pitch axis, and the
//! product C = int r x dm, lumped as m r_c x_c. Its kinetic energy about the hinge, with
//! omega = phi_dot k_phi + theta_dot k_theta ([`wingforce::WingFrame`]), is
//!
//!   T = 1/2 B theta_dot^2 + 1/2 (J + B cos^2 theta) phi_dot^2 - C sin(theta) phi_dot theta_dot
//!
//! and Lagrange's equations with the actuator reflected to the stroke axis (inertia J_a,
//! stiffness k_a + k_t, damping c_s, torque per volt g; see [`super::actuator`]) and the
//! hinge (stiffness k_h, damping c_h, rest angle theta_r) are
//!
//!   (J + J_a + B cos^2 theta) phi_ddot - C sin(theta) theta_ddot
//!       - 2 B sin(theta) cos(theta) phi_dot theta_dot - C cos(theta) theta_dot^2
//!       = g V(t) - (k_a + k_t)(phi - phi_0) - c_s phi_dot + Q_phi,aero
//!   B theta_ddot - C sin(theta) phi_ddot + B sin(theta) cos(theta) phi_dot^2
//!       = -k_h (theta - theta_r) - c_h theta_dot + Q_theta,aero
//!
//! where Q_aero are wingforce's four terms projected on the two axes
//! ([`wingforce::Wing::axis_moments`]), evaluated with the wing's actual angles and rates,
//! and the hinge's moment includes its stops' contact when it has them ([`super::stop`]).
//! A prescribed stroke keeps only the second equation, with phi(t) from the kinematics.
//!
//! Re-derived (issue 24). For a thin plate with points r = s e_span + x e_le about the
//! hinge, the inertia tensor is I = int (|r|^2 1 - r r^T) dm, that is
//! (J + B) 1 - J e_s e_s^T - B e_l e_l^T - C (e_s e_l^T + e_l e_s^T). With
//! [`wingforce::WingFrame`]'s axes k_phi = (0, 0, -s), k_theta = -s e_span and
//! e_le = cos(theta) t + sin(theta) z (s = +-1 by side): omega . e_span = -s theta_dot,
//! omega . e_le = -s sin(theta) phi_dot and |omega|^2 = phi_dot^2 + theta_dot^2, so
//! omega^T I omega / 2 is T above on both sides (s^2 = 1). The B cos^2 theta term is the
//! plate's inertia about the stroke axis growing from J (wing normal to the stroke plane)
//! to J + B (wing flat); the product term has the sign written, and C < 0 (centre of mass
//! behind the axis) makes the trailing edge lag the stroke's acceleration. Lagrange's
//! equations of T give the two equations term by term (the time derivatives of
//! p_phi = (J + B cos^2) phi_dot - C sin theta_dot and p_theta = B theta_dot - C sin
//! phi_dot, and dT/dtheta = -B sin cos phi_dot^2 - C cos phi_dot theta_dot): the
//! equations and the code were right, nothing changed. Checked in `tests/wing_inertia.rs`:
//! without drive, damping and aerodynamics the energy is kept to 3e-12 and, with no stroke
//! spring (phi cyclic), p_phi to 9e-13 over 20 000 steps of large coupled motion; a 1 deg
//! prescribed sinusoidal stroke drives the pitch as B psi_dd + c_h psi_d + k_h psi = C phi_dd
//! says, to 1e-4 in amplitude and 1e-4 deg in phase, for the centre of mass on either side
//! of the axis.
//!
//! # Integrator
//! Each body step of length dt is split into `substeps` equal sub-steps. At the start of a
//! sub-step the aerodynamic loads are evaluated once (the translational strip loop runs
//! there, at the current angles, rates and body motion) and held over the sub-step; the
//! added mass, which is proportional to the angular accelerations, is not held but moved to
//! the inertia side as the matrix A of [`wingforce::Wing::added_inertia`] (holding it would
//! be unstable once A rivals the wing's own inertia). The structural equations above are
//! then advanced by the classical fourth-order Runge-Kutta method over the sub-step. So the
//! structure (inertia, springs, actuator, drive) is integrated to fourth order and the
//! aerodynamic coupling to first order in the sub-step, the same zero-order hold the body
//! itself gets from the simulator. The tests bound both: without aerodynamics the stroke
//! and pitch modes keep their analytic frequency to 0.5% and their energy to 1e-6 over 100
//! periods at 100 steps per period; with aerodynamics, halving the sub-step changes the
//! mean lift by well under 1%.
//!
//! Hinge stops are stiff: near or in a stop the sub-step is cut into contact steps, with the
//! touch and the clamp's onset located within them ([`super::stop`] states how and what it
//! costs). A strike also changes the pitch rate within microseconds, which the loads
//! reported at a step's start would sample at random: with stops, a step reports its mean
//! motion instead (angles at mid-step, the mean rates and accelerations over the step, the
//! loads evaluated there; the mean accelerations make the inertial and added-mass impulses
//! over the step exact). Without stops a step reports its start, as before.
//!
//! Neglected: the body's own acceleration and rotation in the wing's equations (the wing
//! reacts on the body, the body does not shake the wing), the actuator's reaction other
//! than its reflected inertia about the stroke axis, and gravity on the wing.

use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};
use wingforce::{
    AxisMoments, BodyMotion, Kinematics, StrokePhase, StrokeReference, Wing, WingAngles,
    WingForces, WingFrame,
};

use super::actuator::{Actuator, ActuatorState};
use super::drive::Drive;
use super::stop::StopContact;
use crate::error::{Error, Result};

/// Deepest penetration into a contact stop before a run stops with an error, rad (10 deg):
/// a stop is meant to be stiff, so a wing this deep in it says the contact is too soft for
/// the loads, not anything about the robot.
pub const MAX_PENETRATION_RAD: f64 = 10.0 * std::f64::consts::PI / 180.0;

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

/// The dynamic state of a wing.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct WingState {
    /// Stroke angle phi, rad.
    pub phi_rad: f64,
    /// Pitch angle theta, rad.
    pub theta_rad: f64,
    /// Stroke rate, rad/s.
    pub phi_dot_rad_s: f64,
    /// Pitch rate, rad/s.
    pub theta_dot_rad_s: f64,
}

/// What one step of a dynamic wing produced (at the step's start).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WingStep {
    /// The aerodynamic forces at the step's start (zero when aerodynamics is off), except
    /// the impulse-form added mass: its mean over the step, the change of the fluid's
    /// impulse across it over dt (see [`DynamicWing::step`]).
    pub forces: WingForces,
    /// Their moments about the stroke and pitch axes, N m.
    pub aero_axis: AxisMoments,
    /// Hinge spring, damper and stop moment on the wing about the pitch axis, N m.
    pub hinge_moment_nm: f64,
    /// Inertial reaction of the wing and actuator on the body, body frame: force N and
    /// moment about the hinge N m.
    pub inertial_force_n: Vector3<f64>,
    /// See `inertial_force_n`.
    pub inertial_moment_hinge_nm: Vector3<f64>,
    /// The actuator's state.
    pub actuator: ActuatorState,
    /// Angles, rates and accelerations at the step's start.
    pub angles: WingAngles,
}

/// The state of an actuated wing that a step reports (for logs and analyses).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct ActuatedWingOutput {
    /// Angles, rates and accelerations.
    pub angles: WingAngles,
    /// Hinge spring, damper and stop moment on the wing about the pitch axis, N m.
    pub hinge_moment_nm: f64,
    /// Aerodynamic moment about the pitch axis, N m.
    pub aero_pitch_nm: f64,
    /// Aerodynamic moment about the stroke axis, N m.
    pub aero_stroke_nm: f64,
    /// The actuator's state.
    pub actuator: ActuatorState,
}

impl WingStep {
    /// The part of the step a log or an analysis keeps.
    pub fn output(&self) -> ActuatedWingOutput {
        ActuatedWingOutput {
            angles: self.angles,
            hinge_moment_nm: self.hinge_moment_nm,
            aero_pitch_nm: self.aero_axis.pitch_nm,
            aero_stroke_nm: self.aero_axis.stroke_nm,
            actuator: self.actuator,
        }
    }
}

/// A wing whose angles are integrated in time.
#[derive(Debug, Clone)]
pub struct DynamicWing {
    model: WingDynamics,
    drive: Drive,
    state: WingState,
    t_s: f64,
    last_reversal_s: f64,
    half_stroke: i64,
    downstroke: bool,
    /// (t, phi_dot) over the current drive period, to measure the stroke reference.
    samples: Vec<(f64, f64)>,
    period_index: i64,
}

/// The state, time and stroke phase at a step's start (what its report describes).
#[derive(Debug, Clone, Copy)]
struct StepStart {
    state: WingState,
    t_s: f64,
    phase: StrokePhase,
}

/// Held over a sub-step: aerodynamic generalized forces without the added mass's
/// acceleration part, and the added inertia.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Held {
    pub(super) q: [f64; 2],
    pub(super) added: [[f64; 2]; 2],
    /// Integrate as if the hinge had no stops (the contact-free part of a step that
    /// touches one).
    pub(super) free: bool,
}

impl DynamicWing {
    /// A wing at rest at the springs' rest angles (or on its prescribed stroke at t = 0).
    pub fn new(model: WingDynamics, drive: Drive) -> Result<Self> {
        let phi0 = match &model.stroke {
            Stroke::Driven { rest_rad, .. } => *rest_rad,
            Stroke::Prescribed(k) => k.angles(0.0).phi,
        };
        let state = WingState {
            phi_rad: phi0,
            theta_rad: model.hinge.rest_rad,
            phi_dot_rad_s: 0.0,
            theta_dot_rad_s: 0.0,
        };
        let mut w = Self {
            model,
            drive,
            state,
            t_s: 0.0,
            last_reversal_s: 0.0,
            half_stroke: 0,
            downstroke: true,
            samples: Vec::new(),
            period_index: 0,
        };
        w.set_drive(drive)?;
        Ok(w)
    }

    /// Changes the drive (voltage past the actuator's limit is an error).
    pub fn set_drive(&mut self, drive: Drive) -> Result<()> {
        if let Stroke::Driven { actuator, .. } = &self.model.stroke {
            let lim = actuator.voltage_limit_v();
            if !(drive.peak_bound_v() <= lim) || !(drive.freq_hz > 0.0) {
                return Err(Error::Analysis(format!(
                    "drive of {} V bias, {} V amplitude (second harmonic {}) at {} Hz: peak |V| up to {:.1} V, the {} allows |V| <= {lim} V and a frequency > 0",
                    drive.bias_v,
                    drive.amplitude_v,
                    drive.second_harmonic,
                    drive.freq_hz,
                    drive.peak_bound_v(),
                    actuator.kind()
                )));
            }
        }
        self.drive = drive;
        Ok(())
    }

    /// Sets the state (angles and rates) directly.
    pub fn set_state(&mut self, state: WingState) {
        self.state = state;
    }

    /// The state now.
    pub fn state(&self) -> WingState {
        self.state
    }

    /// Time now, s.
    pub fn t_s(&self) -> f64 {
        self.t_s
    }

    /// The model.
    pub fn model(&self) -> &WingDynamics {
        &self.model
    }

    /// The drive.
    pub fn drive(&self) -> &Drive {
        &self.drive
    }

    /// Mechanical energy (kinetic plus the springs', the stops' contact springs included),
    /// J: conserved without aerodynamics, damping, drive and stop strikes (or with
    /// perfectly elastic ones).
    pub fn energy_j(&self) -> f64 {
        let s = &self.state;
        let m = self.mass_matrix(s.theta_rad, &[[0.0; 2]; 2]);
        let v = [s.phi_dot_rad_s, s.theta_dot_rad_s];
        let ke =
            0.5 * (m[0][0] * v[0] * v[0] + 2.0 * m[0][1] * v[0] * v[1] + m[1][1] * v[1] * v[1]);
        let k = self.model.stroke_stiffness_nm_rad();
        let phi0 = self.stroke_rest();
        let dth = s.theta_rad - self.model.hinge.rest_rad;
        let stop = self.model.hinge.contact.map_or(0.0, |c| c.potential_j(dth));
        ke + 0.5 * k * (s.phi_rad - phi0).powi(2)
            + 0.5 * self.model.hinge.stiffness_nm_rad * dth * dth
            + stop
    }

    fn stroke_rest(&self) -> f64 {
        match &self.model.stroke {
            Stroke::Driven { rest_rad, .. } => *rest_rad,
            Stroke::Prescribed(_) => 0.0,
        }
    }

    /// Inertia matrix about (phi, theta) plus the added inertia.
    pub(super) fn mass_matrix(&self, theta: f64, added: &[[f64; 2]; 2]) -> [[f64; 2]; 2] {
        let i = &self.model.inertia;
        let (st, ct) = theta.sin_cos();
        let c = i.product_kg_m2();
        let b = i.pitch_inertia_kg_m2;
        [
            [
                self.model.stroke_inertia_kg_m2() + b * ct * ct + added[0][0],
                -c * st + added[0][1],
            ],
            [-c * st + added[1][0], b + added[1][1]],
        ]
    }

    /// The effective pitch inertia a stop strike meets, kg m^2: M_tt - M_tp^2 / M_pp with
    /// the stroke free (driven), M_tt with the stroke prescribed.
    pub(super) fn pitch_inertia_effective(&self, m: &[[f64; 2]; 2]) -> f64 {
        match &self.model.stroke {
            Stroke::Driven { .. } => m[1][1] - m[0][1] * m[1][0] / m[0][0],
            Stroke::Prescribed(_) => m[1][1],
        }
    }

    /// Accelerations at time t for y = (phi, theta, phi_dot, theta_dot).
    pub(super) fn accelerations(&self, t: f64, y: &[f64; 4], held: &Held) -> [f64; 2] {
        let [phi, theta, mut pd, td] = *y;
        let prescribed = match &self.model.stroke {
            Stroke::Prescribed(k) => {
                let a = k.angles(t * k.freq_hz);
                pd = a.phi_dot;
                Some(a)
            }
            Stroke::Driven { .. } => None,
        };
        let i = &self.model.inertia;
        let (st, ct) = theta.sin_cos();
        let b = i.pitch_inertia_kg_m2;
        let c = i.product_kg_m2();
        let m = self.mass_matrix(theta, &held.added);
        let m_eff = self.pitch_inertia_effective(&m);
        let hinge = if held.free {
            Hinge {
                contact: None,
                ..self.model.hinge
            }
        } else {
            self.model.hinge
        };
        let q_theta = held.q[1] + hinge.moment_nm(theta, td, m_eff) - b * st * ct * pd * pd;
        match &self.model.stroke {
            Stroke::Driven {
                actuator,
                flexure_nm_rad,
                damping_nm_s_rad,
                rest_rad,
            } => {
                let r = actuator.reflected();
                let q_phi = held.q[0] + r.torque_per_volt_nm_v * self.drive.voltage_v(t)
                    - (r.stiffness_nm_rad + flexure_nm_rad) * (phi - rest_rad)
                    - (r.damping_nm_s_rad + damping_nm_s_rad) * pd
                    + 2.0 * b * st * ct * pd * td
                    + c * ct * td * td;
                let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
                [
                    (m[1][1] * q_phi - m[0][1] * q_theta) / det,
                    (m[0][0] * q_theta - m[1][0] * q_phi) / det,
                ]
            }
            Stroke::Prescribed(_) => {
                let a = prescribed.unwrap_or_default();
                [a.phi_ddot, (q_theta - m[1][0] * a.phi_ddot) / m[1][1]]
            }
        }
    }

    /// Angles at the current time with the given accelerations (prescribed stroke: from the
    /// kinematics).
    fn angles(&self, acc: [f64; 2]) -> WingAngles {
        self.angles_at(&self.state, self.t_s, acc)
    }

    /// Angles of `state` at time `t` with the given accelerations.
    fn angles_at(&self, s: &WingState, t: f64, acc: [f64; 2]) -> WingAngles {
        let mut a = WingAngles {
            phi: s.phi_rad,
            theta: s.theta_rad,
            phi_dot: s.phi_dot_rad_s,
            theta_dot: s.theta_dot_rad_s,
            phi_ddot: acc[0],
            theta_ddot: acc[1],
            ..WingAngles::default()
        };
        if let Stroke::Prescribed(k) = &self.model.stroke {
            let p = k.angles(t * k.freq_hz);
            a.phi = p.phi;
            a.phi_dot = p.phi_dot;
            a.phi_ddot = p.phi_ddot;
        }
        a
    }

    fn stroke_phase(&self) -> StrokePhase {
        StrokePhase {
            half_stroke: self.half_stroke,
            t_star: (self.t_s - self.last_reversal_s) * self.drive.freq_hz,
            downstroke: self.downstroke,
        }
    }

    /// Aerodynamic loads at the current state with zero accelerations (so the added-mass
    /// term holds only its velocity part), and the added inertia.
    fn aero_held(&self, wing: &Wing, body: &BodyMotion) -> (Held, Option<(WingForces, WingFrame)>) {
        let at = StepStart {
            state: self.state,
            t_s: self.t_s,
            phase: self.stroke_phase(),
        };
        self.aero_at(wing, body, &at)
    }

    /// [`Self::aero_held`] at a given state, time and stroke phase.
    fn aero_at(
        &self,
        wing: &Wing,
        body: &BodyMotion,
        at: &StepStart,
    ) -> (Held, Option<(WingForces, WingFrame)>) {
        if !self.model.aero {
            return (Held::default(), None);
        }
        let a = self.angles_at(&at.state, at.t_s, [0.0, 0.0]);
        let side = wing.mount().side;
        let frame = WingFrame::new(&a, side);
        let k = wing.kinematic_loads_in(&a, &at.phase, &frame);
        let f = wing.evaluate_with(&k, body);
        let q = wing.axis_moments(&frame, &f.total);
        (
            Held {
                q: [q.stroke_nm, q.pitch_nm],
                added: wing.added_inertia(&frame),
                free: false,
            },
            Some((f, frame)),
        )
    }

    fn y(&self) -> [f64; 4] {
        let s = &self.state;
        [s.phi_rad, s.theta_rad, s.phi_dot_rad_s, s.theta_dot_rad_s]
    }

    /// Advances the wing by `dt_s` with the body moving as given; returns the loads at the
    /// step's start. A pitch past the hinge's break limit (or, with contact stops, a wing
    /// pressed implausibly deep into a stop) or a non-finite state is an error.
    pub fn step(&mut self, wing: &mut Wing, body: &BodyMotion, dt_s: f64) -> Result<WingStep> {
        let n = self.model.substeps.max(1);
        let h = dt_s / n as f64;
        let start = StepStart {
            state: self.state,
            t_s: self.t_s,
            phase: self.stroke_phase(),
        };
        let stops = self.model.hinge.contact.is_some();
        let mut out = None;
        let mut frame_start = None;
        let mut first = None;
        for sub in 0..n {
            let (held, aero) = self.aero_held(wing, body);
            let y0 = self.y();
            let t0 = self.t_s;
            let k1a = self.accelerations(t0, &y0, &held);
            if sub == 0 {
                frame_start = aero.as_ref().map(|(_, frame)| *frame);
                if stops {
                    first = Some(());
                } else {
                    out = Some(self.report(wing, &held, aero, k1a, &start));
                }
            }
            let pd_old = self.angles([0.0; 2]).phi_dot;
            let y = self.advance(t0, &y0, h, &held, k1a)?;
            self.state = WingState {
                phi_rad: y[0],
                theta_rad: y[1],
                phi_dot_rad_s: y[2],
                theta_dot_rad_s: y[3],
            };
            self.t_s = t0 + h;
            self.check(wing)?;
            self.track_reversal(pd_old, t0, h);
            self.track_period(wing);
        }
        if first.is_some() {
            // A strike changes the pitch rate within microseconds: sampled at the step's
            // start, the loads that follow it (rotational, added mass, the wing's inertial
            // reaction) would carry sampling errors of the order of their jump into every
            // cycle mean and every derivative the body sees. With stops the step reports
            // its mean motion instead: the angles at mid-step, the mean rates (change of
            // angle over the step) and the mean accelerations (change of rate over the
            // step, whose impulse is the wing's change of momentum), and the loads there.
            let (s0, s1) = (start.state, self.state);
            let mid = StepStart {
                state: WingState {
                    phi_rad: 0.5 * (s0.phi_rad + s1.phi_rad),
                    theta_rad: 0.5 * (s0.theta_rad + s1.theta_rad),
                    phi_dot_rad_s: (s1.phi_rad - s0.phi_rad) / dt_s,
                    theta_dot_rad_s: (s1.theta_rad - s0.theta_rad) / dt_s,
                },
                t_s: start.t_s + 0.5 * dt_s,
                phase: StrokePhase {
                    t_star: start.phase.t_star + 0.5 * dt_s * self.drive.freq_hz,
                    ..start.phase
                },
            };
            let acc = [
                (s1.phi_dot_rad_s - s0.phi_dot_rad_s) / dt_s,
                (s1.theta_dot_rad_s - s0.theta_dot_rad_s) / dt_s,
            ];
            let (held, aero) = self.aero_at(wing, body, &mid);
            out = Some(self.report(wing, &held, aero, acc, &mid));
        }
        let mut out = out.expect("at least one sub-step");
        if let Some(start) = frame_start {
            // The impulse-form added mass is -dP/dt of the fluid's impulse. Held over the
            // step, its value at the step's start would hand the body an impulse that differs
            // from the fluid's change by O(dt) each step, and those errors do not cancel
            // over a wingbeat (a cycle-mean force of 0.4-1% of the term's peak, measured on
            // the built-in vehicles at 100 steps per wingbeat). The force over the step is
            // therefore the change of P across it: the fluid's momentum is conserved step
            // by step and the cycle mean is zero to the motion's periodicity.
            let end = WingFrame::new(&self.angles([0.0; 2]), wing.mount().side);
            let i = wingforce::Term::AddedMass as usize;
            let downstroke = out.forces.phase.downstroke;
            if let Some(t) =
                wing.added_mass_over_step(&start, &end, dt_s, &out.forces.terms[i], downstroke)
            {
                out.forces.total.force_n += t.force_n - out.forces.terms[i].force_n;
                out.forces.total.c_l += t.c_l - out.forces.terms[i].c_l;
                out.forces.total.c_d += t.c_d - out.forces.terms[i].c_d;
                out.forces.terms[i] = t;
            }
        }
        Ok(out)
    }

    /// One classical fourth-order Runge-Kutta step of length `h` from (t0, y0) with the
    /// loads held (`k1a`: the accelerations at the start, when known); returns the new
    /// state and the three later stage states.
    pub(super) fn rk4(
        &self,
        t0: f64,
        y0: &[f64; 4],
        h: f64,
        held: &Held,
        k1a: Option<[f64; 2]>,
    ) -> ([f64; 4], [[f64; 4]; 3]) {
        let deriv = |a: [f64; 2], y: &[f64; 4]| [y[2], y[3], a[0], a[1]];
        let add = |y: &[f64; 4], k: &[f64; 4], s: f64| {
            [
                y[0] + s * k[0],
                y[1] + s * k[1],
                y[2] + s * k[2],
                y[3] + s * k[3],
            ]
        };
        let k1 = deriv(k1a.unwrap_or_else(|| self.accelerations(t0, y0, held)), y0);
        let y2 = add(y0, &k1, 0.5 * h);
        let k2 = deriv(self.accelerations(t0 + 0.5 * h, &y2, held), &y2);
        let y3 = add(y0, &k2, 0.5 * h);
        let k3 = deriv(self.accelerations(t0 + 0.5 * h, &y3, held), &y3);
        let y4 = add(y0, &k3, h);
        let k4 = deriv(self.accelerations(t0 + h, &y4, held), &y4);
        let mut y = [0.0; 4];
        for i in 0..4 {
            y[i] = y0[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
        (y, [y2, y3, y4])
    }

    fn check(&self, wing: &Wing) -> Result<()> {
        let s = &self.state;
        let side = match wing.mount().side {
            wingforce::Side::Left => "left",
            wingforce::Side::Right => "right",
        };
        if ![s.phi_rad, s.theta_rad, s.phi_dot_rad_s, s.theta_dot_rad_s]
            .iter()
            .all(|x| x.is_finite())
        {
            return Err(Error::Diverged {
                t_s: self.t_s,
                step: 0,
                reason: format!("{side} wing state is not finite: {s:?}"),
            });
        }
        let h = &self.model.hinge;
        let dev = s.theta_rad - h.rest_rad;
        if dev.abs() > h.break_rad {
            return Err(Error::Diverged {
                t_s: self.t_s,
                step: 0,
                reason: format!(
                    "{side} wing pitched {:.1} deg from its hinge rest angle, past the stops at +-{:.1} deg (the hinge's break limit): the hinge (k_h = {:e} N m/rad) is too soft for this drive",
                    dev.to_degrees(),
                    h.break_rad.to_degrees(),
                    h.stiffness_nm_rad
                ),
            });
        }
        if let Some(c) = &h.contact {
            let delta = c.penetration(dev).0;
            if delta > MAX_PENETRATION_RAD {
                return Err(Error::Diverged {
                    t_s: self.t_s,
                    step: 0,
                    reason: format!(
                        "{side} wing pressed {:.1} deg into its stop at +-{:.1} deg (more than {:.0} deg): the stop contact (stiffness {:e} N m/rad) is too soft for the loads; shorten [actuation.hinge.stop] contact_time_s",
                        delta.to_degrees(),
                        c.angle_rad.to_degrees(),
                        MAX_PENETRATION_RAD.to_degrees(),
                        c.stiffness_nm_rad
                    ),
                });
            }
        }
        Ok(())
    }

    fn track_reversal(&mut self, pd_old: f64, t0: f64, h: f64) {
        let pd = self.angles([0.0; 2]).phi_dot;
        let crossed = (pd_old > 0.0 && pd <= 0.0) || (pd_old < 0.0 && pd >= 0.0);
        if crossed {
            let frac = pd_old / (pd_old - pd);
            self.last_reversal_s = t0 + frac * h;
            self.half_stroke += 1;
            self.downstroke = pd > 0.0;
        }
    }

    /// Collects the stroke-rate profile of each drive period and, at its end, measures the
    /// stroke reference (peak rate, dtau_A, dtau_D by the half-peak rule) for the wing.
    fn track_period(&mut self, wing: &mut Wing) {
        let f = self.drive.freq_hz;
        let period = (self.t_s * f).floor() as i64;
        let pd = self.angles([0.0; 2]).phi_dot;
        if period != self.period_index {
            if self.model.aero
                && let Some(r) = measure_reference(&self.samples, self.period_index, f)
            {
                wing.set_stroke_reference(Some(r));
            }
            self.samples.clear();
            self.period_index = period;
        }
        self.samples.push((self.t_s, pd));
    }

    /// The loads at the step's start `at`, with the accelerations `acc`.
    fn report(
        &self,
        wing: &Wing,
        held: &Held,
        aero: Option<(WingForces, WingFrame)>,
        acc: [f64; 2],
        at: &StepStart,
    ) -> WingStep {
        let a = self.angles_at(&at.state, at.t_s, acc);
        let side = wing.mount().side;
        let frame = WingFrame::new(&a, side);
        let (forces, aero_axis) = match aero {
            Some((f, _)) => {
                let k = wing.kinematic_loads_in(&a, &at.phase, &frame);
                let f = Wing::with_kinematic_terms(&f, &k);
                (f, wing.axis_moments(&frame, &f.total))
            }
            None => (
                WingForces {
                    terms: Default::default(),
                    total: Default::default(),
                    angles: a,
                    phase: at.phase,
                },
                AxisMoments::default(),
            ),
        };
        let m_eff = self.pitch_inertia_effective(&self.mass_matrix(a.theta, &held.added));
        let hinge_moment = self.model.hinge.moment_nm(a.theta, a.theta_dot, m_eff);
        // Inertial reaction: -m a_c and -(I_h alpha + omega x I_h omega) about the hinge,
        // plus the actuator's reflected inertia about the stroke axis.
        let i = &self.model.inertia;
        let p_c = i.com_span_m * frame.e_span + i.com_chord_m * frame.e_le;
        let a_c = frame.alpha.cross(&p_c) + frame.omega.cross(&frame.omega.cross(&p_c));
        let (j, b, c) = (
            i.stroke_inertia_kg_m2,
            i.pitch_inertia_kg_m2,
            i.product_kg_m2(),
        );
        let (es, el) = (frame.e_span, frame.e_le);
        let i_h = Matrix3::identity() * (j + b)
            - (j * es * es.transpose()
                + b * el * el.transpose()
                + c * (es * el.transpose() + el * es.transpose()));
        let ja = self.model.stroke_inertia_kg_m2() - j;
        let k_phi = WingFrame::stroke_axis(side);
        let dh =
            i_h * frame.alpha + frame.omega.cross(&(i_h * frame.omega)) + ja * a.phi_ddot * k_phi;
        let r = wing.body_from_stroke();
        let actuator = match &self.model.stroke {
            Stroke::Driven {
                actuator, rest_rad, ..
            } => actuator.state(a.phi - rest_rad, a.phi_dot, self.drive.voltage_v(at.t_s)),
            Stroke::Prescribed(_) => ActuatorState::default(),
        };
        WingStep {
            forces,
            aero_axis,
            hinge_moment_nm: hinge_moment,
            inertial_force_n: r * (-i.mass_kg * a_c),
            inertial_moment_hinge_nm: r * (-dh),
            actuator,
            angles: a,
        }
    }
}

/// The stroke reference of one drive period from its (t, phi_dot) samples: peak |phi_dot|,
/// and dtau_A, dtau_D by wingforce's half-peak rule on the linearly interpolated profile.
/// `None` when the period does not hold two stroke reversals.
fn measure_reference(samples: &[(f64, f64)], period: i64, freq_hz: f64) -> Option<StrokeReference> {
    if samples.len() < 8 {
        return None;
    }
    let t0 = period as f64 / freq_hz;
    let phase: Vec<f64> = samples.iter().map(|(t, _)| (t - t0) * freq_hz).collect();
    let rate: Vec<f64> = samples.iter().map(|s| s.1).collect();
    let peak = rate.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let mut reversals = Vec::new();
    for i in 1..rate.len() {
        let (a, b) = (rate[i - 1], rate[i]);
        if (a > 0.0 && b <= 0.0) || (a < 0.0 && b >= 0.0) {
            let x = phase[i - 1] + (phase[i] - phase[i - 1]) * a / (a - b);
            reversals.push((x.rem_euclid(1.0), b > 0.0));
        }
    }
    if reversals.len() != 2 || !(peak > 0.0) {
        return None;
    }
    reversals.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (dtau_a, dtau_d) = wingforce::kinematics::sampled_acceleration_fractions(
        &phase,
        &rate,
        [reversals[0], reversals[1]],
    );
    Some(StrokeReference {
        peak_stroke_rate_rad_s: peak,
        dtau_a,
        dtau_d,
    })
}
