//! Vehicle model files (TOML): body, wings, kinematics and their control parameters, fluid,
//! gravity, simulation settings and the initial state. Strict: unknown fields are errors and
//! every value is range-checked with an error naming file, field, value and what is allowed.

use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};
use wingforce::model::{build_fluid, build_geometry, parse_toml};
use wingforce::{
    AeroSpec, Fluid, FluidSpec, Kinematics, KinematicsSpec, Mount, Side, Validator, Wing, WingSpec,
};

use crate::actuated::{Actuation, ActuationSpec};
use crate::error::Result;

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

pub use crate::controls::{Controls, DRIVE_CHANNELS, KINEMATIC_CHANNELS};

/// Simulation settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SimSpec {
    /// Physics steps per wingbeat (>= 100 recommended; at least 20 accepted).
    pub steps_per_wingbeat: usize,
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

/// A validated vehicle: everything in SI units, wings prepared.
#[derive(Debug, Clone, PartialEq)]
pub struct Vehicle {
    /// Name.
    pub name: String,
    /// Mass, kg.
    pub mass_kg: f64,
    /// Inertia tensor about the CoM in body axes, kg m^2.
    pub inertia_kg_m2: Matrix3<f64>,
    /// Body length, m.
    pub length_m: f64,
    /// The body's parasite drag area C_D S, m^2 (`[body] drag_area_m2`, [`crate::flight`]).
    pub body_drag_area_m2: f64,
    /// Gravity magnitude, m/s^2.
    pub gravity_m_s2: f64,
    /// The wings, pair by pair, left then right: [L0, R0, L1, R1, ...] (index 0 left, 1 right
    /// of the first pair; further pairs from `[[pairs]]`), with the kinematics in force.
    pub wings: Vec<Wing>,
    /// Base kinematics of each wing, in the order of `wings` (controls are applied on top of
    /// these; a further pair's carry its phase offset).
    pub base_kinematics: Vec<Kinematics>,
    /// Initial controls.
    pub controls: Controls,
    /// Simulation settings.
    pub sim: SimSpec,
    /// Initial position, m (world).
    pub initial_position_m: Vector3<f64>,
    /// Initial attitude (world_from_body).
    pub initial_attitude: UnitQuaternion<f64>,
    /// Initial velocity, world, m/s.
    pub initial_velocity_m_s: Vector3<f64>,
    /// Initial angular velocity, body, rad/s.
    pub initial_angular_velocity_rad_s: Vector3<f64>,
    /// Each pair's two wings have identical kinematics now (set by
    /// [`Vehicle::apply_controls`]), so each right wing can be evaluated as the mirror image
    /// of its left.
    pub mirror_symmetric: bool,
    /// The wings' dynamics and drives when the vehicle is actuated.
    pub actuation: Option<Actuation>,
    /// What a hover trim varies to carry the weight (`[trim] lift_variable`).
    pub trim_lift: crate::trim::spec::LiftVariable,
    /// The sensors, validated, in SI units (`[sensors]`).
    pub sensors: Option<crate::sensors::params::SensorParams>,
    /// The wind (`[wind]`), validated; the runs that fly in it (`simulate`, `hover`) build a
    /// [`crate::Wind`] from it.
    pub wind: Option<crate::wind::WindSpec>,
}

impl VehicleSpec {
    /// Parses TOML text; `origin` (the file path) appears in errors.
    pub fn from_toml(text: &str, origin: &str) -> Result<Self> {
        Ok(parse_toml(text, origin)?)
    }

