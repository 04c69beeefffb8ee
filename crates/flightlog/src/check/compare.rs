//! The comparison of a re-run with its log, step by step: which steps the log kept (the same
//! [`Decimator`]), each kept sample's state and `/wind` against the re-run's, bit for bit,
//! and at the end whether the log holds every sample the re-run would log. One comparison
//! for every kind of re-run (`simulate` steps a [`flapsim::Simulation`] itself, `hover` is
//! fed by [`flapsim::control::run_hover_with`]'s observer).

use std::collections::HashMap;

use nalgebra::Vector3;

use super::outcome::CheckOutcome;
use crate::decimate::Decimator;
use crate::json::Json;

/// A log's samples, compared with a re-run as it steps.
pub(super) struct Comparer {
    /// The logged `/vehicle/state` samples: (step, values).
    logged: Vec<(u64, [f64; 13])>,
    /// The logged wing winds by log time, ns.
    winds: HashMap<u64, Vec<[f64; 3]>>,
    /// The log is JSON (logs before issue #16): a logged 0 matches a non-finite value.
    json: bool,
    decimator: Decimator,
    /// Samples matched so far.
    matched: usize,
    /// The re-run's steps so far.
    steps: u64,
    /// The re-run's step, s (0 before its first).
    dt_s: f64,
}

impl Comparer {
    pub(super) fn new(
        logged: Vec<(u64, [f64; 13])>,
        winds: HashMap<u64, Vec<[f64; 3]>>,
        json: bool,
        rate_hz: Option<f64>,
    ) -> Self {
        Self {
            logged,
            winds,
            json,
            decimator: Decimator::new(rate_hz),
            matched: 0,
            steps: 0,
            dt_s: 0.0,
        }
    }

    /// Every logged sample has been compared.
    pub(super) fn done(&self) -> bool {
        self.matched == self.logged.len()
    }

    /// The last logged step.
    pub(super) fn last_logged_step(&self) -> u64 {
        self.logged.last().map_or(0, |l| l.0)
    }

    /// A re-run that stopped with `why` before the log's end.
    pub(super) fn stopped(&self, why: &str) -> CheckOutcome {
        CheckOutcome::Mismatch {
            samples_matched: self.matched as u64,
            detail: format!(
                "the re-run stopped ({why}) but the log has samples up to step {}",
                self.last_logged_step()
            ),
        }
    }

    /// Compares the re-run's step `out` (the simulation `sim` after it) with the log; `Some`
    /// is the first difference.
    pub(super) fn step(
        &mut self,
        out: &flapsim::StepOutput,
        sim: &flapsim::Simulation,
    ) -> Option<CheckOutcome> {
        self.steps = sim.steps();
        self.dt_s = sim.dt_s();
        let idx = self.matched;
        let mismatch = |detail: String| {
            Some(CheckOutcome::Mismatch {
                samples_matched: idx as u64,
                detail,
            })
        };
        if !self.decimator.take(out.t_s) {
            // Past the next logged step without taking it: the settings (e.g. a forged log
            // rate) cannot reproduce the log; stop instead of running to the end.
            if out.step > self.logged[idx].0 {
                return mismatch(format!(
                    "sample {idx}: the log has step {}, the re-run with the logged settings does not log it",
                    self.logged[idx].0
                ));
            }
            return None;
        }
        let (step, values) = &self.logged[idx];
        if *step != out.step {
            return mismatch(format!(
                "sample {idx}: the log has step {step}, the re-run logs step {}",
                out.step
            ));
        }
        let (t_s, t_ns) = (out.t_s, crate::sample::time_ns(out.t_s));
        let again = rerun_values(&out.state);
        for (k, (a, b)) in values.iter().zip(&again).enumerate() {
            if !same(*a, *b, self.json) {
                return mismatch(format!(
                    "step {step} (t = {t_s:.9} s): {} logged {a:e}, re-run {b:e}",
                    FIELDS[k]
                ));
            }
        }
        if let Some(w) = self.winds.get(&t_ns) {
            let uniform = sim.uniform_wind_m_s();
            let field = sim.wing_winds_m_s();
            let n_wings = if field.is_empty() {
                w.len()
            } else {
                field.len()
            };
            if w.len() != n_wings {
                return mismatch(format!(
                    "step {step} (t = {t_s:.9} s): /wind has {} wings, the re-run {n_wings}",
                    w.len()
                ));
            }
            for (k, logged_w) in w.iter().enumerate() {
                let again = field.get(k).copied().unwrap_or(uniform);
                for (c, (a, b)) in logged_w.iter().zip(again.iter()).enumerate() {
                    if !same(*a, *b, self.json) {
                        return mismatch(format!(
                            "step {step} (t = {t_s:.9} s): /wind wing {k} {} logged {a:e}, re-run {b:e}",
                            ["x", "y", "z"][c]
                        ));
                    }
                }
            }
        }
        self.matched += 1;
        None
    }

