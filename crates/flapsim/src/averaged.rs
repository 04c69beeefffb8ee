//! Cycle-averaged loads at a frozen body state: the averaged model that trim and the
//! stability derivatives of Sun and Xiong (2005) are built on. The body's velocity and
//! attitude are held fixed over one wingbeat while the wings flap; the loads are averaged
//! over `steps` equally spaced phases. A wake that answers (`[aero] inflow = "dynamic"`) is
//! run into its periodic motion at the frozen state first ([`periodic_inflow`]): the
//! averaged model's inflow follows the body's state, as the simulation's does.

use nalgebra::{UnitQuaternion, Vector3};
use wingforce::inflow::InflowState;
use wingforce::{BodyMotion, KinematicLoads, Term, Wing, WingForces};

use crate::error::Result;
use crate::model::Vehicle;
pub use crate::wings::MeanLoads;

/// A frozen body state for averaging.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrozenState {
    /// Attitude world_from_body.
    pub world_from_body: UnitQuaternion<f64>,
    /// Air-relative velocity of the CoM in the body frame, m/s.
    pub velocity_body_m_s: Vector3<f64>,
    /// Angular velocity, body frame, rad/s.
    pub angular_velocity_body_rad_s: Vector3<f64>,
}

/// Mean loads over one wingbeat at a frozen state: `steps` samples of the prescribed
/// kinematics (with the vehicle's midpoint load sampling, `Vehicle::load_sampling`, the
/// means over `steps` steps that a simulation stepping at that count applies:
/// `wingforce::Wing::kinematic_loads_over_step`, the translational term at each step's
/// midpoint; so a trim balances the loads the simulation steps with), or, for an actuated vehicle, the wings run into their periodic motion at
/// that body state by the dynamics ([`crate::actuated::periodic`], which integrates at the
/// simulation's step and ignores `steps`; its error says when there is no periodic motion).
pub fn mean_loads(vehicle: &Vehicle, state: &FrozenState, steps: usize) -> Result<MeanLoads> {
    mean_loads_with(vehicle, state, steps, None)
}

/// Each prescribed wing's kinematic loads over each of `steps` steps of the wingbeat under a
/// second-order load sampling: what [`mean_loads`] computes afresh at every body state (the
/// body's motion enters only the translational term, evaluated on top of them), tabled for
/// the many states of one vehicle (the averaged model's Jacobian: [`mean_loads_tabled`]).
/// The same loads bit for bit.
#[derive(Debug, Clone)]
pub struct StepTable {
    steps: usize,
    /// Step-major, then the wings' order.
    loads: Vec<KinematicLoads>,
}

impl StepTable {
    /// The table of `vehicle` at `steps` steps, or `None` where [`mean_loads`] takes no such
    /// loads (actuated wings, a wake that answers, the step-start sampling).
    pub fn of(vehicle: &Vehicle, steps: usize) -> Option<Self> {
        let rule = vehicle.load_sampling().step_rule()?;
        if vehicle.actuation.is_some() || vehicle.inflow_model() == wingforce::InflowModel::Dynamic
        {
            return None;
        }
        let w = 1.0 / steps as f64;
        let dt_s = w / vehicle.freq_hz();
        let loads = (0..steps)
            .flat_map(|k| {
                vehicle.wings.iter().map(move |wing| {
                    wing.loads_over_step(k as f64 * w, (k + 1) as f64 * w, dt_s, rule)
                        .mean
                })
            })
            .collect();
        Some(Self { steps, loads })
    }
}

/// [`mean_loads`] with the kinematic loads from `table` (of this vehicle, [`StepTable::of`]).
pub fn mean_loads_tabled(
    vehicle: &Vehicle,
    state: &FrozenState,
    table: &StepTable,
) -> Result<MeanLoads> {
    mean_loads_with(vehicle, state, table.steps, Some(table))
}

