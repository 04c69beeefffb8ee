//! Sharded sweeps end to end with the real binary: skip and refuse, merge refusals and the
//! missing-shard report, `submit` (dry run, no sbatch, a stand-in sbatch) and `status` (files
//! only, and a stand-in squeue). The real cluster is `scripts/slurm/test_cluster.sh`.

use crate::common;

use std::path::Path;
use std::process::Command;

use common::{Run, flapwing_in};

const AMPLITUDE_AOA: &str = include_str!("../../../examples/studies/drosophila_amplitude_aoa.toml");
const NAME: &str = "drosophila_amplitude_aoa";

/// Runs the binary in `dir` with PATH set to `path` only.
fn flapwing_with_path(dir: &Path, path: &Path, args: &[&str]) -> Run {
    let out = Command::new(env!("CARGO_BIN_EXE_flapwing"))
        .args(args)
        .current_dir(dir)
        .env("PATH", path)
        .output()
        .expect("run flapwing");
    Run {
        code: out.status.code().expect("exit code"),
        stdout: String::from_utf8(out.stdout).unwrap(),
        stderr: String::from_utf8(out.stderr).unwrap(),
    }
}

/// A stand-in for a Slurm client command: a shell script printing `stdout`.
fn fake_tool(bin: &Path, name: &str, body: &str) {
    use std::os::unix::fs::PermissionsExt;
    let path = bin.join(name);
    std::fs::write(&path, format!("#!/bin/sh\n{body}\n")).unwrap();
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
}

fn setup() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("study.toml"), AMPLITUDE_AOA).unwrap();
    dir
}

fn shard(dir: &Path, k: usize, n: usize, extra: &[&str]) -> Run {
    let s = format!("{k}/{n}");
    let mut args = vec![
        "sweep",
        "study.toml",
        "--out",
        "out",
        "--shard",
        &s,
        "--jobs",
        "1",
    ];
    args.extend_from_slice(extra);
    flapwing_in(dir, &args)
}

fn read(dir: &Path, p: &str) -> String {
    std::fs::read_to_string(dir.join(p)).unwrap()
}

#[test]
fn shards_skip_when_complete_and_refuse_other_studies() {
    let dir = setup();
    let d = dir.path();
    let run = shard(d, 2, 4, &[]);
    assert_eq!(run.code, 0, "{run:?}");
    let file = format!("out/{NAME}-shard-2-of-4.csv");
    let text = read(d, &file);
    let first = text.lines().next().unwrap();
    assert!(first.starts_with("# flapwing study "), "{first}");
    assert!(first.contains(" shard 2/4 cases 5..10 from /"), "{first}");
    let hash = first.split(' ').nth(3).unwrap().to_owned();
    assert_eq!(hash.len(), 64);

    // The same study again: nothing is done, the file is untouched.
    let run = shard(d, 2, 4, &[]);
    assert_eq!(run.code, 0, "{run:?}");
    assert!(run.stdout.starts_with("Skipped shard 2/4"), "{run:?}");
    assert!(run.stdout.contains(&hash), "{run:?}");
    assert_eq!(read(d, &file), text);

    // An edited study is refused, naming the file and both hashes, unless --force.
    std::fs::write(
        d.join("study.toml"),
        AMPLITUDE_AOA.replace("160.0]", "165.0]"),
    )
    .unwrap();
    let run = shard(d, 2, 4, &[]);
    run.assert_bad_input();
    assert!(
        run.stderr.contains(&file) && run.stderr.contains(&hash),
        "{run:?}"
    );
    assert!(run.stderr.contains("--force"), "{run:?}");
    let run = shard(d, 2, 4, &["--force"]);
    assert_eq!(run.code, 0, "{run:?}");
    assert_ne!(read(d, &file), text);

    // A file cut short (same study) is not complete: it is run again without --force.
    let text = read(d, &file);
    std::fs::write(d.join(&file), &text[..text.len() - 30]).unwrap();
    let run = shard(d, 2, 4, &[]);
    assert_eq!(run.code, 0, "{run:?}");
    assert!(
        run.stderr.contains("replacing the incomplete shard"),
        "{run:?}"
    );
    assert_eq!(read(d, &file), text);
}

