//! A run killed with SIGKILL keeps what it reported in its log: the real `flapwing` binary is
//! killed at many points of a logged run, once while its writer thread is blocked in the
//! middle of writing a chunk, and `flapwing replay` reads each log back.
//!
//! The property (flightlog's writer module): chunks reach the file whole and in order, and
//! the writer thread says how many samples are in the file only after flushing them; so a
//! kill at any moment leaves a log that replays to at least the samples last reported with
//! `--report-flushed`, and never to more than were run. None of the checks depends on how
//! fast the process or its threads run: the kill points are chosen by what the process
//! reported, not by a clock.

mod common;

use std::io::{BufRead, BufReader, Read};
use std::path::Path;
use std::process::{Child, ChildStderr, Command, Stdio};

use common::flapwing_in;

/// Samples per chunk at full rate (flightlog closes a chunk after 200 samples; 200 steps of
/// the fly are 9.2 ms, under its 50 ms time limit per chunk).
const CHUNK_SAMPLES: u64 = 200;

/// Steps of a 2 s fly run (dt = 1 / (218 Hz x 100)): 218 chunks. Between two reports (the
/// simulation thread looks once a step) the writer can flush at most the chunks then queued
/// or being written and the one just closed, three, so the run makes at least 70 reports
/// before it ends, whatever the threads' speeds.
const STEPS: u64 = 43_600;

