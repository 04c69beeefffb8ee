//! `flapwing optimize STUDY.toml [--min-lift-over-weight X] [--max-evals N] [--json]`.
//!
//! The search is one deterministic chain (Nelder-Mead stages from the box centre, each stage
//! started from the previous one's best point), not independent restarts, so it has no shards
//! and runs on one machine (see `flapstudy::optimize`).
//!
//! A design whose analysis fails (wings that do not settle, diverged dynamics) or that the
//! model refuses is infeasible: the search goes on, and the report counts such designs. When
//! the box centre fails, the search starts from the first design of a grid around it that
//! does not; when all of them fail, the command says so and exits 1 (the run failed).

use std::fmt::Write as _;
use std::path::PathBuf;

use clap::Args;

use super::analyze::fmt_num;
use super::sweep::load_study;
use crate::error::input_error;
use crate::output::{fmt_sig, print_json, print_stdout};

/// Arguments of `flapwing optimize`.
#[derive(Debug, Args)]
pub struct OptimizeArgs {
    /// A study file: its base model and factors define the search (each factor's `range`,
    /// or its lowest to highest level); its design and responses are not used.
    #[arg(value_name = "STUDY.toml")]
    pub study: PathBuf,
    /// The weight-support constraint: lift_over_weight >= this.
    #[arg(long = "min-lift-over-weight", default_value_t = 1.0, value_parser = parse_positive)]
    pub min_lift_over_weight: f64,
    /// Most objective evaluations (spread over the four penalty stages).
    #[arg(long = "max-evals", default_value_t = 800,
          value_parser = clap::value_parser!(u32).range(16..=1_000_000))]
    pub max_evals: u32,
    /// Print one JSON document on stdout instead of the text report.
    #[arg(long)]
    pub json: bool,
}

fn parse_positive(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 => Ok(x),
        _ => Err(format!("`{s}` is not a finite number > 0")),
    }
}

/// `flapwing optimize`: maximize lift per aerodynamic power over a study's factor box while
/// supporting the weight (Nelder-Mead with a sequence of quadratic penalties; see
/// `flapstudy::optimize`). Responses are tethered at the hover attitude, as in a sweep.
pub fn run(args: OptimizeArgs) -> anyhow::Result<()> {
    use flapstudy::StudyError;
    use flapstudy::optimize::{NelderMeadOptions, optimize_hover};
    let study = load_study(&args.study)?;
    let opts = NelderMeadOptions {
        max_evals: args.max_evals as usize,
        ..NelderMeadOptions::default()
    };
    let opt = optimize_hover(&study, args.min_lift_over_weight, &opts).map_err(|e| match e {
        StudyError::AllFailed { .. } => anyhow::anyhow!("{}: {e}", study.origin),
        e => input_error(e.to_string()),
    })?;
    if args.json {
        return print_json(&opt);
    }
    let mut out = String::new();
    let _ = writeln!(
        out,
        "Optimize {} (base {}): maximize lift per aerodynamic power subject to lift/weight >= {}",
        study.name,
        study.base_origin,
        fmt_sig(opt.target_lift_over_weight, 6)
    );
    let _ = writeln!(
        out,
        "  {:<36} {:>12} {:>12} {:>12} {:>12}",
        "factor", "min", "max", "start", "optimum"
    );
    for (i, f) in opt.factors.iter().enumerate() {
        let _ = writeln!(
            out,
            "  {:<36} {:>12} {:>12} {:>12} {:>12}",
            f,
            fmt_num(opt.bounds[i].0, 6),
            fmt_num(opt.bounds[i].1, 6),
            fmt_num(opt.start.values[i], 6),
            fmt_num(opt.best.values[i], 6)
        );
    }
    let row = |label: &str, a: f64, b: f64| {
        format!(
            "  {label:<36} {:>12} {:>12}\n",
            fmt_num(a, 5),
            fmt_num(b, 5)
        )
    };
    let _ = writeln!(out, "\n  {:<36} {:>12} {:>12}", "", "start", "optimum");
    out.push_str(&row(
        "lift_per_power_n_per_w [N/W]",
        opt.start.lift_per_power_n_per_w,
        opt.best.lift_per_power_n_per_w,
    ));
    out.push_str(&row(
        "lift_over_weight",
        opt.start.lift_over_weight,
        opt.best.lift_over_weight,
    ));
    out.push_str(&row(
        "aero_power_w [W]",
        opt.start.aero_power_w,
        opt.best.aero_power_w,
    ));
    out.push_str(&row(
        "reynolds (Re = V_ref c_bar / nu)",
        opt.start.reynolds,
        opt.best.reynolds,
    ));
    let _ = writeln!(
        out,
        "\n  {} evaluations in {} penalty stages; {}{}",
        opt.evals,
        opt.stages.len(),
        if opt.feasible {
            "the optimum supports the weight"
        } else {
            "NO design found that supports the weight: the optimum is the least infeasible"
        },
        if opt.best.wake_capture_clamped {
            "; wake-capture inputs clamped to the fitted range at the optimum"
        } else {
            ""
        }
    );
    if opt.starts_tried > 1 {
        let _ = writeln!(
            out,
            "  the box centre failed: the search started from design {} of the start grid",
            opt.starts_tried
        );
    }
    if let Some(first) = &opt.first_failure {
        let _ = writeln!(
            out,
            "  {} design(s) failed and counted as infeasible; the first: {first}",
            opt.failed_evals
        );
    }
    print_stdout(&out)
}