fn mean_loads_with(
    vehicle: &Vehicle,
    state: &FrozenState,
    steps: usize,
    table: Option<&StepTable>,
) -> Result<MeanLoads> {
    crate::cancel::check()?;
    let motion = BodyMotion {
        velocity_m_s: state.velocity_body_m_s,
        angular_velocity_rad_s: state.angular_velocity_body_rad_s,
    };
    if vehicle.actuation.is_some() {
        return Ok(crate::actuated::periodic::settle(vehicle, &motion)?.mean);
    }
    if let Some(p) = periodic_inflow(vehicle, &motion, steps)? {
        return Ok(p.mean);
    }
    let mut out = MeanLoads::default();
    let mut forces = Vec::with_capacity(vehicle.wings.len());
    let n = vehicle.wings.len();
    for k in 0..steps {
        match table {
            Some(t) => {
                forces.clear();
                let kin = &t.loads[k * n..(k + 1) * n];
                forces.extend(
                    vehicle
                        .wings
                        .iter()
                        .zip(kin)
                        .map(|(wing, kin)| wing.evaluate_with(kin, &motion)),
                );
            }
            None => step_loads(vehicle, &vehicle.wings, k, steps, &motion, &mut forces),
        }
        accumulate(&vehicle.wings, &forces, 1.0 / steps as f64, &mut out);
    }
    Ok(out)
}

/// Each wing's forces at step `k` of `steps` of the wingbeat, as the vehicle's load sampling
/// takes them, into `out`.
fn step_loads(
    vehicle: &Vehicle,
    wings: &[Wing],
    k: usize,
    steps: usize,
    motion: &BodyMotion,
    out: &mut Vec<WingForces>,
) {
    let w = 1.0 / steps as f64;
    let rule = vehicle.load_sampling().step_rule();
    let dt_s = w / vehicle.freq_hz();
    let phase = k as f64 * w;
    out.clear();
    out.extend(wings.iter().map(|wing| match rule {
        Some(rule) => {
            let s = wing.loads_over_step(phase, (k + 1) as f64 * w, dt_s, rule);
            wing.evaluate_with(&s.mean, motion)
        }
        None => wing.evaluate(phase, motion),
    }));
}

/// Adds `weight` times the wings' aerodynamic loads about the centre of mass to `out`.
fn accumulate(wings: &[Wing], forces: &[WingForces], weight: f64, out: &mut MeanLoads) {
    for (wing, f) in wings.iter().zip(forces) {
        let hinge = &wing.mount().hinge_in_body_m;
        for term in Term::ALL {
            let t = f.term(term);
            let m = t.moment_about_com_nm(hinge);
            out.terms[term as usize].add(weight * t.force_n, weight * m);
            out.total.add(weight * t.force_n, weight * m);
        }
    }
}

/// The wings and their dynamic inflow on its periodic motion at a frozen body state.
#[derive(Debug, Clone)]
pub struct PeriodicInflow {
    /// Mean aerodynamic loads over the last wingbeat (body frame, about the CoM).
    pub mean: MeanLoads,
    /// Each pair's inflow states at the start of a wingbeat on the periodic motion (where a
    /// simulation of the same step count continues it at phase 0).
    pub states: Vec<InflowState>,
    /// Each pair's inflow states averaged over the last wingbeat.
    pub state_means: Vec<InflowState>,
    /// Every wing's forces at each step of the last wingbeat (the wings' order), as the
    /// simulation takes them (what the wings' power over the wingbeat needs).
    pub samples: Vec<Vec<wingforce::WingForces>>,
    /// Wingbeats run.
    pub wingbeats: usize,
}

/// Largest change of an inflow state over the last wingbeat, relative to the mean inflow,
/// for the inflow to count as periodic.
pub const PERIODIC_INFLOW_TOLERANCE: f64 = 1e-9;

/// Most wingbeats [`periodic_inflow`] runs (an inflow slower than this to settle is an
/// error).
pub const MAX_INFLOW_WINGBEATS: usize = 200;

/// Wingbeats for the slowest inflow state to decay by 1e-14 from where one wingbeat took
/// it: the slowest of the states' time constants for small perturbations at that inflow and
/// the body's motion (`PairInflows::slowest_time_constant_s`: Pitt-Peters' m0 / (2 rho A V)
/// and m1 L_ii / (rho A R_e V), V the mass-flow parameter, which forward flight raises well
/// above the hover inflow), at least two and at most [`MAX_INFLOW_WINGBEATS`].
fn settling_wingbeats(inflow: &wingset::PairInflows, motion: &BodyMotion, period_s: f64) -> usize {
    let tau_s = inflow.slowest_time_constant_s(motion);
    let n = (14.0 * std::f64::consts::LN_10 * tau_s / period_s).ceil();
    if n.is_finite() {
        (n as usize).clamp(2, MAX_INFLOW_WINGBEATS)
    } else {
        MAX_INFLOW_WINGBEATS
    }
}

