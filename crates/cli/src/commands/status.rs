//! `flapwing status DIR [--json]`: per study in DIR, which shards are done, running, pending,
//! failed or missing.
//!
//! The files decide "done" (a complete shard with the study's hash) and "failed" (an incomplete
//! shard, or one of another study). For the rest, when `flapwing submit` recorded job ids in
//! `DIR/<study>.slurm.json` and Slurm's `squeue` exists, the task's queue state decides running
//! or pending; `sacct` (when accounting is on) tells a task that ended FAILED, CANCELLED,
//! TIMEOUT and so on. Without them the files alone decide, and the report says which sources
//! it used.
//!
//! A done shard may hold failed cases (rows with `status` = `failed`: a design whose analysis
//! failed, see `flapstudy::sweep`): the shard is done, and the report lists those cases.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::PathBuf;

use clap::Args;
use flapstudy::shard::{ShardState, join_indices, resubmit_command};
use flapstudy::sweep::failed_rows;
use serde::Serialize;

use super::sweep_merge::{StudyShards, studies_in};
use crate::error::input_error;
use crate::output::{print_json, print_stdout};
use crate::slurm::{sacct_states, squeue_states};

/// Arguments of `flapwing status`.
#[derive(Debug, Args)]
pub struct StatusArgs {
    /// The output directory of `flapwing submit` (or any directory of shards).
    #[arg(value_name = "DIR")]
    pub dir: PathBuf,
    /// Print one JSON document on stdout instead of the text report.
    #[arg(long)]
    pub json: bool,
}

/// A shard that did not finish.
#[derive(Debug, Clone, Serialize)]
pub struct FailedShard {
    /// 1-based index.
    pub shard: usize,
    /// Why: the Slurm state or what is wrong with the file.
    pub why: String,
}

/// The status of one study (the JSON of `flapwing status`, one per study).
#[derive(Debug, Clone, Serialize)]
pub struct StudyStatus {
    /// The study name.
    pub study: String,
    /// Number of shards.
    pub shards: usize,
    /// The study content hash the shards are checked against (manifest, else first shard).
    pub study_hash: Option<String>,
    /// The study file, when known.
    pub study_file: Option<String>,
    /// Slurm job ids from the manifest, oldest first.
    pub job_ids: Vec<String>,
    /// What decided the states: "files", and "squeue" / "sacct" when they answered.
    pub sources: Vec<String>,
    /// Why a source was not used (e.g. "sacct: Slurm accounting storage is disabled").
    pub notes: Vec<String>,
    /// Complete shards.
    pub done: Vec<usize>,
    /// Shards whose task is running.
    pub running: Vec<usize>,
    /// Shards whose task is queued.
    pub pending: Vec<usize>,
    /// Shards that ended without a complete file, or whose file is wrong.
    pub failed: Vec<FailedShard>,
    /// Shards with no file and no task in the queue.
    pub missing: Vec<usize>,
    /// Cases of the done shards whose analysis failed (rows with `status` = `failed`).
    pub failed_cases: Vec<usize>,
    /// The command that reruns the failed and missing shards.
    pub resubmit: Option<String>,
}

/// The JSON document.
#[derive(Debug, Serialize)]
struct Status {
    dir: String,
    studies: Vec<StudyStatus>,
}

/// Runs the command.
pub fn run(args: StatusArgs) -> anyhow::Result<()> {
    let shown = args.dir.display().to_string();
    let studies = studies_in(&args.dir)?;
    if studies.is_empty() {
        return Err(input_error(format!(
            "no shard files (<study>-shard-K-of-N.csv) and no submission manifests (<study>.slurm.json) in `{shown}`"
        )));
    }
    let statuses: Vec<StudyStatus> = studies
        .iter()
        .map(|s| study_status(s, &s.dir_for_commands(&args.dir)))
        .collect();
    if args.json {
        return print_json(&Status {
            dir: shown,
            studies: statuses,
        });
    }
    print_stdout(&status_text(&shown, &statuses))
}

