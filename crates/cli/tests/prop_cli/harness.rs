//! The harness: one run of the real `flapwing` binary (killed after a time limit: a hang is a
//! bug too), the contract of every run (exit 0, 1 or 2, never 101, a Rust panic; never
//! "panicked"; an `error` message on any other exit than 0), stdout as one JSON document
//! under `--json`, and the proptest configuration (each shrink step runs the binary, so
//! shrinking is kept short).

use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use proptest::prelude::*;

use crate::prop_config;

/// A run of the binary.
#[derive(Debug)]
pub(crate) struct Run {
    pub(crate) args: Vec<String>,
    pub(crate) code: i32,
    pub(crate) stdout: String,
    pub(crate) stderr: String,
}

/// Longest a single run may take before the test fails (a hang is a bug too).
const TIMEOUT: Duration = Duration::from_secs(60);

/// Runs `flapwing args...` in `dir`, killing it after [`TIMEOUT`].
pub(crate) fn flapwing(dir: &Path, args: &[String]) -> Run {
    let mut child = Command::new(env!("CARGO_BIN_EXE_flapwing"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn flapwing");
    let mut out = child.stdout.take().unwrap();
    let mut err = child.stderr.take().unwrap();
    let t_out = std::thread::spawn(move || {
        let mut b = Vec::new();
        let _ = out.read_to_end(&mut b);
        b
    });
    let t_err = std::thread::spawn(move || {
        let mut b = Vec::new();
        let _ = err.read_to_end(&mut b);
        b
    });
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().expect("wait") {
            break s;
        }
        if start.elapsed() > TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            panic!("flapwing {args:?} did not finish within {TIMEOUT:?}");
        }
        std::thread::sleep(Duration::from_millis(2));
    };
    let stdout = String::from_utf8_lossy(&t_out.join().unwrap()).into_owned();
    let stderr = String::from_utf8_lossy(&t_err.join().unwrap()).into_owned();
    Run {
        args: args.to_vec(),
        // A signal (no code) shows as -1 and fails every check below.
        code: status.code().unwrap_or(-1),
        stdout,
        stderr,
    }
}

/// The contract of every run: exit 0, 1 or 2; no panic; errors on stderr as `error: ...`.
pub(crate) fn check_run(r: &Run) -> Result<(), TestCaseError> {
    prop_assert!(
        matches!(r.code, 0..=2),
        "exit code {} (101 = panic) for {:?}\nstderr: {}",
        r.code,
        r.args,
        r.stderr
    );
    prop_assert!(
        !r.stderr.contains("panicked"),
        "panic for {:?}: {}",
        r.args,
        r.stderr
    );
    if r.code != 0 {
        prop_assert!(
            r.stderr.contains("error"),
            "no error message for {:?}: {}",
            r.args,
            r.stderr
        );
    }
    Ok(())
}

/// With `--json` and exit 0, stdout is one JSON document.
pub(crate) fn check_json(r: &Run, json: bool) -> Result<(), TestCaseError> {
    if json && r.code == 0 {
        let v: Result<serde_json::Value, _> = serde_json::from_str(&r.stdout);
        prop_assert!(
            v.is_ok(),
            "stdout of {:?} is not JSON: {}",
            r.args,
            r.stdout
        );
    }
    Ok(())
}

/// Each shrink step runs the binary: keep shrinking short.
pub(crate) fn config(cases: u32) -> ProptestConfig {
    prop_config::scaled_config(cases, 64)
}
