//! Refitting the seed paper's wake-capture regressions (eq 17-19) to a table of runs.
//!
//! The forms are the paper's:
//! - eq 17 and 18: `y = c0 + c1 exp(c2 Re) + c3 dtau_D + c4 dtau_D^2`, nonlinear in c2, fitted
//!   by nonlinear least squares: a 1-D scan over c2 (for each fixed c2 the problem is linear
//!   and solved exactly), then Levenberg-Marquardt on all five coefficients started from the
//!   best scanned c2 and its linear fit;
//! - eq 19: `mu* = m0 + m1 ln Re + m2 dtau_A`, linear least squares.
//!
//! The standard error of each fit is S = sqrt(SSE / (n - p)) with p = 5 or 3 (what Minitab,
//! the paper's tool, prints as S). Standard errors of the nonlinear coefficients come from
//! the linearization at the solution, S^2 (J^T J)^-1 (the usual asymptotic estimate, e.g.
//! Bates and Watts, *Nonlinear Regression Analysis*, ch. 2).

use nalgebra::{DMatrix, DVector};
use serde::Serialize;
use wingforce::WakeCaptureModel;
use wingforce::coefficients::{ExpQuadratic, FitRange, LinearLn};

use super::error::{StudyError, StudyResult};
use super::stats::{LinearFit, lstsq, ols};
use super::table::Table;

/// The columns a wake-capture data table must have.
pub const REQUIRED_COLUMNS: [&str; 6] =
    ["re", "dtau_d", "dtau_a", "dcl_mean", "dcd_mean", "mu_star"];

/// One run of a wake-capture data table (one CFD run or experiment).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct WakeRun {
    /// Line of the run in its file (1-based).
    pub line: usize,
    /// Reynolds number Re = V_ref c_bar / nu (the paper's definition).
    pub re: f64,
    /// Deceleration fraction of the period at the end of a half stroke.
    pub dtau_d: f64,
    /// Acceleration fraction of the period at the start of a half stroke.
    pub dtau_a: f64,
    /// Mean lift-coefficient increment over the first 0.1 T of a half stroke.
    pub dcl_mean: f64,
    /// Mean drag-coefficient increment over the first 0.1 T.
    pub dcd_mean: f64,
    /// Non-dimensional time of the wake-capture peak.
    pub mu_star: f64,
}

/// A table of wake-capture runs, e.g. the seed paper's Table 4
/// (`data/wake_capture_l18.csv`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WakeCaptureData {
    /// The file the runs came from.
    pub origin: String,
    /// The runs, in file order.
    pub runs: Vec<WakeRun>,
}

impl WakeCaptureData {
    /// Parses CSV text with (at least) the columns of [`REQUIRED_COLUMNS`]; other columns
    /// are ignored. Errors name the file, the line and the column.
    pub fn from_csv(text: &str, origin: &str) -> StudyResult<Self> {
        let table = Table::parse(text, origin)?;
        let mut idx = [0usize; 6];
        for (slot, name) in idx.iter_mut().zip(REQUIRED_COLUMNS) {
            *slot = table.require(name)?;
        }
        let cols: Vec<Vec<f64>> = idx
            .iter()
            .map(|&c| table.numbers(c))
            .collect::<StudyResult<_>>()?;
        let mut runs = Vec::with_capacity(table.rows.len());
        for (r, (line, _)) in table.rows.iter().enumerate() {
            let run = WakeRun {
                line: *line,
                re: cols[0][r],
                dtau_d: cols[1][r],
                dtau_a: cols[2][r],
                dcl_mean: cols[3][r],
                dcd_mean: cols[4][r],
                mu_star: cols[5][r],
            };
            if run.re <= 0.0 {
                return Err(table.cell_error(
                    r,
                    idx[0],
                    format!("Re = {} must be > 0 (eq 19 uses ln Re)", run.re),
                ));
            }
            runs.push(run);
        }
        let data = Self {
            origin: origin.to_owned(),
            runs,
        };
        let n = data.runs.len();
        if n < MIN_RUNS {
            let last = table.rows.last().map_or(table.header_line, |r| r.0);
            return Err(StudyError::Table {
                origin: origin.to_owned(),
                line: last,
                column: None,
                message: format!(
                    "too few rows: {n} data row(s); fitting the eq 17-18 form (5 coefficients) with a standard error needs at least {MIN_RUNS}"
                ),
            });
        }
        Ok(data)
    }
}

