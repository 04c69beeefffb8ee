//! Derivative-free optimization of a study's factors: the Nelder-Mead simplex method and a
//! hover design objective built on it.
//!
//! Nelder-Mead as in Lagarias, Reeds, Wright and Wright (1998), "Convergence properties of
//! the Nelder-Mead simplex method in low dimensions", SIAM J. Optim. 9(1): reflection 1,
//! expansion 2, outside and inside contraction 1/2, shrink 1/2; the vertices are kept sorted
//! and ties keep their order, so a run is deterministic.
//!
//! The hover objective maximizes `lift_per_power_n_per_w` (vertical force per aerodynamic
//! power, [`super::responses`]) over the factors' intervals subject to supporting the weight,
//! `lift_over_weight >= target`, handled as a quadratic penalty:
//!
//! `J(u) = -LPP(x(u)) / LPP(x0) + rho * max(0, target - L/W)^2`,
//!
//! where u in [0, 1]^k maps linearly onto the factors' intervals (coordinates outside are
//! clamped back, so every evaluated design lies inside the box) and x0 is the box centre.
//! A design that fails is infeasible and scores +infinity, and the search goes on: one the
//! model rejects (e.g. dtau_A + dtau_D > 0.5) or whose analysis fails (an actuated wing that
//! does not settle into a periodic motion, diverged dynamics); [`HoverOptimum::failed_evals`]
//! counts them. When the box centre itself fails, the start is the first design that does
//! not of a grid around it ([`start_candidates`]); when every one of those fails, the search
//! stops with [`StudyError::AllFailed`]. A quadratic
//! penalty's minimizer undershoots the constraint by about (objective slope)/(2 rho), so the
//! search runs as a sequence of Nelder-Mead stages with rho = 1e2, 1e4, 1e6, 1e8, each
//! restarted from the previous stage's best point with a smaller simplex (the sequential
//! unconstrained minimization technique of Fiacco and McCormick, 1968); the final
//! undershoot is of order 1e-8, and a design counts as feasible when L/W >= target - 1e-6.

use nalgebra::DVector;
use serde::Serialize;

use super::error::{StudyError, StudyResult};
use super::responses::hover_responses;
use super::spec::Study;

/// Stopping rules and the initial simplex.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NelderMeadOptions {
    /// Most objective evaluations.
    pub max_evals: usize,
    /// Stop when every vertex lies within this (infinity-norm) distance of the best one...
    pub x_tol: f64,
    /// ...and every vertex value lies within this of the best value.
    pub f_tol: f64,
    /// Initial simplex: x0 plus this step along each coordinate.
    pub initial_step: f64,
}

impl Default for NelderMeadOptions {
    fn default() -> Self {
        Self {
            max_evals: 800,
            x_tol: 1e-6,
            f_tol: 1e-9,
            initial_step: 0.1,
        }
    }
}

/// What a Nelder-Mead run found.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NelderMeadResult {
    /// Best point.
    pub x: Vec<f64>,
    /// Objective there.
    pub f: f64,
    /// Objective evaluations used.
    pub evals: usize,
    /// Iterations (reflections tried).
    pub iterations: usize,
    /// True when the tolerances were met before `max_evals`.
    pub converged: bool,
}

