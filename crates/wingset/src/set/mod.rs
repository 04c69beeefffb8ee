//! The wing set: flapping wings as a force element on one rigid body, for any host.
//!
//! A [`WingSet`] holds any number of wings (each with its own hinge position, stroke plane,
//! planform and kinematics, or actuation) and their own state: the wingbeat phase, the
//! actuated wings' stroke and pitch dynamics, each pair's dynamic inflow when its wake
//! answers (module `inflow`) and the table of kinematic loads (what a host carries from one
//! run to another: module `carried`). Each
//! [`WingSet::step`] takes the body's state at t_k from the host and returns the loads on the
//! body over [t_k, t_k + dt] about its centre of mass, body frame: the aerodynamic load of
//! each of wingforce's four terms, the inertial reaction of the wings and actuators, and each
//! wing's forces, angles and hinge state. The host integrates the body.
//!
//! No engine and no I/O: the element depends on wingforce and nalgebra. Controls reach the
//! wings through a [`ControlMap`] (flapsim's vehicle model is one). Its hosts are flapsim's
//! own `Simulation` (a private rapier world), `flapsim::host::RapierWings` (a body in the
//! user's rapier world), the C ABI, the MuJoCo plugin, the FMU and the Python module (crates
//! `flapwing-ffi`, `flapwing-mujoco`, `flapwing-fmu`, `flapwing-python`).
//!
//! The time step is the host's and fixed per set, finite, > 0 and at most 1/10 of the
//! wingbeat period ([`MIN_STEPS_PER_WINGBEAT`]; checked when the set is built and when
//! kinematics or controls change the frequency). When it divides the wingbeat into a whole
//! number of steps N (dt = 1/(f N), as flapsim's own host sizes it), the phase advances by
//! exactly 1/N per step and the kinematic loads repeat bit for bit every wingbeat, so they are
//! computed once per step of the wingbeat and reused; otherwise the phase advances by f dt.
//! Every wing is evaluated at the set's wingbeat phase (wing 0's frequency): a set built
//! with [`WingSet::builder`] refuses wings at different frequencies. A vehicle model whose
//! left and right kinematics tables have different periods keeps flapsim's earlier reading
//! (both wings at the left wing's frequency, the right table stretched to it).

mod body;
mod carried;
mod drag;
mod dt;
mod held_correction;
mod inflow;
mod limits;
mod map;
mod output;
mod rate_damping;
mod rewind;
mod step;
mod step_kinematics;

use nalgebra::Vector3;
use wingforce::{Kinematics, Side, Wing};

pub use body::{BodyLoad, MeanLoads, State};
pub use dt::{MIN_STEPS_PER_WINGBEAT, check_dt, max_dt_s};
pub use inflow::{DiscAmplitude, PairInflows};
pub use map::ControlMap;
pub use output::{WingSetOutput, zero_forces};

use crate::actuated::DynamicWing;
use crate::controls::Controls;
use crate::error::{Error, Result};
use crate::sampling::LoadSampling;

/// Longest wingbeat, in steps, whose kinematic loads are kept (about 500 B per wing and step).
const MAX_TABLE_STEPS: u64 = 4096;

