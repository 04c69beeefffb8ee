//! The vehicle as a rapier3d-f64 rigid body fed wing forces every step.
//!
//! Each step at time t_k: both wings' forces are evaluated from their kinematics at the
//! wingbeat phase of t_k and the body's air-relative linear and angular velocity at t_k;
//! their sum (force and moment about the centre of mass) replaces the body's user force and
//! torque (rapier keeps user forces until reset) and rapier advances the body by dt.
//! [`StepOutput`] pairs the state at t_k with the loads applied over [t_k, t_k + dt].

use nalgebra::{UnitQuaternion, Vector3};
use rapier3d_f64::na::Unit;
use rapier3d_f64::prelude::*;
use serde::{Deserialize, Serialize};
use wingforce::{BodyMotion, KinematicLoads, Term, Wing, WingForces};

use crate::actuated::{ActuatedWingOutput, DynamicWing};
use crate::error::{Error, Result};
use crate::frames::{from_glam, quat_from_glam, quat_to_glam, to_glam};
use crate::model::{Controls, Vehicle};

mod actuated;
use actuated::actuated_loads_into;

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

/// Force and moment about the centre of mass, body frame.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct BodyLoad {
    /// Force, body frame, N.
    pub force_n: Vector3<f64>,
    /// Moment about the centre of mass, body frame, N m.
    pub moment_nm: Vector3<f64>,
}

impl BodyLoad {
    pub(crate) fn add(&mut self, f: Vector3<f64>, m: Vector3<f64>) {
        self.force_n += f;
        self.moment_nm += m;
    }
}

/// The body's state.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct State {
    /// Position of the centre of mass, world (z up), m.
    pub position_m: Vector3<f64>,
    /// Attitude: world_from_body.
    pub world_from_body: UnitQuaternion<f64>,
    /// Velocity of the centre of mass, world frame, m/s.
    pub velocity_m_s: Vector3<f64>,
    /// Angular velocity, body frame, rad/s.
    pub angular_velocity_body_rad_s: Vector3<f64>,
}

impl State {
    /// Roll, pitch (positive nose up) and yaw, rad.
    pub fn euler_rad(&self) -> (f64, f64, f64) {
        let (r, p, y) = self.world_from_body.euler_angles();
        (r, -p, y)
    }
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
    /// Each wing's forces (0 left, 1 right).
    pub wings: [WingForces; 2],
    /// Aerodynamic load of each term, both wings, about the CoM.
    pub terms: [BodyLoad; 4],
    /// Inertial reaction of the wings' masses (zero for massless wings).
    pub wing_inertia: BodyLoad,
    /// Everything applied to the body except gravity.
    pub total: BodyLoad,
    /// Controls in force during this step.
    pub controls: Controls,
    /// Hinge and actuator state of each wing of an actuated vehicle (0 left, 1 right).
    pub actuated: Option<[ActuatedWingOutput; 2]>,
}

/// Longest wingbeat, in steps, whose kinematic loads are kept (about 1 KB per step).
const MAX_TABLE_STEPS: u64 = 4096;

impl StepOutput {
    /// All zeros, at rest, at t = 0.
    fn empty() -> Self {
        let wing = WingForces {
            terms: Default::default(),
            total: Default::default(),
            angles: Default::default(),
            phase: wingforce::StrokePhase {
                half_stroke: 0,
                t_star: 0.0,
                downstroke: true,
            },
        };
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
        }
    }
}

