//! `flapwing fit-wake DATA.csv [--json] [--write MODEL.toml]`: refit the seed paper's
//! wake-capture regressions (eq 17-19) to a table of runs (CFD or experiments), print the
//! coefficients beside the paper's, the standard error S = sqrt(SSE/(n - p)), R^2 and the
//! residuals, and optionally write the refitted model as TOML.
//!
//! The data: a CSV whose header names at least `re,dtau_d,dtau_a,dcl_mean,dcd_mean,mu_star`
//! (other columns are ignored; lines starting with `#` are comments), one run per row,
//! at least 6 runs, e.g. `data/wake_capture_l18.csv` (the paper's Table 4).
//!
//! The written model (`--write`) is a set of `key = value` lines that deserializes as
//! `wingforce::WakeCaptureModel`. To use it, paste the lines under an
//! `[aero.wake_capture_model]` header in a wing or vehicle model file; the file's opening
//! comment says the same.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::PathBuf;

use clap::Args;
use flapstudy::fit_wake::{
    ExpQuadraticFit, WakeCaptureData, WakeCaptureFit, fit_wake_capture, model_toml,
    model_toml_usage,
};
use flapstudy::stats::LinearFit;
use serde::Serialize;
use wingforce::WakeCaptureModel;
use wingforce::coefficients::ExpQuadratic;

use crate::error::{InputContext, input_error};
use crate::output::{create_output_file, fmt_sig, print_json, print_stdout};

/// Arguments of `flapwing fit-wake`.
#[derive(Debug, Args)]
pub struct FitWakeArgs {
    /// The runs: a CSV with columns re, dtau_d, dtau_a, dcl_mean, dcd_mean, mu_star.
    #[arg(value_name = "DATA.csv")]
    pub data: PathBuf,
    /// Print one JSON document on stdout instead of the text report.
    #[arg(long)]
    pub json: bool,
    /// Write the refitted model as TOML (paste its lines under `[aero.wake_capture_model]`).
    #[arg(long, value_name = "MODEL.toml")]
    pub write: Option<PathBuf>,
    /// Replace the --write file if it already exists.
    #[arg(long)]
    pub force: bool,
}

/// One run's data and residuals.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
struct RunResidual {
    line: usize,
    re: f64,
    dtau_d: f64,
    dtau_a: f64,
    dcl_mean: f64,
    dcl_residual: f64,
    dcd_mean: f64,
    dcd_residual: f64,
    mu_star: f64,
    mu_star_residual: f64,
}

/// The JSON document.
#[derive(Debug, Serialize)]
struct Report<'a> {
    data: String,
    runs: usize,
    /// The refits.
    fit: &'a WakeCaptureFit,
    /// The seed paper's eq 17-19 for comparison.
    paper: WakeCaptureModel,
    /// The paper's printed standard errors S of eq 17, 18, 19.
    paper_s: [f64; 3],
    residuals: Vec<RunResidual>,
    written: Option<String>,
}

/// The paper's printed S under eq 17, 18 and 19.
const PAPER_S: [f64; 3] = [0.0345025, 0.0354756, 0.0040837];

/// Runs the command.
pub fn run(args: FitWakeArgs) -> anyhow::Result<()> {
    let origin = args.data.display().to_string();
    let text = std::fs::read_to_string(&args.data)
        .input_context(format!("cannot read data file `{origin}`"))?;
    let data = WakeCaptureData::from_csv(&text, &origin).map_err(|e| input_error(e.to_string()))?;
    let fit = fit_wake_capture(&data).map_err(|e| input_error(e.to_string()))?;

    let written = match &args.write {
        Some(path) => {
            let mut file = create_output_file(path, args.force, "model file")?;
            let body = model_toml(&fit.model, &model_toml_usage(&origin, fit.n));
            file.write_all(body.as_bytes())
                .map_err(|e| anyhow::anyhow!("cannot write `{}`: {e}", path.display()))?;
            Some(path.display().to_string())
        }
        None => None,
    };

    let residuals: Vec<RunResidual> = data
        .runs
        .iter()
        .enumerate()
        .map(|(i, r)| RunResidual {
            line: r.line,
            re: r.re,
            dtau_d: r.dtau_d,
            dtau_a: r.dtau_a,
            dcl_mean: r.dcl_mean,
            dcl_residual: fit.dcl.residuals[i],
            dcd_mean: r.dcd_mean,
            dcd_residual: fit.dcd.residuals[i],
            mu_star: r.mu_star,
            mu_star_residual: fit.mu_star.residuals[i],
        })
        .collect();

    if args.json {
        return print_json(&Report {
            data: origin,
            runs: fit.n,
            fit: &fit,
            paper: WakeCaptureModel::paper(),
            paper_s: PAPER_S,
            residuals,
            written,
        });
    }
    print_stdout(&text_report(&origin, &fit, &residuals, written.as_deref()))
}

/// A p-value: 3 significant digits, in scientific notation below 0.001.
fn fmt_p(p: f64) -> String {
    if p < 1e-3 {
        format!("{p:.2e}")
    } else {
        fmt_sig(p, 3)
    }
}

fn range_text(r: &wingforce::coefficients::FitRange) -> String {
    format!("{}-{}", fmt_sig(r.min, 6), fmt_sig(r.max, 6))
}