/// Flapping wings as a force element: see the module documentation.
#[derive(Debug, Clone)]
pub struct WingSet {
    /// The build this set is (a copy of): [`WingSet::save_state`] copies state only between
    /// copies of one build (module `rewind`).
    origin: u64,
    /// The wings, with the kinematics currently in force.
    wings: Vec<Wing>,
    /// The actuated wings' dynamics (one per wing), or `None` for prescribed kinematics.
    dynamic: Option<Vec<DynamicWing>>,
    /// What maps controls onto these wings (sets built from a model).
    control_map: Option<Box<dyn ControlMap>>,
    /// Mass of each prescribed wing, lumped on its pitch axis at the centroid radius, kg.
    wing_mass_kg: f64,
    /// Centroid radius of each wing, m.
    centroid_r_m: Vec<f64>,
    dt_s: f64,
    step: u64,
    /// Phase at `base_step` and the phase advance per step since then.
    base_phase: f64,
    base_step: u64,
    phase_per_step: f64,
    /// Steps per wingbeat when dt divides the wingbeat (see the module documentation).
    steps_per_wingbeat: Option<u64>,
    /// The wingbeat frequency is the one dt divides, so the kinematics repeat exactly.
    periodic: bool,
    /// The frequency dt was sized for, Hz.
    sized_for_hz: f64,
    /// Each wing's kinematic loads at each step of the wingbeat, `len()` per step (periodic
    /// runs only), valid where `table_gen` holds the current generation: computed the first
    /// time the step comes round and reused every wingbeat until the kinematics change.
    /// Generations are process-wide tags (`rewind::fresh_tag`), so a state restored to an
    /// earlier one finds its entries (module `rewind`).
    table: Vec<step_kinematics::StepKinematics>,
    table_gen: Vec<u64>,
    /// The generation of the kinematics: a fresh tag at every change of the wings'
    /// kinematics, the control map, the load sampling or the held correction
    /// (`restart_phase`, `apply_controls`), on which the table and module `rewind` rely.
    generation: u64,
    pending: Option<Controls>,
    controls: Controls,
    /// Wingbeat index of the last step taken.
    last_cycle: i64,
    wind_world_m_s: Vector3<f64>,
    /// Each wing's wind at its hinge, world frame, m/s, replacing the uniform wind when set
    /// ([`WingSet::set_wing_winds`]).
    wing_winds_world_m_s: Option<Vec<Vector3<f64>>>,
    /// Each wing's motion relative to its air (filled by a prescribed step with per-wing
    /// winds).
    wing_motions: Vec<wingforce::BodyMotion>,
    /// The body's parasite drag area C_D S the set applies, m^2 (0: none, the default).
    body_drag_area_m2: f64,
    /// Where in a step the loads are taken ([`LoadSampling`]).
    sampling: LoadSampling,
    /// The step mean's refinement held across control changes (sets built from a control
    /// map with prescribed wings; module `held_correction`).
    held: Option<held_correction::HeldCorrection>,
    /// What the last step was given and took (the midpoint prediction's previous state;
    /// `None` after a restart).
    prev_body: Option<StepMemory>,
    /// The body state the last step took its loads at ([`WingSet::sampled_state`]).
    sampled: State,
    /// I^-1 D: the body's rate damping over its inertia, when the host gave the inertia
    /// ([`WingSet::set_body_inertia_kg_m2`], module `rate_damping`).
    rate_damping: Option<nalgebra::Matrix3<f64>>,
    /// Each pair's dynamic inflow, when the wings' wake answers (module `inflow`).
    inflow: Option<PairInflows>,
    still: bool,
    out: WingSetOutput,
}

/// The last step's body state, for [`LoadSampling::Midpoint`]'s prediction: the set's
/// memory between steps. A host that restarts a run at a step (a replay from a logged
/// state) and gives the set this memory of the step before continues bit for bit
/// ([`WingSet::step_memory`], [`WingSet::set_step_memory`]); without it the first step
/// after the restart takes its loads at the step's start (one step's O(dt^2) error).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepMemory {
    /// The step's index.
    pub step: u64,
    /// The velocity it was given, world frame, m/s.
    pub velocity_m_s: Vector3<f64>,
    /// The body rates it was given, rad/s.
    pub rates_rad_s: Vector3<f64>,
    /// The body rates it took its loads at, rad/s.
    pub mid_rates_rad_s: Vector3<f64>,
    /// The body's attitude at the step's start as the set integrates it from the rates
    /// (trapezoidal rule; the host's own update is first order).
    pub world_from_body: nalgebra::UnitQuaternion<f64>,
}

/// Builds a [`WingSet`] of prescribed-kinematics wings, one by one.
#[derive(Debug, Clone)]
pub struct WingSetBuilder {
    dt_s: f64,
    wings: Vec<Wing>,
    wing_mass_kg: f64,
}

impl WingSetBuilder {
    /// Adds a wing (its mount gives the hinge position and stroke plane).
    pub fn wing(mut self, wing: Wing) -> Self {
        self.wings.push(wing);
        self
    }

    /// Mass of each wing, lumped on its pitch axis at the centroid radius, kg (0: massless).
    pub fn wing_mass_kg(mut self, m: f64) -> Self {
        self.wing_mass_kg = m;
        self
    }

