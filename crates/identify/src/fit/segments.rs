//! The fit's segments and residuals: segments restarted from known states (cut by `super::setup`), flown on the logged controls at trial parameters, compared with the measurements (see the module documentation of [`crate::fit`]).

use std::ops::Range;

use flapsim::{Controls, Mode, Simulation, State, Vehicle, VehicleSpec};
use nalgebra::{UnitQuaternion, Vector3};
use rayon::prelude::*;

use crate::data::FlightData;
use crate::params::Param;

use super::types::PENALTY;

/// One segment of the flight.
#[derive(Debug, Clone)]
pub(super) struct Segment {
    pub(super) state: State,
    /// The wing set's memory of the step before the start, where the log holds it.
    pub(super) memory: Option<flapsim::StepMemory>,
    /// First global step.
    pub(super) step0: u64,
    pub(super) controls: Vec<Controls>,
    pub(super) steps: usize,
    /// (local step, frame index).
    pub(super) mocap: Vec<(usize, usize)>,
    pub(super) imu: Vec<(usize, usize)>,
}

pub(super) struct Weights {
    pub(super) pos: f64,
    pub(super) att: f64,
    pub(super) gyro: f64,
    pub(super) accel: f64,
}

/// Unknowns of a segment's start state when it is fitted: position (3, world), attitude (3,
/// a rotation vector in body axes), velocity (3, world), body rates (3).
pub(super) const STATE_UNKNOWNS: usize = 12;

/// An actuated vehicle's wings where a segment ended: what the next segment continues
/// from (see [`Setup::fly`]).
#[derive(Debug, Clone)]
pub(super) struct Carried {
    pub(super) wings: flapsim::actuated::ActuatedWings,
    /// The controls in force (the drive the wings carry).
    pub(super) in_force: Controls,
    /// The global step they are at.
    pub(super) step: u64,
}

/// How an actuated vehicle's wings start a segment (see [`Setup::fly`]).
#[derive(Debug, Clone)]
pub(super) enum WingStart {
    /// As the simulation starts them: prescribed kinematics, or actuated wings at rest.
    Own,
    /// From these wings.
    From(Carried),
    /// Actuated wings with no periodic motion at the trial parameters.
    Failed,
}

/// Everything fixed during a fit.
pub(super) struct Setup<'a> {
    pub(super) data: &'a FlightData,
    pub(super) base: VehicleSpec,
    pub(super) params: Vec<Param>,
    pub(super) scales: Vec<f64>,
    pub(super) segments: Vec<Segment>,
    /// Each segment's rows of the residual vector.
    pub(super) rows: Vec<Range<usize>>,
    /// Whether the start states are unknowns: then the scaled unknowns are the parameters
    /// followed by [`STATE_UNKNOWNS`] corrections per segment.
    pub(super) fit_states: bool,
    /// Scales of a start-state correction (m, rad, m/s, rad/s, three each).
    pub(super) state_scales: [f64; STATE_UNKNOWNS],
    pub(super) weights: Weights,
    pub(super) dt_s: f64,
    /// The Jacobian's central-difference step ([`FitOptions::fd_step`] resolved).
    pub(super) fd_step: f64,
    pub(super) gravity_m_s2: f64,
    pub(super) m: usize,
}

/// A trial model: the vehicle at trial parameters and the sensors' trial biases.
pub(super) struct Trial {
    pub(super) vehicle: Vehicle,
    mocap_bias: Vector3<f64>,
    gyro_bias: Vector3<f64>,
    accel_bias: Vector3<f64>,
}

