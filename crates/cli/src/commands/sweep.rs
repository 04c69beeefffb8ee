//! `flapwing sweep`: run a parameter study (see `flapsim::study::spec` for the file format).
//!
//! - `flapwing sweep STUDY.toml [--out DIR] [--jobs N] [--shard K/N] [--force]`: evaluate
//!   the study's cases (tethered hover responses, in parallel on N threads) and write
//!   `DIR/<study>.csv`, or `DIR/<study>-shard-K-of-N.csv` for one shard (cases are split into
//!   N contiguous blocks; run the N shards anywhere, then merge);
//! - `flapwing sweep merge DIR [--force]` (or `flapwing sweep --merge DIR`): join every
//!   complete set of shards in DIR into `DIR/<study>.csv`, sorted by case index; the result
//!   equals an unsharded run byte for byte;
//! - `flapwing sweep analyze FILE.csv --response NAME [--snr larger|smaller|nominal]
//!   [--ln FACTOR]... [--plot FILE.svg] [--json]`: the Taguchi analysis of one response: SNR
//!   per run (eq 15 for larger-the-better; runs with identical factor settings are
//!   replicates), main effects of the SNR and of the mean response per factor level, and the
//!   full second-order regression of eq 16 on the factors (`--ln` regresses on the log of a
//!   factor, as eq 16 does with Re), with standard errors, t values and p-values; `--plot`
//!   draws the SNR main effects (SVG, or PNG by extension).
//!
//! A progress bar is drawn on stderr when stderr is a terminal.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::{Args, Subcommand};
use flapsim::study::regression::{Term, fit_terms};
use flapsim::study::stats::LinearFit;
use flapsim::study::sweep::FLAG_COLUMNS;
use flapsim::study::table::Table;
use flapsim::study::taguchi::{MainEffect, main_effects, snr};
use flapsim::study::{Response, SnrKind, Study, StudySpec, merge_csv};
use plotters::prelude::*;
use serde::Serialize;

use crate::error::{InputContext, input_error};
use crate::output::{create_output_file, fmt_sig, print_json, print_stdout};

/// Arguments of `flapwing sweep`.
#[derive(Debug, Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct SweepArgs {
    /// `merge` or `analyze` (see below); without one, run STUDY.toml.
    #[command(subcommand)]
    pub action: Option<SweepAction>,
    /// The study file (TOML).
    #[arg(value_name = "STUDY.toml", required_unless_present = "merge")]
    pub study: Option<PathBuf>,
    /// Directory for the CSV (created if missing).
    #[arg(long, value_name = "DIR", default_value = ".")]
    pub out: PathBuf,
    /// Worker threads (default: one per core).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..=1024))]
    pub jobs: Option<u16>,
    /// Run only shard K of N (1 <= K <= N): the K-th of N contiguous blocks of cases.
    #[arg(long, value_name = "K/N", value_parser = parse_shard)]
    pub shard: Option<Shard>,
    /// Merge the shards in DIR instead of running a study (same as `sweep merge DIR`).
    #[arg(long, value_name = "DIR", conflicts_with_all = ["study", "shard", "jobs"])]
    pub merge: Option<PathBuf>,
    /// Replace output files that already exist.
    #[arg(long)]
    pub force: bool,
}

/// The sweep subcommands.
#[derive(Debug, Subcommand)]
pub enum SweepAction {
    /// Join the shard CSVs in DIR into one CSV per study, sorted by case index.
    Merge(MergeArgs),
    /// Taguchi SNR, main effects and the eq 16 regression of one response of a sweep CSV.
    Analyze(AnalyzeArgs),
    /// Map a response over two factors of a sweep CSV (like the paper's Fig 19-21).
    Contour(super::contour::ContourArgs),
}

/// Arguments of `flapwing sweep merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// The directory holding `<study>-shard-K-of-N.csv` files.
    #[arg(value_name = "DIR")]
    pub dir: PathBuf,
    /// Replace a merged CSV that already exists.
    #[arg(long)]
    pub force: bool,
}

/// Shard K of N.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// 1-based shard index.
    pub k: usize,
    /// Number of shards.
    pub n: usize,
}

