//! The Slurm job-array script of a sharded sweep (`flapwing submit`): one array task per shard,
//! each running `flapwing sweep STUDY --out DIR --shard $SLURM_ARRAY_TASK_ID/N`.

use std::fmt::Write as _;

use super::shard::{join_indices, shell_quote};

/// Everything the script says.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct JobArray {
    /// The study name (job name `flapwing-<study>`, log file names).
    pub study: String,
    /// The study content hash (recorded in a comment).
    pub hash: String,
    /// Absolute path of the flapwing binary the tasks run.
    pub flapwing: String,
    /// Absolute path of the study file.
    pub study_file: String,
    /// Absolute path of the output directory.
    pub out_dir: String,
    /// Number of shards N.
    pub shards: usize,
    /// The shard indices to run (1-based, ascending); all of 1..=N when empty.
    pub only: Vec<usize>,
    /// At most this many tasks at once (`%K`).
    pub throttle: Option<usize>,
    /// `--partition`.
    pub partition: Option<String>,
    /// `--time`, as Slurm reads it (e.g. `00:30:00` or `1-00:00:00`).
    pub time_limit: Option<String>,
    /// `--cpus-per-task`; each task's sweep uses that many threads.
    pub cpus_per_task: usize,
    /// Further `#SBATCH` lines, verbatim.
    pub extra_lines: Vec<String>,
    /// Every task reruns its shard even when complete (`sweep --force`).
    pub force: bool,
}

impl JobArray {
    /// The `--array` value: `1-N`, or the listed indices (ranges collapsed), then `%K`.
    pub fn array_spec(&self) -> String {
        let mut spec = if self.only.is_empty() {
            format!("1-{}", self.shards)
        } else {
            collapse_ranges(&self.only)
        };
        if let Some(k) = self.throttle {
            let _ = write!(spec, "%{k}");
        }
        spec
    }

    /// Where task K writes its Slurm output: `DIR/slurm/<study>-<job>_<K>.out`.
    pub fn log_pattern(&self) -> String {
        format!("{}/slurm/{}-%A_%a.out", self.out_dir, self.study)
    }

    /// The whole script.
    pub fn script(&self) -> String {
        let mut s = String::from("#!/bin/bash\n");
        let _ = writeln!(
            s,
            "# flapwing submit: study `{}` ({}), {} shard(s), into {}",
            self.study, self.study_file, self.shards, self.out_dir
        );
        let _ = writeln!(s, "# study hash {}", self.hash);
        let _ = writeln!(s, "#SBATCH --job-name=flapwing-{}", self.study);
        let _ = writeln!(s, "#SBATCH --array={}", self.array_spec());
        let _ = writeln!(s, "#SBATCH --cpus-per-task={}", self.cpus_per_task);
        let _ = writeln!(s, "#SBATCH --ntasks=1");
        if let Some(t) = &self.time_limit {
            let _ = writeln!(s, "#SBATCH --time={t}");
        }
        if let Some(p) = &self.partition {
            let _ = writeln!(s, "#SBATCH --partition={p}");
        }
        let _ = writeln!(s, "#SBATCH --output={}", self.log_pattern());
        for line in &self.extra_lines {
            let _ = writeln!(s, "{line}");
        }
        s.push_str("set -eu\n");
        let _ = writeln!(
            s,
            "exec {} sweep {} --out {} --shard \"${{SLURM_ARRAY_TASK_ID}}/{}\" --jobs \"${{SLURM_CPUS_PER_TASK:-{}}}\"{}",
            shell_quote(&self.flapwing),
            shell_quote(&self.study_file),
            shell_quote(&self.out_dir),
            self.shards,
            self.cpus_per_task,
            if self.force { " --force" } else { "" }
        );
        s
    }
}

/// `[1, 2, 3, 5, 7, 8]` -> `"1-3,5,7-8"` (ascending input).
pub fn collapse_ranges(indices: &[usize]) -> String {
    let mut out: Vec<String> = Vec::new();
    let mut i = 0;
    while i < indices.len() {
        let start = indices[i];
        let mut end = start;
        while i + 1 < indices.len() && indices[i + 1] == end + 1 {
            i += 1;
            end = indices[i];
        }
        out.push(if end > start {
            format!("{start}-{end}")
        } else {
            start.to_string()
        });
        i += 1;
    }
    if out.is_empty() {
        join_indices(indices)
    } else {
        out.join(",")
    }
}

/// Checks a time limit as `flapwing submit --time` takes it: `HH:MM:SS` or `D-HH:MM:SS`, with
/// minutes and seconds below 60.
pub fn parse_time_limit(s: &str) -> Result<String, String> {
    let bad = || {
        format!(
            "`{s}` is not a time limit: give HH:MM:SS or D-HH:MM:SS (e.g. 00:30:00, 1-12:00:00)"
        )
    };
    let (days, hms) = match s.split_once('-') {
        Some((d, rest)) => (Some(d), rest),
        None => (None, s),
    };
    if days.is_some_and(|d| d.is_empty() || !d.bytes().all(|b| b.is_ascii_digit())) {
        return Err(bad());
    }
    let parts: Vec<&str> = hms.split(':').collect();
    if parts.len() != 3
        || parts
            .iter()
            .any(|p| p.is_empty() || p.len() > 3 || !p.bytes().all(|b| b.is_ascii_digit()))
    {
        return Err(bad());
    }
    let num = |p: &str| p.parse::<u32>().map_err(|_| bad());
    let (h, m, sec) = (num(parts[0])?, num(parts[1])?, num(parts[2])?);
    if m >= 60 || sec >= 60 || (days.is_some() && h >= 24) {
        return Err(format!(
            "`{s}`: minutes and seconds must be below 60 (and hours below 24 after a day count)"
        ));
    }
    if days.is_none() && h == 0 && m == 0 && sec == 0 {
        return Err(format!("`{s}`: a time limit must be longer than zero"));
    }
    Ok(s.to_owned())
}

/// Checks a `--sbatch-line`: `--option[=value]` becomes `#SBATCH --option[=value]`; a line
/// that already starts with `#SBATCH ` is kept. Anything else (in particular a shell command
/// or a line break) is refused.
pub fn sbatch_line(s: &str) -> Result<String, String> {
    if s.contains(['\n', '\r']) {
        return Err(format!("{s:?}: one line only"));
    }
    let opt = s.strip_prefix("#SBATCH ").unwrap_or(s).trim();
    if !opt.starts_with("--") || opt.len() < 3 {
        return Err(format!(
            "`{s}` is not an sbatch option: give e.g. --mem=2G or \"#SBATCH --qos=short\""
        ));
    }
    Ok(format!("#SBATCH {opt}"))
}
