//! Vehicle model files (TOML): body, wings, kinematics and their control parameters, fluid,
//! gravity, simulation settings and the initial state. Strict: unknown fields are errors and
//! every value is range-checked with an error naming file, field, value and what is allowed.
//!
//! The file's tables are plain data in `spec`; `build` validates them into a [`Vehicle`].

mod build;
mod file;
mod spec;

use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use wingforce::{Kinematics, Wing};

use crate::actuated::spec::Actuation;
use crate::error::Result;

pub use crate::controls::{Controls, DRIVE_CHANNELS, KINEMATIC_CHANNELS};
pub use file::{MAX_MODEL_FILE_BYTES, read_bounded_text, read_model_file};
pub use spec::{BodySpec, ControlSpec, HingeSpec, InitialSpec, PairSpec, SimSpec, VehicleSpec};

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
    /// How the control channels move each pair (`[[pairs]] control_gain`; 1 for the first
    /// pair): a factor on each kinematic offset but the frequency.
    pub pair_control_gains: Vec<f64>,
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

impl Vehicle {
    /// Loads a vehicle from TOML text.
    pub fn from_toml(text: &str, origin: &str) -> Result<Self> {
        VehicleSpec::from_toml(text, origin)?.build(origin)
    }

    /// The induced flow the wings meet (`[aero] inflow`; MODEL.md 4.5).
    pub fn inflow_model(&self) -> wingforce::InflowModel {
        wingforce::InflowModel::of(self.wings[0].options().induced_inflow.as_ref())
    }

    /// The vehicle with its wings meeting `model`'s induced flow instead (the comparison
    /// of `validate`'s wake columns, a `--inflow` option): the hover downwash of the weight,
    /// frozen there or the dynamic inflow's start. An error where the model file would
    /// refuse it (several pairs, actuated wings: `model/build.rs`).
    pub fn with_inflow_model(&self, model: wingforce::InflowModel) -> Result<Vehicle> {
        let mut v = self.clone();
        if model == self.inflow_model() {
            return Ok(v);
        }
        if model == wingforce::InflowModel::Frozen && v.wings.len() > 2 {
            return Err(crate::error::Error::Input(format!(
                "{}: inflow = \"frozen\" on {} wings: the frozen downwash is one pair's disc, and tandem pairs overlap theirs (the dynamic wake models that); allowed: \"off\" or \"dynamic\"",
                v.name,
                v.wings.len()
            )));
        }
        if model == wingforce::InflowModel::Frozen && v.actuation.is_some() {
            return Err(crate::error::Error::Input(format!(
                "{}: inflow = \"frozen\" on actuated wings: a frozen wake's disc is a prescribed stroke, and their stroke is an output of their dynamics; allowed: \"off\" or \"dynamic\"",
                v.name
            )));
        }
        let thrust_n = v.weight_n() / v.wings.len() as f64;
        for w in &mut v.wings {
            let mut o = w.options().clone();
            o.induced_inflow = match model {
                wingforce::InflowModel::Off => None,
                m => {
                    let mut i = o
                        .induced_inflow
                        .unwrap_or_else(|| wingforce::InducedInflow::hover(thrust_n));
                    i.dynamic = m == wingforce::InflowModel::Dynamic;
                    Some(i)
                }
            };
            w.set_options(o);
        }
        Ok(v)
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
        let gain = self.pair_control_gains.get(i / 2).copied().unwrap_or(1.0);
        // The first pair (gain 1) is moved exactly as before pairs had gains.
        let g = |x: f64| if gain == 1.0 { x } else { gain * x };
        // A measured table has no mid-stroke angle of attack; apply_controls refuses an
        // offset on one before it gets here.
        let mut k = base
            .with_aoa_offset(g(c.aoa_rad))
            .unwrap_or_else(|| base.clone());
        k.mean_stroke_rad += g(c.mean_stroke_rad + half * c.diff_mean_stroke_rad);
        k.amplitude_rad += g(c.amplitude_rad + half * c.diff_amplitude_rad);
        k.pitch_bias_rad += g(c.pitch_bias_rad + half * c.diff_pitch_bias_rad);
        k.freq_hz += c.freq_hz;
        k
    }

