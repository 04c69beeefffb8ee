//! A run killed with SIGKILL keeps what it reported in its log: the real `flapwing` binary is
//! killed at eleven points of a logged run chosen by its reports, and at seven points while
//! its writer thread is in the middle of a chunk (the log a named pipe the test stops
//! draining), and `flapwing replay` reads each log back.
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

/// Simulated seconds of a run: 20 s are 436,000 steps and 2180 chunks, tens of seconds of
/// wall time, so the kills below (after at most 55 reports, or with the log a pipe the test
/// stops draining) come long before the run could end by itself. Between two reports (the
/// simulation thread looks once a step) the writer can flush at most three chunks (the one
/// queued, the one being written and the one just closed), so 55 reports come after at most
/// 165 chunks, whatever the threads' speeds.
const DURATION_S: &str = "20";
const STEPS: u64 = 436_000;

fn spawn_run(dir: &Path, mcap: &str, force: bool) -> Child {
    let mut args = vec![
        "simulate",
        "--model",
        "drosophila",
        "--duration-s",
        DURATION_S,
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

/// Reads stderr until `k` flushed lines were seen; the samples of the last one.
fn wait_flushed(stderr: &mut BufReader<ChildStderr>, k: usize) -> u64 {
    let (mut seen, mut last) = (0, 0);
    let mut line = String::new();
    while seen < k {
        line.clear();
        assert!(
            stderr.read_line(&mut line).unwrap() > 0,
            "the run ended before its {k}th flushed report"
        );
        if let Some(n) = flushed_samples(line.trim_end()) {
            assert!(n > last, "flushed went back: {last} then {n}");
            assert_eq!(n % CHUNK_SAMPLES, 0, "{line}");
            last = n;
            seen += 1;
        }
    }
    last
}

/// Kills the run; the most samples it ever reported flushed (`before`, or a later line).
fn kill(mut child: Child, mut stderr: BufReader<ChildStderr>, before: u64) -> u64 {
    child.kill().unwrap();
    assert!(!child.wait().unwrap().success(), "the run was not killed");
    let mut rest = String::new();
    stderr.read_to_string(&mut rest).unwrap();
    assert!(!rest.contains("panicked"), "{rest}");
    let after = rest.lines().filter_map(flushed_samples).max().unwrap_or(0);
    before.max(after)
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
    // Kill after the k-th report: early, in the middle, late. The process is wherever its
    // threads happen to be: stepping, encoding, compressing, writing.
    for k in [1usize, 2, 3, 4, 6, 9, 13, 19, 28, 42, 55] {
        let mcap = format!("k{k}.mcap");
        let mut child = spawn_run(dir.path(), &mcap, false);
        let mut stderr = BufReader::new(child.stderr.take().unwrap());
        let before = wait_flushed(&mut stderr, k);
        let reported = kill(child, stderr, before);
        let (samples, damage) = replay(dir.path(), &mcap);
        assert!(
            samples >= reported,
            "k = {k}: replay recovered {samples} samples, the run had reported {reported} flushed ({damage})"
        );
        assert!(samples <= STEPS, "k = {k}: {samples} samples");
        assert_eq!(samples % CHUNK_SAMPLES, 0, "k = {k}: whole chunks only");
    }
}

/// Runs with the log a named pipe that the test drains record by record: it reads `whole`
/// chunks of samples, then `tenths` tenths of the next chunk record (0: its 9-byte header
/// only), stops reading and kills the run. What the test read, plus what the run had left in
/// the pipe's buffer, is what a disk would hold.
/// Returns (the chunk's length, samples replayed, samples reported flushed).
fn kill_while_writing(dir: &Path, whole: u64, tenths: u64) -> (u64, u64, u64) {
    let name = format!("pipe-{whole}-{tenths}.mcap");
    let fifo = dir.join(&name);
    let made = Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(made.success());
    let mut child = spawn_run(dir, &name, true);
    // Opening a pipe's reading end blocks until the run opens its writing end: open it on a
    // thread, so that a run that fails before it opens its log fails the test instead of
    // hanging it.
    let (tx, rx) = std::sync::mpsc::channel();
    let path = fifo.clone();
    std::thread::spawn(move || tx.send(std::fs::File::open(path)));
    let Ok(opened) = rx.recv_timeout(std::time::Duration::from_secs(120)) else {
        let _ = child.kill();
        let mut err = String::new();
        let _ = BufReader::new(child.stderr.take().unwrap()).read_to_string(&mut err);
        panic!("the run never opened its log:\n{err}");
    };
    let mut pipe = opened.unwrap();
    let stderr = BufReader::new(child.stderr.take().unwrap());
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
        if is_samples(head[0], len) && chunks == whole {
            let mut part = vec![0u8; (len * tenths / 10) as usize];
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
    let reported = kill(child, stderr, 0);
    // The run is dead, so its writing end is closed: what it left in the pipe's buffer (up to
    // 64 KiB, possibly the rest of the cut chunk) reads out, then end of file.
    pipe.read_to_end(&mut bytes).unwrap();
    drop(pipe);
    let disk = format!("disk-{whole}-{tenths}.mcap");
    std::fs::write(dir.join(&disk), &bytes).unwrap();
    let (samples, damage) = replay(dir, &disk);
    assert!(
        samples >= reported,
        "{whole} chunks + {tenths}/10: replay recovered {samples} samples, the run had reported {reported} flushed ({damage})"
    );
    assert_eq!(samples % CHUNK_SAMPLES, 0, "whole chunks only: {damage}");
    (partial_len, samples, reported)
}

#[test]
fn a_run_killed_while_writing_a_chunk_keeps_the_chunks_before() {
    let dir = tempfile::tempdir().unwrap();
    for (whole, tenths) in [(0, 0), (0, 5), (1, 1), (2, 1), (3, 0), (5, 5), (8, 9)] {
        let (len, samples, reported) = kill_while_writing(dir.path(), whole, tenths);
        let (read_whole, next) = (whole * CHUNK_SAMPLES, (whole + 1) * CHUNK_SAMPLES);
        if tenths < 5 {
            // More of the chunk is left than a pipe's 64 KiB buffer holds: the writer thread
            // was blocked inside its write of this chunk when the kill came, so the chunks
            // read whole are recovered and nothing of the one cut, which it never reported.
            assert!(
                len * (10 - tenths) / 10 > 64 * 1024,
                "the chunk ({len} bytes) could pass whole into the pipe's buffer"
            );
            assert_eq!(samples, read_whole, "{whole} chunks + {tenths}/10");
            assert!(
                reported <= read_whole,
                "{whole} chunks + {tenths}/10: {reported}"
            );
        } else {
            // The rest of the chunk may have fit in the buffer: the writer finished it or
            // not, and a sample chunk (about 140 kB) is too long to follow it whole.
            assert!(
                samples == read_whole || samples == next,
                "{whole} chunks + {tenths}/10: {samples} samples"
            );
        }
    }
}
