//! `flapwing sweep analyze FILE.csv --response NAME [--snr larger|smaller|nominal]
//! [--ln FACTOR]... [--plot FILE.svg] [--json]`: the Taguchi analysis of one response of a sweep
//! CSV: SNR per run (eq 15 for larger-the-better; runs with identical factor settings are
//! replicates), main effects of the SNR and of the mean response per factor level, and the full
//! second-order regression of eq 16 on the factors (`--ln` regresses on the log of a factor, as
//! eq 16 does with Re), with standard errors, t values and p-values; `--plot` draws the SNR main
//! effects (SVG, or PNG by extension).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use clap::Args;
use flapstudy::regression::{Term, fit_terms};
use flapstudy::stats::LinearFit;
use flapstudy::sweep::FLAG_COLUMNS;
use flapstudy::table::Table;
use flapstudy::taguchi::{MainEffect, main_effects, snr};
use flapstudy::{Response, SnrKind};
use plotters::prelude::*;
use serde::Serialize;

use crate::error::{InputContext, input_error};
use crate::output::{create_output_file, fmt_sig, print_json, print_stdout};

/// Arguments of `flapwing sweep analyze`.
#[derive(Debug, Args)]
pub struct AnalyzeArgs {
    /// A sweep CSV (`flapwing sweep` output, merged or not).
    #[arg(value_name = "FILE.csv")]
    pub file: PathBuf,
    /// The response column to analyze, e.g. lift_over_weight.
    #[arg(long, value_name = "NAME")]
    pub response: String,
    /// SNR: larger (eq 15, larger-the-better), smaller or nominal (needs replicates).
    #[arg(long, default_value = "larger", value_parser = parse_snr)]
    pub snr: SnrKind,
    /// Regress on the natural log of this factor column (repeatable).
    #[arg(long = "ln", value_name = "FACTOR")]
    pub ln: Vec<String>,
    /// Draw the SNR main effects to this file (.svg, or .png).
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
    /// Replace the --plot file if it already exists.
    #[arg(long)]
    pub force: bool,
    /// Print one JSON document on stdout instead of the text report.
    #[arg(long)]
    pub json: bool,
}

fn parse_snr(s: &str) -> Result<SnrKind, String> {
    SnrKind::parse(s).ok_or_else(|| format!("`{s}` is not one of larger, smaller, nominal"))
}

/// The analysis of one response (the JSON of `sweep analyze`).
#[derive(Debug, Serialize)]
struct Analysis {
    file: String,
    response: String,
    snr: SnrKind,
    runs: usize,
    /// Distinct factor settings (replicate groups).
    settings: usize,
    factors: Vec<String>,
    snr_main_effects: Vec<MainEffect>,
    mean_main_effects: Vec<MainEffect>,
    /// The eq 16 regression (None when the data cannot support it; see `regression_note`).
    regression: Option<LinearFit>,
    regression_note: String,
}

