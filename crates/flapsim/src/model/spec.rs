//! The model file's tables as plain data (serde): body, hinge, further wing pairs, controls,
//! simulation settings, initial state, and the whole file. No validation here: `build`
//! turns a [`VehicleSpec`] into a [`super::Vehicle`].

use serde::{Deserialize, Serialize};
use wingforce::{AeroSpec, FluidSpec, KinematicsSpec, WingSpec};
use wingset::actuated::{StageLoads, StrikeShare};

use crate::actuated::spec::ActuationSpec;

/// Rigid body of the vehicle (wings excluded unless `wing_mass_kg` is set).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// Mass, kg.
    pub mass_kg: f64,
    /// Inertia tensor about the centre of mass in body axes [Ixx, Iyy, Izz], kg m^2.
    pub inertia_diag_kg_m2: [f64; 3],
    /// Product of inertia Ixz (the only one a left-right symmetric body has), kg m^2.
    #[serde(default)]
    pub inertia_xz_kg_m2: f64,
    /// Body length, m (for reports: excursions in body lengths).
    pub length_m: f64,
    /// The body's parasite drag area C_D S, m^2: in forward flight the body feels
    /// 0.5 rho |V| V C_D S against its velocity V through the air, at the centre of mass
    /// (`flapsim::flight`). 0 (the default) leaves body drag out; hover is unaffected.
    #[serde(default)]
    pub drag_area_m2: f64,
}

/// Where the wings attach.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HingeSpec {
    /// Left hinge in body axes from the centre of mass, m; the right hinge mirrors it in y.
    pub left_in_body_m: [f64; 3],
    /// Stroke-plane tilt relative to the body, deg (see `wingforce::Mount`).
    pub stroke_plane_tilt_deg: f64,
}

/// A further pair of wings (`[[pairs]]`, after the first pair of `[wing]`, `[hinge]` and
/// `[kinematics]`): a dragonfly's hindwings. Its own hinge (the left one, mirrored to the
/// right) and stroke plane; its planform and kinematics, or the first pair's; and its
/// wingbeat's lead over the first pair's. Every wing flaps at one frequency, and the
/// controls act on every pair alike.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PairSpec {
    /// How far this pair's wingbeat leads the first pair's, deg of the wingbeat (360 = one
    /// whole wingbeat; a dragonfly's hindwings lead its forewings). Required: there is no
    /// default phase between two pairs (`Option` only so that a missing value gets an error
    /// naming the pair).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub phase_offset_deg: Option<f64>,
    /// The pair's hinges and stroke plane (required).
    pub hinge: HingeSpec,
    /// The pair's planform; the first pair's `[wing]` when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wing: Option<WingSpec>,
    /// The pair's kinematics (both wings); the first pair's (its left and right kinematics)
    /// when absent. Same frequency as the first pair.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kinematics: Option<KinematicsSpec>,
    /// How the control channels move this pair, a factor on each kinematic offset (mean
    /// stroke, amplitude, pitch bias, angle of attack and their left-minus-right
    /// differences; not the frequency, which all wings share): 1 (the default) moves it as
    /// the first pair, 0 holds its base kinematics, -1 moves it the opposite way (a mean-stroke
    /// command then shifts fore and hind pairs apart: a pitch couple).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub control_gain: Option<f64>,
}

/// Control parameters of the kinematics, changed once per wingbeat. Deltas are added to
/// the base kinematics; `diff_*` are left minus right (half added to the left wing, half
/// subtracted from the right).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ControlSpec {
    /// Mean stroke angle offset, deg (moves the lift forward: pitch control).
    pub mean_stroke_deg: f64,
    /// Amplitude offset, deg (lift: height control).
    pub amplitude_deg: f64,
    /// Pitch bias offset, deg.
    pub pitch_bias_deg: f64,
    /// Mid-stroke angle-of-attack offset of both half strokes, deg (lift).
    pub aoa_deg: f64,
    /// Frequency offset, Hz.
    pub freq_hz: f64,
    /// Left-minus-right amplitude, deg (roll control).
    pub diff_amplitude_deg: f64,
    /// Left-minus-right pitch bias, deg (yaw control).
    pub diff_pitch_bias_deg: f64,
    /// Left-minus-right mean stroke angle, deg.
    pub diff_mean_stroke_deg: f64,
    /// Actuated vehicles: drive bias offset, V (shifts the mean stroke angle: pitch control).
    pub bias_v: f64,
    /// Actuated vehicles: drive amplitude offset, V (lift: height control).
    pub amplitude_v: f64,
    /// Actuated vehicles: left-minus-right drive amplitude, V (roll control).
    pub diff_amplitude_v: f64,
    /// Actuated vehicles: left-minus-right drive bias, V.
    pub diff_bias_v: f64,
    /// Actuated vehicles: left-minus-right second-harmonic fraction (split-cycle: unequal
    /// down- and upstroke speeds, opposite on the two wings: yaw control).
    pub diff_second_harmonic: f64,
}