/// For a prescribed vehicle whose wake answers (`[aero] inflow = "dynamic"`), its pairs'
/// inflow run into its periodic motion at a frozen body state, stepped as a simulation of
/// `steps` steps per wingbeat steps it (module `wingset::set::inflow`), and the wings' mean
/// loads over the last wingbeat; `None` for a vehicle whose wake does not answer.
///
/// The run is long enough for the slowest state to decay by 1e-14 ([`settling_wingbeats`]),
/// so the mean loads are a smooth function of the body state to round-off (for
/// finite-difference Jacobians). An inflow still drifting then is an error.
pub fn periodic_inflow(
    vehicle: &Vehicle,
    motion: &BodyMotion,
    steps: usize,
) -> Result<Option<PeriodicInflow>> {
    if vehicle.actuation.is_some() {
        // Actuated wings' inflow goes round with their dynamics (`actuated::periodic`).
        return Ok(None);
    }
    let mut wings = vehicle.wings.clone();
    let Some(mut inflow) = wingset::PairInflows::of(&wings, wingset::DiscAmplitude::Kinematics)?
    else {
        return Ok(None);
    };
    let period_s = 1.0 / vehicle.freq_hz();
    let dt_s = period_s / steps as f64;
    let sampling = vehicle.load_sampling();
    let mut forces = Vec::with_capacity(wings.len());
    let mut mean = MeanLoads::default();
    let mut start = inflow.states();
    // The first wingbeat from the hover inflow of the weight; then as many as the slowest
    // time constant at the inflow it reached needs.
    let mut wingbeats = MAX_INFLOW_WINGBEATS;
    let mut beat = 0;
    let mut state_means = Vec::new();
    let mut samples = Vec::with_capacity(steps);
    while beat < wingbeats {
        if beat == 1 {
            wingbeats = settling_wingbeats(&inflow, motion, period_s);
        }
        crate::cancel::check()?;
        start = inflow.states();
        mean = MeanLoads::default();
        state_means.clear();
        for k in 0..steps {
            inflow.add_states_to(&mut state_means, 1.0 / steps as f64);
            inflow.apply(&mut wings, sampling);
            step_loads(vehicle, &wings, k, steps, motion, &mut forces);
            accumulate(&wings, &forces, 1.0 / steps as f64, &mut mean);
            if beat + 1 == wingbeats {
                samples.push(forces.clone());
            }
            inflow
                .advance(&wings, &forces, motion, dt_s)
                .map_err(|e| {
                    crate::error::Error::Analysis(format!(
                        "the dynamic inflow of {} at this body state (velocity {:?} m/s, rates {:?} rad/s, body frame) in wingbeat {beat}: {}",
                        vehicle.name,
                        motion.velocity_m_s.as_slice(),
                        motion.angular_velocity_rad_s.as_slice(),
                        e.reason()
                    ))
                })?;
        }
        beat += 1;
    }
    let end = inflow.states();
    let scale = end.iter().map(|s| s.mean_m_s.abs()).fold(0.0, f64::max);
    let drift = start
        .iter()
        .zip(&end)
        .flat_map(|(a, b)| {
            let (a, b) = (a.to_array(), b.to_array());
            (0..3).map(move |i| (a[i] - b[i]).abs())
        })
        .fold(0.0, f64::max);
    if !(drift <= PERIODIC_INFLOW_TOLERANCE * scale.max(f64::MIN_POSITIVE)) {
        return Err(crate::error::Error::Analysis(format!(
            "the dynamic inflow of {} did not settle into a periodic motion in {wingbeats} wingbeats: a state still changes by {drift:.3e} m/s per wingbeat (allowed: {:.1e} of the mean inflow {scale:.4} m/s)",
            vehicle.name, PERIODIC_INFLOW_TOLERANCE
        )));
    }
    Ok(Some(PeriodicInflow {
        mean,
        states: end,
        state_means,
        samples,
        wingbeats,
    }))
}