pub fn run(args: AnalyzeArgs) -> anyhow::Result<()> {
    let origin = args.file.display().to_string();
    let text = std::fs::read_to_string(&args.file)
        .input_context(format!("cannot read sweep CSV `{origin}`"))?;
    let table = Table::parse(&text, &origin).map_err(|e| input_error(e.to_string()))?;
    if table.columns.first().map(String::as_str) != Some("case") {
        return Err(input_error(format!(
            "{origin}, line {}: not a sweep CSV (the first column is not `case`)",
            table.header_line
        )));
    }
    // Factor columns: from the second column up to the first response or flag column.
    let is_output = |c: &str| Response::parse(c).is_some() || FLAG_COLUMNS.contains(&c);
    let end = table
        .columns
        .iter()
        .position(|c| is_output(c))
        .unwrap_or(table.columns.len());
    let factors: Vec<String> = table.columns[1..end].to_vec();
    if factors.is_empty() {
        return Err(input_error(format!(
            "{origin}, line {}: no factor columns between `case` and the responses",
            table.header_line
        )));
    }
    let resp_col = table.require(&args.response).map_err(|e| {
        input_error(format!(
            "{e}; responses in this file: {}",
            table.columns[end..]
                .iter()
                .filter(|c| !FLAG_COLUMNS.contains(&c.as_str()))
                .cloned()
                .collect::<Vec<_>>()
                .join(", ")
        ))
    })?;
    if resp_col < end {
        return Err(input_error(format!(
            "`{}` is a factor column of {origin}, not a response",
            args.response
        )));
    }
    for name in &args.ln {
        if !factors.contains(name) {
            return Err(input_error(format!(
                "--ln {name}: not a factor column of {origin} (factors: {})",
                factors.join(", ")
            )));
        }
    }
    let x: Vec<Vec<f64>> = (1..end)
        .map(|c| table.numbers(c))
        .collect::<Result<_, _>>()
        .map_err(|e| input_error(e.to_string()))?;
    let y = table
        .numbers(resp_col)
        .map_err(|e| input_error(e.to_string()))?;
    let n = y.len();
    if n < 2 {
        return Err(input_error(format!(
            "{origin}: {n} run(s); an analysis needs at least 2"
        )));
    }

    // Replicate groups: identical factor settings, in first-appearance order.
    let mut groups: Vec<(Vec<f64>, Vec<f64>)> = Vec::new();
    for i in 0..n {
        let key: Vec<f64> = x.iter().map(|col| col[i]).collect();
        match groups.iter_mut().find(|g| g.0 == key) {
            Some(g) => g.1.push(y[i]),
            None => groups.push((key, vec![y[i]])),
        }
    }
    let mut snrs = Vec::with_capacity(groups.len());
    for (key, ys) in &groups {
        let v = snr(args.snr, ys).map_err(|e| {
            input_error(format!(
                "{origin}: SNR of `{}` at {}: {e}",
                args.response,
                factors
                    .iter()
                    .zip(key)
                    .map(|(f, v)| format!("{f} = {v}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ))
        })?;
        snrs.push(v);
    }
    let settings: Vec<Vec<f64>> = (0..factors.len())
        .map(|f| groups.iter().map(|g| g.0[f]).collect())
        .collect();
    let means: Vec<f64> = groups
        .iter()
        .map(|g| g.1.iter().sum::<f64>() / g.1.len() as f64)
        .collect();
    let snr_effects = main_effects(&factors, &settings, &snrs);
    let mean_effects = main_effects(&factors, &settings, &means);

    // Eq 16 on all runs: a factor with one level is left out, squares need 3 levels.
    let mut names = Vec::new();
    let mut cols = Vec::new();
    for (f, name) in factors.iter().enumerate() {
        if snr_effects[f].levels.len() < 2 {
            continue;
        }
        if args.ln.contains(name) {
            if x[f].iter().any(|&v| v <= 0.0) {
                return Err(input_error(format!(
                    "--ln {name}: the column holds values <= 0"
                )));
            }
            names.push(format!("ln({name})"));
            cols.push(x[f].iter().map(|v| v.ln()).collect::<Vec<f64>>());
        } else {
            names.push(name.clone());
            cols.push(x[f].clone());
        }
    }
    let k = cols.len();
    let mut terms = vec![Term(vec![])];
    terms.extend((0..k).map(|i| Term(vec![i])));
    for i in 0..k {
        for j in (i + 1)..k {
            terms.push(Term(vec![i, j]));
        }
    }
    let mut dropped = Vec::new();
    for i in 0..k {
        let mut lv = cols[i].clone();
        lv.sort_by(f64::total_cmp);
        lv.dedup();
        if lv.len() >= 3 {
            terms.push(Term(vec![i, i]));
        } else {
            dropped.push(format!("{}^2", names[i]));
        }
    }
    let (regression, regression_note) = if k == 0 {
        (None, "no factor varies".to_owned())
    } else {
        match fit_terms(&names, &terms, &cols, &y) {
            Ok(fit) => {
                let note = if dropped.is_empty() {
                    "full second-order model (eq 16)".to_owned()
                } else {
                    format!("eq 16 without {} (fewer than 3 levels)", dropped.join(", "))
                };
                (Some(fit), note)
            }
            Err(e) => (None, format!("not fitted: {e}")),
        }
    };

    if let Some(path) = &args.plot {
        // Refuse an existing file the same way every output does.
        drop(create_output_file(path, args.force, "plot file")?);
        plot_effects(path, &snr_effects, &args.response, args.snr)?;
    }
    let analysis = Analysis {
        file: origin,
        response: args.response.clone(),
        snr: args.snr,
        runs: n,
        settings: groups.len(),
        factors,
        snr_main_effects: snr_effects,
        mean_main_effects: mean_effects,
        regression,
        regression_note,
    };
    if args.json {
        return print_json(&analysis);
    }
    print_stdout(&analysis_text(&analysis, args.plot.as_deref()))
}

fn snr_name(k: SnrKind) -> &'static str {
    match k {
        SnrKind::LargerTheBetter => "larger-the-better, eq 15",
        SnrKind::SmallerTheBetter => "smaller-the-better",
        SnrKind::NominalTheBest => "nominal-the-best",
    }
}

fn analysis_text(a: &Analysis, plot: Option<&Path>) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "Analysis of `{}` in {}: {} runs, {} distinct settings, {} factor(s)",
        a.response,
        a.file,
        a.runs,
        a.settings,
        a.factors.len()
    );
    let _ = writeln!(
        out,
        "\nMain effects: mean SNR (dB; {}) and mean response per level; rank 1 = largest delta",
        snr_name(a.snr)
    );
    for (s, m) in a.snr_main_effects.iter().zip(&a.mean_main_effects) {
        let _ = writeln!(
            out,
            "  {}: rank {}, SNR delta {} dB, mean delta {}",
            s.factor,
            s.rank,
            fmt_sig(s.delta, 4),
            fmt_sig(m.delta, 4)
        );
        let row = |label: &str, v: &[f64], digits: usize| {
            let cells: Vec<String> = v
                .iter()
                .map(|x| format!(" {:>12}", fmt_num(*x, digits)))
                .collect();
            format!("    {label:<6}{}\n", cells.join(""))
        };
        out.push_str(&row("level", &s.levels, 6));
        out.push_str(&row("SNR", &s.means, 5));
        out.push_str(&row("mean", &m.means, 5));
    }
    let _ = writeln!(
        out,
        "\nRegression of `{}`: {}",
        a.response, a.regression_note
    );
    if let Some(f) = &a.regression {
        let width = f.names.iter().map(|n| n.len()).max().unwrap_or(4).max(4);
        let _ = writeln!(
            out,
            "  {:<width$} {:>13} {:>11} {:>9} {:>10}",
            "term", "coef", "std err", "t", "p"
        );
        for k in 0..f.names.len() {
            let p = f.p_values[k];
            let _ = writeln!(
                out,
                "  {:<width$} {:>13} {:>11} {:>9} {:>10}",
                f.names[k],
                fmt_sig(f.coefficients[k], 6),
                fmt_sig(f.std_errors[k], 3),
                fmt_sig(f.t_values[k], 4),
                if p < 1e-3 {
                    format!("{p:.2e}")
                } else {
                    fmt_sig(p, 3)
                }
            );
        }
        let _ = writeln!(
            out,
            "  S = {}   R^2 = {}   adj R^2 = {}   residual dof = {}",
            fmt_sig(f.s, 6),
            fmt_sig(f.r_squared, 4),
            fmt_sig(f.adj_r_squared, 4),
            f.dof
        );
    }
    if let Some(p) = plot {
        let _ = writeln!(out, "\nWrote the SNR main-effects plot to {}", p.display());
    }
    out
}

/// A table number: scientific below 1e-3 or from 1e6 in magnitude, else `digits`
/// significant digits.
pub fn fmt_num(x: f64, digits: usize) -> String {
    if x != 0.0 && (x.abs() < 1e-3 || x.abs() >= 1e6) {
        format!("{:.*e}", digits.saturating_sub(1), x)
    } else {
        fmt_sig(x, digits)
    }
}

/// Tick label: scientific for very small or large axes, else 4 significant digits.
fn axis_label(v: f64, scale: f64) -> String {
    if v.abs() < scale * 1e-9 {
        "0".to_owned()
    } else if scale < 1e-2 || scale >= 1e5 {
        format!("{v:.2e}")
    } else {
        fmt_sig(v, 4)
    }
}

fn plot_effects(
    path: &Path,
    effects: &[MainEffect],
    response: &str,
    kind: SnrKind,
) -> anyhow::Result<()> {
    let width = (360 * effects.len() as u32).clamp(480, 2400);
    let size = (width, 420);
    let title = format!("{response}: SNR main effects ({})", snr_name(kind));
    crate::plot::render!(path, size, draw_effects(effects, &title))
}

fn draw_effects<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    effects: &[MainEffect],
    title: &str,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let e = crate::plot::draw_error::<DB::ErrorType>;
    let root = crate::plot::titled_white(root, title, 18)?;
    // One shared SNR axis so that the panels compare.
    let lo = effects
        .iter()
        .flat_map(|m| m.means.iter().copied())
        .fold(f64::INFINITY, f64::min);
    let hi = effects
        .iter()
        .flat_map(|m| m.means.iter().copied())
        .fold(f64::NEG_INFINITY, f64::max);
    let pad = ((hi - lo) * 0.1).max(0.05);
    let panels = root.split_evenly((1, effects.len()));
    for (panel, m) in panels.iter().zip(effects) {
        let xlo = m.levels[0];
        let xhi = *m.levels.last().unwrap_or(&xlo);
        let xpad = if xhi > xlo {
            (xhi - xlo) * 0.08
        } else {
            xlo.abs().max(1.0) * 0.1
        };
        let mut chart = ChartBuilder::on(panel)
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(55)
            .build_cartesian_2d((xlo - xpad)..(xhi + xpad), (lo - pad)..(hi + pad))
            .map_err(e)?;
        chart
            .configure_mesh()
            .x_desc(m.factor.as_str())
            .y_desc("mean SNR [dB]")
            .x_labels(5)
            .x_label_formatter(&|v| axis_label(*v, xhi.abs().max(xlo.abs())))
            .draw()
            .map_err(e)?;
        let pts: Vec<(f64, f64)> = m
            .levels
            .iter()
            .copied()
            .zip(m.means.iter().copied())
            .collect();
        chart
            .draw_series(LineSeries::new(pts.clone(), BLUE.stroke_width(2)))
            .map_err(e)?;
        chart
            .draw_series(pts.iter().map(|&p| Circle::new(p, 4, BLUE.filled())))
            .map_err(e)?;
    }
    root.present().map_err(e)?;
    Ok(())
}
