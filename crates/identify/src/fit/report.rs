//! What a fit reports: the Student t quantile, the termination in words, standard errors, intervals and identifiability, and the report's text form.

use nalgebra::{DMatrix, DVector};

use crate::data::StartSource;

use super::segments::Setup;
use super::types::{FitReport, NO_EFFECT, ParamResult};

/// The quantile of Student's t with `nu` degrees of freedom at probability `p` in (0.5, 1),
/// by bisection of flapsim's `student_t_cdf` (to 1e-12).
pub fn t_quantile(p: f64, nu: f64) -> f64 {
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    while flapstudy::stats::student_t_cdf(hi, nu) < p && hi < 1e12 {
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if flapstudy::stats::student_t_cdf(mid, nu) < p {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo < 1e-12 * hi.max(1.0) {
            break;
        }
    }
    0.5 * (lo + hi)
}

pub(super) fn describe(t: &levenberg_marquardt::TerminationReason, max_evals: usize) -> String {
    use levenberg_marquardt::TerminationReason as T;
    match t {
        T::Converged { ftol, xtol } => match (ftol, xtol) {
            (true, true) => "converged (relative cost and step changes below tolerance)".into(),
            (true, false) => "converged (relative cost change below tolerance)".into(),
            _ => "converged (relative step below tolerance)".into(),
        },
        T::Orthogonal => "converged (residuals orthogonal to the Jacobian: gradient zero)".into(),
        T::ResidualsZero => "converged (residuals zero)".into(),
        T::LostPatience => format!(
            "did not converge: {max_evals} residual evaluations (the patience) used up; raise the patience or start closer"
        ),
        T::NoImprovementPossible(what) => {
            format!("did not converge: no improvement possible in {what} at machine precision")
        }
        T::Numerical(what) => format!("did not converge: non-finite numbers in the {what}"),
        T::User(what) => format!("stopped: the {what} could not be computed"),
        other => format!("did not converge: {other:?}"),
    }
}

/// Standard errors, intervals and identifiability from the Jacobian at the solution.
pub(super) fn statistics(
    setup: &Setup<'_>,
    j: &DMatrix<f64>,
    starts: &[f64],
    fitted: &[f64],
    sigma2: f64,
    t: f64,
) -> (Vec<ParamResult>, f64) {
    let n = j.ncols();
    let norms: Vec<f64> = (0..n).map(|i| j.column(i).norm()).collect();
    let max_norm = norms.iter().cloned().fold(0.0, f64::max);
    let effective: Vec<usize> = (0..n)
        .filter(|&i| norms[i] > NO_EFFECT * max_norm && norms[i] > 0.0)
        .collect();
    // Column-normalized Jacobian of the parameters that have an effect.
    let mut jn = DMatrix::zeros(j.nrows(), effective.len());
    for (c, &i) in effective.iter().enumerate() {
        jn.set_column(c, &(j.column(i) / norms[i]));
    }
    let mut cov_n = DMatrix::from_element(effective.len(), effective.len(), f64::INFINITY);
    let mut vif = vec![f64::INFINITY; effective.len()];
    let mut condition = f64::INFINITY;
    let mut singular_dirs: Vec<DVector<f64>> = Vec::new();
    if !effective.is_empty() {
        let svd = jn.clone().svd(false, true);
        let s = &svd.singular_values;
        let smax = s.max();
        let smin = s.min();
        condition = if smin > 0.0 {
            smax / smin
        } else {
            f64::INFINITY
        };
        if let Some(vt) = &svd.v_t {
            let mut inv = DMatrix::zeros(effective.len(), effective.len());
            for k in 0..s.len() {
                let v = vt.row(k).transpose();
                if s[k] > 1e-12 * smax {
                    inv += &v * v.transpose() / (s[k] * s[k]);
                } else {
                    singular_dirs.push(v);
                }
            }
            for c in 0..effective.len() {
                vif[c] = inv[(c, c)];
            }
            cov_n = inv;
        }
    }
    let mut out = Vec::with_capacity(n);
    for (i, p) in setup.params.iter().enumerate() {
        let scale = setup.scales[i];
        let c = effective.iter().position(|&e| e == i);
        let in_null = c.is_some_and(|c| singular_dirs.iter().any(|v| v[c].abs() > 1e-3));
        let (se, reason) = match c {
            None => (
                f64::INFINITY,
                Some(format!(
                    "the measurements do not depend on it (Jacobian column norm {:.3e}, the largest {:.3e})",
                    norms[i], max_norm
                )),
            ),
            Some(c) => {
                let var = sigma2 * cov_n[(c, c)] / (norms[i] * norms[i]);
                let se = var.sqrt() * scale;
                let reason = if in_null || !vif[c].is_finite() {
                    Some(format!(
                        "its effect is a combination of the other parameters' (Jacobian singular, condition number {condition:.3e})"
                    ))
                } else if vif[c] > 1e6 {
                    Some(format!(
                        "its effect is nearly a combination of the other parameters' (variance inflation {:.3e}, condition number {condition:.3e})",
                        vif[c]
                    ))
                } else {
                    let half = t * se;
                    let size = fitted[i].abs().max(scale);
                    (half > size).then(|| {
                        format!(
                            "its 95 % interval +-{half:.3e} is wider than its size {size:.3e} (relative half-width {:.2})",
                            half / size
                        )
                    })
                };
                (if in_null { f64::INFINITY } else { se }, reason)
            }
        };
        let half = t * se;
        out.push(ParamResult {
            name: p.name(),
            model_field: p.model_field(),
            start: starts[i],
            fitted: fitted[i],
            std_error: se,
            ci95: [fitted[i] - half, fitted[i] + half],
            relative_ci: half / fitted[i].abs().max(scale),
            identifiable: reason.is_none(),
            reason,
            scanned_start: None,
        });
    }
    (out, condition)
}

impl std::fmt::Display for FitReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "identified {} from {} ({}, model {})",
            self.params
                .iter()
                .map(|p| p.name.as_str())
                .collect::<Vec<_>>()
                .join(", "),
            self.source,
            self.format,
            self.model
        )?;
        let start = match (self.start_source, self.start_states_fitted) {
            (StartSource::LoggedState, false) => "the logged state",
            (StartSource::Mocap, false) => "the motion capture",
            (StartSource::LoggedState, true) => "the logged state, fitted: 12 unknowns each",
            (StartSource::Mocap, true) => "the motion capture, fitted: 12 unknowns each",
        };
        writeln!(
            f,
            "data: {} segments of up to {} wingbeats (starts from {start}), {} motion-capture frames, {} IMU samples, {} residuals",
            self.segments,
            self.segment_wingbeats,
            self.mocap_frames,
            self.imu_samples,
            self.residuals
        )?;
        writeln!(
            f,
            "{}: {} iterations, {} simulations, {:.2} s",
            self.termination, self.iterations, self.simulations, self.runtime_s
        )?;
        writeln!(
            f,
            "cost (chi-square) {:.6e} -> {:.6e}; rms weighted residual {:.4} -> {:.4} (1 = the sensors' noise)",
            self.cost_before, self.cost_after, self.rms_before, self.rms_after
        )?;
        if self.diverged_segments > 0 {
            writeln!(
                f,
                "warning: {} segments diverge at the fitted parameters",
                self.diverged_segments
            )?;
        }
        writeln!(
            f,
            "{:<24} {:>13} {:>13} {:>11} {:>29}  identifiable",
            "parameter", "start", "fitted", "std error", "95% interval"
        )?;
        for p in &self.params {
            writeln!(
                f,
                "{:<24} {:>13.6e} {:>13.6e} {:>11.3e} [{:>13.6e}, {:>13.6e}]  {}",
                p.name,
                p.start,
                p.fitted,
                p.std_error,
                p.ci95[0],
                p.ci95[1],
                if p.identifiable { "yes" } else { "NO" }
            )?;
            if let Some(s) = p.scanned_start {
                writeln!(
                    f,
                    "    started from {s:.6e}: the lowest cost of a scan of its range (its cost has several minima)"
                )?;
            }
            if let Some(r) = &p.reason {
                writeln!(f, "    not identifiable: {r}")?;
            }
        }
        writeln!(
            f,
            "condition number {:.3e}, t(0.975, {}) = {:.4}",
            self.condition_number, self.dof, self.t_quantile
        )
    }
}