#[test]
fn merge_refuses_other_studies_and_prints_the_resubmit_command() {
    let dir = setup();
    let d = dir.path();
    let whole = flapwing_in(d, &["sweep", "study.toml", "--out", "whole"]);
    assert_eq!(whole.code, 0, "{whole:?}");
    let whole = read(d, &format!("whole/{NAME}.csv"));
    assert!(
        whole.starts_with("case,"),
        "the unsharded table has no comment line"
    );
    for k in [1, 2, 4] {
        assert_eq!(shard(d, k, 4, &[]).code, 0);
    }
    // A leftover temporary file of shard 3 (a killed task) does not count as shard 3.
    std::fs::write(
        d.join(format!("out/.{NAME}-shard-3-of-4.csv.tmp-99")),
        "# half",
    )
    .unwrap();
    let run = flapwing_in(d, &["sweep", "merge", "out"]);
    run.assert_bad_input();
    let abs = std::fs::canonicalize(d).unwrap();
    let expected = format!(
        "error: `out`: study `{NAME}` has 3 of 4 shards complete; missing shard(s) 3\nresubmit just those with:\n  flapwing submit {0}/study.toml --out {0}/out --shards 4 --only 3\n",
        abs.display()
    );
    // The temp dir may be reached through a symlink: compare with either spelling.
    let expected_plain = expected.replace(&abs.display().to_string(), &d.display().to_string());
    assert!(
        run.stderr == expected || run.stderr == expected_plain,
        "{}",
        run.stderr
    );

    // Shard 3 of another study: refused, naming the file and both hashes.
    std::fs::write(
        d.join("other.toml"),
        AMPLITUDE_AOA.replace("120.0,", "121.0,"),
    )
    .unwrap();
    let run = flapwing_in(d, &["sweep", "other.toml", "--out", "o2", "--shard", "3/4"]);
    assert_eq!(run.code, 0, "{run:?}");
    let foreign = read(d, &format!("o2/{NAME}-shard-3-of-4.csv"));
    std::fs::write(d.join(format!("out/{NAME}-shard-3-of-4.csv")), &foreign).unwrap();
    let run = flapwing_in(d, &["sweep", "merge", "out"]);
    run.assert_bad_input();
    let other_hash = foreign.split(' ').nth(3).unwrap();
    let own_hash = read(d, &format!("out/{NAME}-shard-1-of-4.csv"))
        .split(' ')
        .nth(3)
        .unwrap()
        .to_owned();
    assert!(
        run.stderr.contains(&format!("{NAME}-shard-3-of-4.csv"))
            && run.stderr.contains(other_hash)
            && run.stderr.contains(&own_hash),
        "{run:?}"
    );

    // The right shard 3: the merge is the unsharded table byte for byte.
    std::fs::remove_file(d.join(format!("out/{NAME}-shard-3-of-4.csv"))).unwrap();
    assert_eq!(shard(d, 3, 4, &[]).code, 0);
    let run = flapwing_in(d, &["sweep", "merge", "out"]);
    assert_eq!(run.code, 0, "{run:?}");
    assert_eq!(read(d, &format!("out/{NAME}.csv")), whole);
}