/// The seed paper's Table 4 (the 18 CFD runs of its Taguchi L18 design; Re, dtau_D and
/// dtau_A at the Table 1-2 levels; means and standard deviations over cycles 8-10; mu_star
/// the non-dimensional time of the peak): `data/wake_capture_l18.csv` in the repository.
pub const PAPER_TABLE4_CSV: &str = include_str!("../../../data/wake_capture_l18.csv");

/// The fewest runs that give the 5-coefficient fits one residual degree of freedom.
pub const MIN_RUNS: usize = 6;

/// A fit of the eq 17/18 form `c0 + c1 exp(c2 Re) + c3 dtau_D + c4 dtau_D^2`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ExpQuadraticFit {
    /// The fitted coefficients.
    pub model: ExpQuadratic,
    /// Standard errors of c0..c4 (linearized).
    pub std_errors: [f64; 5],
    /// Sum of squared residuals.
    pub sse: f64,
    /// S = sqrt(SSE / (n - 5)).
    pub s: f64,
    /// 1 - SSE / SST.
    pub r_squared: f64,
    /// Fitted values, in run order.
    pub fitted: Vec<f64>,
    /// Residuals y - fitted, in run order.
    pub residuals: Vec<f64>,
    /// The c2 the 1-D scan picked as the start.
    pub scan_c2: f64,
    /// Levenberg-Marquardt iterations taken.
    pub iterations: usize,
}

/// The three refits and the model they make.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WakeCaptureFit {
    /// Number of runs.
    pub n: usize,
    /// Eq 17 form fitted to `dcl_mean`.
    pub dcl: ExpQuadraticFit,
    /// Eq 18 form fitted to `dcd_mean`.
    pub dcd: ExpQuadraticFit,
    /// Eq 19 form fitted to `mu_star` (terms m0, m1 (ln Re), m2 (dtau_A)).
    pub mu_star: LinearFit,
    /// The refitted model, with the fitted ranges taken from the data's min and max.
    pub model: WakeCaptureModel,
}

/// Fits eq 17-19's forms to `data` (at least [`MIN_RUNS`] runs).
pub fn fit_wake_capture(data: &WakeCaptureData) -> StudyResult<WakeCaptureFit> {
    let runs = &data.runs;
    if runs.len() < MIN_RUNS {
        return Err(StudyError::Fit(format!(
            "{}: {} runs; the eq 17-18 fits need at least {MIN_RUNS}",
            data.origin,
            runs.len()
        )));
    }
    let re: Vec<f64> = runs.iter().map(|r| r.re).collect();
    let dd: Vec<f64> = runs.iter().map(|r| r.dtau_d).collect();
    let da: Vec<f64> = runs.iter().map(|r| r.dtau_a).collect();
    let cl: Vec<f64> = runs.iter().map(|r| r.dcl_mean).collect();
    let cd: Vec<f64> = runs.iter().map(|r| r.dcd_mean).collect();
    let mu: Vec<f64> = runs.iter().map(|r| r.mu_star).collect();
    let ctx = |what: &str, e: StudyError| StudyError::Fit(format!("{}: {what}: {e}", data.origin));
    let dcl = fit_exp_quadratic(&re, &dd, &cl).map_err(|e| ctx("dcl_mean (eq 17 form)", e))?;
    let dcd = fit_exp_quadratic(&re, &dd, &cd).map_err(|e| ctx("dcd_mean (eq 18 form)", e))?;
    let mu_fit = fit_linear_ln(&re, &da, &mu).map_err(|e| ctx("mu_star (eq 19 form)", e))?;
    let range = |v: &[f64]| FitRange {
        min: v.iter().copied().fold(f64::INFINITY, f64::min),
        max: v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    };
    let model = WakeCaptureModel {
        source: format!(
            "flapwing fit-wake: eq 17-19 forms refitted to {} ({} runs)",
            data.origin,
            runs.len()
        ),
        dcl: dcl.model,
        dcd: dcd.model,
        mu_star: LinearLn {
            m0: mu_fit.coefficients[0],
            m1: mu_fit.coefficients[1],
            m2: mu_fit.coefficients[2],
        },
        re_range: range(&re),
        dtau_a_range: range(&da),
        dtau_d_range: range(&dd),
    };
    Ok(WakeCaptureFit {
        n: runs.len(),
        dcl,
        dcd,
        mu_star: mu_fit,
        model,
    })
}