/// Parses `K/N` with 1 <= K <= N.
pub fn parse_shard(s: &str) -> Result<Shard, String> {
    let (k, n) = s
        .split_once('/')
        .ok_or_else(|| format!("`{s}` is not K/N (e.g. 2/8)"))?;
    let k: usize = k
        .trim()
        .parse()
        .map_err(|_| format!("`{k}` in `{s}` is not a shard number"))?;
    let n: usize = n
        .trim()
        .parse()
        .map_err(|_| format!("`{n}` in `{s}` is not a shard count"))?;
    if n >= 1 && (1..=n).contains(&k) {
        Ok(Shard { k, n })
    } else {
        Err(format!("{k}/{n} is not allowed: need 1 <= K <= N"))
    }
}

/// Runs the command.
pub fn run(args: SweepArgs) -> anyhow::Result<()> {
    match args.action {
        Some(SweepAction::Merge(m)) => return merge(&m.dir, m.force),
        Some(SweepAction::Analyze(a)) => return analyze(a),
        Some(SweepAction::Contour(c)) => return super::contour::run(c),
        None => {}
    }
    if let Some(dir) = &args.merge {
        return merge(dir, args.force);
    }
    let path = args
        .study
        .as_ref()
        .ok_or_else(|| input_error("give a study file (or `merge DIR`)"))?;
    let study = load_study(path)?;
    let (range, file_name) = match args.shard {
        Some(Shard { k, n }) => (
            study.shard_range(k, n),
            format!("{}-shard-{k}-of-{n}.csv", study.name),
        ),
        None => (0..study.case_count(), format!("{}.csv", study.name)),
    };
    std::fs::create_dir_all(&args.out).input_context(format!(
        "cannot create the output directory `{}`",
        args.out.display()
    ))?;
    let out_path = args.out.join(&file_name);
    // Refuse an existing file before spending time on the cases.
    let mut file = create_output_file(&out_path, args.force, "sweep CSV")?;

    let count = range.len();
    let bar = crate::progress::progress_bar(count as u64, study.name.clone(), "cases");
    let started = Instant::now();
    let run_cases = || study.run_until(range.clone(), &|| bar.inc(1), &crate::interrupt::requested);
    let results = match args.jobs {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n as usize)
            .build()
            .map_err(|e| anyhow::anyhow!("cannot start {n} worker threads: {e}"))?
            .install(run_cases),
        None => run_cases(),
    };
    bar.finish_and_clear();
    let results = match results {
        Ok(r) => r,
        Err(e) => {
            drop(file);
            let _ = std::fs::remove_file(&out_path);
            return Err(input_error(e.to_string()));
        }
    };
    let elapsed = started.elapsed().as_secs_f64();
    file.write_all(study.csv(&results).as_bytes())
        .map_err(|e| anyhow::anyhow!("cannot write `{}`: {e}", out_path.display()))?;
    if results.len() < count {
        return Err(anyhow::anyhow!(
            "interrupted by Ctrl-C: wrote the {} of {count} cases that finished to `{}`",
            results.len(),
            out_path.display()
        ));
    }
    let clamped = results
        .iter()
        .filter(|r| r.all.wake_capture_clamped)
        .count();
    let mut out = String::new();
    let _ = writeln!(
        out,
        "Wrote {}: {} of {} cases ({}, {} factor(s), {} response(s)) in {:.2} s",
        out_path.display(),
        count,
        study.case_count(),
        study.design.name(),
        study.factors.len(),
        study.responses.len(),
        elapsed
    );
    if clamped > 0 {
        let _ = writeln!(
            out,
            "{clamped} case(s) have wake_capture_clamped = 1: Re, dtau_A or dtau_D outside the wake-capture model's fitted range (inputs clamped)"
        );
    }
    print_stdout(&out)
}