fn exp_block(out: &mut String, title: &str, f: &ExpQuadraticFit, paper: &ExpQuadratic, s: f64) {
    let _ = writeln!(out, "{title}");
    let _ = writeln!(
        out,
        "  {:<5} {:>14} {:>12} {:>14}",
        "coef", "refit", "std err", "paper"
    );
    let refit = [f.model.c0, f.model.c1, f.model.c2, f.model.c3, f.model.c4];
    let pap = [paper.c0, paper.c1, paper.c2, paper.c3, paper.c4];
    for k in 0..5 {
        let _ = writeln!(
            out,
            "  {:<5} {:>14} {:>12} {:>14}",
            format!("c{k}"),
            fmt_sig(refit[k], 6),
            fmt_sig(f.std_errors[k], 3),
            fmt_sig(pap[k], 6)
        );
    }
    let _ = writeln!(
        out,
        "  S = {} (paper: {})   R^2 = {}   SSE = {}   (scan start c2 = {}, {} LM iterations)",
        fmt_sig(f.s, 6),
        s,
        fmt_sig(f.r_squared, 4),
        fmt_sig(f.sse, 6),
        fmt_sig(f.scan_c2, 4),
        f.iterations
    );
}

fn linear_block(out: &mut String, f: &LinearFit, paper: [f64; 3]) {
    let _ = writeln!(
        out,
        "  {:<12} {:>12} {:>11} {:>9} {:>10} {:>10}",
        "term", "refit", "std err", "t", "p", "paper"
    );
    for k in 0..f.coefficients.len() {
        let _ = writeln!(
            out,
            "  {:<12} {:>12} {:>11} {:>9} {:>10} {:>10}",
            f.names[k],
            fmt_sig(f.coefficients[k], 6),
            fmt_sig(f.std_errors[k], 3),
            fmt_sig(f.t_values[k], 4),
            fmt_p(f.p_values[k]),
            fmt_sig(paper[k], 4)
        );
    }
    let _ = writeln!(
        out,
        "  S = {} (paper: {})   R^2 = {}   adj R^2 = {}   SSE = {}",
        fmt_sig(f.s, 6),
        PAPER_S[2],
        fmt_sig(f.r_squared, 4),
        fmt_sig(f.adj_r_squared, 4),
        fmt_sig(f.sse, 6)
    );
}

fn text_report(
    origin: &str,
    fit: &WakeCaptureFit,
    residuals: &[RunResidual],
    written: Option<&str>,
) -> String {
    let m = &fit.model;
    let paper = WakeCaptureModel::paper();
    let mut out = String::new();
    let _ = writeln!(
        out,
        "Wake-capture refit of {origin}: {} runs; Re {}, dtau_A {}, dtau_D {}",
        fit.n,
        range_text(&m.re_range),
        range_text(&m.dtau_a_range),
        range_text(&m.dtau_d_range)
    );
    let _ = writeln!(
        out,
        "(Re = V_ref c_bar / nu, the seed paper's definition; \"paper\" = its eq 17-19)\n"
    );
    exp_block(
        &mut out,
        "eq 17: dcl_mean = c0 + c1 exp(c2 Re) + c3 dtau_D + c4 dtau_D^2  (nonlinear least squares)",
        &fit.dcl,
        &paper.dcl,
        PAPER_S[0],
    );
    let _ = writeln!(out);
    exp_block(
        &mut out,
        "eq 18: dcd_mean = c0 + c1 exp(c2 Re) + c3 dtau_D + c4 dtau_D^2  (nonlinear least squares)",
        &fit.dcd,
        &paper.dcd,
        PAPER_S[1],
    );
    let _ = writeln!(out);
    let _ = writeln!(
        out,
        "eq 19: mu_star = m0 + m1 ln Re + m2 dtau_A  (linear least squares; t and p on {} dof)",
        fit.mu_star.dof
    );
    linear_block(
        &mut out,
        &fit.mu_star,
        [paper.mu_star.m0, paper.mu_star.m1, paper.mu_star.m2],
    );
    let _ = writeln!(out, "\nResiduals (data - fit):");
    let _ = writeln!(
        out,
        "  {:>5} {:>8} {:>7} {:>7} {:>9} {:>10} {:>9} {:>10} {:>8} {:>10}",
        "line",
        "Re",
        "dtau_D",
        "dtau_A",
        "dcl_mean",
        "resid",
        "dcd_mean",
        "resid",
        "mu_star",
        "resid"
    );
    for r in residuals {
        let _ = writeln!(
            out,
            "  {:>5} {:>8} {:>7} {:>7} {:>9} {:>10} {:>9} {:>10} {:>8} {:>10}",
            r.line,
            fmt_sig(r.re, 6),
            fmt_sig(r.dtau_d, 4),
            fmt_sig(r.dtau_a, 4),
            fmt_sig(r.dcl_mean, 4),
            format!("{:+.5}", r.dcl_residual),
            fmt_sig(r.dcd_mean, 4),
            format!("{:+.5}", r.dcd_residual),
            fmt_sig(r.mu_star, 4),
            format!("{:+.6}", r.mu_star_residual)
        );
    }
    if let Some(path) = written {
        let _ = writeln!(
            out,
            "\nWrote the refitted model to {path}; paste its lines under [aero.wake_capture_model] in a wing or vehicle model."
        );
    }
    out
}