    /// Validates everything and prepares the wings.
    pub fn build(&self, origin: &str) -> Result<Vehicle> {
        let v = Validator::new(origin);
        let mass = v.positive("body.mass_kg", self.body.mass_kg)?;
        let [ixx, iyy, izz] = self.body.inertia_diag_kg_m2;
        for (i, x) in [ixx, iyy, izz].into_iter().enumerate() {
            v.positive(&format!("body.inertia_diag_kg_m2[{i}]"), x)?;
        }
        let ixz = v.finite("body.inertia_xz_kg_m2", self.body.inertia_xz_kg_m2)?;
        // Positive definite and satisfying the triangle inequalities of a real body.
        if ixz * ixz >= ixx * izz || ixx + iyy < izz || iyy + izz < ixx || ixx + izz < iyy {
            return Err(v
                .invalid(
                    "body.inertia_diag_kg_m2",
                    format!("[{ixx}, {iyy}, {izz}] with Ixz {ixz}"),
                    "a physical inertia: each diagonal entry at most the sum of the other two, and Ixz^2 < Ixx Izz",
                )
                .into());
        }
        let length = v.positive("body.length_m", self.body.length_m)?;
        let drag_area = v.within("body.drag_area_m2", self.body.drag_area_m2, 0.0, 1.0)?;
        let g = v.within("gravity_m_s2", self.gravity_m_s2, 0.0, 100.0)?;
        let mut aero = self.aero.build(&v, "aero")?;
        if !self.pairs.is_empty() && self.actuation.is_some() {
            return Err(v
                .invalid(
                    "pairs",
                    format!("{} further pair(s)", self.pairs.len()),
                    "no [[pairs]] on an actuated vehicle (its drives and wing dynamics are one left/right pair)",
                )
                .into());
        }
        if self.aero.induced_inflow {
            if !self.pairs.is_empty() {
                return Err(v
                    .invalid(
                        "aero.induced_inflow",
                        true,
                        "false for a model with [[pairs]] (the momentum-theory downwash is that of one pair's disc; tandem pairs share and overlap theirs)",
                    )
                    .into());
            }
            if self.actuation.is_some() {
                return Err(v
                    .invalid(
                        "aero.induced_inflow",
                        true,
                        "false for an actuated vehicle (its amplitude is an output of the wing dynamics, and the inflow's disc area needs it)",
                    )
                    .into());
            }
            // Hover: the pair carries the weight, each wing half of it (wingforce::inflow).
            aero.induced_inflow = Some(wingforce::InducedInflow::hover(0.5 * mass * g));
        }
        let geometry = build_geometry(&self.wing, &v, "wing", &self.aero)?;
        let base = self
            .kinematics
            .build(&v, "kinematics", geometry.r_gyration_m)?;
        let left_k = match &self.left_kinematics {
            Some(k) => k.build(&v, "left_kinematics", geometry.r_gyration_m)?,
            None => base.clone(),
        };
        let right_k = match &self.right_kinematics {
            Some(k) => k.build(&v, "right_kinematics", geometry.r_gyration_m)?,
            None => base.clone(),
        };
        let fluid: Fluid = build_fluid(&self.fluid, &v, "fluid", &geometry, &base)?;
        let (hinge_left, tilt) = build_hinge(&v, "hinge", &self.hinge)?;
        let mut pairs = Vec::with_capacity(self.pairs.len());
        for (p, pair) in self.pairs.iter().enumerate() {
            pairs.push(self.build_pair(&v, p, pair, &geometry, [&left_k, &right_k])?);
        }
        let sim = &self.sim;
        if !(20..=100_000).contains(&sim.steps_per_wingbeat) {
            return Err(v
                .invalid(
                    "sim.steps_per_wingbeat",
                    sim.steps_per_wingbeat,
                    "an integer in [20, 100000] (100+ recommended)",
                )
                .into());
        }
        if !(1..=16).contains(&sim.solver_iterations) {
            return Err(v
                .invalid(
                    "sim.solver_iterations",
                    sim.solver_iterations,
                    "an integer in [1, 16]",
                )
                .into());
        }
        v.non_negative("sim.wing_mass_kg", sim.wing_mass_kg)?;
        v.positive("sim.max_speed_m_s", sim.max_speed_m_s)?;
        v.positive("sim.max_angular_speed_rad_s", sim.max_angular_speed_rad_s)?;
        let c = &self.controls;
        let controls = Controls {
            mean_stroke_rad: v
                .within("controls.mean_stroke_deg", c.mean_stroke_deg, -60.0, 60.0)?
                .to_radians(),
            amplitude_rad: v
                .within("controls.amplitude_deg", c.amplitude_deg, -90.0, 90.0)?
                .to_radians(),
            pitch_bias_rad: v
                .within("controls.pitch_bias_deg", c.pitch_bias_deg, -30.0, 30.0)?
                .to_radians(),
            aoa_rad: v
                .within("controls.aoa_deg", c.aoa_deg, -60.0, 60.0)?
                .to_radians(),
            freq_hz: v.within("controls.freq_hz", c.freq_hz, -1e4, 1e4)?,
            diff_amplitude_rad: v
                .within(
                    "controls.diff_amplitude_deg",
                    c.diff_amplitude_deg,
                    -90.0,
                    90.0,
                )?
                .to_radians(),
            diff_pitch_bias_rad: v
                .within(
                    "controls.diff_pitch_bias_deg",
                    c.diff_pitch_bias_deg,
                    -30.0,
                    30.0,
                )?
                .to_radians(),
            diff_mean_stroke_rad: v
                .within(
                    "controls.diff_mean_stroke_deg",
                    c.diff_mean_stroke_deg,
                    -60.0,
                    60.0,
                )?
                .to_radians(),
            bias_v: v.finite("controls.bias_v", c.bias_v)?,
            amplitude_v: v.finite("controls.amplitude_v", c.amplitude_v)?,
            diff_amplitude_v: v.finite("controls.diff_amplitude_v", c.diff_amplitude_v)?,
            diff_bias_v: v.finite("controls.diff_bias_v", c.diff_bias_v)?,
            diff_second_harmonic: v.within(
                "controls.diff_second_harmonic",
                c.diff_second_harmonic,
                -1.0,
                1.0,
            )?,
        };
        let init = &self.initial;
        let vec = |name: &str, a: [f64; 3], lim: f64| -> Result<Vector3<f64>> {
            for (i, x) in a.into_iter().enumerate() {
                v.within(&format!("initial.{name}[{i}]"), x, -lim, lim)?;
            }
            Ok(Vector3::new(a[0], a[1], a[2]))
        };
        let pos = vec("position_m", init.position_m, 1e4)?;
        let att = vec("attitude_deg", init.attitude_deg, 180.0)?;
        let vel = vec("velocity_m_s", init.velocity_m_s, 100.0)?;
        let rate = vec("angular_velocity_deg_s", init.angular_velocity_deg_s, 1e5)?;
        let make = |geometry: &wingforce::Geometry,
                    hinge_left: Vector3<f64>,
                    tilt: f64,
                    side: Side,
                    k: &Kinematics| {
            Wing::builder(geometry.clone(), k.clone())
                .mount(mount(hinge_left, tilt, side))
                .fluid(fluid)
                .options(aero.clone())
                .build()
        };
        let mut wings = vec![
            make(&geometry, hinge_left, tilt, Side::Left, &left_k),
            make(&geometry, hinge_left, tilt, Side::Right, &right_k),
        ];
        let mut base_kinematics = vec![left_k, right_k];
        for pair in pairs {
            let [kl, kr] = pair.kinematics;
            for (side, k) in [(Side::Left, kl), (Side::Right, kr)] {
                wings.push(make(&pair.geometry, pair.hinge_left, pair.tilt, side, &k));
                base_kinematics.push(k);
            }
        }
        let mut vehicle = Vehicle {
            name: self.name.clone(),
            mass_kg: mass,
            inertia_kg_m2: Matrix3::new(ixx, 0.0, -ixz, 0.0, iyy, 0.0, -ixz, 0.0, izz),
            length_m: length,
            body_drag_area_m2: drag_area,
            gravity_m_s2: g,
            wings,
            base_kinematics,
            controls,
            sim: sim.clone(),
            initial_position_m: pos,
            initial_attitude: UnitQuaternion::from_euler_angles(
                att.x.to_radians(),
                -att.y.to_radians(),
                att.z.to_radians(),
            ),
            initial_velocity_m_s: vel,
            initial_angular_velocity_rad_s: rate.map(f64::to_radians),
            mirror_symmetric: false,
            actuation: self
                .actuation
                .as_ref()
                .map(|a| a.build(&v, "actuation"))
                .transpose()?,
            trim_lift: self.trim.lift_variable,
            sensors: self.sensors.as_ref().map(|x| x.build(&v)).transpose()?,
            wind: match &self.wind {
                Some(w) => {
                    w.build(&v, "wind")?;
                    Some(w.clone())
                }
                None => None,
            },
        };
        if vehicle.actuation.is_some()
            && vehicle.trim_lift != crate::trim::spec::LiftVariable::Amplitude
        {
            return Err(v
                .invalid(
                    "trim.lift_variable",
                    vehicle.trim_lift.name(),
                    "`amplitude` for an actuated vehicle (it trims its drive amplitude)",
                )
                .into());
        }
        // The controlled kinematics must stay valid (checked before applying them, so the
        // error names the controls field rather than a wing).
        for i in 0..vehicle.wings.len() {
            let k = vehicle.controlled_kinematics(i, &controls);
            let side = Vehicle::wing_name(i);
            v.within_open_low(
                &format!("controls (resulting {side} stroke amplitude, deg)"),
                k.amplitude_rad.to_degrees(),
                0.0,
                180.0,
            )?;
            v.within_open_low(
                &format!("controls (resulting {side} frequency, Hz)"),
                k.freq_hz,
                0.0,
                1e5,
            )?;
        }
        vehicle.apply_controls(&controls)?;
        check_wings(&v, &vehicle.wings)?;
        Ok(vehicle)
    }
}

