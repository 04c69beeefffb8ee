//! flapwing's own host of the wing set: one vehicle as a rapier3d-f64 rigid body in a
//! private world.
//!
//! Each step at time t_k: the [`WingSet`] returns the loads over [t_k, t_k + dt] from the
//! body's state at t_k (see [`crate::wings`]); their sum (force and moment about the centre
//! of mass) replaces the body's user force and torque (rapier keeps user forces until reset)
//! and rapier advances the body by dt. [`StepOutput`] pairs the state at t_k with the loads
//! applied over [t_k, t_k + dt].

use nalgebra::{UnitQuaternion, Vector3};
use rapier3d_f64::na::Unit;
use rapier3d_f64::prelude::*;
use serde::{Deserialize, Serialize};
use wingforce::WingForces;

use crate::actuated::ActuatedWingOutput;
use crate::error::{Error, Result};
use crate::frames::{quat_to_glam, to_glam};
use crate::model::{Controls, Vehicle};
use crate::wind::Wind;
pub use crate::wings::{BodyLoad, State};
use crate::wings::{FromVehicle, WingSet, WingSetOutput};

mod actuated;

/// Which degrees of freedom the body has.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Mode {
    /// All six degrees of freedom.
    Free,
    /// Body held still; the loads are what a force sensor on the tether would read.
    Tethered,
    /// Free with some world-axis translations and rotations locked.
    Locked {
        /// Translations along world x, y, z allowed.
        translations: [bool; 3],
        /// Rotations about world x, y, z allowed.
        rotations: [bool; 3],
    },
}

impl Mode {
    /// Longitudinal motion only: surge (x), heave (z) and pitch (about y).
    pub const LONGITUDINAL: Mode = Mode::Locked {
        translations: [true, false, true],
        rotations: [false, true, false],
    };
}

/// What one step computed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepOutput {
    /// Step index k.
    pub step: u64,
    /// t_k, s.
    pub t_s: f64,
    /// Wingbeat phase at t_k (cycles).
    pub phase: f64,
    /// State at t_k.
    pub state: State,
    /// The first pair's forces (0 left, 1 right). A vehicle with further pairs (`[[pairs]]`)
    /// has theirs in the totals below and each wing's in [`Simulation::wings`]' output.
    pub wings: [WingForces; 2],
    /// Aerodynamic load of each term, all wings, about the CoM.
    pub terms: [BodyLoad; 4],
    /// Inertial reaction of the wings' masses (zero for massless wings).
    pub wing_inertia: BodyLoad,
    /// Everything applied to the body except gravity.
    pub total: BodyLoad,
    /// Controls in force during this step.
    pub controls: Controls,
    /// Hinge and actuator state of each wing of an actuated vehicle (0 left, 1 right).
    pub actuated: Option<[ActuatedWingOutput; 2]>,
    /// The wing set's memory of the step before this one, which this step's midpoint
    /// prediction used (`None` for the step-start sampling and after a restart): logged,
    /// it lets a replay restart here bit for bit ([`Simulation::set_step_memory`]).
    pub memory: Option<wingset::StepMemory>,
}

impl StepOutput {
    /// The first two wings' results of a wing-set step, with the body's state at t_k.
    fn fill(&mut self, o: &WingSetOutput, state: &State) {
        self.step = o.step;
        self.t_s = o.t_s;
        self.phase = o.phase;
        self.state = *state;
        for (w, f) in self.wings.iter_mut().zip(&o.wings) {
            *w = *f;
        }
        self.terms = o.terms;
        self.wing_inertia = o.wing_inertia;
        self.total = o.total;
        self.controls = o.controls;
        self.actuated = match o.actuated.as_slice() {
            [l, r, ..] => Some([*l, *r]),
            _ => None,
        };
    }

    /// All zeros, at rest, at t = 0.
    fn empty() -> Self {
        let wing = crate::wings::zero_forces();
        Self {
            step: 0,
            t_s: 0.0,
            phase: 0.0,
            state: State {
                position_m: Vector3::zeros(),
                world_from_body: UnitQuaternion::identity(),
                velocity_m_s: Vector3::zeros(),
                angular_velocity_body_rad_s: Vector3::zeros(),
            },
            wings: [wing; 2],
            terms: Default::default(),
            wing_inertia: BodyLoad::default(),
            total: BodyLoad::default(),
            controls: Controls::default(),
            actuated: None,
            memory: None,
        }
    }
}