fn spawn_run(dir: &Path, mcap: &str, force: bool) -> Child {
    let mut args = vec![
        "simulate",
        "--model",
        "drosophila",
        "--duration-s",
        "2",
        "--full-rate",
        "--report-flushed",
        "--mcap",
        mcap,
    ];
    if force {
        args.push("--force");
    }
    Command::new(env!("CARGO_BIN_EXE_flapwing"))
        .args(&args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// The samples of a `flushed: N samples to t = T s` line.
fn flushed_samples(line: &str) -> Option<u64> {
    let rest = line.strip_prefix("flushed: ")?;
    rest.split_whitespace().next()?.parse().ok()
}

/// Reads stderr until `k` flushed lines were seen (or the run ended); the samples of the
/// last one (0 before any) and whether `k` were seen.
fn wait_flushed(stderr: &mut BufReader<ChildStderr>, k: usize) -> (u64, bool) {
    let (mut seen, mut last) = (0, 0);
    let mut line = String::new();
    while seen < k {
        line.clear();
        if stderr.read_line(&mut line).unwrap() == 0 {
            return (last, false);
        }
        if let Some(n) = flushed_samples(line.trim_end()) {
            assert!(n > last, "flushed went back: {last} then {n}");
            assert_eq!(n % CHUNK_SAMPLES, 0, "{line}");
            last = n;
            seen += 1;
        }
    }
    (last, true)
}

/// `flapwing replay --json` of a killed run's log: (samples, the damage note).
fn replay(dir: &Path, mcap: &str) -> (u64, String) {
    let run = flapwing_in(dir, &["replay", "--json", mcap]);
    assert_eq!(run.code, 0, "{run:?}");
    let v = run.json();
    assert_eq!(v["complete"], false, "{v}");
    let damage = v["damage"].as_str().unwrap().to_owned();
    assert!(damage.contains("truncated"), "{damage}");
    (v["samples"].as_u64().unwrap(), damage)
}

#[test]
fn a_killed_run_replays_to_at_least_what_it_reported_flushed() {
    let dir = tempfile::tempdir().unwrap();
    let mut killed = 0;
    // Kill after the k-th report: early, in the middle, late.
    for k in [1usize, 2, 3, 4, 6, 9, 13, 19, 28, 42, 55] {
        let mcap = format!("k{k}.mcap");
        let mut child = spawn_run(dir.path(), &mcap, false);
        let mut stderr = BufReader::new(child.stderr.take().unwrap());
        let (reported, seen) = wait_flushed(&mut stderr, k);
        assert!(seen, "the run ended before its {k}th flushed report");
        child.kill().unwrap();
        let status = child.wait().unwrap();
        assert!(
            !status.success(),
            "k = {k}: the run finished before the kill"
        );
        // Whatever else it printed after the kill point.
        let mut rest = String::new();
        let _ = stderr.read_to_string(&mut rest);
        let after = rest.lines().filter_map(flushed_samples).max().unwrap_or(0);
        let reported = reported.max(after);
        let (samples, damage) = replay(dir.path(), &mcap);
        assert!(
            samples >= reported,
            "k = {k}: replay recovered {samples} samples, the run had reported {reported} flushed ({damage})"
        );
        assert!(samples <= STEPS, "k = {k}: {samples} samples");
        assert_eq!(samples % CHUNK_SAMPLES, 0, "k = {k}: whole chunks only");
        killed += 1;
    }
    assert_eq!(killed, 11);
}

#[test]
fn a_run_killed_while_writing_a_chunk_keeps_the_chunks_before() {
    let dir = tempfile::tempdir().unwrap();
    // The log is a named pipe that this test drains: it reads two whole chunks of samples and
    // the start of the third, then stops reading, so the writer thread cannot finish that
    // chunk (it is larger than a pipe's 64 KiB buffer) and is blocked inside its write when
    // the kill comes. What the test read is what a disk would hold.
    let fifo = dir.path().join("pipe.mcap");
    let made = Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(made.success());
    let mut child = spawn_run(dir.path(), "pipe.mcap", true);
    let mut stderr = BufReader::new(child.stderr.take().unwrap());
    let mut pipe = std::fs::File::open(&fifo).unwrap();
    let mut bytes = vec![0u8; 8];
    pipe.read_exact(&mut bytes).unwrap();
    assert_eq!(&bytes, b"\x89MCAP0\r\n");
    // Chunk records of samples (at full rate 200 samples, about 140 kB); the schemas and
    // the start-up warning event come in small chunks of their own before them.
    let is_samples = |op: u8, len: u64| op == 0x06 && len > 64 * 1024;
    let mut chunks = 0;
    let partial_len = loop {
        let mut head = [0u8; 9];
        pipe.read_exact(&mut head).unwrap();
        bytes.extend_from_slice(&head);
        let len = u64::from_le_bytes(head[1..9].try_into().unwrap());
        if is_samples(head[0], len) && chunks == 2 {
            // The third chunk of samples: take a tenth of it and stop.
            let mut part = vec![0u8; (len / 10) as usize];
            pipe.read_exact(&mut part).unwrap();
            bytes.extend_from_slice(&part);
            break len;
        }
        let mut body = vec![0u8; len as usize];
        pipe.read_exact(&mut body).unwrap();
        bytes.extend_from_slice(&body);
        if is_samples(head[0], len) {
            chunks += 1;
        }
    };
    assert!(
        partial_len * 9 / 10 > 64 * 1024,
        "the third chunk ({partial_len} bytes) could pass whole into the pipe's buffer"
    );
    child.kill().unwrap();
    assert!(!child.wait().unwrap().success());
    drop(pipe);
    let mut err = String::new();
    stderr.read_to_string(&mut err).unwrap();
    let reported = err.lines().filter_map(flushed_samples).max().unwrap_or(0);
    std::fs::write(dir.path().join("disk.mcap"), &bytes).unwrap();
    let (samples, damage) = replay(dir.path(), "disk.mcap");
    assert!(
        samples >= reported,
        "replay recovered {samples} samples, the run had reported {reported} flushed ({damage})\n{err}"
    );
    // The two chunks of samples read whole are recovered, and nothing of the third.
    assert_eq!(samples, 2 * CHUNK_SAMPLES, "{damage}");
    // The run could not report the chunk it was blocked in.
    assert!(reported <= samples, "{err}");
}