impl Vehicle {
    /// Loads a vehicle from TOML text.
    pub fn from_toml(text: &str, origin: &str) -> Result<Self> {
        VehicleSpec::from_toml(text, origin)?.build(origin)
    }

    /// Weight m g, N.
    pub fn weight_n(&self) -> f64 {
        self.mass_kg * self.gravity_m_s2
    }

    /// The kinematics of wing `i` (even left, odd right; 0 and 1 the first pair) under
    /// `controls`: every pair gets the same offsets (the left-minus-right ones split between
    /// each pair's two wings).
    pub fn controlled_kinematics(&self, i: usize, c: &Controls) -> Kinematics {
        let half = if i % 2 == 0 { 0.5 } else { -0.5 };
        let base = &self.base_kinematics[i];
        // A measured table has no mid-stroke angle of attack; apply_controls refuses an
        // offset on one before it gets here.
        let mut k = base
            .with_aoa_offset(c.aoa_rad)
            .unwrap_or_else(|| base.clone());
        k.mean_stroke_rad += c.mean_stroke_rad + half * c.diff_mean_stroke_rad;
        k.amplitude_rad += c.amplitude_rad + half * c.diff_amplitude_rad;
        k.pitch_bias_rad += c.pitch_bias_rad + half * c.diff_pitch_bias_rad;
        k.freq_hz += c.freq_hz;
        k
    }

