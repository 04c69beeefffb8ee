//! `flapwing sweep`: run a parameter study (see `flapstudy::spec` for the file format).
//!
//! - `flapwing sweep STUDY.toml [--out DIR] [--jobs N] [--shard K/N] [--force]`: evaluate
//!   the study's cases (tethered hover responses, in parallel on N threads) and write
//!   `DIR/<study>.csv`, or `DIR/<study>-shard-K-of-N.csv` for one shard (cases are split into
//!   N contiguous blocks; run the N shards anywhere, then merge). A shard is written
//!   atomically with the study content hash on its first line (`flapstudy::shard`); a
//!   shard already complete with the same hash is skipped, one of another study is refused
//!   unless `--force`;
//! - `flapwing sweep merge DIR [--force]` (or `flapwing sweep --merge DIR`, see
//!   [`super::sweep_merge`]): join the shards into `DIR/<study>.csv`;
//! - `flapwing sweep analyze` ([`super::analyze`]) and `flapwing sweep contour`.
//!
//! A progress bar is drawn on stderr when stderr is a terminal; it counts failed cases.
//!
//! A case whose analysis fails (wings that do not settle, diverged dynamics) is a row of the
//! table with `status` = `failed` and its reason in `error` (see `flapstudy::sweep`); the
//! other cases finish, and the summary says how many failed and which. The exit code is 0
//! when the table is written, failed cases or not (a study explores corners where designs
//! fail); `--strict` makes it 1 when any case failed, after the table is written. A bad study
//! (unknown field, a value or a combination the model refuses) is bad input (2) and writes no
//! table (see `flapstudy::sweep::BLOCK` for when a combination is found).

use std::fmt::Write as _;
use std::io::Write as _;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use clap::{Args, Subcommand};
use flapstudy::shard::{ShardHeader, ShardState, shard_file_name, shard_state, study_hash};
use flapstudy::sweep::failure_summary;
use flapstudy::{CaseResult, Study, StudySpec};

use crate::error::{InputContext, input_error};
use crate::output::{create_output_file, note, print_stdout};

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
    /// Run only shard K of N (1 <= K <= N): the K-th of N contiguous blocks of cases, written
    /// atomically to DIR/<study>-shard-K-of-N.csv with the study hash on its first line; a
    /// shard already complete with the same hash is skipped.
    #[arg(long, value_name = "K/N", value_parser = parse_shard)]
    pub shard: Option<Shard>,
    /// Merge the shards in DIR instead of running a study (same as `sweep merge DIR`).
    #[arg(long, value_name = "DIR", conflicts_with_all = ["study", "shard", "jobs"])]
    pub merge: Option<PathBuf>,
    /// Replace output files that already exist (for a shard: rerun it even when complete, or
    /// when the file holds another study's shard).
    #[arg(long)]
    pub force: bool,
    /// Exit 1 (after writing the table) when any case failed; without it a sweep whose table
    /// is written exits 0 and the summary lists the failed cases.
    #[arg(long)]
    pub strict: bool,
}

/// The sweep subcommands.
#[derive(Debug, Subcommand)]
pub enum SweepAction {
    /// Join the shard CSVs in DIR into one CSV per study, sorted by case index.
    Merge(MergeArgs),
    /// Taguchi SNR, main effects and the eq 16 regression of one response of a sweep CSV.
    Analyze(super::analyze::AnalyzeArgs),
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
    /// Exit 1 (after writing the merged tables) when any case of them failed.
    #[arg(long)]
    pub strict: bool,
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
        Some(SweepAction::Merge(m)) => {
            return super::sweep_merge::run(&m.dir, m.force, m.strict);
        }
        Some(SweepAction::Analyze(a)) => return super::analyze::run(a),
        Some(SweepAction::Contour(c)) => return super::contour::run(c),
        None => {}
    }
    if let Some(dir) = &args.merge {
        return super::sweep_merge::run(dir, args.force, args.strict);
    }
    let path = args
        .study
        .as_ref()
        .ok_or_else(|| input_error("give a study file (or `merge DIR`)"))?;
    let study = load_study(path)?;
    std::fs::create_dir_all(&args.out).input_context(format!(
        "cannot create the output directory `{}`",
        args.out.display()
    ))?;
    match args.shard {
        Some(shard) => run_shard(&study, path, &args, shard),
        None => run_whole(&study, &args),
    }
}

/// The unsharded run: `DIR/<study>.csv`, exactly the table (no comment line).
fn run_whole(study: &Study, args: &SweepArgs) -> anyhow::Result<()> {
    let out_path = args.out.join(format!("{}.csv", study.name));
    // Refuse an existing file before spending time on the cases.
    let mut file = create_output_file(&out_path, args.force, "sweep CSV")?;
    let range = 0..study.case_count();
    let results = match run_cases(study, range.clone(), args.jobs) {
        Ok(r) => r,
        Err(e) => {
            drop(file);
            let _ = std::fs::remove_file(&out_path);
            return Err(e);
        }
    };
    file.write_all(study.csv(&results.0).as_bytes())
        .map_err(|e| anyhow::anyhow!("cannot write `{}`: {e}", out_path.display()))?;
    report(study, &out_path, range.len(), &results, args.strict)
}