    /// The set, or an error naming what is wrong (no wings, two wings at one place, wings at
    /// different frequencies, a step that is not positive and finite or longer than 1/10 of
    /// the wingbeat period, [`check_dt`]).
    pub fn build(self) -> Result<WingSet> {
        if !(self.wing_mass_kg >= 0.0 && self.wing_mass_kg.is_finite()) {
            return Err(Error::Input(format!(
                "wing set: wing_mass_kg = {}; allowed: a finite mass >= 0",
                self.wing_mass_kg
            )));
        }
        if let Some(w0) = self.wings.first() {
            let f0 = w0.kinematics().freq_hz;
            for (i, w) in self.wings.iter().enumerate() {
                let f = w.kinematics().freq_hz;
                if f != f0 {
                    return Err(Error::Input(format!(
                        "wing set: wing {i} flaps at {f} Hz, wing 0 at {f0} Hz; allowed: one wingbeat frequency for all wings"
                    )));
                }
            }
        }
        WingSet::assemble(self.wings, None, None, self.wing_mass_kg, self.dt_s)
    }
}

impl WingSet {
    /// A builder for a set of prescribed-kinematics wings stepped by `dt_s`.
    pub fn builder(dt_s: f64) -> WingSetBuilder {
        WingSetBuilder {
            dt_s,
            wings: Vec::new(),
            wing_mass_kg: 0.0,
        }
    }

    /// A set whose controls map onto its wings through `map` (flapsim's `Vehicle`), with
    /// `map`'s wings and, for actuated wings, their `dynamic` wings (one per wing), stepped by
    /// `dt_s`, `controls` in force and applied at the first step (flapsim's
    /// `FromVehicle::from_vehicle` builds one from a vehicle model).
    pub fn with_control_map(
        map: Box<dyn ControlMap>,
        dynamic: Option<Vec<DynamicWing>>,
        wing_mass_kg: f64,
        dt_s: f64,
        controls: Controls,
    ) -> Result<Self> {
        let wings = map.wings().to_vec();
        let mut base = map.clone_box();
        let held = (dynamic.is_none() && base.apply(&controls).is_ok())
            .then(|| held_correction::HeldCorrection::new(base.wings().to_vec()));
        let mut set = Self::assemble(wings, dynamic, Some(map), wing_mass_kg, dt_s)?;
        set.held = held;
        set.controls = controls;
        set.pending = Some(controls);
        Ok(set)
    }

    fn assemble(
        wings: Vec<Wing>,
        dynamic: Option<Vec<DynamicWing>>,
        control_map: Option<Box<dyn ControlMap>>,
        wing_mass_kg: f64,
        dt_s: f64,
    ) -> Result<Self> {
        if wings.is_empty() {
            return Err(Error::Input(
                "wing set: no wings; allowed: one or more wings".into(),
            ));
        }
        let freq_hz = match &dynamic {
            Some(d) => d[0].drive().freq_hz,
            None => wings[0].kinematics().freq_hz,
        };
        check_dt(dt_s, freq_hz)?;
        for (i, a) in wings.iter().enumerate() {
            for (j, b) in wings.iter().enumerate().skip(i + 1) {
                let (ma, mb) = (a.mount(), b.mount());
                if ma.hinge_in_body_m == mb.hinge_in_body_m
                    && ma.side == mb.side
                    && ma.stroke_plane_tilt_rad == mb.stroke_plane_tilt_rad
                {
                    return Err(Error::Input(format!(
                        "wing set: wings {i} and {j} are at the same place (hinge at {:?} m in the body, {:?} side, stroke plane tilted {:.2} deg); allowed: each wing at its own hinge or side",
                        ma.hinge_in_body_m.as_slice(),
                        ma.side,
                        ma.stroke_plane_tilt_rad.to_degrees()
                    )));
                }
            }
        }
        let centroid_r_m = wings
            .iter()
            .map(|w| {
                let g = w.geometry();
                g.strips.iter().map(|s| s.area_m2 * s.r_m).sum::<f64>() / g.area_m2
            })
            .collect();
        // Actuated wings sweep the disc their dynamics make (module `inflow`).
        let disc = match dynamic {
            Some(_) => DiscAmplitude::Measured,
            None => DiscAmplitude::Kinematics,
        };
        let inflow = PairInflows::of(&wings, disc)?;
        let n = wings.len();
        let sampling = match dynamic {
            Some(_) => LoadSampling::StepStart,
            None => LoadSampling::StepMean,
        };
        let mut set = Self {
            origin: rewind::fresh_tag(),
            wings,
            dynamic,
            control_map,
            wing_mass_kg,
            centroid_r_m,
            dt_s,
            step: 0,
            base_phase: 0.0,
            base_step: 0,
            phase_per_step: 0.0,
            steps_per_wingbeat: None,
            periodic: false,
            sized_for_hz: freq_hz,
            table: Vec::new(),
            table_gen: Vec::new(),
            generation: 0,
            pending: None,
            controls: Controls::default(),
            last_cycle: 0,
            wind_world_m_s: Vector3::zeros(),
            wing_winds_world_m_s: None,
            wing_motions: Vec::new(),
            body_drag_area_m2: 0.0,
            // Actuated wings step-start until told otherwise (their own default,
            // `DynamicWing::set_load_sampling`); prescribed ones at the midpoint.
            sampling,
            held: None,
            prev_body: None,
            sampled: State::at_rest(),
            rate_damping: None,
            inflow,
            still: false,
            out: WingSetOutput::empty(n),
        };
        // Whole steps per wingbeat: dt = 1/(f N) exactly, as flapsim's own host sizes it.
        let n_steps = (1.0 / (freq_hz * dt_s)).round();
        if n_steps >= 1.0 && 1.0 / (freq_hz * n_steps) == dt_s {
            set.steps_per_wingbeat = Some(n_steps as u64);
        }
        set.restart_phase(0.0);
        Ok(set)
    }