    /// The verdict once the re-run of `duration_s` (round(duration_s / dt) steps, as the runs
    /// count them) has ended or the log has been compared to its end; `complete`: the log
    /// file was not truncated.
    pub(super) fn finish(mut self, duration_s: f64, complete: bool) -> CheckOutcome {
        let dt_s = self.dt_s;
        let n = if dt_s > 0.0 {
            (duration_s / dt_s).round() as u64
        } else {
            0
        };
        let idx = self.matched;
        if idx < self.logged.len() {
            return CheckOutcome::Mismatch {
                samples_matched: idx as u64,
                detail: format!(
                    "the log has {} samples but the re-run of {} steps logs only {idx}",
                    self.logged.len(),
                    n
                ),
            };
        }
        let last = self.last_logged_step();
        // Would the run have logged more samples after the last one in the file?
        let more = (self.steps..n).any(|k| self.decimator.take(k as f64 * dt_s));
        let note = if !complete {
            Some(format!(
                "the log is truncated: compared up to step {last} of {n}"
            ))
        } else if more {
            Some(format!(
                "the log ends at step {last} of {n}: the run stopped early"
            ))
        } else {
            None
        };
        CheckOutcome::Match {
            samples: idx as u64,
            note,
        }
    }
}

const FIELDS: [&str; 13] = [
    "position_m.x",
    "position_m.y",
    "position_m.z",
    "velocity_m_s.x",
    "velocity_m_s.y",
    "velocity_m_s.z",
    "attitude.x",
    "attitude.y",
    "attitude.z",
    "attitude.w",
    "body_rates_rad_s.x",
    "body_rates_rad_s.y",
    "body_rates_rad_s.z",
];

pub(super) fn logged_values(v: &Json) -> Option<(u64, [f64; 13])> {
    let step = v.get("step")?.as_u64()?;
    let mut out = [0.0; 13];
    for (o, f) in out.iter_mut().zip(FIELDS) {
        *o = v.f64_at(f)?;
    }
    Some((step, out))
}

fn rerun_values(s: &flapsim::State) -> [f64; 13] {
    let v = |x: &Vector3<f64>| [x.x, x.y, x.z];
    let (p, u, w) = (
        v(&s.position_m),
        v(&s.velocity_m_s),
        v(&s.angular_velocity_body_rad_s),
    );
    let q = &s.world_from_body;
    [
        p[0], p[1], p[2], u[0], u[1], u[2], q.i, q.j, q.k, q.w, w[0], w[1], w[2],
    ]
}

/// True when a logged number is the re-run's: the same bits; or zeros of either sign (proto3
/// leaves zeros off the wire, so a -0.0 reads back as 0.0); or (JSON logs only) 0 for a
/// non-finite value.
fn same(logged: f64, rerun: f64, json: bool) -> bool {
    logged.to_bits() == rerun.to_bits()
        || (logged == 0.0 && rerun == 0.0)
        || (json && !rerun.is_finite() && logged == 0.0)
}
