//! A controller's steps under the step mean (issue 37): the quadrature's refinement held
//! across small changes of the kinematics.
//!
//! Under [`LoadSampling::StepMean`] a step's kinematic loads are their means over the step,
//! each taken by two-point Gauss-Legendre on pieces of at most 0.02 of the wingbeat, the
//! translational term's still-air mean too: at the fly's 20 steps per wingbeat, 14 wing
//! evaluations per wing and step (wingforce's `Wing::loads_over_step`). Open loop they are
//! tabled once per step of the wingbeat; a controller that changes the kinematics every
//! wingbeat (hover, the Gym tasks, a frequency response) pays them every step: measured with
//! callgrind on the fly's 0.3 s hover, 67 % of the run's instructions, and the default
//! hover ran only 1.6x the wingbeats per second of the 100-step default it replaced.
//!
//! The step mean is the step's loads from samples alone (wingforce's
//! `Wing::sampled_loads_over_step`: the added mass's force and jump exactly from the wing's
//! motion at the step's ends, the rest at the midpoint, one evaluation) plus a correction C,
//! the quadrature's refinement over those samples: C = O(dt^2) where the loads are smooth,
//! and a function of the kinematics that changes with them by O(dt^2 dk). So while the
//! controls differ from those the set was built with (the trim, for a hover), each wing's
//! step is its sampled loads at the kinematics in force plus C tabled once per step of the
//! wingbeat at the kinematics the set was built with: one evaluation where the step mean
//! takes 14, and an error O(dt^2 dk) against the step mean at the new kinematics, still
//! second order in the step (measured: docs/speed.md row 29 and
//! `flapsim/tests/second_order.rs`).
//!
//! The rule is a function of the controls and the step alone, so a run restarted from a
//! logged step with its build controls (flapwing-identify's segments of a hover) takes the
//! loads it took: a wing takes the held correction when its kinematics are those its
//! controls give (not set by hand), differ from the build's, share their frequency and the
//! step falls on the wingbeat's grid of whole steps; else the step mean in full. A run whose
//! controls stay the build's never takes it, so `replay --check`, which re-runs `simulate`
//! logs (no controller), replays logs written before it bit for bit;
//! [`super::WingSet::set_held_correction`] turns it off for a set.

use std::sync::OnceLock;

use wingforce::{StepRule, TermForce, Wing};

use crate::sampling::LoadSampling;

/// The held correction of a set built from a control map: the wings at the build's
/// controls, and their corrections per step of the wingbeat, tabled when first needed.
#[derive(Debug, Clone)]
pub(super) struct HeldCorrection {
    /// The wings with the kinematics the build's controls give.
    base: Vec<Wing>,
    /// Whether steps take it (else the step mean in full every time).
    pub enabled: bool,
    /// Per step q of the wingbeat (phase q/N to (q+1)/N), per wing in the set's order: the
    /// step mean's terms minus the sampled step's, of the base wings.
    table: OnceLock<Vec<[TermForce; 4]>>,
}

impl HeldCorrection {
    pub fn new(base: Vec<Wing>) -> Self {
        Self {
            base,
            enabled: true,
            table: OnceLock::new(),
        }
    }

    /// The base wings' corrections for step `q` of a wingbeat of `per` steps of `dt_s`, or
    /// `None` when `phase_start` is not on that grid (within 1e-6 of a step).
    pub fn at(&self, phase_start: f64, per: u64, dt_s: f64) -> Option<&[[TermForce; 4]]> {
        let x = phase_start * per as f64;
        let q = x.round();
        if !self.enabled || (x - q).abs() > 1e-6 {
            return None;
        }
        let n = self.base.len();
        let table = self.table.get_or_init(|| {
            let mut t = Vec::with_capacity(per as usize * n);
            for q in 0..per {
                let (p0, p1) = (q as f64 / per as f64, (q + 1) as f64 / per as f64);
                for w in &self.base {
                    let full = w.loads_over_step(p0, p1, dt_s, StepRule::StepMean);
                    let sampled = w.sampled_loads_over_step(p0, p1, dt_s);
                    t.push(std::array::from_fn(|i| {
                        let (a, b) = (&full.mean.terms[i], &sampled.mean.terms[i]);
                        TermForce {
                            force_n: a.force_n - b.force_n,
                            moment_hinge_nm: a.moment_hinge_nm - b.moment_hinge_nm,
                            c_l: a.c_l - b.c_l,
                            c_d: a.c_d - b.c_d,
                        }
                    }));
                }
            }
            t
        });
        let q = (q as i64).rem_euclid(per as i64) as usize;
        Some(&table[q * n..(q + 1) * n])
    }

    /// Whether wing `i`, whose kinematics the controls gave (`from_controls`), takes the
    /// held correction: its kinematics differ from the base's at the same frequency.
    pub fn applies(&self, i: usize, wing: &Wing, from_controls: bool) -> bool {
        let base = self.base[i].kinematics();
        from_controls && wing.kinematics() != base && wing.kinematics().freq_hz == base.freq_hz
    }
}

/// Wing `wing`'s loads over the step from `p0` to `p1` under the step mean with the held
/// correction `c` ([`HeldCorrection`]).
pub(super) fn held_step(
    wing: &Wing,
    p0: f64,
    p1: f64,
    dt_s: f64,
    c: &[TermForce; 4],
) -> wingforce::StepKinematicLoads {
    let mut k = wing.sampled_loads_over_step(p0, p1, dt_s);
    for (t, c) in k.mean.terms.iter_mut().zip(c) {
        t.force_n += c.force_n;
        t.moment_hinge_nm += c.moment_hinge_nm;
        t.c_l += c.c_l;
        t.c_d += c.c_d;
    }
    k
}

/// Whether `sampling` tables the step mean (the only one the held correction serves).
pub(super) fn serves(sampling: LoadSampling) -> bool {
    sampling == LoadSampling::StepMean
}