    /// Number of wings.
    pub fn len(&self) -> usize {
        self.wings.len()
    }
    /// Always false: a set has at least one wing.
    pub fn is_empty(&self) -> bool {
        self.wings.is_empty()
    }
    /// The wings, with the kinematics in force.
    pub fn wings(&self) -> &[Wing] {
        &self.wings
    }
    /// What maps controls onto the wings (the vehicle model the set was built from, with
    /// the controls in force), if any.
    pub fn control_map(&self) -> Option<&dyn ControlMap> {
        self.control_map.as_deref()
    }
    /// The host's time step, s.
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
    /// Controls in force.
    pub fn controls(&self) -> Controls {
        self.controls
    }
    /// The controls last set: those waiting for the next wingbeat, else those in force.
    pub fn requested_controls(&self) -> Controls {
        self.pending.unwrap_or(self.controls)
    }
    /// Whether the wings are actuated (their angles integrated in time).
    pub fn is_actuated(&self) -> bool {
        self.dynamic.is_some()
    }
    /// Wingbeat frequency now, Hz.
    pub fn freq_hz(&self) -> f64 {
        match &self.dynamic {
            Some(d) => d[0].drive().freq_hz,
            None => self.wings[0].kinematics().freq_hz,
        }
    }
    /// What the last step computed.
    pub fn output(&self) -> &WingSetOutput {
        &self.out
    }

    /// Wingbeat phase now, cycles. While the frequency is the one the step divides, the phase
    /// advances by exactly 1/N per step within a wingbeat and by exactly 1 per wingbeat, and
    /// the kinematics are evaluated at the phase's first wingbeat after the last control
    /// change: they repeat bit for bit every wingbeat.
    pub fn phase(&self) -> f64 {
        let (cycles, table_phase, _) = self.phase_parts();
        table_phase + cycles as f64
    }

    /// Whole wingbeats since the last control change, the phase at t_k (within the first
    /// wingbeat after it) and the index of the step in the wingbeat (periodic runs only).
    fn phase_parts(&self) -> (u64, f64, Option<usize>) {
        self.phase_parts_at(0.0)
    }

    /// [`Self::phase_parts`] at the point of the step where the loads are sampled
    /// ([`LoadSampling`]): the phase at which the kinematics are evaluated.
    fn sample_phase_parts(&self) -> (u64, f64, Option<usize>) {
        self.phase_parts_at(self.sampling.step_fraction())
    }

    fn phase_parts_at(&self, fraction: f64) -> (u64, f64, Option<usize>) {
        let n = self.step - self.base_step;
        match self.steps_per_wingbeat {
            Some(per) if self.periodic => {
                let (m, j) = (n / per, n % per);
                (
                    m,
                    self.base_phase + (j as f64 + fraction) * self.phase_per_step,
                    Some(j as usize),
                )
            }
            _ => (
                0,
                self.base_phase + (n as f64 + fraction) * self.phase_per_step,
                None,
            ),
        }
    }

    /// Where in a step the loads are taken.
    pub fn load_sampling(&self) -> LoadSampling {
        self.sampling
    }