/// A simulation of one vehicle. Drive it step by step ([`Simulation::step`]) or run it for a
/// duration ([`Simulation::run_for`]).
pub struct Simulation {
    vehicle: Vehicle,
    mode: Mode,
    world: PhysicsWorld,
    body: RigidBodyHandle,
    dt_s: f64,
    step: u64,
    /// Phase at `base_step` and the phase advance per step since then.
    base_phase: f64,
    base_step: u64,
    phase_per_step: f64,
    /// Steps per wingbeat at the frequency the step was sized for.
    steps_per_wingbeat: u64,
    /// The wingbeat frequency is still the one the step was sized for, so the kinematics
    /// repeat exactly every `steps_per_wingbeat` steps (see [`Simulation::phase`]).
    periodic: bool,
    /// Both wings' [`KinematicLoads`] at each step of the wingbeat (periodic runs only),
    /// computed the first time the step comes round and reused every wingbeat after until
    /// the controls change. An entry holds for the controls of generation `table_gen` only
    /// (so that a control change needs no clearing).
    phase_table: Vec<Option<(u64, [KinematicLoads; 2])>>,
    table_gen: u64,
    /// The wingbeat frequency the step was sized for, Hz.
    sized_for_hz: f64,
    /// What the last step computed (boxed so that it moves cheaply).
    out: Option<Box<StepOutput>>,
    pending: Option<Controls>,
    /// Wingbeat index of the last step taken.
    last_cycle: i64,
    wind_world_m_s: Vector3<f64>,
    /// Centroid radius of each wing (for wing inertia), m.
    wing_centroid_r_m: f64,
    /// Wings held still: no aerodynamic or wing-inertia loads (free fall, tests).
    wings_still: bool,
    /// The wings' dynamics of an actuated vehicle (left, right).
    dynamic: Option<Box<[DynamicWing; 2]>>,
}

impl std::fmt::Debug for Simulation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Simulation")
            .field("vehicle", &self.vehicle.name)
            .field("mode", &self.mode)
            .field("dt_s", &self.dt_s)
            .field("step", &self.step)
            .finish_non_exhaustive()
    }
}

impl Simulation {
    /// A simulation of `vehicle` in `mode`, starting from the vehicle's initial state at t = 0
    /// (an actuated vehicle's wings at rest at their springs' rest angles).
    pub fn new(vehicle: Vehicle, mode: Mode) -> Self {
        let dynamic = vehicle.actuation.as_ref().map(|a| {
            Box::new([0, 1].map(|i| {
                DynamicWing::new(a.dynamics.clone(), a.drives[i]).expect(
                    "drives were checked against the voltage limit when the model was built",
                )
            }))
        });
        let dt_s = 1.0 / (vehicle.freq_hz() * vehicle.sim.steps_per_wingbeat as f64);
        let mut world = PhysicsWorld::new();
        world.gravity = Vector::new(0.0, 0.0, -vehicle.gravity_m_s2);
        world.integration_parameters.dt = dt_s;
        world.integration_parameters.num_solver_iterations = vehicle.sim.solver_iterations;
        world.integration_parameters.length_unit = 1.0;
        let i = &vehicle.inertia_kg_m2;
        let inertia = Matrix::from_cols_array(&[
            i[(0, 0)],
            i[(1, 0)],
            i[(2, 0)],
            i[(0, 1)],
            i[(1, 1)],
            i[(2, 1)],
            i[(0, 2)],
            i[(1, 2)],
            i[(2, 2)],
        ]);
        let props = MassProperties::with_inertia_matrix(Vector::ZERO, vehicle.mass_kg, inertia);
        let q = quat_to_glam(&vehicle.initial_attitude);
        let mut builder = RigidBodyBuilder::dynamic()
            .pose(Pose::from_parts(to_glam(&vehicle.initial_position_m), q))
            .additional_mass_properties(props)
            .can_sleep(false)
            .allow_fast_rotation(true);
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
        let g = vehicle.wings[0].geometry();
        let wing_centroid_r_m = g.strips.iter().map(|s| s.area_m2 * s.r_m).sum::<f64>() / g.area_m2;
        let steps_per_wingbeat = vehicle.sim.steps_per_wingbeat as u64;
        let vehicle_freq_hz = vehicle.freq_hz();
        let controls = vehicle.controls;
        let mut sim = Self {
            vehicle,
            mode,
            world,
            body,
            dt_s,
            step: 0,
            base_phase: 0.0,
            base_step: 0,
            phase_per_step: 1.0 / steps_per_wingbeat as f64,
            steps_per_wingbeat,
            periodic: true,
            phase_table: Vec::new(),
            table_gen: 0,
            sized_for_hz: vehicle_freq_hz,
            out: None,
            pending: None,
            last_cycle: 0,
            wind_world_m_s: Vector3::zeros(),
            wing_centroid_r_m,
            wings_still: false,
            dynamic,
        };
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
        sim.pending = Some(controls);
        sim
    }