impl Setup<'_> {
    /// The parameters' values at scaled unknowns `x` (the start-state corrections after them
    /// are not parameters).
    pub(super) fn values(&self, x: &[f64]) -> Vec<f64> {
        x.iter().zip(&self.scales).map(|(x, s)| x * s).collect()
    }

    /// Number of scaled unknowns: the parameters, then the start-state corrections.
    pub(super) fn unknowns(&self) -> usize {
        self.params.len()
            + if self.fit_states {
                STATE_UNKNOWNS * self.segments.len()
            } else {
                0
            }
    }

    /// Segment `k`'s start state at scaled unknowns `x`: the logged or estimated state
    /// corrected by its unknowns when they are fitted.
    pub(super) fn start_state(&self, k: usize, x: &[f64]) -> State {
        let mut s = self.segments[k].state;
        if !self.fit_states {
            return s;
        }
        let at = self.params.len() + STATE_UNKNOWNS * k;
        let d: Vec<f64> = (0..STATE_UNKNOWNS)
            .map(|i| x[at + i] * self.state_scales[i])
            .collect();
        let v = |i: usize| Vector3::new(d[i], d[i + 1], d[i + 2]);
        s.position_m += v(0);
        s.world_from_body *= UnitQuaternion::from_scaled_axis(v(3));
        s.velocity_m_s += v(6);
        s.angular_velocity_body_rad_s += v(9);
        s
    }

    /// The vehicle and biases at scaled unknowns `x`; `None` when the parameters make the
    /// model invalid.
    pub(super) fn trial(&self, x: &[f64]) -> Option<Trial> {
        let values = self.values(x);
        let mut spec = self.base.clone();
        let mut mocap_bias = Vector3::zeros();
        let mut gyro_bias = Vector3::zeros();
        let mut accel_bias = Vector3::zeros();
        for (p, v) in self.params.iter().zip(&values) {
            p.apply(&mut spec, &self.base, *v);
            match p {
                Param::MocapBias(k) => mocap_bias[*k] = *v,
                Param::GyroBias(k) => gyro_bias[*k] = *v,
                Param::AccelBias(k) => accel_bias[*k] = *v,
                _ => {}
            }
        }
        let vehicle = match spec.build(&self.data.model_origin) {
            Ok(v) => v,
            Err(e) => {
                if std::env::var_os("FLAPWING_IDENTIFY_DEBUG").is_some() {
                    eprintln!("identify: trial model invalid: {e}");
                }
                return None;
            }
        };
        Some(Trial {
            vehicle,
            mocap_bias,
            gyro_bias,
            accel_bias,
        })
    }

    /// Weighted residuals at scaled unknowns `x`, and the segments that diverged
    /// (`usize::MAX` when the parameters make the model invalid).
    pub(super) fn residuals(&self, x: &[f64]) -> (Vec<f64>, usize) {
        let (r, diverged, _) = self.residuals_and_wings(x);
        (r, diverged)
    }

    /// [`Setup::residuals`], and each segment's start wings of an actuated vehicle (what a
    /// segment flown again alone continues from: see [`Setup::fly`]; empty otherwise).
    pub(super) fn residuals_and_wings(&self, x: &[f64]) -> (Vec<f64>, usize, Vec<WingStart>) {
        let penalty = || (vec![PENALTY; self.m], usize::MAX, Vec::new());
        let Some(trial) = self.trial(x) else {
            return penalty();
        };
        let (per_segment, wings): (Vec<(Vec<f64>, bool)>, Vec<WingStart>) =
            if trial.vehicle.actuation.is_some() {
                // The wings' states chain from segment to segment: flown in order.
                let mut carried: Option<Carried> = None;
                let mut out = Vec::with_capacity(self.segments.len());
                let mut starts = Vec::with_capacity(self.segments.len());
                for k in 0..self.segments.len() {
                    let at_start = self.wings_at_start(&trial, k, carried.take());
                    let flown = self.segment_flown(&trial, k, &self.start_state(k, x), &at_start);
                    starts.push(at_start);
                    carried = flown.1;
                    out.push(flown.0);
                }
                (out, starts)
            } else {
                let out = (0..self.segments.len())
                    .into_par_iter()
                    .map(|k| {
                        self.segment_flown(&trial, k, &self.start_state(k, x), &WingStart::Own)
                            .0
                    })
                    .collect();
                (out, Vec::new())
            };
        let mut r = Vec::with_capacity(self.m);
        let mut diverged = 0;
        for (v, d) in per_segment {
            r.extend(v);
            diverged += usize::from(d);
        }
        if r.len() != self.m {
            return penalty();
        }
        for x in &mut r {
            if !x.is_finite() {
                *x = PENALTY;
            }
        }
        (r, diverged, wings)
    }

    /// The vehicle segment `k` is flown with, its clock at the segment's first step (the
    /// wing phases of the original run). A run trimmed first (a hover) built its vehicle at
    /// the trim and set its controls on the running simulation: the replay does the same, bit
    /// for bit; otherwise the first wingbeat's controls are the vehicle's.
    fn segment_vehicle(&self, trial: &Trial, k: usize) -> Option<Vehicle> {
        match &self.data.trim {
            Some(t) => flapsim::trim::trimmed_vehicle(&trial.vehicle, t).ok(),
            None => {
                let mut v = trial.vehicle.clone();
                v.apply_controls(&self.segments[k].controls[0]).ok()?;
                Some(v)
            }
        }
    }

    /// The controls in force when segment `k`'s vehicle is built ([`Setup::segment_vehicle`]).
    fn built_in_force(&self, k: usize) -> Controls {
        self.data
            .trim
            .as_ref()
            .map_or(self.segments[k].controls[0], |t| t.controls)
    }

    /// The wings segment `k` starts from. An actuated vehicle's wings (hinge and actuator
    /// states) are not measured: the model carries them. A segment continues the wings the
    /// previous one ended with (`previous`, when it ends where `k` starts); a segment without
    /// (the first, or after a gap or a divergence) starts them on their periodic motion
    /// settled at rest under its first controls, as a hover starts
    /// (`flapsim::control::run_hover`), or at rest at step 0 of a run that started them there
    /// (a `simulate` log). A segment's body restart leaves the wings as they were.
    pub(super) fn wings_at_start(
        &self,
        trial: &Trial,
        k: usize,
        previous: Option<Carried>,
    ) -> WingStart {
        let seg = &self.segments[k];
        if let Some(c) = previous.filter(|c| c.step == seg.step0) {
            return WingStart::From(c);
        }
        if trial.vehicle.actuation.is_none() || (self.data.wings_at_rest_at_start && seg.step0 == 0)
        {
            return WingStart::Own;
        }
        let settled = self.segment_vehicle(trial, k).and_then(|v| {
            flapsim::actuated::periodic::settle_at_rest(&v)
                .ok()
                .flatten()
        });
        match settled {
            Some(p) => WingStart::From(Carried {
                wings: flapsim::actuated::ActuatedWings {
                    dynamic: p.dynamic.to_vec(),
                    wings: p.wings.to_vec(),
                    inflow: p.inflow,
                },
                in_force: self.built_in_force(k),
                step: seg.step0,
            }),
            None => WingStart::Failed,
        }
    }

    /// Segment `k` flown from `start` on a trial model, its wings from `wings`
    /// ([`Setup::wings_at_start`]): the state after each of its steps (fewer when it
    /// diverged), whether it diverged, and an actuated vehicle's wings at its end; `None`
    /// when the trial model cannot start the segment.
    pub(super) fn fly(
        &self,
        trial: &Trial,
        k: usize,
        start: &State,
        wings: &WingStart,
    ) -> Option<(Vec<State>, bool, Option<Carried>)> {
        let seg = &self.segments[k];
        let vehicle = &trial.vehicle;
        if matches!(wings, WingStart::Failed) {
            return None;
        }
        let v = self.segment_vehicle(trial, k)?;
        let Ok(mut sim) = Simulation::try_new(v, Mode::Free) else {
            return None;
        };
        if sim.start_at_step(seg.step0).is_err() {
            return None;
        }
        if let WingStart::From(c) = wings {
            sim.continue_wings(&c.wings);
        }
        sim.set_state(start);
        // A logged start with the wing set's memory continues as the run did, bit for bit
        // (a corrected start is not the state that memory led to).
        if let (false, Some(m)) = (self.fit_states, seg.memory)
            && sim.set_step_memory(m).is_err()
        {
            return None;
        }
        // The run's wind field, a function of the point and the time: the segment meets
        // the wind the run met (a fresh field per segment; its samples are generated again).
        if let Some((spec, reference)) = &self.data.wind {
            match flapsim::wind::Wind::from_spec(spec, &self.data.model_origin, *reference) {
                Ok(w) => sim.set_wind_model(Some(w)),
                Err(_) => return None,
            }
        }
        let per = vehicle.sim.steps_per_wingbeat;
        let mut states: Vec<State> = Vec::with_capacity(seg.steps);
        // Continued wings carry the drive of the controls the previous segment ended with.
        let mut in_force = match wings {
            WingStart::From(c) => c.in_force,
            _ => self.built_in_force(k),
        };
        for j in 0..seg.steps {
            if j % per == 0 {
                let c = seg.controls[j / per];
                if self.data.controls_each_wingbeat || c != in_force {
                    sim.set_controls(c);
                    in_force = c;
                }
            }
            if let Some(g) = &self.data.gust {
                let t = (seg.step0 + j as u64) as f64 * self.dt_s;
                let on = t >= g.start_s && t < g.start_s + g.duration_s;
                sim.set_wind(if on {
                    Vector3::from(g.velocity_m_s)
                } else {
                    Vector3::zeros()
                });
            }
            match sim.step() {
                Ok(out) => states.push(out.state),
                Err(_) => return Some((states, true, None)),
            }
        }
        let end = sim.wings_now().map(|wings| Carried {
            wings,
            in_force,
            step: seg.step0 + seg.steps as u64,
        });
        Some((states, false, end))
    }

    /// Segment `k`'s weighted residuals (non-finite ones replaced by [`PENALTY`]) flown
    /// from `start` on a trial model, and whether it diverged; an actuated vehicle's wings
    /// start from `wings` (see [`Setup::wings_at_start`]).
    pub(super) fn segment_residuals(
        &self,
        trial: &Trial,
        k: usize,
        start: &State,
        wings: &WingStart,
    ) -> (Vec<f64>, bool) {
        self.segment_flown(trial, k, start, wings).0
    }

    /// [`Setup::segment_residuals`], and an actuated vehicle's wings at the segment's end.
    fn segment_flown(
        &self,
        trial: &Trial,
        k: usize,
        start: &State,
        wings: &WingStart,
    ) -> ((Vec<f64>, bool), Option<Carried>) {
        let seg = &self.segments[k];
        let Trial {
            mocap_bias,
            gyro_bias,
            accel_bias,
            ..
        } = trial;
        let n_res = 6 * seg.mocap.len() + 6 * seg.imu.len();
        let Some((states, diverged, end)) = self.fly(trial, k, start, wings) else {
            return ((vec![PENALTY; n_res], true), None);
        };
        let last = states.last().copied().unwrap_or(*start);
        let at = |j: usize| states.get(j).copied().unwrap_or(last);
        let w = &self.weights;
        let mut r = Vec::with_capacity(n_res);
        for &(j, i) in &seg.mocap {
            let f = &self.data.mocap[i];
            let s = at(j);
            let dp = (s.position_m + mocap_bias - f.position_m) / w.pos;
            let da = (f.attitude.inverse() * s.world_from_body).scaled_axis() / w.att;
            r.extend([dp.x, dp.y, dp.z, da.x, da.y, da.z]);
        }
        for &(j, i) in &seg.imu {
            let f = &self.data.imu[i];
            let s = at(j);
            let prev = at(j - 1);
            let a = (s.velocity_m_s - prev.velocity_m_s) / self.dt_s;
            let g = Vector3::new(0.0, 0.0, -self.gravity_m_s2);
            let spec_force = s.world_from_body.inverse() * (a - g);
            let dg = (s.angular_velocity_body_rad_s + gyro_bias - f.gyro_rad_s) / w.gyro;
            let da = (spec_force + accel_bias - f.accel_m_s2) / w.accel;
            r.extend([dg.x, dg.y, dg.z, da.x, da.y, da.z]);
        }
        for x in &mut r {
            if !x.is_finite() {
                *x = PENALTY;
            }
        }
        ((r, diverged), end)
    }
}