/// Eq 19's form `m0 + m1 ln Re + m2 dtau_A` by ordinary least squares.
pub fn fit_linear_ln(re: &[f64], dtau_a: &[f64], y: &[f64]) -> StudyResult<LinearFit> {
    let n = y.len();
    let x = DMatrix::from_fn(n, 3, |i, j| match j {
        0 => 1.0,
        1 => re[i].ln(),
        _ => dtau_a[i],
    });
    ols(
        vec!["m0".into(), "m1 (ln Re)".into(), "m2 (dtau_A)".into()],
        &x,
        y,
    )
}

/// Model value and Jacobian row of `c0 + c1 exp(k re/scale) + c3 d + c4 d^2` in the scaled
/// parameters (c0, c1, k, c3, c4), k = c2 * scale.
fn eq17_row(p: &[f64; 5], re_s: f64, d: f64) -> (f64, [f64; 5]) {
    let e = (p[2] * re_s).exp();
    (
        p[0] + p[1] * e + p[3] * d + p[4] * d * d,
        [1.0, e, p[1] * re_s * e, d, d * d],
    )
}

fn sse_of(p: &[f64; 5], re_s: &[f64], d: &[f64], y: &[f64]) -> f64 {
    re_s.iter()
        .zip(d)
        .zip(y)
        .map(|((&r, &dd), &yy)| {
            let v = yy - eq17_row(p, r, dd).0;
            v * v
        })
        .sum()
}

/// The linear fit of (c0, c1, c3, c4) for a fixed scaled rate k; `None` when degenerate.
fn linear_at(k: f64, re_s: &[f64], d: &[f64], y: &[f64]) -> Option<([f64; 5], f64)> {
    let n = y.len();
    let x = DMatrix::from_fn(n, 4, |i, j| match j {
        0 => 1.0,
        1 => (k * re_s[i]).exp(),
        2 => d[i],
        _ => d[i] * d[i],
    });
    let sol = lstsq(&x, &DVector::from_column_slice(y))?;
    let b = &sol.beta;
    let p = [b[0], b[1], k, b[2], b[3]];
    let sse = sse_of(&p, re_s, d, y);
    sse.is_finite().then_some((p, sse))
}