fn study_status(s: &StudyShards, dir: &str) -> StudyStatus {
    let g = &s.group;
    let expected = s.expected();
    let hash = expected
        .as_ref()
        .map(|e| e.hash.clone())
        .or_else(|| g.first_hash().map(str::to_owned));
    let study_file = expected
        .as_ref()
        .map(|e| e.study_file.clone())
        .or_else(|| g.first_study_file().map(str::to_owned));
    let job_ids = s
        .manifest
        .as_ref()
        .map(|(_, m)| m.job_ids())
        .unwrap_or_default();
    let mut sources = vec!["files".to_owned()];
    let mut notes = Vec::new();
    let (mut queue, mut acct) = (BTreeMap::new(), BTreeMap::new());
    if job_ids.is_empty() {
        notes.push("no submission manifest: files only".to_owned());
    } else {
        match squeue_states(&job_ids) {
            Ok(q) => {
                queue = q;
                sources.push("squeue".to_owned());
            }
            Err(e) => notes.push(e),
        }
        match sacct_states(&job_ids) {
            Ok(a) => {
                acct = a;
                sources.push("sacct".to_owned());
            }
            Err(e) => notes.push(e),
        }
    }
    let mut st = StudyStatus {
        study: g.study.clone(),
        shards: g.n,
        study_hash: hash.clone(),
        study_file: study_file.clone(),
        job_ids,
        sources,
        notes,
        done: Vec::new(),
        running: Vec::new(),
        pending: Vec::new(),
        failed: Vec::new(),
        missing: Vec::new(),
        failed_cases: Vec::new(),
        resubmit: None,
    };
    for k in 1..=g.n {
        let file = g.files.get(&k);
        let task = s
            .manifest
            .as_ref()
            .and_then(|(_, m)| m.job_of(k))
            .map(|job| format!("{job}_{k}"));
        let queued = task.as_ref().and_then(|t| queue.get(t));
        let ended = task.as_ref().and_then(|t| acct.get(t));
        let file_hash = file.and_then(|f| f.state.header()).map(|h| &h.hash);
        let foreign = file.is_some() && file_hash != hash.as_ref();
        match file.map(|f| &f.state) {
            Some(ShardState::Complete(_)) if !foreign => {
                st.done.push(k);
                let path = &g.files[&k].path;
                let shown = path.display().to_string();
                match std::fs::read_to_string(path)
                    .map_err(|e| e.to_string())
                    .and_then(|t| failed_rows(&t, &shown).map_err(|e| e.to_string()))
                {
                    Ok(rows) => st.failed_cases.extend(rows.iter().map(|r| r.case)),
                    Err(e) => st
                        .notes
                        .push(format!("cannot list the failed cases of `{shown}`: {e}")),
                }
            }
            _ if queued.is_some_and(|q| is_running(q)) => st.running.push(k),
            _ if queued.is_some() => st.pending.push(k),
            Some(f) if foreign => st.failed.push(FailedShard {
                shard: k,
                why: match f.header() {
                    Some(h) => format!("the file is of another study (hash {})", h.hash),
                    None => "the file has no flapwing shard header".to_owned(),
                },
            }),
            Some(ShardState::Incomplete(_, why)) => st.failed.push(FailedShard {
                shard: k,
                why: format!("incomplete file: {why}"),
            }),
            _ => match ended {
                Some(state) if state != "COMPLETED" => st.failed.push(FailedShard {
                    shard: k,
                    why: format!("task {} ended {state}", task.as_deref().unwrap_or("?")),
                }),
                _ => st.missing.push(k),
            },
        }
    }
    let mut redo: Vec<usize> = st
        .missing
        .iter()
        .copied()
        .chain(st.failed.iter().map(|f| f.shard))
        .collect();
    redo.sort_unstable();
    if let (false, Some(file)) = (redo.is_empty(), &study_file) {
        st.resubmit = Some(resubmit_command(file, dir, g.n, &redo));
    }
    st
}

fn is_running(state: &str) -> bool {
    matches!(
        state,
        "RUNNING" | "COMPLETING" | "CONFIGURING" | "STAGE_OUT" | "SIGNALING" | "RESIZING"
    )
}

fn status_text(dir: &str, statuses: &[StudyStatus]) -> String {
    let mut out = String::new();
    for s in statuses {
        let _ = writeln!(
            out,
            "{dir}: study `{}`, {} shard(s), study hash {}",
            s.study,
            s.shards,
            s.study_hash.as_deref().unwrap_or("unknown")
        );
        if !s.job_ids.is_empty() {
            let _ = writeln!(out, "  jobs     {}", s.job_ids.join(", "));
        }
        let _ = writeln!(
            out,
            "  sources  {}{}",
            s.sources.join(", "),
            if s.notes.is_empty() {
                String::new()
            } else {
                format!(" ({})", s.notes.join("; "))
            }
        );
        let list = |v: &[usize]| {
            if v.is_empty() {
                "-".to_owned()
            } else {
                join_indices(v)
            }
        };
        let _ = writeln!(out, "  done     {:>3}  {}", s.done.len(), list(&s.done));
        let _ = writeln!(
            out,
            "  running  {:>3}  {}",
            s.running.len(),
            list(&s.running)
        );
        let _ = writeln!(
            out,
            "  pending  {:>3}  {}",
            s.pending.len(),
            list(&s.pending)
        );
        let failed: Vec<String> = s
            .failed
            .iter()
            .map(|f| format!("{} ({})", f.shard, f.why))
            .collect();
        let _ = writeln!(
            out,
            "  failed   {:>3}  {}",
            s.failed.len(),
            if failed.is_empty() {
                "-".to_owned()
            } else {
                failed.join(", ")
            }
        );
        let _ = writeln!(
            out,
            "  missing  {:>3}  {}",
            s.missing.len(),
            list(&s.missing)
        );
        if !s.failed_cases.is_empty() {
            let _ = writeln!(
                out,
                "  failed cases in done shards: {} ({}; status = failed, the reason in the `error` column)",
                s.failed_cases.len(),
                join_indices(&s.failed_cases)
            );
        }
        if let Some(cmd) = &s.resubmit {
            let _ = writeln!(out, "  resubmit {cmd}");
        } else if s.done.len() == s.shards {
            let _ = writeln!(out, "  complete: flapwing sweep merge {dir}");
        }
    }
    out
}