/// Simulation settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SimSpec {
    /// Physics steps per wingbeat (at least 10 accepted).
    pub steps_per_wingbeat: usize,
    /// The fewest steps per wingbeat that hold the accuracy the model file states, chosen
    /// from the error-cost frontier (docs/speed.md): a vehicle stepped more coarsely warns
    /// ([`crate::Vehicle::coarse_step_warning`]). Absent: no stated bound.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accurate_steps_per_wingbeat: Option<usize>,
    /// Where in a step the wings' loads are taken: `"step_mean"` or `"midpoint"` (second
    /// order; logs of the midpoint replay with it) or `"step_start"` (first order, the only
    /// one before issue 37; logs written before it replay with it). See
    /// [`wingset::sampling`]. Absent: the step mean for prescribed wings,
    /// step-start for actuated ones (`Vehicle::load_sampling`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub load_sampling: Option<wingset::LoadSampling>,
    /// rapier's own angular-velocity update (the world inertia and the gyroscopic term at the
    /// step's start) under a second-order load sampling, as before 2026-12-06: a log written
    /// before the midpoint rotation (no `body_rotation` metadata) re-runs with it. Not a
    /// model-file field. See [`crate::host::midpoint_torque_world`].
    #[serde(skip)]
    pub rotation_at_step_start: bool,
    /// How an actuated wing's stop strike is shared between the body step it falls in and
    /// the next (wingset's `actuated::StrikeShare`): `None`, by the host (flapsim's moves the
    /// body by the trapezoidal rule under a second-order sampling,
    /// [`crate::Vehicle::strike_share`]); a log re-runs with the rule its `strike_impulse`
    /// metadata names (whole in its step without it, as before 2026-12-06). Not a
    /// model-file field.
    #[serde(skip)]
    pub strike_share: Option<StrikeShare>,
    /// How an actuated wing on inelastic hinge stops takes its aerodynamic loads within a
    /// step (wingset's `actuated::StageLoads`): the split scheme since 2026-12-07; a log
    /// re-runs with the way its `actuated_stage_loads`
    /// metadata names (afresh at every Runge-Kutta stage without it, as before 2026-12-07).
    /// Not a model-file field. Wings without stops take their loads at every stage either
    /// way.
    #[serde(skip)]
    pub actuated_stage_loads: StageLoads,
    /// rapier solver iterations (substeps) per step.
    pub solver_iterations: usize,
    /// Add a ground plane at z = 0 and a contact sphere on the body (take-off and landing).
    pub ground: bool,
    /// Mass of each wing, kg: when > 0, the inertial reaction of the wing's accelerating
    /// centre of mass is applied to the body (wings massless when 0).
    pub wing_mass_kg: f64,
    /// Speed above which a run counts as diverged, m/s.
    pub max_speed_m_s: f64,
    /// Angular speed above which a run counts as diverged, rad/s.
    pub max_angular_speed_rad_s: f64,
}

impl Default for SimSpec {
    fn default() -> Self {
        Self {
            steps_per_wingbeat: 100,
            accurate_steps_per_wingbeat: None,
            load_sampling: None,
            rotation_at_step_start: false,
            strike_share: None,
            actuated_stage_loads: StageLoads::default(),
            solver_iterations: 1,
            ground: false,
            wing_mass_kg: 0.0,
            max_speed_m_s: 50.0,
            max_angular_speed_rad_s: 5000.0,
        }
    }
}

/// Initial state of the body.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct InitialSpec {
    /// Position of the centre of mass in the world (z up), m.
    pub position_m: [f64; 3],
    /// Attitude as roll, pitch, yaw (intrinsic z-y-x), deg. Pitch positive nose up.
    pub attitude_deg: [f64; 3],
    /// Velocity in the world frame, m/s.
    pub velocity_m_s: [f64; 3],
    /// Angular velocity in the body frame, deg/s.
    pub angular_velocity_deg_s: [f64; 3],
}

/// A vehicle model file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VehicleSpec {
    /// Name for reports and logs.
    pub name: String,
    /// The fluid (air at 20 C if absent).
    #[serde(default)]
    pub fluid: FluidSpec,
    /// Gravitational acceleration, m/s^2.
    #[serde(default = "default_gravity")]
    pub gravity_m_s2: f64,
    /// The body.
    pub body: BodySpec,
    /// Both wings' planform.
    pub wing: WingSpec,
    /// Hinge positions and stroke plane.
    pub hinge: HingeSpec,
    /// Base kinematics of both wings.
    pub kinematics: KinematicsSpec,
    /// Left-wing kinematics replacing the base (optional).
    #[serde(default)]
    pub left_kinematics: Option<KinematicsSpec>,
    /// Right-wing kinematics replacing the base (optional).
    #[serde(default)]
    pub right_kinematics: Option<KinematicsSpec>,
    /// `[[pairs]]`: further wing pairs after the first (none for a two-winged vehicle).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub pairs: Vec<PairSpec>,
    /// Control offsets applied from the start.
    #[serde(default)]
    pub controls: ControlSpec,
    /// Aerodynamic options.
    #[serde(default)]
    pub aero: AeroSpec,
    /// Simulation settings.
    #[serde(default)]
    pub sim: SimSpec,
    /// Initial state.
    #[serde(default)]
    pub initial: InitialSpec,
    /// Actuated wings (stroke driven by an actuator, pitch passive about a hinge); absent
    /// for prescribed kinematics. See [`crate::actuated`].
    #[serde(default)]
    pub actuation: Option<ActuationSpec>,
    /// `[trim]`: what a hover trim varies to carry the weight.
    #[serde(default)]
    pub trim: crate::trim::spec::TrimSpec,
    /// `[sensors]`: the body IMU and motion capture (see [`crate::sensors`]); absent when
    /// the model has none.
    #[serde(default)]
    pub sensors: Option<crate::sensors::params::SensorSpec>,
    /// `[wind]`: steady wind, Dryden turbulence and 1 - cosine gusts (see [`crate::wind`]);
    /// absent for still air.
    #[serde(default)]
    pub wind: Option<crate::wind::WindSpec>,
}

fn default_gravity() -> f64 {
    9.81
}