    /// The vehicle (wings carry the kinematics currently in force).
    pub fn vehicle(&self) -> &Vehicle {
        &self.vehicle
    }
    /// The mode.
    pub fn mode(&self) -> Mode {
        self.mode
    }
    /// Step length, s.
    pub fn dt_s(&self) -> f64 {
        self.dt_s
    }
    /// Steps taken so far.
    pub fn steps(&self) -> u64 {
        self.step
    }
    /// Current time, s.
    pub fn time_s(&self) -> f64 {
        self.step as f64 * self.dt_s
    }
    /// Wingbeat phase now, cycles. While the frequency is the one the step was sized for,
    /// the phase advances by exactly 1/`steps_per_wingbeat` per step within a wingbeat and
    /// by exactly 1 per wingbeat, and the kinematics are evaluated at the phase's first
    /// wingbeat after the last control change: they repeat bit for bit every wingbeat.
    pub fn phase(&self) -> f64 {
        let (cycles, table_phase, _) = self.phase_parts();
        table_phase + cycles as f64
    }

    /// Whole wingbeats since the last control change, the phase at which the kinematics are
    /// evaluated, and the index of the step in the wingbeat (periodic runs only).
    fn phase_parts(&self) -> (u64, f64, Option<usize>) {
        let n = self.step - self.base_step;
        if self.periodic {
            let (m, j) = (n / self.steps_per_wingbeat, n % self.steps_per_wingbeat);
            (
                m,
                self.base_phase + j as f64 * self.phase_per_step,
                Some(j as usize),
            )
        } else {
            (0, self.base_phase + n as f64 * self.phase_per_step, None)
        }
    }

    /// Both wings' kinematic loads at a phase.
    fn kinematic_loads(&self, phase: f64) -> [KinematicLoads; 2] {
        let [l, r] = &self.vehicle.wings;
        if self.vehicle.mirror_symmetric {
            Wing::mirrored_kinematic_loads(l, r, phase)
        } else {
            [l.kinematic_loads(phase), r.kinematic_loads(phase)]
        }
    }

    /// Controls to apply at the start of the next wingbeat (immediately if none has begun).
    pub fn set_controls(&mut self, controls: Controls) {
        self.pending = Some(controls);
    }

    /// Holds the wings still (no aerodynamic loads at all) or lets them flap again.
    pub fn set_wings_still(&mut self, still: bool) {
        self.wings_still = still;
    }

    /// Uniform wind, world frame, m/s (a gust is a wind that changes with time).
    pub fn set_wind(&mut self, wind_world_m_s: Vector3<f64>) {
        self.wind_world_m_s = wind_world_m_s;
    }

    /// The body's state now.
    pub fn state(&self) -> State {
        let rb = &self.world.bodies[self.body];
        let q = quat_from_glam(rb.rotation());
        State {
            position_m: from_glam(rb.translation()),
            world_from_body: q,
            velocity_m_s: from_glam(rb.linvel()),
            angular_velocity_body_rad_s: q.inverse() * from_glam(rb.angvel()),
        }
    }