/// Minimizes `f` from `x0` (see the module docs). Non-finite values count as worse than any
/// finite one.
pub fn nelder_mead(
    mut f: impl FnMut(&DVector<f64>) -> f64,
    x0: &DVector<f64>,
    opts: &NelderMeadOptions,
) -> NelderMeadResult {
    let n = x0.len();
    let mut evals = 0usize;
    let mut eval = |x: &DVector<f64>, evals: &mut usize| {
        *evals += 1;
        let v = f(x);
        if v.is_nan() { f64::INFINITY } else { v }
    };
    let mut simplex: Vec<(DVector<f64>, f64)> = Vec::with_capacity(n + 1);
    let v0 = eval(x0, &mut evals);
    simplex.push((x0.clone(), v0));
    for i in 0..n {
        let mut x = x0.clone();
        x[i] += opts.initial_step;
        let v = eval(&x, &mut evals);
        simplex.push((x, v));
    }
    let mut iterations = 0;
    let mut converged = false;
    while evals < opts.max_evals {
        simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
        let best = &simplex[0];
        let spread_x = simplex[1..]
            .iter()
            .map(|(x, _)| (x - &best.0).amax())
            .fold(0.0, f64::max);
        let spread_f = simplex[1..]
            .iter()
            .map(|(_, v)| (v - best.1).abs())
            .fold(0.0, f64::max);
        if spread_x <= opts.x_tol && spread_f <= opts.f_tol {
            converged = true;
            break;
        }
        iterations += 1;
        let centroid = simplex[..n]
            .iter()
            .fold(DVector::zeros(n), |acc, (x, _)| acc + x)
            / n as f64;
        let (worst_x, worst_f) = simplex[n].clone();
        let second_worst = simplex[n - 1].1;
        let best_f = simplex[0].1;
        let xr = &centroid + (&centroid - &worst_x);
        let fr = eval(&xr, &mut evals);
        if fr < best_f {
            let xe = &centroid + (&xr - &centroid) * 2.0;
            let fe = eval(&xe, &mut evals);
            simplex[n] = if fe < fr { (xe, fe) } else { (xr, fr) };
            continue;
        }
        if fr < second_worst {
            simplex[n] = (xr, fr);
            continue;
        }
        // Contraction: outside when the reflection beat the worst, inside otherwise.
        let (xc, fc) = if fr < worst_f {
            let xc = &centroid + (&xr - &centroid) * 0.5;
            let fc = eval(&xc, &mut evals);
            (xc, fc)
        } else {
            let xc = &centroid + (&worst_x - &centroid) * 0.5;
            let fc = eval(&xc, &mut evals);
            (xc, fc)
        };
        if fc < fr.min(worst_f) {
            simplex[n] = (xc, fc);
            continue;
        }
        // Shrink towards the best vertex.
        let x_best = simplex[0].0.clone();
        for v in simplex.iter_mut().skip(1) {
            let x = &x_best + (&v.0 - &x_best) * 0.5;
            let fx = eval(&x, &mut evals);
            *v = (x, fx);
        }
    }
    simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
    NelderMeadResult {
        x: simplex[0].0.iter().copied().collect(),
        f: simplex[0].1,
        evals,
        iterations,
        converged,
    }
}

/// The penalty weights rho of the successive stages of the hover search.
pub const PENALTIES: [f64; 4] = [1e2, 1e4, 1e6, 1e8];

/// Initial simplex steps (unit box) of the successive stages, relative to the options' step.
const STAGE_STEPS: [f64; 4] = [1.0, 0.3, 0.1, 0.03];

/// How far below the target a design may support the weight and still count as feasible.
pub const FEASIBILITY_TOL: f64 = 1e-6;

/// One evaluated design of the hover optimization.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HoverDesign {
    /// Factor values, in the study's order.
    pub values: Vec<f64>,
    /// Vertical force over weight.
    pub lift_over_weight: f64,
    /// Vertical force per aerodynamic power, N/W.
    pub lift_per_power_n_per_w: f64,
    /// Aerodynamic power, W.
    pub aero_power_w: f64,
    /// The paper's Re.
    pub reynolds: f64,
    /// Wake-capture inputs clamped to the fitted range.
    pub wake_capture_clamped: bool,
}

/// The result of [`optimize_hover`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HoverOptimum {
    /// Factor paths, in order.
    pub factors: Vec<String>,
    /// Factor intervals searched.
    pub bounds: Vec<(f64, f64)>,
    /// The start (box centre).
    pub start: HoverDesign,
    /// The best design found.
    pub best: HoverDesign,
    /// True when the best design supports the weight (L/W >= target - [`FEASIBILITY_TOL`]).
    pub feasible: bool,
    /// The weight-support target.
    pub target_lift_over_weight: f64,
    /// The Nelder-Mead stages (in the unit box), one per penalty weight.
    pub stages: Vec<NelderMeadResult>,
    /// Objective evaluations over all stages.
    pub evals: usize,
    /// Designs tried for a start that does not fail (1 when the box centre works).
    pub starts_tried: usize,
    /// Evaluations (start search and stages) whose design failed and scored +infinity.
    pub failed_evals: usize,
    /// Why the first failed design failed, with its factor settings.
    pub first_failure: Option<String>,
}

/// At most this many designs are tried for a start (see [`start_candidates`]).
pub const MAX_START_CANDIDATES: usize = 64;

/// The unit-box points tried, in order, for a start that does not fail: the centre, then the
/// points of the grid of levels 0.5, 0.25, 0.75, 0 and 1 on every factor, nearest the centre
/// first (ties in a fixed order), at most [`MAX_START_CANDIDATES`] in all.
pub fn start_candidates(k: usize) -> Vec<DVector<f64>> {
    const LEVELS: [f64; 5] = [0.5, 0.25, 0.75, 0.0, 1.0];
    let dist = |p: &[f64]| p.iter().map(|x| (x - 0.5) * (x - 0.5)).sum::<f64>();
    // Factor by factor, keeping the nearest points: the distance adds up over the factors,
    // so the nearest full points extend the nearest partial ones.
    let mut grid: Vec<Vec<f64>> = vec![Vec::new()];
    for _ in 0..k {
        grid = grid
            .into_iter()
            .flat_map(|p| {
                LEVELS.iter().map(move |&l| {
                    let mut q = p.clone();
                    q.push(l);
                    q
                })
            })
            .collect();
        grid.sort_by(|a, b| dist(a).total_cmp(&dist(b)));
        grid.truncate(MAX_START_CANDIDATES);
    }
    grid.into_iter().map(DVector::from_vec).collect()
}