#[test]
fn submit_dry_run_and_a_missing_sbatch() {
    let dir = setup();
    let d = dir.path();
    let run = flapwing_in(
        d,
        &[
            "submit",
            "study.toml",
            "--out",
            "res",
            "--shards",
            "4",
            "--throttle",
            "2",
            "--time",
            "00:10:00",
            "--partition",
            "short",
            "--cpus-per-task",
            "2",
            "--sbatch-line",
            "--mem=1G",
            "--dry-run",
        ],
    );
    assert_eq!(run.code, 0, "{run:?}");
    let s = &run.stdout;
    let exe = std::fs::canonicalize(env!("CARGO_BIN_EXE_flapwing")).unwrap();
    for line in [
        "#SBATCH --array=1-4%2",
        "#SBATCH --time=00:10:00",
        "#SBATCH --partition=short",
        "#SBATCH --cpus-per-task=2",
        "#SBATCH --mem=1G",
    ] {
        assert!(s.lines().any(|l| l == line), "no `{line}` in\n{s}");
    }
    let exec = s.lines().last().unwrap();
    assert!(
        exec.contains(&exe.display().to_string()) || exec.contains(env!("CARGO_BIN_EXE_flapwing")),
        "{exec}"
    );
    assert!(
        exec.contains("--shard \"${SLURM_ARRAY_TASK_ID}/4\""),
        "{exec}"
    );
    assert!(!d.join("res").exists(), "a dry run writes nothing");

    // Bad values name the flag and what is allowed.
    for (args, needle) in [
        (vec!["--shards", "21"], "at most 20 shards"),
        (vec!["--shards", "4", "--only", "2,5"], "--only 5"),
        (vec!["--time", "90:00"], "HH:MM:SS"),
        (vec!["--sbatch-line", "rm -rf /"], "not an sbatch option"),
    ] {
        let mut a = vec!["submit", "study.toml", "--out", "res", "--dry-run"];
        a.extend(args);
        let run = flapwing_in(d, &a);
        assert_eq!(run.code, 2, "{run:?}");
        assert!(run.stderr.contains(needle), "{needle}: {run:?}");
    }

    // No sbatch on PATH: a clear error, exit 2, nothing recorded.
    let empty = tempfile::tempdir().unwrap();
    let run = flapwing_with_path(
        d,
        empty.path(),
        &["submit", "study.toml", "--out", "res", "--shards", "4"],
    );
    run.assert_bad_input();
    assert!(run.stderr.contains("`sbatch` is not on PATH"), "{run:?}");
    assert!(!d.join(format!("res/{NAME}.slurm.json")).exists());
}