    /// Applies control inputs to every wing (call between wingbeats): kinematic offsets for
    /// prescribed kinematics, drive offsets (on the model's drives) for an actuated vehicle;
    /// offsets of the other kind are an error.
    pub fn apply_controls(&mut self, c: &Controls) -> Result<()> {
        if let Some(act) = &mut self.actuation {
            if !c.kinematic_is_zero() {
                return Err(crate::Error::Analysis(format!(
                    "{} is actuated: its wing motion comes from the drive, so kinematic control offsets (mean stroke {:.2} deg, amplitude {:.2} deg, pitch bias {:.2} deg, ...) do not apply; use the drive controls (bias_v, amplitude_v, diff_amplitude_v, diff_bias_v, diff_second_harmonic)",
                    self.name,
                    c.mean_stroke_rad.to_degrees(),
                    c.amplitude_rad.to_degrees(),
                    c.pitch_bias_rad.to_degrees()
                )));
            }
            act.drives = act.controlled_drives(c)?;
            self.controls = *c;
            return Ok(());
        }
        if !c.drive_is_zero() {
            return Err(crate::Error::Analysis(format!(
                "{} has prescribed kinematics: drive control offsets (bias {} V, amplitude {} V, ...) apply to actuated vehicles only",
                self.name, c.bias_v, c.amplitude_v
            )));
        }
        for i in 0..self.wings.len() {
            if c.aoa_rad != 0.0 {
                let Some((down, up)) = self.base_kinematics[i].mid_stroke_aoa_rad() else {
                    return Err(crate::Error::Analysis(format!(
                        "{}: an angle-of-attack offset ({:.2} deg) needs a kinematics family with a mid-stroke angle of attack (trapezoidal, harmonic, harmonic_flip); measured (tabulated) kinematics have none",
                        self.name,
                        c.aoa_rad.to_degrees()
                    )));
                };
                for (half, aoa) in [("downstroke", down), ("upstroke", up)] {
                    let moved = aoa + c.aoa_rad;
                    if !(moved > 0.0 && moved <= 0.5 * std::f64::consts::PI) {
                        return Err(crate::Error::Analysis(format!(
                            "controls give wing {i} a {half} angle of attack of {:.2} deg ({:.2} deg + offset {:.2} deg); allowed: (0, 90] deg",
                            moved.to_degrees(),
                            aoa.to_degrees(),
                            c.aoa_rad.to_degrees()
                        )));
                    }
                }
            }
            let k = self.controlled_kinematics(i, c);
            if !(k.amplitude_rad > 0.0
                && k.amplitude_rad <= std::f64::consts::PI
                && k.freq_hz > 0.0)
            {
                return Err(crate::Error::Analysis(format!(
                    "controls give wing {i} an amplitude of {:.2} deg and a frequency of {:.2} Hz; allowed: amplitude in (0, 180] deg, frequency > 0",
                    k.amplitude_rad.to_degrees(),
                    k.freq_hz
                )));
            }
            self.wings[i].set_kinematics(k);
        }
        self.controls = *c;
        self.mirror_symmetric = self
            .wings
            .chunks(2)
            .all(|p| p.len() == 2 && p[0].kinematics() == p[1].kinematics());
        Ok(())
    }