/// A simulation of one vehicle. Drive it step by step ([`Simulation::step`]) or run it for a
/// duration ([`Simulation::run_for`]).
pub struct Simulation {
    /// The model as loaded (the wing set holds the one with the controls in force).
    vehicle: Vehicle,
    mode: Mode,
    world: PhysicsWorld,
    body: RigidBodyHandle,
    /// The wings: the force element this host steps.
    wings: WingSet,
    /// What the last step computed (boxed so that it moves cheaply).
    out: Option<Box<StepOutput>>,
    /// The uniform wind of [`Simulation::set_wind`], world, m/s.
    uniform_wind_m_s: Vector3<f64>,
    /// A wind field evaluated at each wing's hinge every step ([`Simulation::set_wind_model`]).
    wind: Option<Box<Wind>>,
    /// Each wing's wind at the last step, world, m/s (with a wind field).
    wing_winds_m_s: Vec<Vector3<f64>>,
    /// Whether the wings' dynamic inflow still has to be started on its periodic motion at
    /// the first step's body state ([`Simulation::step`]).
    settle_inflow: bool,
    /// Whether the body's angular velocity is advanced by the midpoint rule
    /// ([`crate::host::midpoint_torque_world`]): free flight under a second-order load
    /// sampling, unless the model asks for rapier's own update (`sim.rotation_at_step_start`,
    /// logs written before it).
    midpoint_rotation: bool,
}

impl std::fmt::Debug for Simulation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Simulation")
            .field("vehicle", &self.vehicle.name)
            .field("mode", &self.mode)
            .field("dt_s", &self.dt_s())
            .field("step", &self.steps())
            .finish_non_exhaustive()
    }
}

impl Simulation {
    /// A simulation of `vehicle` in `mode`, starting from the vehicle's initial state at t = 0
    /// (an actuated vehicle's wings at rest at their springs' rest angles).
    pub fn new(vehicle: Vehicle, mode: Mode) -> Self {
        // A built vehicle's drives were checked against the voltage limit and its two wings
        // are on opposite sides: the wing set accepts every vehicle `Vehicle::from_toml` built.
        Self::try_new(vehicle, mode)
            .expect("a vehicle that was built checks out as a wing set (model/build.rs checks)")
    }