/// Maximizes lift per aerodynamic power over the study's factor intervals subject to
/// `lift_over_weight >= target` (see the module docs).
pub fn optimize_hover(
    study: &Study,
    target: f64,
    opts: &NelderMeadOptions,
) -> StudyResult<HoverOptimum> {
    let k = study.factors.len();
    let bounds: Vec<(f64, f64)> = (0..k).map(|f| study.factor_bounds(f)).collect();
    for (f, (lo, hi)) in bounds.iter().enumerate() {
        if !(lo < hi) {
            return Err(StudyError::Invalid {
                origin: study.origin.clone(),
                message: format!(
                    "factor `{}` spans [{lo}, {hi}]: optimization needs an interval (a range, or at least two levels)",
                    study.factors[f].path
                ),
            });
        }
    }
    let to_values = |u: &DVector<f64>| -> Vec<f64> {
        u.iter()
            .zip(&bounds)
            .map(|(&ui, &(lo, hi))| lo + (hi - lo) * ui.clamp(0.0, 1.0))
            .collect()
    };
    let design = |values: Vec<f64>| -> flapsim::Result<HoverDesign> {
        let v = study.vehicle_at(&values)?;
        let r = hover_responses(&v, study.steps_per_wingbeat)?;
        Ok(HoverDesign {
            values,
            lift_over_weight: r.vertical_force_n / r.weight_n,
            lift_per_power_n_per_w: r.vertical_force_n / r.aero_power_w,
            aero_power_w: r.aero_power_w,
            reynolds: r.reynolds,
            wake_capture_clamped: r.wake_capture_clamped,
        })
    };
    let settings = |values: &[f64]| study.settings_at(values);
    let failed_evals = std::cell::Cell::new(0usize);
    let first_failure = std::cell::RefCell::new(None::<(String, String)>);
    let note_failure = |values: &[f64], e: &flapsim::Error| {
        failed_evals.set(failed_evals.get() + 1);
        first_failure
            .borrow_mut()
            .get_or_insert_with(|| (settings(values), e.to_string()));
    };
    let candidates = start_candidates(k);
    let mut found = None;
    let mut tried = 0;
    for u in &candidates {
        tried += 1;
        let values = to_values(u);
        match design(values.clone()) {
            Ok(d) => {
                found = Some((u.clone(), d));
                break;
            }
            Err(e) => note_failure(&values, &e),
        }
    }
    let Some((u0, start)) = found else {
        let (settings, reason) = first_failure.borrow_mut().take().unwrap_or_default();
        return Err(StudyError::AllFailed {
            tried,
            settings,
            reason,
        });
    };
    let scale = start.lift_per_power_n_per_w.abs().max(f64::MIN_POSITIVE);
    let mut u = u0;
    let mut stages = Vec::with_capacity(PENALTIES.len());
    for (rho, step) in PENALTIES.iter().zip(STAGE_STEPS) {
        let objective = |u: &DVector<f64>| match design(to_values(u)) {
            Ok(d) => {
                let short = (target - d.lift_over_weight).max(0.0);
                -d.lift_per_power_n_per_w / scale + rho * short * short
            }
            Err(e) => {
                note_failure(&to_values(u), &e);
                f64::INFINITY
            }
        };
        let stage_opts = NelderMeadOptions {
            max_evals: (opts.max_evals / PENALTIES.len()).max(2 * k + 2),
            initial_step: opts.initial_step * step,
            ..*opts
        };
        let r = nelder_mead(objective, &u, &stage_opts);
        u = DVector::from_iterator(k, r.x.iter().map(|x| x.clamp(0.0, 1.0)));
        stages.push(r);
    }
    let best = design(to_values(&u)).map_err(|source| StudyError::Case {
        case: 0,
        settings: "the optimum".to_owned(),
        source,
    })?;
    let evals = stages.iter().map(|s| s.evals).sum();
    Ok(HoverOptimum {
        factors: study.factors.iter().map(|f| f.path.clone()).collect(),
        bounds,
        feasible: best.lift_over_weight >= target - FEASIBILITY_TOL,
        target_lift_over_weight: target,
        start,
        best,
        stages,
        evals,
        starts_tried: tried,
        failed_evals: failed_evals.get(),
        first_failure: first_failure
            .into_inner()
            .map(|(settings, reason)| format!("{settings}: {reason}")),
    })
}
