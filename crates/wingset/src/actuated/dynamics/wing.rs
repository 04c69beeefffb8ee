//! A wing whose angles are integrated in time: its state, what one step reports, and the
//! [`DynamicWing`] that holds them with its drive (built, driven and read here; its
//! equations are in [`super::equations`], its step in [`super::step`]).

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use wingforce::{AxisMoments, TermForce, WingAngles, WingForces};

use super::super::actuator::ActuatorState;
use super::super::drive::Drive;
use super::memo::WingKey;
use super::model::{Stroke, WingDynamics};
use super::stage_loads::{StageLoads, StrikeShare};
use crate::error::{Error, Result};
use crate::sampling::LoadSampling;

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

impl WingState {
    /// The state of the integrator's vector (phi, theta, phi_dot, theta_dot).
    pub(in crate::actuated) fn from_y(y: &[f64; 4]) -> Self {
        Self {
            phi_rad: y[0],
            theta_rad: y[1],
            phi_dot_rad_s: y[2],
            theta_dot_rad_s: y[3],
        }
    }
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
    /// The step with its loads (aerodynamic, hinge, inertial) times `w`; the motion and the
    /// actuator unchanged.
    pub(super) fn scaled(mut self, w: f64) -> Self {
        let scale = |t: &mut TermForce| {
            t.force_n *= w;
            t.moment_hinge_nm *= w;
            t.c_l *= w;
            t.c_d *= w;
        };
        self.forces.terms.iter_mut().for_each(scale);
        scale(&mut self.forces.total);
        self.aero_axis.stroke_nm *= w;
        self.aero_axis.pitch_nm *= w;
        self.hinge_moment_nm *= w;
        self.inertial_force_n *= w;
        self.inertial_moment_hinge_nm *= w;
        self
    }

    /// Adds `w` times the loads of `other` (a weighted mean's accumulation).
    pub(super) fn add_scaled(&mut self, other: &WingStep, w: f64) {
        let add = |t: &mut TermForce, o: &TermForce| {
            t.force_n += w * o.force_n;
            t.moment_hinge_nm += w * o.moment_hinge_nm;
            t.c_l += w * o.c_l;
            t.c_d += w * o.c_d;
        };
        for (t, o) in self.forces.terms.iter_mut().zip(&other.forces.terms) {
            add(t, o);
        }
        add(&mut self.forces.total, &other.forces.total);
        self.aero_axis.stroke_nm += w * other.aero_axis.stroke_nm;
        self.aero_axis.pitch_nm += w * other.aero_axis.pitch_nm;
        self.hinge_moment_nm += w * other.hinge_moment_nm;
        self.inertial_force_n += w * other.inertial_force_n;
        self.inertial_moment_hinge_nm += w * other.inertial_moment_hinge_nm;
    }

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
    pub(super) model: WingDynamics,
    pub(super) drive: Drive,
    pub(super) state: WingState,
    pub(super) t_s: f64,
    pub(super) last_reversal_s: f64,
    pub(super) half_stroke: i64,
    pub(super) downstroke: bool,
    /// Largest |phi_dot| since the last reversal (the step mean's reversals, see
    /// `reversal_within`), rad/s.
    pub(super) half_stroke_peak_rate_rad_s: f64,
    /// (t, phi_dot) over the current drive period, to measure the stroke reference.
    pub(super) samples: Vec<(f64, f64)>,
    pub(super) period_index: i64,
    /// What a step reports ([`LoadSampling`]): with `Midpoint` (or hinge stops) the
    /// aerodynamic loads are taken afresh at every Runge-Kutta stage (on inelastic stops, at
    /// each segment's start and the sub-step's end and linear between them, `actuated::contact`) and the step reports
    /// its mean loads; with `StepStart` (no stops) they are held and reported at its start.
    pub(super) sampling: LoadSampling,
    /// The share of the last step's strikes' impulses the next step reports
    /// ([`super::strike`]).
    pub(super) carried_strike: Option<WingStep>,
    /// The share the step after the next reports ([`StrikeShare::TrapezoidalPose`]).
    pub(super) carried_strike_after: Option<WingStep>,
    /// How a strike's impulse is shared among the body's steps
    /// ([`DynamicWing::set_strike_share`]).
    pub(super) strike_share: StrikeShare,
    /// How, on an inelastic stop, the aerodynamic loads are taken within a step
    /// ([`DynamicWing::set_stage_loads`]).
    pub(super) stage_loads: StageLoads,
    /// The key of this wing's model and drive in the memo of what a step asks for more than
    /// once (`memo`; a run is the same without it).
    pub(super) memo: WingKey,
    /// The drive's voltage at the current sub-step's start, middle (two roundings) and end: (time's bits,
    /// V) (`DynamicWing::voltage_v`).
    pub(super) volts: [(u64, f64); 4],
}

impl DynamicWing {
    /// What a step reports from now on ([`LoadSampling`]; the wing set sets its own).
    pub fn set_load_sampling(&mut self, sampling: LoadSampling) {
        self.sampling = sampling;
    }

    /// What a step reports.
    pub fn load_sampling(&self) -> LoadSampling {
        self.sampling
    }

    /// How a wing on inelastic hinge stops takes its aerodynamic loads within a step
    /// ([`StageLoads`], by default the split scheme, `stage_loads`); a log written before
    /// re-runs with its own.
    pub fn set_stage_loads(&mut self, stage_loads: StageLoads) {
        self.stage_loads = stage_loads;
    }

    /// See [`Self::set_stage_loads`].
    pub fn stage_loads(&self) -> StageLoads {
        self.stage_loads
    }

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
            half_stroke_peak_rate_rad_s: 0.0,
            samples: Vec::new(),
            period_index: 0,
            // Step-start until a wing set that samples at the midpoint says otherwise (the
            // actuated vehicles' default, `flapsim::Vehicle::load_sampling`).
            sampling: LoadSampling::StepStart,
            carried_strike: None,
            carried_strike_after: None,
            strike_share: StrikeShare::default(),
            stage_loads: StageLoads::default(),
            memo: WingKey::fresh(),
            volts: [(f64::NAN.to_bits(), f64::NAN); 4],
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
        self.memo = WingKey::fresh();
        self.volts = [(f64::NAN.to_bits(), f64::NAN); 4];
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
}