    /// [`Simulation::new`], with the wing set's objections (a vehicle assembled by hand with
    /// a bad drive) as an error.
    pub fn try_new(vehicle: Vehicle, mode: Mode) -> Result<Self> {
        let mut wings = WingSet::from_vehicle_sized(&vehicle)?;
        // This host moves the body by the trapezoidal rule under a second-order sampling.
        wings.set_strike_share(vehicle.strike_share());
        let dt_s = wings.dt_s();
        let mut world = PhysicsWorld::new();
        world.gravity = Vector::new(0.0, 0.0, -vehicle.gravity_m_s2);
        world.integration_parameters.dt = dt_s;
        world.integration_parameters.num_solver_iterations = vehicle.sim.solver_iterations;
        world.integration_parameters.length_unit = 1.0;
        let mut builder = crate::host::vehicle_body(&vehicle);
        let (lin, ang) = match mode {
            Mode::Tethered => (Vector3::zeros(), Vector3::zeros()),
            _ => (
                vehicle.initial_velocity_m_s,
                vehicle.initial_attitude * vehicle.initial_angular_velocity_rad_s,
            ),
        };
        builder = builder.linvel(to_glam(&lin)).angvel(to_glam(&ang));
        builder = match mode {
            Mode::Free => builder,
            Mode::Tethered => {
                builder.locked_axes(LockedAxes::TRANSLATION_LOCKED | LockedAxes::ROTATION_LOCKED)
            }
            Mode::Locked {
                translations: t,
                rotations: r,
            } => builder
                .enabled_translations(t[0], t[1], t[2])
                .enabled_rotations(r[0], r[1], r[2]),
        };
        let midpoint_rotation = matches!(mode, Mode::Free)
            && vehicle.load_sampling().is_second_order()
            && !vehicle.sim.rotation_at_step_start;
        builder = builder.gyroscopic_forces_enabled(!midpoint_rotation);
        let body = world.insert_body(builder);
        if vehicle.sim.ground {
            world.insert_collider(
                ColliderBuilder::halfspace(Unit::new_unchecked(Vector::Z)).friction(0.8),
                None,
            );
            world.insert_collider(
                ColliderBuilder::ball(0.5 * vehicle.length_m)
                    .density(0.0)
                    .restitution(0.0),
                Some(body),
            );
        }
        let mut sim = Self {
            vehicle,
            mode,
            world,
            body,
            wings,
            out: None,
            uniform_wind_m_s: Vector3::zeros(),
            wind: None,
            wing_winds_m_s: Vec::new(),
            settle_inflow: true,
            midpoint_rotation,
        };
        sim.settle_inflow = sim.wings.pair_inflows().is_some();
        // Zero the velocities on locked axes (rapier leaves them as given).
        if let Mode::Locked {
            translations: t,
            rotations: r,
        } = mode
        {
            let mask = |on: bool, x: f64| if on { x } else { 0.0 };
            let v = Vector3::new(mask(t[0], lin.x), mask(t[1], lin.y), mask(t[2], lin.z));
            let w = Vector3::new(mask(r[0], ang.x), mask(r[1], ang.y), mask(r[2], ang.z));
            let rb = &mut sim.world.bodies[sim.body];
            rb.set_linvel(to_glam(&v), true);
            rb.set_angvel(to_glam(&w), true);
        }
        Ok(sim)
    }

    /// The vehicle (wings carry the kinematics currently in force).
    pub fn vehicle(&self) -> &Vehicle {
        self.wings.vehicle().unwrap_or(&self.vehicle)
    }
    /// The wing set this host steps (the force element; see [`crate::wings`]).
    pub fn wing_set(&self) -> &WingSet {
        &self.wings
    }
    /// The mode.
    pub fn mode(&self) -> Mode {
        self.mode
    }
    /// Step length, s.
    pub fn dt_s(&self) -> f64 {
        self.wings.dt_s()
    }
    /// Steps taken so far.
    pub fn steps(&self) -> u64 {
        self.wings.steps()
    }
    /// Current time, s.
    pub fn time_s(&self) -> f64 {
        self.wings.time_s()
    }
    /// Wingbeat phase now, cycles (see [`WingSet::phase`]).
    pub fn phase(&self) -> f64 {
        self.wings.phase()
    }

    /// Controls to apply at the start of the next wingbeat (immediately if none has begun).
    pub fn set_controls(&mut self, controls: Controls) {
        // A set built from a vehicle always takes controls.
        let _ = self.wings.set_controls(controls);
    }

    /// Continues the clock from step `step` (time `step * dt`), as if the steps before had
    /// been flown with the controls in force now ([`WingSet::start_at_step`]): with
    /// [`Simulation::set_state`] to the state a logged run had at that step, a segment of the
    /// run replays it bit for bit. Call before the first step; prescribed wings only.
    pub fn start_at_step(&mut self, step: u64) -> Result<()> {
        Ok(self.wings.start_at_step(step)?)
    }

    /// Holds the wings still (no aerodynamic loads at all) or lets them flap again.
    pub fn set_wings_still(&mut self, still: bool) {
        self.wings.set_still(still);
    }

    /// Uniform wind, world frame, m/s (a gust is a wind that changes with time). With a
    /// wind field ([`Simulation::set_wind_model`]) it adds to the field.
    pub fn set_wind(&mut self, wind_world_m_s: Vector3<f64>) {
        self.uniform_wind_m_s = wind_world_m_s;
        self.wings.set_wind(wind_world_m_s);
    }

    /// The uniform wind of [`Simulation::set_wind`], world frame, m/s.
    pub fn uniform_wind_m_s(&self) -> Vector3<f64> {
        self.uniform_wind_m_s
    }

