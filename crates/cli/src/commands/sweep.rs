//! `flapwing sweep`: run a parameter study (see `flapsim::study::spec` for the file format).
//!
//! - `flapwing sweep STUDY.toml [--out DIR] [--jobs N] [--shard K/N] [--force]`: evaluate
//!   the study's cases (tethered hover responses, in parallel on N threads) and write
//!   `DIR/<study>.csv`, or `DIR/<study>-shard-K-of-N.csv` for one shard (cases are split into
//!   N contiguous blocks; run the N shards anywhere, then merge);
//! - `flapwing sweep merge DIR [--force]` (or `flapwing sweep --merge DIR`): join every
//!   complete set of shards in DIR into `DIR/<study>.csv`, sorted by case index; the result
//!   equals an unsharded run byte for byte;
//!
//! A progress bar is drawn on stderr when stderr is a terminal.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::{Args, Subcommand};
use flapsim::study::{Study, StudySpec, merge_csv};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::error::{InputContext, input_error};
use crate::output::{create_output_file, print_stdout};

/// Arguments of `flapwing sweep`.
#[derive(Debug, Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct SweepArgs {
    /// `merge` (see below); without it, run STUDY.toml.
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
    let bar = ProgressBar::with_draw_target(Some(count as u64), ProgressDrawTarget::stderr());
    if let Ok(style) =
        ProgressStyle::with_template("{msg} {bar:40} {pos}/{len} cases ({elapsed}, eta {eta})")
    {
        bar.set_style(style);
    }
    bar.set_message(study.name.clone());
    let started = Instant::now();
    let run_cases = || study.run(range.clone(), &|| bar.inc(1));
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
                "{origin}: base_model `{}` is not a built-in model (drosophila, robobee, bumblebee) and `{shown}` cannot be read",
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
