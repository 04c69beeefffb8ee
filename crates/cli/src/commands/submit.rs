//! `flapwing submit STUDY.toml --out DIR [--shards N] [--only 3,7] [--partition P]
//! [--time HH:MM:SS] [--cpus-per-task C] [--throttle K] [--sbatch-line LINE]... [--dry-run]
//! [--force]`: run a sweep's shards as one Slurm job array.
//!
//! Writes the job-array script (`flapstudy::slurm`) to `DIR/slurm/`, submits it with
//! `sbatch --parsable`, and records the job id, the study content hash, the shard count and the
//! submit time in `DIR/<study>.slurm.json` (a later submission of the same study, e.g. the
//! resubmission of missing shards, is appended). Each task runs
//! `flapwing sweep STUDY --out DIR --shard $SLURM_ARRAY_TASK_ID/N` with the absolute path of
//! this flapwing binary; tasks skip shards already complete. `--dry-run` prints the script and
//! submits nothing. Sweep studies only: `optimize` is one sequential search, with nothing to
//! shard.

use std::fmt::Write as _;
use std::path::PathBuf;

use clap::Args;
use flapstudy::shard::{ShardState, scan_dir, study_hash, write_atomic};
use flapstudy::slurm::{JobArray, parse_time_limit, sbatch_line};

use crate::error::{InputContext, input_error};
use crate::output::print_stdout;
use crate::slurm::{Manifest, Submission, ToolOutput, read_manifest, run_tool, utc_now};

/// Arguments of `flapwing submit`.
#[derive(Debug, Args)]
pub struct SubmitArgs {
    /// The study file (TOML), as for `flapwing sweep`.
    #[arg(value_name = "STUDY.toml")]
    pub study: PathBuf,
    /// Output directory for the shards, the script, the Slurm logs and the manifest (created
    /// if missing). It must be visible from the compute nodes.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Number of shards N, one array task each (default: 16, or the case count if smaller).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    pub shards: Option<u32>,
    /// Submit only these shard indices (comma-separated, 1..=N), e.g. the ones merge lists.
    #[arg(long, value_name = "K,K,...", value_delimiter = ',',
          value_parser = clap::value_parser!(u32).range(1..))]
    pub only: Vec<u32>,
    /// Slurm partition (`#SBATCH --partition`).
    #[arg(long, value_name = "P")]
    pub partition: Option<String>,
    /// Time limit per task, HH:MM:SS or D-HH:MM:SS (`#SBATCH --time`).
    #[arg(long, value_name = "HH:MM:SS", value_parser = parse_time_limit)]
    pub time: Option<String>,
    /// CPUs per task; each task's sweep runs that many threads.
    #[arg(long = "cpus-per-task", value_name = "C", default_value_t = 1,
          value_parser = clap::value_parser!(u16).range(1..=1024))]
    pub cpus_per_task: u16,
    /// At most K tasks at once (`--array=...%K`).
    #[arg(long, value_name = "K", value_parser = clap::value_parser!(u32).range(1..))]
    pub throttle: Option<u32>,
    /// A further sbatch option, e.g. `--mem=2G` or `"#SBATCH --qos=short"` (repeatable).
    #[arg(long = "sbatch-line", value_name = "LINE", value_parser = sbatch_line, allow_hyphen_values = true)]
    pub sbatch_line: Vec<String>,
    /// Print the script instead of submitting it.
    #[arg(long = "dry-run")]
    pub dry_run: bool,
    /// Replace a manifest (and the shards) of a different study, or rerun complete shards:
    /// every task runs with --force.
    #[arg(long)]
    pub force: bool,
}