    /// A wind field (steady wind, gusts, turbulence: [`crate::wind`]) evaluated every step
    /// at each wing's hinge, body position + attitude * hinge_in_body_m, at t_k, plus the
    /// uniform wind of [`Simulation::set_wind`]; `None` returns to the uniform wind alone.
    pub fn set_wind_model(&mut self, wind: Option<Wind>) {
        self.wind = wind.map(Box::new);
        if self.wind.is_none() {
            self.wings.set_wind(self.uniform_wind_m_s);
            self.wing_winds_m_s.clear();
        }
    }

    /// The wind field, if one is set.
    pub fn wind_model(&self) -> Option<&Wind> {
        self.wind.as_deref()
    }

    /// Each wing's wind at the last step's t_k, world frame, m/s (empty before the first
    /// step or without a wind field).
    pub fn wing_winds_m_s(&self) -> &[Vector3<f64>] {
        &self.wing_winds_m_s
    }

    /// Evaluates the wind field at each wing's hinge at the state's time and hands the
    /// winds to the wing set.
    fn update_wing_winds(&mut self, state: &State) -> Result<()> {
        let Some(wind) = &mut self.wind else {
            return Ok(());
        };
        let t = self.wings.time_s();
        self.wing_winds_m_s.clear();
        for w in self.wings.wings() {
            let p = state.position_m + state.world_from_body * w.mount().hinge_in_body_m;
            self.wing_winds_m_s
                .push(self.uniform_wind_m_s + wind.velocity_world_m_s(&p, t));
        }
        Ok(self.wings.set_wing_winds(&self.wing_winds_m_s)?)
    }

    /// The body's state now.
    pub fn state(&self) -> State {
        crate::host::body_state(&self.world.bodies[self.body])
    }

    /// After [`Simulation::set_state`] at a step a log recorded: gives the wings the
    /// memory of the step before that the log holds ([`StepOutput::memory`]), so the run
    /// continues as the logged one did, bit for bit. An error unless it is the memory of the
    /// step just before the next one.
    pub fn set_step_memory(&mut self, memory: wingset::StepMemory) -> Result<()> {
        Ok(self.wings.set_step_memory(memory)?)
    }

    /// Overwrites the body's state (for disturbances and Floquet perturbations).
    pub fn set_state(&mut self, s: &State) {
        // Not a state the loads moved the body to: the next step starts the midpoint
        // prediction afresh (wingset::sampling).
        self.wings.restart_motion();
        let rb = &mut self.world.bodies[self.body];
        rb.set_position(
            Pose::from_parts(to_glam(&s.position_m), quat_to_glam(&s.world_from_body)),
            true,
        );
        rb.set_linvel(to_glam(&s.velocity_m_s), true);
        rb.set_angvel(
            to_glam(&(s.world_from_body * s.angular_velocity_body_rad_s)),
            true,
        );
    }

    /// Loads at the current state without stepping (with a wind field, in the wings' winds
    /// of the last step).
    pub fn loads(&self) -> StepOutput {
        let state = self.state();
        let mut out = StepOutput::empty();
        match self.wings.loads(&state) {
            Ok(o) => out.fill(&o, &state),
            // The state came from rapier's integration of finite loads; a non-finite one is
            // reported by the next step.
            Err(_) => out.state = state,
        }
        out
    }

    /// Replaces each wing pair's dynamic inflow states (a Floquet perturbation, a start
    /// where a run left off); the first step then keeps them instead of starting the inflow
    /// on its periodic motion.
    pub fn set_inflow_states(&mut self, states: &[wingforce::inflow::InflowState]) -> Result<()> {
        self.wings.set_inflow_states(states)?;
        self.settle_inflow = false;
        Ok(())
    }