    /// Takes the loads at another point of the step from the next step on (the kinematic
    /// loads' table is recomputed, the actuated wings report accordingly).
    pub fn set_load_sampling(&mut self, sampling: LoadSampling) {
        if sampling != self.sampling {
            self.sampling = sampling;
            self.generation = rewind::fresh_tag();
            if let Some(d) = &mut self.dynamic {
                for w in d {
                    w.set_load_sampling(sampling);
                }
            }
        }
    }

    /// Whether a step under the step mean whose kinematics the controls moved from the
    /// build's takes its sampled loads plus the build's quadrature refinement (true, the
    /// default) or the step mean in full (as before the held correction: logs written
    /// before it replay with it). Module `held_correction`.
    pub fn set_held_correction(&mut self, on: bool) {
        if let Some(h) = &mut self.held
            && h.enabled != on
        {
            h.enabled = on;
            self.generation = rewind::fresh_tag();
        }
    }

    /// Controls to apply at the start of the next wingbeat (immediately if none has begun).
    /// Only a set built from a vehicle model has controls; for others see
    /// [`WingSet::set_kinematics`].
    pub fn set_controls(&mut self, controls: Controls) -> Result<()> {
        if self.control_map.is_none() {
            return Err(Error::Input(
                "wing set: controls need a vehicle model to map them onto the wings (WingSet::from_vehicle); set each wing's kinematics instead".into(),
            ));
        }
        self.pending = Some(controls);
        Ok(())
    }

    /// Continues the set's clock from step `step`, as if the steps before it had been taken
    /// with the kinematics and controls it has now and no control change since the first
    /// step (prescribed wings, before the first step; the controls it was built with are
    /// applied at phase 0 first). The time, the phase and the phases at which the
    /// kinematics are evaluated are then those of that longer run, bit for bit, and so are
    /// later control changes (they restart the wingbeat bookkeeping at the same phase): a
    /// segment of a logged run restarted from its logged state replays it exactly
    /// (flapwing-identify). Actuated wings keep their own clock and state: continue them
    /// from that step's ([`WingSet::start_dynamic_from`]), or they start from rest there.
    /// Errors: steps were already taken.
    pub fn start_at_step(&mut self, step: u64) -> Result<()> {
        if self.step != 0 {
            return Err(Error::Input(format!(
                "wing set: start_at_step({step}) after {} steps were taken; call it before the first step",
                self.step
            )));
        }
        if let Some(c) = self.pending.take() {
            self.apply_controls(&c)?;
        }
        if step > 0 {
            self.step = step - 1;
            self.last_cycle = self.phase().floor() as i64;
            self.step = step;
        }
        Ok(())
    }

    /// Replaces wing `i`'s kinematics now (prescribed wings) and restarts the wingbeat
    /// bookkeeping from the current phase.
    pub fn set_kinematics(&mut self, i: usize, kinematics: Kinematics) -> Result<()> {
        if self.dynamic.is_some() {
            return Err(Error::Input(
                "wing set: the wings are actuated; their motion comes from the drive".into(),
            ));
        }
        let n = self.wings.len();
        let f0 = self.wings[0].kinematics().freq_hz;
        if i >= n {
            return Err(Error::Input(format!(
                "wing set: wing index {i}; allowed: 0..{n}"
            )));
        }
        if n > 1 && kinematics.freq_hz != f0 {
            return Err(Error::Input(format!(
                "wing set: new kinematics of wing {i} at {} Hz, the set flaps at {f0} Hz; allowed: one frequency for all wings (change every wing's)",
                kinematics.freq_hz
            )));
        }
        check_dt(self.dt_s, kinematics.freq_hz)?;
        let phase = self.phase();
        self.wings[i].set_kinematics(kinematics);
        self.restart_phase(phase);
        Ok(())
    }

    /// Holds the wings still (no aerodynamic or wing-inertia loads) or lets them flap again.
    pub fn set_still(&mut self, still: bool) {
        self.still = still;
    }

    /// Uniform wind, world frame, m/s: every wing's air moves at this velocity (replaces
    /// any per-wing winds).
    pub fn set_wind(&mut self, wind_world_m_s: Vector3<f64>) {
        self.wind_world_m_s = wind_world_m_s;
        self.wing_winds_world_m_s = None;
    }