/// One shard: skipped when its file is already complete with this study's hash, refused when
/// the file is another study's (unless --force), else run and written atomically.
fn run_shard(study: &Study, path: &Path, args: &SweepArgs, shard: Shard) -> anyhow::Result<()> {
    let Shard { k, n } = shard;
    let hash = study_hash(study);
    let study_file = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let header = ShardHeader::new(study, &hash, k, n, &study_file.display().to_string());
    let out_path = args.out.join(shard_file_name(&study.name, k, n));
    let shown = out_path.display().to_string();
    if out_path.is_dir() {
        return Err(input_error(format!(
            "shard CSV `{shown}` is a directory; remove it or use another --out"
        )));
    }
    if out_path.exists() {
        let text = std::fs::read_to_string(&out_path)
            .input_context(format!("cannot read the existing shard `{shown}`"))?;
        let state = shard_state(&text, &shown);
        let same = state
            .header()
            .is_some_and(|h| h.hash == hash && h.cases == header.cases);
        match (&state, same, args.force) {
            (_, _, true) => note(&format!("replacing `{shown}` (--force)")),
            (ShardState::Complete(_), true, false) => {
                let failed = flapstudy::sweep::failed_rows(&text, &shown)
                    .map_err(|e| input_error(e.to_string()))?;
                print_stdout(&format!(
                    "Skipped shard {k}/{n} of `{}`: `{shown}` is already complete (study hash {hash})\n{}",
                    study.name,
                    failure_summary(&failed, header.cases.len())
                ))?;
                return super::sweep_merge::strict_check(
                    args.strict,
                    failed.len(),
                    &format!("the shard `{shown}`"),
                );
            }
            (ShardState::Incomplete(_, why), true, false) => {
                note(&format!("replacing the incomplete shard `{shown}` ({why})"));
            }
            (state, _, false) => {
                let found = match state.header() {
                    Some(h) => format!(
                        "study hash {}, cases {}..{}",
                        h.hash, h.cases.start, h.cases.end
                    ),
                    None => "no flapwing shard header".to_owned(),
                };
                return Err(input_error(format!(
                    "`{shown}` holds another study's shard ({found}); this is study `{}` with hash {hash}, cases {}..{}: pass --force to replace it, or use another --out",
                    study.name, header.cases.start, header.cases.end
                )));
            }
        }
    }
    let range = header.cases.clone();
    let results = run_cases(study, range.clone(), args.jobs)?;
    let mut text = header.line();
    text.push('\n');
    text.push_str(&study.csv(&results.0));
    flapstudy::shard::write_atomic(&out_path, text.as_bytes())
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    report(study, &out_path, range.len(), &results, args.strict)
}

/// Runs `range` on `jobs` threads (default: the global pool): the results and the seconds.
fn run_cases(
    study: &Study,
    range: Range<usize>,
    jobs: Option<u16>,
) -> anyhow::Result<(Vec<CaseResult>, f64)> {
    let bar = crate::progress::progress_bar(range.len() as u64, study.name.clone(), "cases");
    let failed = AtomicUsize::new(0);
    let progress = |r: &CaseResult| {
        if r.failure().is_some() {
            let n = failed.fetch_add(1, Ordering::Relaxed) + 1;
            bar.set_message(format!("{} ({n} failed)", study.name));
        }
        bar.inc(1);
    };
    let started = Instant::now();
    let run = || study.run_until(range.clone(), &progress, &crate::interrupt::requested);
    let results = match jobs {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n as usize)
            .build()
            .map_err(|e| anyhow::anyhow!("cannot start {n} worker threads: {e}"))?
            .install(run),
        None => run(),
    };
    bar.finish_and_clear();
    let results = results.map_err(|e| input_error(e.to_string()))?;
    Ok((results, started.elapsed().as_secs_f64()))
}

/// The summary (or the Ctrl-C error) after the CSV is written: the count, the clamped
/// wake-capture inputs, and the failed cases with their reasons.
fn report(
    study: &Study,
    out_path: &Path,
    count: usize,
    (results, elapsed): &(Vec<CaseResult>, f64),
    strict: bool,
) -> anyhow::Result<()> {
    let failed = study.failed_cases(results);
    if results.len() < count {
        return Err(anyhow::anyhow!(
            "interrupted by Ctrl-C: wrote the {} of {count} cases that finished to `{}`{}",
            results.len(),
            out_path.display(),
            if failed.is_empty() {
                String::new()
            } else {
                format!(" ({} of them failed)", failed.len())
            }
        ));
    }
    let clamped = results
        .iter()
        .filter(|r| r.done().is_some_and(|a| a.wake_capture_clamped))
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
    out.push_str(&failure_summary(&failed, count));
    print_stdout(&out)?;
    super::sweep_merge::strict_check(
        strict,
        failed.len(),
        &format!("the table `{}`", out_path.display()),
    )
}

/// Reads and resolves a study file; its `base_model` is a built-in name or a path relative
/// to the study file.
pub fn load_study(path: &Path) -> anyhow::Result<Study> {
    let origin = path.display().to_string();
    let text = flapsim::model::read_bounded_text(path, "study file")
        .input_context(format!("cannot read study file `{origin}`"))?;
    let spec = StudySpec::from_toml(&text, &origin).map_err(|e| input_error(e.to_string()))?;
    let (base_text, base_origin) = match flapsim::builtin_model(&spec.base_model) {
        Some(t) => (t.to_owned(), spec.base_model.clone()),
        None => {
            let dir = path.parent().unwrap_or(Path::new("."));
            let base_path = dir.join(&spec.base_model);
            let shown = base_path.display().to_string();
            let text = flapsim::model::read_model_file(&base_path).input_context(format!(
                "{origin}: base_model `{}` is not a built-in model (drosophila, bumblebee, robobee_kinematic, dragonfly, robobee, hummingbird) and `{shown}` cannot be read",
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