    /// Starts a dynamic inflow on its periodic motion at the body's state now (held frozen:
    /// `crate::averaged::periodic_inflow`), as a run that has been going on would have it,
    /// instead of at the hover inflow of the weight the set starts from. Where the inflow
    /// has no periodic motion at that state (`periodic_inflow`'s error), the run starts
    /// from the set's own start and its first steps are the wake building up.
    fn start_inflow(&mut self, state: &State) -> Result<()> {
        self.settle_inflow = false;
        let motion = wingforce::BodyMotion {
            velocity_m_s: state.world_from_body.inverse()
                * (state.velocity_m_s - self.uniform_wind_m_s),
            angular_velocity_rad_s: state.angular_velocity_body_rad_s,
        };
        let steps = self.vehicle.sim.steps_per_wingbeat as usize;
        if let Ok(Some(p)) = crate::averaged::periodic_inflow(&self.vehicle, &motion, steps) {
            self.wings.set_inflow_states(&p.states)?;
        }
        crate::cancel::check()
    }

    /// Advances one step; returns what was applied during it.
    pub fn step(&mut self) -> Result<&StepOutput> {
        let state = self.state();
        // A runaway state names the bound it broke (sim.max_speed_m_s, ...) before the wings
        // see it (their loads would overflow at such speeds, with no knob to name).
        self.check_state(&state)?;
        if self.settle_inflow {
            self.start_inflow(&state)?;
        }
        if self.wind.is_some() && state.first_non_finite().is_none() {
            self.update_wing_winds(&state)?;
        }
        let mut out = self
            .out
            .take()
            .unwrap_or_else(|| Box::new(StepOutput::empty()));
        let memory = self.wings.step_memory();
        let r = match self.wings.step(&state) {
            Ok(o) => {
                out.fill(o, &state);
                out.memory = memory;
                self.check(&out)
            }
            // The wing set refuses a non-finite state: here that is the run diverging.
            Err(Error::Input(_)) if state.first_non_finite().is_some() => Err(Error::Diverged {
                t_s: self.wings.time_s(),
                step: self.wings.steps(),
                reason: "the body state is not finite".into(),
            }),
            Err(e) => Err(e),
        };
        if let Err(e) = r {
            // What the wings computed before the failure stays readable.
            out.fill(self.wings.output(), &state);
            self.out = Some(out);
            return Err(e);
        }
        // The body drag is taken where the wings took their loads (wingset::sampling).
        let drag_velocity_m_s = self.wings.sampled_state().velocity_m_s;
        Ok(self.apply_and_advance(out, &drag_velocity_m_s))
    }

    /// Applies a step's loads to the body and advances the world by one step.
    fn apply_and_advance(
        &mut self,
        out: Box<StepOutput>,
        drag_velocity_m_s: &Vector3<f64>,
    ) -> &StepOutput {
        let rb = &mut self.world.bodies[self.body];
        let q = out.state.world_from_body;
        rb.reset_forces(false);
        rb.reset_torques(false);
        // The body's parasite drag (`[body] drag_area_m2`, crate::flight) in the air at its
        // centre of mass: the uniform wind, or the wings' winds averaged with a wind field.
        let air_m_s = if self.wing_winds_m_s.is_empty() {
            self.uniform_wind_m_s
        } else {
            self.wing_winds_m_s.iter().sum::<Vector3<f64>>() / self.wing_winds_m_s.len() as f64
        };
        let drag_n = self
            .vehicle
            .body_drag_world_n(&(drag_velocity_m_s - air_m_s));
        rb.add_force(to_glam(&(q * out.total.force_n + drag_n)), false);
        let moment_world = q * out.total.moment_nm;
        let torque_world = match self.midpoint_rotation {
            true => crate::host::midpoint_torque_world(
                &moment_world,
                &q,
                self.wings.sampled_state(),
                &self.vehicle.inertia_kg_m2,
            ),
            false => moment_world,
        };
        rb.add_torque(to_glam(&torque_world), false);
        self.world.step();
        if self.wings.load_sampling().is_second_order() {
            self.trapezoid_pose(&out.state);
        }
        self.out.insert(out)
    }

    /// Moves the pose rapier integrated from the step's start `before` to the trapezoidal
    /// rule's ([`crate::host::trapezoid_pose`]).
    fn trapezoid_pose(&mut self, before: &State) {
        let substeps = self.world.integration_parameters.num_solver_iterations;
        let rb = &mut self.world.bodies[self.body];
        crate::host::trapezoid_pose(rb, before, self.wings.dt_s(), substeps);
    }

