//! `flapwing sweep merge DIR [--force]`: join every study's shards in DIR into
//! `DIR/<study>.csv`, sorted by case index, byte for byte the unsharded table.
//!
//! Every shard must carry the same study content hash: the one in the study's submission
//! manifest (`DIR/<study>.slurm.json`, written by `flapwing submit`) when there is one, else
//! that of the lowest-index shard. A shard of another study is refused, naming the file and both
//! hashes. Missing and incomplete shards are listed by index with the exact `flapwing submit`
//! command that reruns just those, and the merge of that study exits 2 without writing.
//!
//! Failed cases (rows with `status` = `failed`) are rows like any other: the merge keeps them
//! and reports how many failed and which; `--strict` then exits 1 after writing.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::Path;

use flapstudy::shard::{Expected, ShardError, ShardGroup, merge_group, scan_dir};
use flapstudy::sweep::{failed_rows, failure_summary};

use crate::error::input_error;
use crate::output::{create_output_file, print_stdout};
use crate::slurm::{Manifest, read_manifests};

/// A study's shards in a directory, with its manifest when `submit` wrote one.
#[derive(Debug)]
pub struct StudyShards {
    /// The shard files found (none when only the manifest is there).
    pub group: ShardGroup,
    /// The manifest, if its shard count is the group's.
    pub manifest: Option<(String, Manifest)>,
}

/// Every study in `dir`: one entry per study and shard count among the shard files, plus one
/// per manifest whose study has no shard file yet.
pub fn studies_in(dir: &Path) -> anyhow::Result<Vec<StudyShards>> {
    let groups = scan_dir(dir).map_err(|e| input_error(e.to_string()))?;
    let mut manifests = read_manifests(dir)?;
    let mut out = Vec::new();
    for group in groups {
        let manifest = match manifests.get(&group.study) {
            Some((_, m)) if m.shards == group.n => manifests
                .remove(&group.study)
                .map(|(p, m)| (p.display().to_string(), m)),
            _ => None,
        };
        out.push(StudyShards { group, manifest });
    }
    for (study, (path, m)) in manifests {
        out.push(StudyShards {
            group: ShardGroup {
                study,
                n: m.shards,
                files: Default::default(),
            },
            manifest: Some((path.display().to_string(), m)),
        });
    }
    Ok(out)
}

impl StudyShards {
    /// The hash every shard must carry, from the manifest when there is one.
    pub fn expected(&self) -> Option<Expected> {
        self.manifest.as_ref().map(|(path, m)| Expected {
            hash: m.study_hash.clone(),
            why: format!("the manifest `{path}`"),
            study_file: m.study_file.clone(),
        })
    }

    /// The output directory as the resubmit command should name it.
    pub fn dir_for_commands(&self, dir: &Path) -> String {
        match &self.manifest {
            Some((_, m)) => m.out_dir.clone(),
            None => std::path::absolute(dir)
                .unwrap_or_else(|_| dir.to_path_buf())
                .display()
                .to_string(),
        }
    }
}

/// Runs the command.
pub fn run(dir: &Path, force: bool, strict: bool) -> anyhow::Result<()> {
    let shown = dir.display().to_string();
    let studies = studies_in(dir)?;
    if studies.is_empty() {
        return Err(input_error(ShardError::NoShards(shown.clone()).to_string()));
    }
    let mut report = String::new();
    let mut errors = Vec::new();
    let mut failed_total = 0;
    for s in &studies {
        let (study, n) = (&s.group.study, s.group.n);
        let merged = match merge_group(&s.group, s.expected().as_ref(), &s.dir_for_commands(dir)) {
            Ok(m) => m,
            Err(e) => {
                errors.push(format!("`{shown}`: {e}"));
                continue;
            }
        };
        let out_path = dir.join(format!("{study}.csv"));
        let mut file = create_output_file(&out_path, force, "merged CSV")?;
        file.write_all(merged.as_bytes())
            .map_err(|e| anyhow::anyhow!("cannot write `{}`: {e}", out_path.display()))?;
        let rows = merged.lines().count().saturating_sub(1);
        let failed = failed_rows(&merged, &out_path.display().to_string())
            .map_err(|e| input_error(e.to_string()))?;
        failed_total += failed.len();
        let _ = writeln!(
            report,
            "Merged {n} shard(s) of `{study}` into {}: {rows} cases",
            out_path.display()
        );
        report.push_str(&failure_summary(&failed, rows));
    }
    if !errors.is_empty() {
        if !report.is_empty() {
            print_stdout(&report)?;
        }
        return Err(input_error(errors.join("\n")));
    }
    print_stdout(&report)?;
    strict_check(
        strict,
        failed_total,
        &format!("the merged table in `{shown}`"),
    )
}

/// With `--strict`, an error (exit 1) when `failed` > 0 cases of the written table(s) failed;
/// `written` says which, e.g. "the table `DIR/study.csv`".
pub fn strict_check(strict: bool, failed: usize, written: &str) -> anyhow::Result<()> {
    if strict && failed > 0 {
        return Err(anyhow::anyhow!(
            "--strict: {failed} case(s) failed ({written} is written; the reasons are in its `error` column)"
        ));
    }
    Ok(())
}