/// Fits the eq 17/18 form to `y` over (`re`, `dtau_d`): scan, then Levenberg-Marquardt.
pub fn fit_exp_quadratic(re: &[f64], dtau_d: &[f64], y: &[f64]) -> StudyResult<ExpQuadraticFit> {
    let n = y.len();
    if n < MIN_RUNS {
        return Err(StudyError::Fit(format!(
            "{n} runs cannot fit 5 coefficients with an error estimate: at least {MIN_RUNS} are needed"
        )));
    }
    let distinct = |v: &[f64]| {
        let mut s: Vec<f64> = v.to_vec();
        s.sort_by(f64::total_cmp);
        s.dedup();
        s.len()
    };
    if distinct(dtau_d) < 3 {
        return Err(StudyError::Fit(format!(
            "dtau_D takes {} distinct value(s); the quadratic in dtau_D needs at least 3",
            distinct(dtau_d)
        )));
    }
    if distinct(re) < 3 {
        return Err(StudyError::Fit(format!(
            "Re takes {} distinct value(s); the exponential in Re needs at least 3",
            distinct(re)
        )));
    }
    // Scale Re so that the rate k = c2 * scale is of order one for the data's range.
    let scale = re.iter().fold(0.0f64, |m, r| m.max(r.abs()));
    let re_s: Vec<f64> = re.iter().map(|r| r / scale).collect();

    // 1-D scan of k over +-[1e-2, 1e2] on a log grid (exp(k) at the largest Re from
    // 1.01 to e^100 and back down to e^-100), each point an exact linear fit.
    let mut best: Option<([f64; 5], f64)> = None;
    for sign in [-1.0, 1.0] {
        for i in 0..=240 {
            let k = sign * 10f64.powf(-2.0 + 4.0 * i as f64 / 240.0);
            if let Some((p, sse)) = linear_at(k, &re_s, dtau_d, y)
                && best.as_ref().is_none_or(|b| sse < b.1)
            {
                best = Some((p, sse));
            }
        }
    }
    let Some((mut p, mut sse)) = best else {
        return Err(StudyError::Fit(
            "no rate c2 gives a full-rank linear fit: the data cannot separate the exponential in Re from the constant".to_owned(),
        ));
    };
    let scan_c2 = p[2] / scale;

    // Levenberg-Marquardt (Marquardt 1963, with the diagonal of J^T J as the damping
    // scale) on all five coefficients.
    let mut lambda = 1e-3;
    let mut iterations = 0;
    for it in 1..=500 {
        iterations = it;
        let mut jtj = nalgebra::SMatrix::<f64, 5, 5>::zeros();
        let mut jtr = nalgebra::SVector::<f64, 5>::zeros();
        for i in 0..n {
            let (v, j) = eq17_row(&p, re_s[i], dtau_d[i]);
            let r = y[i] - v;
            let jv = nalgebra::SVector::<f64, 5>::from(j);
            jtj += jv * jv.transpose();
            jtr += jv * r;
        }
        let mut improved = false;
        while lambda < 1e16 {
            let mut a = jtj;
            for k in 0..5 {
                a[(k, k)] += lambda * jtj[(k, k)].max(1e-300);
            }
            let Some(step) = a.cholesky().map(|c| c.solve(&jtr)) else {
                lambda *= 10.0;
                continue;
            };
            let trial = [
                p[0] + step[0],
                p[1] + step[1],
                p[2] + step[2],
                p[3] + step[3],
                p[4] + step[4],
            ];
            let trial_sse = sse_of(&trial, &re_s, dtau_d, y);
            if trial_sse.is_finite() && trial_sse <= sse {
                let rel = (sse - trial_sse) / sse.max(f64::MIN_POSITIVE);
                let small_step = step
                    .iter()
                    .zip(&p)
                    .all(|(s, q)| s.abs() <= 1e-12 * (q.abs() + 1e-12));
                p = trial;
                sse = trial_sse;
                lambda = (lambda / 10.0).max(1e-12);
                improved = rel > 1e-15 && !small_step;
                break;
            }
            lambda *= 10.0;
        }
        if !improved {
            break;
        }
    }

    // Statistics at the solution.
    let mut jm = DMatrix::zeros(n, 5);
    let mut fitted = Vec::with_capacity(n);
    for i in 0..n {
        let (v, j) = eq17_row(&p, re_s[i], dtau_d[i]);
        fitted.push(v);
        for k in 0..5 {
            jm[(i, k)] = j[k];
        }
    }
    let residuals: Vec<f64> = y.iter().zip(&fitted).map(|(a, b)| a - b).collect();
    let s2 = sse / (n - 5) as f64;
    let mean = y.iter().sum::<f64>() / n as f64;
    let sst: f64 = y.iter().map(|v| (v - mean) * (v - mean)).sum();
    let mut std_errors = [f64::NAN; 5];
    if let Some(sol) = lstsq(&jm, &DVector::zeros(n)) {
        for k in 0..5 {
            std_errors[k] = (s2 * sol.xtx_inv[(k, k)]).sqrt();
        }
        std_errors[2] /= scale;
    }
    Ok(ExpQuadraticFit {
        model: ExpQuadratic {
            c0: p[0],
            c1: p[1],
            c2: p[2] / scale,
            c3: p[3],
            c4: p[4],
        },
        std_errors,
        sse,
        s: s2.sqrt(),
        r_squared: if sst > 0.0 { 1.0 - sse / sst } else { f64::NAN },
        fitted,
        residuals,
        scan_c2,
        iterations,
    })
}

