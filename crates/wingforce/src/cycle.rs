//! Cycle averages and time series of a wing's forces.

use crate::forces::WingForces;
use crate::mount::BodyMotion;
use crate::terms::TermForce;
use crate::wing::Wing;

/// Cycle-mean forces, moments and coefficients of each term and their sum.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CycleMean {
    /// Per term, in the order of [`crate::Term::ALL`].
    pub terms: [TermForce; 4],
    /// Sum of the terms.
    pub total: TermForce,
}

impl CycleMean {
    /// Accumulates one sample with weight `w`.
    pub fn accumulate(&mut self, f: &WingForces, w: f64) {
        for (acc, t) in self.terms.iter_mut().zip(&f.terms) {
            scale_add(acc, t, w);
        }
        scale_add(&mut self.total, &f.total, w);
    }
}

fn scale_add(acc: &mut TermForce, t: &TermForce, w: f64) {
    acc.force_n += w * t.force_n;
    acc.moment_hinge_nm += w * t.moment_hinge_nm;
    acc.c_l += w * t.c_l;
    acc.c_d += w * t.c_d;
}

/// The mean over one wingbeat starting at `start_phase`, sampled at `steps` (at least 1)
/// equally spaced phases: the rectangle rule, spectrally accurate for smooth periodic
/// integrands. The trapezoidal family's pitch flip has jumps in theta_ddot (so in the
/// added-mass force) at the ends of each flip, which lie on the grid k/steps when
/// `start_phase` is 0; pass `0.5 / steps` to sample mid-step and halve that error.
pub fn cycle_mean(wing: &Wing, body: &BodyMotion, start_phase: f64, steps: usize) -> CycleMean {
    let steps = steps.max(1);
    let mut mean = CycleMean::default();
    let w = 1.0 / steps as f64;
    for k in 0..steps {
        let f = wing.evaluate(start_phase + k as f64 * w, body);
        mean.accumulate(&f, w);
    }
    mean
}