#[test]
fn submit_records_the_job_and_status_reads_the_queue() {
    let dir = setup();
    let d = dir.path();
    let bin = tempfile::tempdir().unwrap();
    let log = bin.path().join("sbatch-args");
    fake_tool(
        bin.path(),
        "sbatch",
        &format!("echo \"$@\" >> '{}'; echo '42;cluster'", log.display()),
    );
    let run = flapwing_with_path(
        d,
        bin.path(),
        &["submit", "study.toml", "--out", "res", "--shards", "4"],
    );
    assert_eq!(run.code, 0, "{run:?}");
    assert!(
        run.stdout
            .starts_with("Submitted job 42: array 1-4 of 4 shard(s)"),
        "{run:?}"
    );
    let args = std::fs::read_to_string(&log).unwrap();
    assert!(
        args.starts_with("--parsable ") && args.contains("/res/slurm/"),
        "{args}"
    );
    let manifest: serde_json::Value =
        serde_json::from_str(&read(d, &format!("res/{NAME}.slurm.json"))).unwrap();
    assert_eq!(manifest["shards"], 4);
    assert_eq!(manifest["cases"], 20);
    assert_eq!(manifest["submissions"][0]["job_id"], "42");
    assert_eq!(
        manifest["submissions"][0]["shard_indices"],
        serde_json::json!([1, 2, 3, 4])
    );
    assert!(
        manifest["submissions"][0]["submitted_utc"]
            .as_str()
            .unwrap()
            .ends_with('Z')
    );
    let hash = manifest["study_hash"].as_str().unwrap().to_owned();

    // Shard 1 done (run here), 2 running, 3 pending, 4 ended without a file.
    let run = flapwing_in(
        d,
        &["sweep", "study.toml", "--out", "res", "--shard", "1/4"],
    );
    assert_eq!(run.code, 0, "{run:?}");
    fake_tool(
        bin.path(),
        "squeue",
        "printf '42_2|RUNNING\\n42_3|PENDING\\n'",
    );
    fake_tool(
        bin.path(),
        "sacct",
        "echo 'Slurm accounting storage is disabled' >&2; exit 1",
    );
    let run = flapwing_with_path(d, bin.path(), &["status", "res", "--json"]);
    assert_eq!(run.code, 0, "{run:?}");
    let s = &run.json()["studies"][0];
    assert_eq!(s["study_hash"], hash.as_str());
    assert_eq!(s["done"], serde_json::json!([1]));
    assert_eq!(s["running"], serde_json::json!([2]));
    assert_eq!(s["pending"], serde_json::json!([3]));
    assert_eq!(s["missing"], serde_json::json!([4]));
    assert_eq!(s["sources"], serde_json::json!(["files", "squeue"]));
    assert!(
        s["notes"][0]
            .as_str()
            .unwrap()
            .contains("accounting storage is disabled"),
        "{s}"
    );
    assert!(
        s["resubmit"]
            .as_str()
            .unwrap()
            .ends_with("--shards 4 --only 4"),
        "{s}"
    );

    // With sacct answering, a cancelled task is failed, not missing.
    fake_tool(bin.path(), "sacct", "printf '42_4|CANCELLED by 0\\n'");
    let run = flapwing_with_path(d, bin.path(), &["status", "res"]);
    assert_eq!(run.code, 0, "{run:?}");
    assert!(
        run.stdout.contains("sources  files, squeue, sacct"),
        "{run:?}"
    );
    assert!(
        run.stdout
            .contains("failed     1  4 (task 42_4 ended CANCELLED)"),
        "{run:?}"
    );

    // Without Slurm's commands the files alone decide, and the report says so.
    let empty = tempfile::tempdir().unwrap();
    let run = flapwing_with_path(d, empty.path(), &["status", "res", "--json"]);
    assert_eq!(run.code, 0, "{run:?}");
    let s = &run.json()["studies"][0];
    assert_eq!(s["sources"], serde_json::json!(["files"]));
    assert_eq!(
        s["notes"],
        serde_json::json!(["squeue not found", "sacct not found"])
    );
    assert_eq!(s["missing"], serde_json::json!([2, 3, 4]));

    // A resubmission is appended to the manifest; squeue refusing a job that has left the
    // controller ("Invalid job id") means nothing of it is queued, not an error.
    fake_tool(bin.path(), "sbatch", "echo 43");
    let run = flapwing_with_path(
        d,
        bin.path(),
        &[
            "submit",
            "study.toml",
            "--out",
            "res",
            "--shards",
            "4",
            "--only",
            "4",
        ],
    );
    assert_eq!(run.code, 0, "{run:?}");
    assert!(
        run.stdout.starts_with("Submitted job 43: array 4 of 4"),
        "{run:?}"
    );
    fake_tool(
        bin.path(),
        "squeue",
        "case \"$4\" in 42) printf '42_2|RUNNING\\n';; *) echo 'slurm_load_jobs error: Invalid job id specified' >&2; exit 1;; esac",
    );
    std::fs::remove_file(bin.path().join("sacct")).unwrap();
    let run = flapwing_with_path(d, bin.path(), &["status", "res", "--json"]);
    assert_eq!(run.code, 0, "{run:?}");
    let s = &run.json()["studies"][0];
    assert_eq!(s["job_ids"], serde_json::json!(["42", "43"]));
    assert_eq!(s["running"], serde_json::json!([2]));
    assert_eq!(s["missing"], serde_json::json!([3, 4]));
    assert_eq!(s["sources"], serde_json::json!(["files", "squeue"]));

    // A second study in the same directory under the same name is refused before sbatch.
    std::fs::write(
        d.join("study.toml"),
        AMPLITUDE_AOA.replace("160.0]", "161.0]"),
    )
    .unwrap();
    let run = flapwing_with_path(
        d,
        bin.path(),
        &["submit", "study.toml", "--out", "res", "--shards", "4"],
    );
    run.assert_bad_input();
    assert!(
        run.stderr.contains(&hash) && run.stderr.contains("--force"),
        "{run:?}"
    );
}
