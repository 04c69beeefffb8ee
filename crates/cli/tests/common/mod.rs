//! Runs the real `flapwing` binary.

#![allow(dead_code)] // each test file uses part of this module

use std::path::Path;
use std::process::Command;

/// The robofly model as shipped (the binary's built-in default).
pub const ROBOFLY: &str = include_str!("../../../../models/robofly.toml");

/// What one run of the binary produced.
#[derive(Debug)]
pub struct Run {
    pub code: i32,
    pub stdout: String,
    pub stderr: String,
}

impl Run {
    /// The one JSON document on stdout (fails if there is anything else on stdout).
    pub fn json(&self) -> serde_json::Value {
        serde_json::from_str(&self.stdout)
            .unwrap_or_else(|e| panic!("stdout is not one JSON document ({e}):\n{}", self.stdout))
    }

    /// Asserts a bad-input exit: code 2, an `error:` line, no panic, nothing on stdout.
    pub fn assert_bad_input(&self) {
        assert_eq!(self.code, 2, "{self:?}");
        assert!(self.stderr.contains("error:"), "{self:?}");
        assert!(!self.stderr.contains("panicked"), "{self:?}");
        assert!(self.stdout.is_empty(), "{self:?}");
    }
}

/// Runs `flapwing args...` in `dir`.
pub fn flapwing_in(dir: &Path, args: &[&str]) -> Run {
    let out = Command::new(env!("CARGO_BIN_EXE_flapwing"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run flapwing");
    Run {
        code: out
            .status
            .code()
            .expect("exit code (not killed by a signal)"),
        stdout: String::from_utf8(out.stdout).expect("UTF-8 stdout"),
        stderr: String::from_utf8(out.stderr).expect("UTF-8 stderr"),
    }
}

/// Runs `flapwing args...` in a fresh empty directory: the binary must not need the
/// workspace's files.
pub fn flapwing(args: &[&str]) -> Run {
    let dir = tempfile::tempdir().expect("temp dir");
    flapwing_in(dir.path(), args)
}

/// `x` rounded to 5 significant digits (as in crates/wingforce/tests/paper.rs).
pub fn sig5(x: f64) -> f64 {
    let mag = 10f64.powf(x.abs().log10().floor() - 4.0);
    (x / mag).round() * mag
}

/// A command line split at white space (so no argument may contain a space):
/// `argv("forces --cycles 1")` is `["forces", "--cycles", "1"]`.
pub fn argv(line: &str) -> Vec<&str> {
    line.split_whitespace().collect()
}