    /// The body state at a step's start against the run's bounds (finite, sim.max_speed_m_s,
    /// sim.max_angular_speed_rad_s): a divergence at the step about to be taken.
    fn check_state(&self, s: &State) -> Result<()> {
        let fail = |reason: String| {
            Err(Error::Diverged {
                t_s: self.wings.time_s(),
                step: self.wings.steps(),
                reason,
            })
        };
        let finite = |v: &Vector3<f64>| v.iter().all(|x| x.is_finite());
        if !finite(&s.position_m)
            || !finite(&s.velocity_m_s)
            || !finite(&s.angular_velocity_body_rad_s)
        {
            // The last step's loads may have driven the body past a bound in one step, and the
            // integrator overflowed on the way: name the bound they broke.
            if let Some(out) = &self.out {
                let dt = self.wings.dt_s();
                let p = &out.state;
                let v = (p.velocity_m_s
                    + dt * (p.world_from_body * out.total.force_n) / self.vehicle.mass_kg)
                    .norm();
                let w = self
                    .vehicle
                    .inertia_kg_m2
                    .try_inverse()
                    .map_or(f64::INFINITY, |i| {
                        (p.angular_velocity_body_rad_s + dt * (i * out.total.moment_nm)).norm()
                    });
                let (max_v, max_w) = (
                    self.vehicle.sim.max_speed_m_s,
                    self.vehicle.sim.max_angular_speed_rad_s,
                );
                if !(w <= max_w) {
                    return fail(format!(
                        "the last step's loads drove the angular speed to {w:.3e} rad/s, beyond sim.max_angular_speed_rad_s = {max_w}, and the body state is no longer finite"
                    ));
                }
                if !(v <= max_v) {
                    return fail(format!(
                        "the last step's loads drove the speed to {v:.3e} m/s, beyond sim.max_speed_m_s = {max_v}, and the body state is no longer finite"
                    ));
                }
            }
            return fail("the body state is not finite".into());
        }
        let speed = s.velocity_m_s.norm();
        if speed > self.vehicle.sim.max_speed_m_s {
            return fail(format!(
                "speed {speed:.3} m/s exceeds sim.max_speed_m_s = {}",
                self.vehicle.sim.max_speed_m_s
            ));
        }
        let w = s.angular_velocity_body_rad_s.norm();
        if w > self.vehicle.sim.max_angular_speed_rad_s {
            return fail(format!(
                "angular speed {w:.1} rad/s exceeds sim.max_angular_speed_rad_s = {}",
                self.vehicle.sim.max_angular_speed_rad_s
            ));
        }
        Ok(())
    }

    /// A step's loads: finite (after [`Simulation::check_state`], so a load that overflowed
    /// at a runaway speed has named the speed already).
    fn check(&self, out: &StepOutput) -> Result<()> {
        let finite = |v: &Vector3<f64>| v.iter().all(|x| x.is_finite());
        if !finite(&out.total.force_n) || !finite(&out.total.moment_nm) {
            return Err(Error::Diverged {
                t_s: out.t_s,
                step: out.step,
                reason: "the aerodynamic load is not finite".into(),
            });
        }
        Ok(())
    }

    /// Like [`Simulation::run_for`], but stops early (returning `Ok(false)`) as soon as
    /// `observer` returns false, e.g. on Ctrl-C; `Ok(true)` when the whole duration ran.
    pub fn run_while(
        &mut self,
        duration_s: f64,
        mut observer: impl FnMut(&StepOutput) -> bool,
    ) -> Result<bool> {
        let n = (duration_s / self.dt_s()).round() as u64;
        for _ in 0..n {
            let out = self.step()?;
            if !observer(&out) {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// Runs for `duration_s` (rounded to whole steps), calling `observer` after every step.
    /// On divergence the observer has seen every step up to the failing one.
    pub fn run_for(
        &mut self,
        duration_s: f64,
        mut observer: impl FnMut(&StepOutput),
    ) -> Result<()> {
        self.run_while(duration_s, |o| {
            observer(o);
            true
        })
        .map(|_| ())
    }
}