    /// Wing `i`'s name in messages: `left` and `right` for the first pair, `pairs[k] left`
    /// and `pairs[k] right` for the model file's `[[pairs]]` entry k.
    pub fn wing_name(i: usize) -> String {
        let side = if i % 2 == 0 { "left" } else { "right" };
        match i / 2 {
            0 => side.to_string(),
            p => format!("pairs[{}] {side}", p - 1),
        }
    }

    /// Number of wing pairs (1 for a two-winged vehicle).
    pub fn pair_count(&self) -> usize {
        self.wings.len() / 2
    }

    /// The wing pairs' wingbeat leads over the first pair, wingbeats (0 for the first).
    pub fn pair_phase_offsets(&self) -> Vec<f64> {
        self.wings
            .chunks(2)
            .map(|p| p[0].kinematics().phase_offset)
            .collect()
    }

    /// Refuses a vehicle with more than one wing pair in a component that supports one pair
    /// only: an error naming the model (`name`), what refuses it, and what is allowed.
    pub fn require_one_pair(&self, what: &str) -> Result<()> {
        if self.wings.len() == 2 {
            return Ok(());
        }
        Err(crate::Error::Input(format!(
            "{}: {} wings in {} pairs ([[pairs]] in the model file); {what} supports one left/right pair only (a model without [[pairs]])",
            self.name,
            self.wings.len(),
            self.pair_count()
        )))
    }

    /// Whether the control channels are drive parameters (an actuated vehicle).
    pub fn drive_controlled(&self) -> bool {
        self.actuation.is_some()
    }

    /// Names (with units) of the four control channels of this vehicle.
    pub fn control_channels(&self) -> [&'static str; 4] {
        if self.drive_controlled() {
            DRIVE_CHANNELS
        } else {
            KINEMATIC_CHANNELS
        }
    }

    /// `base` with offsets `u` on this vehicle's four control channels.
    pub fn controls_with(&self, base: &Controls, u: &[f64]) -> Controls {
        base.with_channels(self.drive_controlled(), u)
    }

    /// A typical excursion of each control channel (rad for kinematics; for a drive, a
    /// tenth of the actuator's voltage limit and 0.1 of second harmonic): the scale of
    /// finite differences and of the LQR's control weights.
    pub fn control_scales(&self) -> [f64; 4] {
        match &self.actuation {
            Some(a) => {
                let v = 0.1 * a.dynamics.stroke.voltage_limit_v();
                [v, v, v, 0.1]
            }
            None => [1.0; 4],
        }
    }

    /// Wingbeat frequency now, Hz (both wings share it): the drive frequency of an
    /// actuated vehicle.
    pub fn freq_hz(&self) -> f64 {
        match &self.actuation {
            Some(a) => a.drives[0].freq_hz,
            None => self.wings[0].kinematics().freq_hz,
        }
    }
}

