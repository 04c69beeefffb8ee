//! What `submit` and `status` share: the submission manifest `DIR/<study>.slurm.json`, running
//! Slurm's client commands (`sbatch`, `squeue`, `sacct`), and the UTC time of a submission.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use serde::{Deserialize, Serialize};

use crate::error::input_error;

/// What `flapwing submit` records in the output directory, one file per study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// The study name.
    pub study: String,
    /// Absolute path of the study file.
    pub study_file: String,
    /// The study content hash (`flapstudy::shard::study_hash`).
    pub study_hash: String,
    /// Number of shards N.
    pub shards: usize,
    /// Number of cases of the study.
    pub cases: usize,
    /// Absolute path of the output directory.
    pub out_dir: String,
    /// Every submission, oldest first.
    pub submissions: Vec<Submission>,
}

/// One `sbatch` of a job array.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Submission {
    /// The Slurm job id of the array.
    pub job_id: String,
    /// The shard indices it runs.
    pub shard_indices: Vec<usize>,
    /// The `--array` value.
    pub array: String,
    /// UTC time of the submission, `YYYY-MM-DDTHH:MM:SSZ`.
    pub submitted_utc: String,
    /// The script submitted.
    pub script: String,
}

impl Manifest {
    /// `DIR/<study>.slurm.json`.
    pub fn path(dir: &Path, study: &str) -> PathBuf {
        dir.join(format!("{study}.slurm.json"))
    }

    /// The job id of the latest submission that ran shard `k`.
    pub fn job_of(&self, k: usize) -> Option<&str> {
        self.submissions
            .iter()
            .rev()
            .find(|s| s.shard_indices.contains(&k))
            .map(|s| s.job_id.as_str())
    }

    /// Every job id, oldest first.
    pub fn job_ids(&self) -> Vec<String> {
        self.submissions.iter().map(|s| s.job_id.clone()).collect()
    }
}

/// Reads a manifest; a file that is not one is bad input naming the file.
pub fn read_manifest(path: &Path) -> anyhow::Result<Manifest> {
    let shown = path.display();
    let text = std::fs::read_to_string(path)
        .map_err(|e| input_error(format!("cannot read the manifest `{shown}`: {e}")))?;
    serde_json::from_str(&text).map_err(|e| {
        input_error(format!(
            "`{shown}` is not a flapwing submission manifest: {e}"
        ))
    })
}

/// Every `*.slurm.json` manifest in `dir`, by study name.
pub fn read_manifests(dir: &Path) -> anyhow::Result<BTreeMap<String, (PathBuf, Manifest)>> {
    let mut out = BTreeMap::new();
    let entries = std::fs::read_dir(dir).map_err(|e| {
        input_error(format!(
            "cannot read the directory `{}`: {e}",
            dir.display()
        ))
    })?;
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        if name
            .strip_suffix(".slurm.json")
            .is_some_and(|s| !s.is_empty())
        {
            let path = entry.path();
            let m = read_manifest(&path)?;
            out.insert(m.study.clone(), (path, m));
        }
    }
    Ok(out)
}

/// What running a client command gave.
#[derive(Debug)]
pub enum ToolOutput {
    /// It ran and exited 0: its stdout.
    Ok(String),
    /// It is not installed (not on PATH).
    NotFound,
    /// It ran and failed: its stderr (or the exit status).
    Failed(String),
}

/// Runs `program args...` (in `dir` when given).
pub fn run_tool(program: &str, args: &[&str], dir: Option<&Path>) -> ToolOutput {
    let mut cmd = Command::new(program);
    cmd.args(args);
    if let Some(d) = dir {
        cmd.current_dir(d);
    }
    match cmd.output() {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => ToolOutput::NotFound,
        Err(e) => ToolOutput::Failed(e.to_string()),
        Ok(out) if out.status.success() => {
            ToolOutput::Ok(String::from_utf8_lossy(&out.stdout).into_owned())
        }
        Ok(out) => {
            let err = String::from_utf8_lossy(&out.stderr).trim().to_owned();
            ToolOutput::Failed(if err.is_empty() {
                format!("exited with {}", out.status)
            } else {
                err
            })
        }
    }
}

/// The state of every array task `JOB_K` of `jobs` as `squeue -r` reports it (tasks that
/// have ended are not listed). One query per job: squeue refuses a whole list when one job has
/// already left the controller's memory.
pub fn squeue_states(jobs: &[String]) -> Result<BTreeMap<String, String>, String> {
    let mut states = BTreeMap::new();
    for job in jobs {
        match run_tool("squeue", &["-h", "-r", "-j", job, "-o", "%i|%T"], None) {
            ToolOutput::Ok(text) => states.extend(parse_states(&text)),
            ToolOutput::NotFound => return Err("squeue not found".to_owned()),
            // A job that has left the controller's memory: nothing queued.
            ToolOutput::Failed(e) if e.contains("Invalid job id") => {}
            ToolOutput::Failed(e) => return Err(format!("squeue failed: {e}")),
        }
    }
    Ok(states)
}

/// The final or current state of every array task of `jobs` from `sacct` (needs Slurm's
/// accounting).
pub fn sacct_states(jobs: &[String]) -> Result<BTreeMap<String, String>, String> {
    let list = jobs.join(",");
    match run_tool(
        "sacct",
        &["-n", "-X", "-P", "-j", &list, "-o", "JobID,State"],
        None,
    ) {
        ToolOutput::Ok(text) => Ok(parse_states(&text)),
        ToolOutput::NotFound => Err("sacct not found".to_owned()),
        ToolOutput::Failed(e) => Err(format!("sacct: {e}")),
    }
}

/// `JOB_K|STATE` lines -> map (the first word of the state: `CANCELLED by 0` -> `CANCELLED`).
fn parse_states(text: &str) -> BTreeMap<String, String> {
    text.lines()
        .filter_map(|l| {
            let (id, state) = l.trim().split_once('|')?;
            let state = state.split_whitespace().next()?;
            Some((id.trim().to_owned(), state.to_owned()))
        })
        .collect()
}

/// The current UTC time as `YYYY-MM-DDTHH:MM:SSZ`.
pub fn utc_now() -> String {
    let (y, m, d, hh, mm, ss) = crate::logging::utc_civil_now();
    format!("{y:04}-{m:02}-{d:02}T{hh:02}:{mm:02}:{ss:02}Z")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn states_parse_and_jobs_resolve() {
        let s = parse_states("12_1|COMPLETED\n12_3|CANCELLED by 0\n12_[4-5%1]|PENDING\n");
        assert_eq!(s["12_1"], "COMPLETED");
        assert_eq!(s["12_3"], "CANCELLED");
        assert_eq!(s["12_[4-5%1]"], "PENDING");
        let sub = |job: &str, idx: &[usize]| Submission {
            job_id: job.into(),
            shard_indices: idx.to_vec(),
            array: String::new(),
            submitted_utc: String::new(),
            script: String::new(),
        };
        let m = Manifest {
            study: "s".into(),
            study_file: "/s.toml".into(),
            study_hash: "h".into(),
            shards: 4,
            cases: 20,
            out_dir: "/o".into(),
            submissions: vec![sub("7", &[1, 2, 3, 4]), sub("9", &[3])],
        };
        assert_eq!(m.job_of(3), Some("9"));
        assert_eq!(m.job_of(4), Some("7"));
        assert_eq!(m.job_of(5), None);
        assert!(utc_now().ends_with('Z') && utc_now().len() == 20);
    }
}