/// Runs the command.
pub fn run(args: SubmitArgs) -> anyhow::Result<()> {
    let study = super::sweep::load_study(&args.study)?;
    let hash = study_hash(&study);
    let cases = study.case_count();
    let n = args.shards.map_or(cases.clamp(1, 16), |s| s as usize);
    if n > cases.max(1) {
        return Err(input_error(format!(
            "--shards {n}: study `{}` ({}) has {cases} case(s); give at most {cases} shards",
            study.name, study.origin
        )));
    }
    let mut only: Vec<usize> = args.only.iter().map(|&k| k as usize).collect();
    only.sort_unstable();
    only.dedup();
    if let Some(&k) = only.iter().find(|&&k| k > n) {
        return Err(input_error(format!(
            "--only {k}: shard indices run from 1 to --shards {n}"
        )));
    }
    let absolute = |p: &std::path::Path| std::path::absolute(p).unwrap_or_else(|_| p.to_owned());
    let study_file = absolute(&args.study).display().to_string();
    let out_dir = absolute(&args.out);
    let flapwing = std::env::current_exe()
        .map_err(|e| anyhow::anyhow!("cannot find the path of this flapwing binary: {e}"))?;
    let job = JobArray {
        study: study.name.clone(),
        hash: hash.clone(),
        flapwing: flapwing.display().to_string(),
        study_file: study_file.clone(),
        out_dir: out_dir.display().to_string(),
        shards: n,
        only: only.clone(),
        throttle: args.throttle.map(|k| k as usize),
        partition: args.partition.clone(),
        time_limit: args.time.clone(),
        cpus_per_task: args.cpus_per_task as usize,
        extra_lines: args.sbatch_line.clone(),
        force: args.force,
    };
    let script = job.script();
    if args.dry_run {
        return print_stdout(&script);
    }

    // Refuse to mix studies in one directory before anything is submitted.
    let manifest_path = Manifest::path(&out_dir, &study.name);
    let previous = if manifest_path.exists() {
        let m = read_manifest(&manifest_path)?;
        if (m.study_hash != hash || m.shards != n) && !args.force {
            return Err(input_error(format!(
                "`{}` records study hash {} with {} shard(s); this submission is study hash {hash} with {n}: use another --out, or pass --force to start over",
                manifest_path.display(),
                m.study_hash,
                m.shards
            )));
        }
        (m.study_hash == hash && m.shards == n).then_some(m)
    } else {
        None
    };
    if out_dir.is_dir() && !args.force {
        for g in scan_dir(&out_dir).map_err(|e| input_error(e.to_string()))? {
            if g.study != study.name || g.n != n {
                continue;
            }
            for f in g.files.values() {
                let other = match &f.state {
                    ShardState::Foreign(_) => Some("no study hash".to_owned()),
                    s => s
                        .header()
                        .filter(|h| h.hash != hash)
                        .map(|h| h.hash.clone()),
                };
                if let Some(found) = other {
                    return Err(input_error(format!(
                        "`{}` is a shard of a different study (study hash {found}, this one {hash}): remove it, use another --out, or pass --force",
                        f.path.display()
                    )));
                }
            }
        }
    }

    let slurm_dir = out_dir.join("slurm");
    std::fs::create_dir_all(&slurm_dir).input_context(format!(
        "cannot create the output directory `{}`",
        slurm_dir.display()
    ))?;
    let submitted_utc = utc_now();
    let script_path = slurm_dir.join(format!(
        "{}-{}.sbatch",
        study.name,
        crate::logging::utc_stamp()
    ));
    write_atomic(&script_path, script.as_bytes()).map_err(|e| anyhow::anyhow!("{e}"))?;
    let script_arg = script_path.display().to_string();
    let job_id = match run_tool("sbatch", &["--parsable", &script_arg], Some(&out_dir)) {
        ToolOutput::Ok(out) => parse_job_id(&out)
            .ok_or_else(|| anyhow::anyhow!("sbatch printed `{}`, not a job id", out.trim()))?,
        ToolOutput::NotFound => {
            return Err(input_error(format!(
                "`sbatch` is not on PATH: `flapwing submit` needs Slurm's client commands (run it on a login node of the cluster), or pass --dry-run to print the script (written to `{script_arg}`)"
            )));
        }
        ToolOutput::Failed(e) => {
            return Err(anyhow::anyhow!("sbatch refused `{script_arg}`: {e}"));
        }
    };
    let shard_indices: Vec<usize> = if only.is_empty() {
        (1..=n).collect()
    } else {
        only
    };
    let submission = Submission {
        job_id: job_id.clone(),
        shard_indices,
        array: job.array_spec(),
        submitted_utc,
        script: script_arg.clone(),
    };
    let mut manifest = previous.unwrap_or(Manifest {
        study: study.name.clone(),
        study_file,
        study_hash: hash.clone(),
        shards: n,
        cases,
        out_dir: out_dir.display().to_string(),
        submissions: Vec::new(),
    });
    manifest.submissions.push(submission);
    let json = serde_json::to_string_pretty(&manifest)? + "\n";
    write_atomic(&manifest_path, json.as_bytes()).map_err(|e| anyhow::anyhow!("{e}"))?;

    let mut out = String::new();
    let _ = writeln!(
        out,
        "Submitted job {job_id}: array {} of {n} shard(s) of `{}` ({cases} cases, study hash {hash})",
        job.array_spec(),
        study.name
    );
    let _ = writeln!(out, "script:   {script_arg}");
    let _ = writeln!(out, "manifest: {}", manifest_path.display());
    let _ = writeln!(out, "logs:     {}", job.log_pattern());
    let shown = flapstudy::shard::shell_quote(&manifest.out_dir);
    let _ = writeln!(out, "progress: flapwing status {shown}");
    let _ = writeln!(out, "then:     flapwing sweep merge {shown}");
    print_stdout(&out)
}

/// `sbatch --parsable` prints `JOBID` or `JOBID;CLUSTER`.
fn parse_job_id(out: &str) -> Option<String> {
    let id = out.trim().split(';').next()?.trim();
    (!id.is_empty() && id.bytes().all(|b| b.is_ascii_digit())).then(|| id.to_owned())
}

#[cfg(test)]
mod tests {
    use super::parse_job_id;

    #[test]
    fn job_ids() {
        assert_eq!(parse_job_id("123\n").as_deref(), Some("123"));
        assert_eq!(parse_job_id("77;cluster\n").as_deref(), Some("77"));
        assert_eq!(parse_job_id("Submitted batch job 5"), None);
        assert_eq!(parse_job_id(""), None);
    }
}