    /// Overwrites the body's state (for disturbances and Floquet perturbations).
    pub fn set_state(&mut self, s: &State) {
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

    /// Loads at the current state without stepping.
    pub fn loads(&self) -> StepOutput {
        if let Some(d) = &self.dynamic {
            // The wings' accelerations come out of a step: step copies of them.
            let mut d = d.clone();
            let mut wings = self.vehicle.wings.clone();
            let mut out = StepOutput::empty();
            // A state the step would reject still gets its loads reported as far as known.
            let _ = actuated_loads_into(&self.actuated_ctx(), &mut d, &mut wings, &mut out);
            return out;
        }
        let (cycles, table_phase, j) = self.phase_parts();
        let kin = match j.and_then(|j| self.phase_table.get(j)) {
            Some(Some((g, k))) if *g == self.table_gen => *k,
            _ => self.kinematic_loads(table_phase),
        };
        let mut out = StepOutput::empty();
        self.loads_into(&kin, cycles, table_phase, &mut out);
        out
    }

    /// The loads at the current state from both wings' kinematic loads, written into `out`.
    fn loads_into(
        &self,
        kin: &[KinematicLoads; 2],
        cycles: u64,
        table_phase: f64,
        out: &mut StepOutput,
    ) {
        let state = self.state();
        let body_from_world = state.world_from_body.inverse();
        let motion = BodyMotion {
            velocity_m_s: body_from_world * (state.velocity_m_s - self.wind_world_m_s),
            angular_velocity_rad_s: state.angular_velocity_body_rad_s,
        };
        let [l, r] = &self.vehicle.wings;
        out.wings = Wing::evaluate_pair_with(l, r, kin, &motion);
        if cycles > 0 {
            for w in &mut out.wings {
                w.phase.half_stroke += 2 * cycles as i64;
            }
        }
        let mut terms = [BodyLoad::default(); 4];
        let mut total = BodyLoad::default();
        if !self.wings_still {
            for (w, f) in self.vehicle.wings.iter().zip(&out.wings) {
                let hinge = &w.mount().hinge_in_body_m;
                for term in Term::ALL {
                    let t = f.term(term);
                    let m = t.moment_about_com_nm(hinge);
                    terms[term as usize].add(t.force_n, m);
                    total.add(t.force_n, m);
                }
            }
        }
        let mut wing_inertia = BodyLoad::default();
        let m_w = self.vehicle.sim.wing_mass_kg;
        if m_w > 0.0 && !self.wings_still {
            for (w, k) in self.vehicle.wings.iter().zip(kin) {
                // Reaction of the wing's centre of mass (on the pitch axis at its centroid
                // radius) accelerating with the kinematics: -m a, applied at the hinge.
                let fr = &k.frame;
                let p = self.wing_centroid_r_m * fr.e_span;
                let a = fr.alpha.cross(&p) + fr.omega.cross(&fr.omega.cross(&p));
                let f_s = -m_w * a;
                let r = w.body_from_stroke();
                let f_b = r * f_s;
                let m_b = r * p.cross(&f_s) + w.mount().hinge_in_body_m.cross(&f_b);
                wing_inertia.add(f_b, m_b);
                total.add(f_b, m_b);
            }
        }
        out.step = self.step;
        out.t_s = self.time_s();
        out.phase = table_phase + cycles as f64;
        out.state = state;
        out.terms = terms;
        out.wing_inertia = wing_inertia;
        out.total = total;
        out.controls = self.vehicle.controls;
    }

    /// Advances one step; returns what was applied during it.
    pub fn step(&mut self) -> Result<&StepOutput> {
        // Controls change only at the first step of a wingbeat.
        let cycle = self.phase().floor() as i64;
        if self.pending.is_some() && (self.step == 0 || cycle != self.last_cycle) {
            if let Some(c) = self.pending.take() {
                self.apply_controls(&c)?;
            }
        }
        self.last_cycle = cycle;
        if let Some(mut d) = self.dynamic.take() {
            let mut out = self
                .out
                .take()
                .unwrap_or_else(|| Box::new(StepOutput::empty()));
            let ctx = self.actuated_ctx();
            let r = actuated_loads_into(&ctx, &mut d, &mut self.vehicle.wings, &mut out);
            self.dynamic = Some(d);
            let r = r.and_then(|_| self.check(&out));
            if let Err(e) = r {
                self.out = Some(out);
                return Err(e);
            }
            return Ok(self.apply_and_advance(out));
        }
        let (cycles, table_phase, j) = self.phase_parts();
        // The output lives in a box that moves out and back (a pointer, not a kilobyte).
        let mut out = self
            .out
            .take()
            .unwrap_or_else(|| Box::new(StepOutput::empty()));
        match j {
            Some(j) if j < self.phase_table.len() => {
                let generation = self.table_gen;
                if !matches!(&self.phase_table[j], Some((g, _)) if *g == generation) {
                    self.phase_table[j] = Some((generation, self.kinematic_loads(table_phase)));
                }
                if let Some((_, kin)) = &self.phase_table[j] {
                    self.loads_into(kin, cycles, table_phase, &mut out);
                }
            }
            _ => {
                let kin = self.kinematic_loads(table_phase);
                self.loads_into(&kin, cycles, table_phase, &mut out);
            }
        }
        if let Err(e) = self.check(&out) {
            self.out = Some(out);
            return Err(e);
        }
        Ok(self.apply_and_advance(out))
    }

    /// Applies a step's loads to the body and advances the world by one step.
    fn apply_and_advance(&mut self, out: Box<StepOutput>) -> &StepOutput {
        let rb = &mut self.world.bodies[self.body];
        let q = out.state.world_from_body;
        rb.reset_forces(false);
        rb.reset_torques(false);
        rb.add_force(to_glam(&(q * out.total.force_n)), false);
        rb.add_torque(to_glam(&(q * out.total.moment_nm)), false);
        self.world.step();
        self.step += 1;
        self.out.insert(out)
    }

    /// Applies controls now and restarts the wingbeat bookkeeping from the current phase.
    fn apply_controls(&mut self, c: &Controls) -> Result<()> {
        let phase = self.phase();
        self.vehicle.apply_controls(c)?;
        if let (Some(d), Some(a)) = (&mut self.dynamic, &self.vehicle.actuation) {
            for (w, drive) in d.iter_mut().zip(a.drives) {
                w.set_drive(drive)?;
            }
        }
        self.base_phase = phase;
        self.base_step = self.step;
        let freq_hz = self.vehicle.freq_hz();
        // The step was sized for the model's frequency: while it holds, the phase advances
        // by exactly 1/N per step and the kinematics repeat every N steps.
        self.periodic = freq_hz == self.sized_for_hz;
        self.phase_per_step = if self.periodic {
            1.0 / self.steps_per_wingbeat as f64
        } else {
            freq_hz * self.dt_s
        };
        self.table_gen += 1;
        let len = if self.periodic && self.steps_per_wingbeat <= MAX_TABLE_STEPS {
            self.steps_per_wingbeat as usize
        } else {
            0
        };
        if self.phase_table.len() != len {
            self.phase_table.clear();
            self.phase_table.resize(len, None);
        }
        Ok(())
    }

    fn check(&self, out: &StepOutput) -> Result<()> {
        let s = &out.state;
        let fail = |reason: String| {
            Err(Error::Diverged {
                t_s: out.t_s,
                step: out.step,
                reason,
            })
        };
        let finite = |v: &Vector3<f64>| v.iter().all(|x| x.is_finite());
        if !finite(&s.position_m)
            || !finite(&s.velocity_m_s)
            || !finite(&s.angular_velocity_body_rad_s)
        {
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
        // After the speeds: a load that overflowed at a runaway speed names the speed.
        if !finite(&out.total.force_n) || !finite(&out.total.moment_nm) {
            return fail("the aerodynamic load is not finite".into());
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
        let n = (duration_s / self.dt_s).round() as u64;
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
