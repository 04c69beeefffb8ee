//! Run summaries: cycle-mean loads per term over complete wingbeats, lift over weight, final
//! pose and drift, and an actuated vehicle's wing motion over its last complete drive period.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::actuated::{MotionRecorder, RecordedMotion};
use crate::sim::{BodyLoad, State, StepOutput};

/// What a run did, in the numbers people ask for first.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunSummary {
    /// Simulated time, s.
    pub duration_s: f64,
    /// Steps taken.
    pub steps: u64,
    /// Complete wingbeats the means are taken over.
    pub wingbeats_averaged: u64,
    /// Cycle-mean load per term (translational, rotational, added mass, wake capture), body frame.
    pub mean_terms: [BodyLoad; 4],
    /// Cycle-mean total load (aerodynamic plus wing inertia), body frame.
    pub mean_total: BodyLoad,
    /// Mean vertical (world z) force over the weight.
    pub mean_lift_over_weight: f64,
    /// State at the end.
    pub final_state: State,
    /// Final roll, pitch, yaw, deg.
    pub final_euler_deg: [f64; 3],
    /// Distance from the start to the end position, m.
    pub drift_m: f64,
    /// Largest distance from the start position during the run, m.
    pub max_excursion_m: f64,
    /// An actuated vehicle's wing motion over the last complete drive period (stroke and
    /// pitch amplitude, pitch-stroke phase, mid-stroke angle of attack, drive; see
    /// [`crate::actuated::motion`]); absent for prescribed kinematics or a run shorter than
    /// one period.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wing_motion: Option<RecordedMotion>,
}

/// Accumulates a [`RunSummary`] from step outputs.
#[derive(Debug, Clone)]
pub struct SummaryBuilder {
    weight_n: f64,
    start: Option<Vector3<f64>>,
    cycle: Option<i64>,
    cycle_terms: [BodyLoad; 4],
    cycle_total: BodyLoad,
    cycle_vertical: f64,
    cycle_n: u64,
    sum_terms: [BodyLoad; 4],
    sum_total: BodyLoad,
    sum_vertical: f64,
    cycles: u64,
    steps: u64,
    t_end_s: f64,
    max_excursion_m: f64,
    motion: MotionRecorder,
}

fn add(a: &mut BodyLoad, b: &BodyLoad, w: f64) {
    a.force_n += w * b.force_n;
    a.moment_nm += w * b.moment_nm;
}

impl SummaryBuilder {
    /// A builder for a vehicle of weight `weight_n`.
    pub fn new(weight_n: f64) -> Self {
        Self {
            weight_n,
            start: None,
            cycle: None,
            cycle_terms: Default::default(),
            cycle_total: Default::default(),
            cycle_vertical: 0.0,
            cycle_n: 0,
            sum_terms: Default::default(),
            sum_total: Default::default(),
            sum_vertical: 0.0,
            cycles: 0,
            steps: 0,
            t_end_s: 0.0,
            max_excursion_m: 0.0,
            motion: MotionRecorder::new(),
        }
    }

    /// Takes one step's output.
    pub fn observe(&mut self, out: &StepOutput, dt_s: f64) {
        let start = *self.start.get_or_insert(out.state.position_m);
        self.max_excursion_m = self
            .max_excursion_m
            .max((out.state.position_m - start).norm());
        let cycle = out.phase.floor() as i64;
        if self.cycle != Some(cycle) {
            if self.cycle.is_some() && self.cycle_n > 0 {
                let w = 1.0 / self.cycle_n as f64;
                for (s, c) in self.sum_terms.iter_mut().zip(&self.cycle_terms) {
                    add(s, c, w);
                }
                add(&mut self.sum_total, &self.cycle_total.clone(), w);
                self.sum_vertical += w * self.cycle_vertical;
                self.cycles += 1;
            }
            self.cycle = Some(cycle);
            self.cycle_terms = Default::default();
            self.cycle_total = Default::default();
            self.cycle_vertical = 0.0;
            self.cycle_n = 0;
        }
        for (c, t) in self.cycle_terms.iter_mut().zip(&out.terms) {
            add(c, t, 1.0);
        }
        add(&mut self.cycle_total, &out.total, 1.0);
        self.cycle_vertical += (out.state.world_from_body * out.total.force_n).z;
        self.cycle_n += 1;
        if let Some([l, r]) = &out.actuated {
            self.motion.observe(
                out.t_s,
                out.phase,
                [
                    (&l.angles, l.actuator.voltage_v),
                    (&r.angles, r.actuator.voltage_v),
                ],
            );
        }
        self.steps += 1;
        self.t_end_s = out.t_s + dt_s;
    }

    /// The summary, given the state after the last step. Means cover the complete
    /// wingbeats seen (the one in progress at the end is left out).
    pub fn finish(&self, final_state: State) -> RunSummary {
        let n = self.cycles.max(1) as f64;
        let mut mean_terms = self.sum_terms;
        for t in &mut mean_terms {
            t.force_n /= n;
            t.moment_nm /= n;
        }
        let mut mean_total = self.sum_total;
        mean_total.force_n /= n;
        mean_total.moment_nm /= n;
        let (r, p, y) = final_state.euler_rad();
        let start = self.start.unwrap_or(final_state.position_m);
        RunSummary {
            duration_s: self.t_end_s,
            steps: self.steps,
            wingbeats_averaged: self.cycles,
            mean_terms,
            mean_total,
            mean_lift_over_weight: self.sum_vertical / n / self.weight_n,
            final_state,
            final_euler_deg: [r.to_degrees(), p.to_degrees(), y.to_degrees()],
            drift_m: (final_state.position_m - start).norm(),
            max_excursion_m: self
                .max_excursion_m
                .max((final_state.position_m - start).norm()),
            wing_motion: self.motion.finish(),
        }
    }
}