/// The SSE of given eq 17/18 coefficients on data (to compare a published fit with a refit
/// on the same table).
pub fn exp_quadratic_sse(model: &ExpQuadratic, re: &[f64], dtau_d: &[f64], y: &[f64]) -> f64 {
    re.iter()
        .zip(dtau_d)
        .zip(y)
        .map(|((&r, &d), &v)| {
            let e = v - model.eval(r, d);
            e * e
        })
        .sum()
}

/// The refitted model as TOML text that deserializes as [`WakeCaptureModel`]. The lines are
/// `key = value` pairs with inline tables, so the same text can be pasted verbatim under an
/// `[aero.wake_capture_model]` header of a wing or vehicle model (see the comment it
/// starts with). Numbers are printed with Rust's shortest round-trip formatting, so reading
/// the file back gives the fitted coefficients bit for bit.
pub fn model_toml(model: &WakeCaptureModel, header_comment: &str) -> String {
    let mut out = String::new();
    for line in header_comment.lines() {
        out.push_str("# ");
        out.push_str(line);
        out.push('\n');
    }
    let q = |s: &str| {
        let mut t = String::from("\"");
        for ch in s.chars() {
            match ch {
                '"' => t.push_str("\\\""),
                '\\' => t.push_str("\\\\"),
                c if c.is_control() => t.push_str(&format!("\\u{:04X}", c as u32)),
                c => t.push(c),
            }
        }
        t.push('"');
        t
    };
    let eq = |e: &ExpQuadratic| {
        format!(
            "{{ c0 = {:?}, c1 = {:?}, c2 = {:?}, c3 = {:?}, c4 = {:?} }}",
            e.c0, e.c1, e.c2, e.c3, e.c4
        )
    };
    let rng = |r: &FitRange| format!("{{ min = {:?}, max = {:?} }}", r.min, r.max);
    out.push_str(&format!("source = {}\n", q(&model.source)));
    out.push_str(&format!("dcl = {}\n", eq(&model.dcl)));
    out.push_str(&format!("dcd = {}\n", eq(&model.dcd)));
    out.push_str(&format!(
        "mu_star = {{ m0 = {:?}, m1 = {:?}, m2 = {:?} }}\n",
        model.mu_star.m0, model.mu_star.m1, model.mu_star.m2
    ));
    out.push_str(&format!("re_range = {}\n", rng(&model.re_range)));
    out.push_str(&format!("dtau_a_range = {}\n", rng(&model.dtau_a_range)));
    out.push_str(&format!("dtau_d_range = {}\n", rng(&model.dtau_d_range)));
    out
}

/// The comment [`model_toml`] output starts with when written by `flapwing fit-wake`: how
/// to use the file.
pub fn model_toml_usage(data_origin: &str, n: usize) -> String {
    format!(
        "Wake-capture model refitted by `flapwing fit-wake` from {data_origin} ({n} runs):\n\
         the forms of the seed paper's eq 17-19; ranges are the data's min and max.\n\
         To use it in a wing or vehicle model, paste every line below under the header\n\
         [aero.wake_capture_model]\n\
         (the [aero] section may exist or not; keep `wake_capture = true`, the default).\n\
         The lines alone deserialize as wingforce::WakeCaptureModel."
    )
}