    /// Applies control inputs to every wing (call between wingbeats): kinematic offsets for
    /// prescribed kinematics, drive offsets (on the model's drives) for an actuated vehicle;
    /// offsets of the other kind are an error.
    pub fn apply_controls(&mut self, c: &Controls) -> Result<()> {
        if let Some(act) = &mut self.actuation {
            if !c.kinematic_is_zero() {
                return Err(crate::error::Error::Analysis(format!(
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
            return Err(crate::error::Error::Analysis(format!(
                "{} has prescribed kinematics: drive control offsets (bias {} V, amplitude {} V, ...) apply to actuated vehicles only",
                self.name, c.bias_v, c.amplitude_v
            )));
        }
        for i in 0..self.wings.len() {
            if c.aoa_rad != 0.0 {
                let Some((down, up)) = self.base_kinematics[i].mid_stroke_aoa_rad() else {
                    return Err(crate::error::Error::Analysis(format!(
                        "{}: an angle-of-attack offset ({:.2} deg) needs a kinematics family with a mid-stroke angle of attack (trapezoidal, harmonic, harmonic_flip); measured (tabulated) kinematics have none",
                        self.name,
                        c.aoa_rad.to_degrees()
                    )));
                };
                for (half, aoa) in [("downstroke", down), ("upstroke", up)] {
                    let moved = aoa + c.aoa_rad;
                    if !(moved > 0.0 && moved <= 0.5 * std::f64::consts::PI) {
                        return Err(crate::error::Error::Analysis(format!(
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
                return Err(crate::error::Error::Analysis(format!(
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
        Err(crate::error::Error::Input(format!(
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

    /// A warning when the vehicle is stepped more coarsely than its model file's stated
    /// accuracy bound (`[sim] accurate_steps_per_wingbeat`, from the error-cost frontier of
    /// docs/speed.md); `None` at or above it, or without a bound.
    pub fn coarse_step_warning(&self) -> Option<String> {
        let n = self.sim.accurate_steps_per_wingbeat?;
        (self.sim.steps_per_wingbeat < n).then(|| {
            format!(
                "`{}` is stepped at {} steps per wingbeat, coarser than the {n} its model file states for its accuracy (sim.accurate_steps_per_wingbeat, from the error-cost frontier in docs/speed.md): expect larger trajectory errors",
                self.name, self.sim.steps_per_wingbeat
            )
        })
    }

    /// Where in a step the wings' loads are taken: the model's `[sim] load_sampling`, else
    /// the step mean (second order) for prescribed wings and step-start for actuated ones. Why the
    /// actuated default stays first order, measured (docs/speed.md rows 25-26): over 30
    /// wingbeats the RoboBee and the hummingbird converge under neither sampling (each
    /// period's stroke reference is a discrete event), over one period the RoboBee's error
    /// still has a first-order remainder beyond 100 steps per wingbeat, and the midpoint costs
    /// the RoboBee 2.1x per step.
    pub fn load_sampling(&self) -> wingset::LoadSampling {
        self.sim.load_sampling.unwrap_or(match self.actuation {
            Some(_) => wingset::LoadSampling::StepStart,
            None => wingset::LoadSampling::StepMean,
        })
    }

    /// How flapsim's hosts share an actuated wing's stop strike between body steps
    /// (wingset's `actuated::StrikeShare`): the model's replay setting, else by their pose
    /// update, the trapezoidal rule under a second-order sampling
    /// ([`crate::host::trapezoid_pose`]) and rapier's semi-implicit Euler otherwise.
    pub fn strike_share(&self) -> wingset::actuated::StrikeShare {
        use wingset::actuated::StrikeShare;
        self.sim
            .strike_share
            .unwrap_or(match self.load_sampling().is_second_order() {
                true => StrikeShare::TrapezoidalPose,
                false => StrikeShare::SemiImplicitPose,
            })
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