    /// Each wing's own wind, world frame, m/s, in the set's order (the air's velocity at the
    /// wing, e.g. a wind field evaluated at each hinge, see `flapsim::wind`): each wing's
    /// forces use the body's velocity relative to its own air, uniform over the wing. In
    /// force until the next call or [`WingSet::set_wind`]. One wind per wing and finite
    /// components, or an error that changes nothing.
    pub fn set_wing_winds(&mut self, winds_world_m_s: &[Vector3<f64>]) -> Result<()> {
        let n = self.wings.len();
        if winds_world_m_s.len() != n {
            return Err(Error::Input(format!(
                "wing set: {} winds for {n} wings; allowed: one wind per wing",
                winds_world_m_s.len()
            )));
        }
        if let Some(i) = winds_world_m_s
            .iter()
            .position(|w| w.iter().any(|x| !x.is_finite()))
        {
            return Err(Error::Input(format!(
                "wing set: wind of wing {i} = {:?} m/s; allowed: finite components",
                winds_world_m_s[i].as_slice()
            )));
        }
        match &mut self.wing_winds_world_m_s {
            Some(w) => w.copy_from_slice(winds_world_m_s),
            None => self.wing_winds_world_m_s = Some(winds_world_m_s.to_vec()),
        }
        Ok(())
    }

    /// The wind each wing sees now, world frame, m/s (the uniform wind unless per-wing
    /// winds are set).
    pub fn wing_winds(&self) -> Vec<Vector3<f64>> {
        match &self.wing_winds_world_m_s {
            Some(w) => w.clone(),
            None => vec![self.wind_world_m_s; self.wings.len()],
        }
    }

    /// Applies controls now and restarts the wingbeat bookkeeping from the current phase.
    /// Controls whose wingbeat the step no longer resolves ([`check_dt`]) are an error, and
    /// those in force stay.
    fn apply_controls(&mut self, c: &Controls) -> Result<()> {
        let phase = self.phase();
        if self.control_map.is_some() {
            // The map changes now, even if the controls are refused below: a new generation
            // (module `rewind` copies the map only across generations).
            self.generation = rewind::fresh_tag();
        }
        let Some(v) = &mut self.control_map else {
            return Ok(());
        };
        v.apply(c)?;
        let freq_hz = match v.drives() {
            Some(d) if self.dynamic.is_some() => d[0].freq_hz,
            _ => v.wings()[0].kinematics().freq_hz,
        };
        if let Err(e) = check_dt(self.dt_s, freq_hz) {
            v.apply(&self.controls)?;
            return Err(e);
        }
        if let (Some(d), Some(drives)) = (&mut self.dynamic, v.drives()) {
            for (w, drive) in d.iter_mut().zip(drives) {
                w.set_drive(*drive)?;
            }
        } else {
            for (w, vw) in self.wings.iter_mut().zip(v.wings()) {
                w.set_kinematics(vw.kinematics().clone());
            }
        }
        self.controls = *c;
        self.restart_phase(phase);
        Ok(())
    }

    /// Restarts the wingbeat bookkeeping at `phase` (after the kinematics changed).
    fn restart_phase(&mut self, phase: f64) {
        self.base_phase = phase;
        self.base_step = self.step;
        let freq_hz = self.freq_hz();
        self.periodic = self.steps_per_wingbeat.is_some() && freq_hz == self.sized_for_hz;
        self.phase_per_step = match self.steps_per_wingbeat {
            Some(per) if self.periodic => 1.0 / per as f64,
            _ => freq_hz * self.dt_s,
        };
        self.generation = rewind::fresh_tag();
        let per = match self.steps_per_wingbeat {
            Some(per) if self.periodic && per <= MAX_TABLE_STEPS && self.dynamic.is_none() => {
                per as usize
            }
            _ => 0,
        };
        if self.table_gen.len() != per {
            self.table_gen.clear();
            self.table_gen.resize(per, 0);
            self.table.clear();
            let blank = step_kinematics::StepKinematics {
                kin: self.wings[0].kinematic_loads(0.0),
                inertia: BodyLoad::default(),
            };
            self.table.resize(per * self.wings.len(), blank);
        }
    }

    /// Whether wings `i` and `i + 1` are a mirror-symmetric pair (left then right, same
    /// kinematics): their kinematic loads are computed together.
    fn mirrored_pair(&self, i: usize) -> bool {
        let (a, b) = (&self.wings[i], &self.wings[i + 1]);
        a.mount().side == Side::Left
            && b.mount().side == Side::Right
            && a.kinematics() == b.kinematics()
    }
}
