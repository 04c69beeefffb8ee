//! Ctrl-C (SIGINT) during a run: the command stops at the next step, finishes its log, prints
//! what it has and exits with 1; the log replays as a complete file.

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_flapwing");

#[test]
fn sigint_finishes_the_log_and_exits_1() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("run.mcap");
    let child = Command::new(BIN)
        .args(["simulate", "--duration-s", "3000", "--tethered", "--mcap"])
        .arg(&log)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Wait until the run is under way (the log exists and holds data), then interrupt.
    let start = Instant::now();
    while std::fs::metadata(&log)
        .map(|m| m.len() < 50_000)
        .unwrap_or(true)
    {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "the run never started"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    let status = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("interrupted by Ctrl-C") && !stderr.contains("panicked"),
        "{stderr}"
    );
    assert!(stdout.contains("stopped: interrupted (Ctrl-C)"), "{stdout}");
    let replay = Command::new(BIN).arg("replay").arg(&log).output().unwrap();
    let text = String::from_utf8_lossy(&replay.stdout);
    assert_eq!(replay.status.code(), Some(0), "{text}");
    assert!(
        text.contains("complete") && text.contains("interrupted"),
        "{text}"
    );
}