/// Reads and resolves a study file; its `base_model` is a built-in name or a path relative
/// to the study file.
pub fn load_study(path: &Path) -> anyhow::Result<Study> {
    let origin = path.display().to_string();
    let text = std::fs::read_to_string(path)
        .input_context(format!("cannot read study file `{origin}`"))?;
    let spec = StudySpec::from_toml(&text, &origin).map_err(|e| input_error(e.to_string()))?;
    let (base_text, base_origin) = match flapsim::builtin_model(&spec.base_model) {
        Some(t) => (t.to_owned(), spec.base_model.clone()),
        None => {
            let dir = path.parent().unwrap_or(Path::new("."));
            let base_path = dir.join(&spec.base_model);
            let shown = base_path.display().to_string();
            let text = std::fs::read_to_string(&base_path).input_context(format!(
                "{origin}: base_model `{}` is not a built-in model (drosophila, bumblebee, robobee_kinematic, robobee, hummingbird) and `{shown}` cannot be read",
                spec.base_model
            ))?;
            (text, shown)
        }
    };
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "study".to_owned());
    spec.resolve(&origin, &stem, &base_text, &base_origin)
        .map_err(|e| input_error(e.to_string()))
}

/// `<study>-shard-K-of-N.csv` -> (study, K, N).
fn shard_name(file: &str) -> Option<(String, usize, usize)> {
    let stem = file.strip_suffix(".csv")?;
    let (study, rest) = stem.rsplit_once("-shard-")?;
    let (k, n) = rest.split_once("-of-")?;
    let (k, n): (usize, usize) = (k.parse().ok()?, n.parse().ok()?);
    (!study.is_empty() && n >= 1 && (1..=n).contains(&k)).then(|| (study.to_owned(), k, n))
}

fn merge(dir: &Path, force: bool) -> anyhow::Result<()> {
    let shown = dir.display().to_string();
    let entries =
        std::fs::read_dir(dir).input_context(format!("cannot read the directory `{shown}`"))?;
    let mut groups: BTreeMap<(String, usize), BTreeMap<usize, PathBuf>> = BTreeMap::new();
    for entry in entries {
        let entry = entry.input_context(format!("cannot read the directory `{shown}`"))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if let Some((study, k, n)) = shard_name(&name) {
            groups
                .entry((study, n))
                .or_default()
                .insert(k, entry.path());
        }
    }
    if groups.is_empty() {
        return Err(input_error(format!(
            "no shard files (<study>-shard-K-of-N.csv) in `{shown}`"
        )));
    }
    let mut report = String::new();
    for ((study, n), shards) in &groups {
        let missing: Vec<String> = (1..=*n)
            .filter(|k| !shards.contains_key(k))
            .map(|k| k.to_string())
            .collect();
        if !missing.is_empty() {
            return Err(input_error(format!(
                "`{shown}`: study `{study}` has {} of {n} shards; missing shard(s) {} (files {study}-shard-K-of-{n}.csv)",
                shards.len(),
                missing.join(", ")
            )));
        }
        let mut parts = Vec::with_capacity(*n);
        for path in shards.values() {
            let origin = path.display().to_string();
            let text = std::fs::read_to_string(path)
                .input_context(format!("cannot read shard `{origin}`"))?;
            parts.push((origin, text));
        }
        let merged = merge_csv(&parts).map_err(|e| input_error(e.to_string()))?;
        let out_path = dir.join(format!("{study}.csv"));
        let mut file = create_output_file(&out_path, force, "merged CSV")?;
        file.write_all(merged.as_bytes())
            .map_err(|e| anyhow::anyhow!("cannot write `{}`: {e}", out_path.display()))?;
        let rows = merged.lines().count().saturating_sub(1);
        let _ = writeln!(
            report,
            "Merged {n} shard(s) of `{study}` into {}: {rows} cases",
            out_path.display()
        );
    }
    print_stdout(&report)
}

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

fn analyze(args: AnalyzeArgs) -> anyhow::Result<()> {
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
fn fmt_num(x: f64, digits: usize) -> String {
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
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| anyhow::anyhow!("cannot draw the plot: {x}");
    root.fill(&WHITE).map_err(e)?;
    let root = root.titled(title, ("sans-serif", 18)).map_err(e)?;
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
/// `flapsim::study::optimize`). Responses are tethered at the hover attitude, as in a sweep.
pub fn run_optimize(args: OptimizeArgs) -> anyhow::Result<()> {
    use flapsim::study::optimize::{NelderMeadOptions, optimize_hover};
    let study = load_study(&args.study)?;
    let opts = NelderMeadOptions {
        max_evals: args.max_evals as usize,
        ..NelderMeadOptions::default()
    };
    let opt = optimize_hover(&study, args.min_lift_over_weight, &opts)
        .map_err(|e| input_error(e.to_string()))?;
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
    print_stdout(&out)
}
