//! Output paths: an unwritable log path fails before the simulation starts (exit 2, no
//! simulation output); an existing log is not replaced without --force.

use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_flapwing");

fn run(dir: &std::path::Path, args: &[&str]) -> (i32, String, String) {
    let out = Command::new(BIN)
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

#[test]
fn unwritable_log_path_fails_before_the_run() {
    let dir = tempfile::tempdir().unwrap();
    // A regular file where the log folder should be: the folder cannot be created.
    std::fs::write(dir.path().join("blocker"), "x").unwrap();
    let (code, stdout, stderr) = run(
        dir.path(),
        &[
            "simulate",
            "--duration-s",
            "1",
            "--mcap",
            "blocker/run.mcap",
        ],
    );
    assert_eq!(code, 2, "{stderr}");
    assert!(stdout.is_empty(), "the simulation ran: {stdout}");
    assert!(
        stderr.contains("blocker") && !stderr.contains("panicked"),
        "{stderr}"
    );
}

#[test]
fn existing_log_is_not_overwritten_without_force() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("run.mcap"), "keep me").unwrap();
    let (code, _, stderr) = run(
        dir.path(),
        &["simulate", "--duration-s", "0.001", "--mcap", "run.mcap"],
    );
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("refusing to overwrite") && stderr.contains("--force"),
        "{stderr}"
    );
    assert_eq!(
        std::fs::read_to_string(dir.path().join("run.mcap")).unwrap(),
        "keep me"
    );
    let (code, _, stderr) = run(
        dir.path(),
        &[
            "simulate",
            "--duration-s",
            "0.001",
            "--mcap",
            "run.mcap",
            "--force",
        ],
    );
    assert_eq!(code, 0, "{stderr}");
    assert_ne!(
        std::fs::read(dir.path().join("run.mcap")).unwrap(),
        b"keep me"
    );
}

#[test]
fn default_logs_go_under_logs_with_a_timestamp() {
    let dir = tempfile::tempdir().unwrap();
    let (code, _, stderr) = run(dir.path(), &["hover", "--duration-s", "0.01"]);
    assert_eq!(code, 0, "{stderr}");
    let names: Vec<String> = std::fs::read_dir(dir.path().join("logs"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(
        names
            .iter()
            .any(|n| n.starts_with("hover-") && n.ends_with(".mcap")),
        "{names:?}"
    );
    assert!(
        names
            .iter()
            .any(|n| n.starts_with("hover-") && n.ends_with(".rrd")),
        "{names:?}"
    );
}