/// A validated further pair: its geometry, left hinge, stroke-plane tilt (rad) and the
/// kinematics of its left and right wings (with the phase offset).
struct BuiltPair {
    geometry: wingforce::Geometry,
    hinge_left: Vector3<f64>,
    tilt: f64,
    kinematics: [Kinematics; 2],
}

impl VehicleSpec {
    /// Validates `[[pairs]]` entry `p`: its fields are named `pairs[p].…` in errors.
    fn build_pair(
        &self,
        v: &Validator<'_>,
        p: usize,
        pair: &PairSpec,
        first_geometry: &wingforce::Geometry,
        first_kinematics: [&Kinematics; 2],
    ) -> Result<BuiltPair> {
        let field = format!("pairs[{p}]");
        let allowed = "the pair's wingbeat lead over the first pair, deg: a finite number in [-360, 360] (required; 180 = half a wingbeat)";
        let offset_deg = match pair.phase_offset_deg {
            None => {
                return Err(v
                    .invalid(&format!("{field}.phase_offset_deg"), "missing", allowed)
                    .into());
            }
            Some(x) if !(x.is_finite() && (-360.0..=360.0).contains(&x)) => {
                return Err(v
                    .invalid(&format!("{field}.phase_offset_deg"), x, allowed)
                    .into());
            }
            Some(x) => x,
        };
        let (hinge_left, tilt) = build_hinge(v, &format!("{field}.hinge"), &pair.hinge)?;
        let geometry = match &pair.wing {
            Some(w) => build_geometry(w, v, &format!("{field}.wing"), &self.aero)?,
            None => first_geometry.clone(),
        };
        let mut kinematics = match &pair.kinematics {
            Some(k) => {
                let k = k.build(v, &format!("{field}.kinematics"), geometry.r_gyration_m)?;
                [k.clone(), k]
            }
            None => [first_kinematics[0].clone(), first_kinematics[1].clone()],
        };
        let f0 = first_kinematics[0].freq_hz;
        if kinematics[0].freq_hz != f0 {
            return Err(v
                .invalid(
                    &format!("{field}.kinematics (frequency, Hz)"),
                    kinematics[0].freq_hz,
                    &format!(
                        "the first pair's frequency, {f0} Hz: all wings flap at one frequency"
                    ),
                )
                .into());
        }
        for k in &mut kinematics {
            k.phase_offset = offset_deg / 360.0;
        }
        Ok(BuiltPair {
            geometry,
            hinge_left,
            tilt,
            kinematics,
        })
    }
}

/// A `[hinge]` table validated: the left hinge in the body, m, and the stroke-plane tilt, rad.
fn build_hinge(v: &Validator<'_>, field: &str, h: &HingeSpec) -> Result<(Vector3<f64>, f64)> {
    let [hx, hy, hz] = h.left_in_body_m;
    for (i, x) in [hx, hy, hz].into_iter().enumerate() {
        v.within(&format!("{field}.left_in_body_m[{i}]"), x, -1.0, 1.0)?;
    }
    let tilt = v
        .within(
            &format!("{field}.stroke_plane_tilt_deg"),
            h.stroke_plane_tilt_deg,
            -90.0,
            90.0,
        )?
        .to_radians();
    Ok((Vector3::new(hx, hy, hz), tilt))
}

/// The mount of the `side` wing of a pair whose left hinge is `hinge_left` (the right one
/// mirrors it in y).
fn mount(hinge_left: Vector3<f64>, tilt: f64, side: Side) -> Mount {
    Mount {
        side,
        hinge_in_body_m: if side == Side::Left {
            hinge_left
        } else {
            Vector3::new(hinge_left.x, -hinge_left.y, hinge_left.z)
        },
        stroke_plane_tilt_rad: tilt,
    }
}

/// Rejects models whose derived quantities or forces are not finite (extreme but finite
/// inputs such as a 1e300 m span), naming the part of the model at fault.
pub(crate) fn check_wings(v: &Validator<'_>, wings: &[Wing]) -> Result<()> {
    for w in wings {
        wingforce::model::check_wing(v, w)?;
    }
    Ok(())
}
