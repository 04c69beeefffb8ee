//! Truncated and damaged logs: never a panic; every complete chunk before the cut is
//! recovered; what was lost is reported.

use crate::common;

use common::{ORIGIN, mcap_opts, record, wingbeats};
use flightlog::Error;
use flightlog::replay::read_summary;

/// (end offset of each chunk record, messages in it), in file order.
fn chunk_ends(bytes: &[u8]) -> Vec<(u64, u64)> {
    let summary = mcap::Summary::read(bytes).unwrap().unwrap();
    let mut out: Vec<(u64, u64)> = summary
        .chunk_indexes
        .iter()
        .map(|ci| {
            let start = ci.chunk_start_offset as usize;
            let end = start + ci.chunk_length as usize;
            let rec = mcap::parse_record(bytes[start], &bytes[start + 9..end]).unwrap();
            let mcap::records::Record::Chunk { header, data } = rec else {
                panic!("not a chunk")
            };
            let n = mcap::read::ChunkReader::new(header, &data)
                .unwrap()
                .filter(|r| matches!(r, Ok(mcap::records::Record::Message { .. })))
                .count() as u64;
            (end as u64, n)
        })
        .collect();
    out.sort();
    out
}

#[test]
fn truncated_files_recover_every_complete_chunk() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("full.mcap");
    // 2000 steps: 100 wingbeats at the fly's 20 steps per wingbeat.
    let run = record(&mcap_opts(&path, None), "simulate", wingbeats(100.0));
    let bytes = std::fs::read(&path).unwrap();
    let len = bytes.len() as u64;
    let chunks = chunk_ends(&bytes);
    assert!(chunks.len() >= 8, "only {} chunks", chunks.len());
    let total: u64 = chunks.iter().map(|c| c.1).sum();
    assert_eq!(total, run.stats.mcap_messages);
    // Where the `flapwing` metadata record ends: before it, a cut file is not a flapwing log.
    let summary = mcap::Summary::read(&bytes).unwrap().unwrap();
    let md = summary
        .metadata_indexes
        .iter()
        .find(|m| m.name == "flapwing")
        .unwrap();
    let md_end = md.offset + md.length;
    let data_end = chunks.last().unwrap().0;

    let mut cuts: Vec<u64> = (0..60).map(|i| i * len / 60).collect();
    cuts.extend([1, 7, 8, 9, 17, md_end - 1, md_end, md_end + 1, len - 1]);
    for (end, _) in &chunks {
        cuts.extend([end - 1, *end, end + 1]);
    }
    cuts.sort();
    cuts.dedup();
    let cut_path = dir.path().join("cut.mcap");
    let mut last_recovered = 0;
    for &cut in &cuts {
        std::fs::write(&cut_path, &bytes[..cut as usize]).unwrap();
        let expect: u64 = chunks.iter().filter(|c| c.0 <= cut).map(|c| c.1).sum();
        match read_summary(&cut_path) {
            Ok(s) => {
                assert!(
                    cut >= md_end,
                    "cut {cut}: read a file cut inside the metadata"
                );
                assert!(!s.complete, "cut {cut}");
                let d = s.damage.as_deref().unwrap();
                if cut <= data_end {
                    assert!(d.contains("truncated"), "cut {cut}: {d}");
                    assert!(
                        d.contains(&format!("recovered {expect} messages")),
                        "cut {cut}: {d}"
                    );
                }
                assert_eq!(s.message_count, expect, "cut {cut}: {d}");
                assert!(s.message_count >= last_recovered);
                last_recovered = s.message_count;
                assert_eq!(s.metadata["model_toml"], flapsim::DROSOPHILA_TOML);
                // Every channel defined so far, counts consistent.
                let sum: u64 = s.channels.iter().map(|c| c.message_count).sum();
                assert_eq!(sum, s.message_count);
            }
            Err(e) => {
                assert!(cut < md_end, "cut {cut}: {e}");
                assert!(
                    matches!(e, Error::NotMcap { .. } | Error::NotFlapwing { .. }),
                    "cut {cut}: {e}"
                );
                assert!(e.is_bad_input());
            }
        }
    }
    // The whole file.
    let s = read_summary(&path).unwrap();
    assert!(s.complete);
    assert_eq!(s.message_count, total);
    // Cut in the summary section: all data, the summary reported damaged.
    std::fs::write(&cut_path, &bytes[..(len - 20) as usize]).unwrap();
    let s = read_summary(&cut_path).unwrap();
    assert_eq!(s.message_count, total);
    assert!(!s.complete && s.damage.is_some());
}

#[test]
fn damaged_bytes_never_panic() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("full.mcap");
    record(&mcap_opts(&path, Some(4000.0)), "simulate", wingbeats(4.0));
    let bytes = std::fs::read(&path).unwrap();
    let chunks = chunk_ends(&bytes);
    let bad = dir.path().join("bad.mcap");
    let len = bytes.len();
    for i in 0..80 {
        let at = (i * 7919 + 13) % len;
        let mut b = bytes.clone();
        b[at] ^= 0x5a;
        std::fs::write(&bad, &b).unwrap();
        match read_summary(&bad) {
            Ok(s) => {
                // A flipped bit inside chunk k loses chunk k and what follows, nothing before.
                let before: u64 = chunks
                    .iter()
                    .filter(|c| (c.0 as usize) <= at)
                    .map(|c| c.1)
                    .sum();
                assert!(s.message_count >= before, "flip at {at}: {:?}", s.damage);
                let _ = s.to_string();
            }
            Err(e) => {
                let _ = e.to_string();
            }
        }
    }
}

#[test]
fn a_killed_run_keeps_its_flushed_chunks() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("killed.mcap");
    let toml = flapsim::DROSOPHILA_TOML;
    let vehicle = flapsim::Vehicle::from_toml(toml, ORIGIN).unwrap();
    let info = flightlog::RunInfo::new(
        "simulate",
        "flapwing simulate",
        toml,
        ORIGIN,
        flightlog::SimSettings::new(flapsim::Mode::Free, 0.4, None, [0.0; 3]).to_json(),
    );
    let mut rec = flightlog::Recorder::create(&mcap_opts(&path, None), &info, &vehicle).unwrap();
    let mut sim = flapsim::Simulation::new(vehicle, flapsim::Mode::Free);
    // At full rate a chunk closes after every 200 samples (200 drosophila steps are 45.9 ms
    // at its 20 steps per wingbeat, so the 50 ms time limit on a chunk never comes first):
    // 0.3 s = 1308 steps close six chunks and leave 108 samples in the seventh.
    let n = (0.3 / sim.dt_s()).round() as u64;
    for _ in 0..n {
        rec.record(&sim.step().unwrap()).unwrap();
    }
    let closed = n / 200;
    assert_eq!(closed, 6);
    // What the writer thread had reported in the file before the "kill".
    let reported = rec.flushed().unwrap();
    // Simulate a kill: no finish, no Drop. The writer thread may still be writing either of
    // the two newest closed chunks, so take the file as it is at this moment, as a kill would
    // leave it.
    std::mem::forget(rec);
    let killed = dir.path().join("killed-copy.mcap");
    std::fs::copy(&path, &killed).unwrap();
    let path = killed;
    let s = read_summary(&path).unwrap();
    assert!(!s.complete);
    assert!(s.end_metadata.is_none());
    let d = s.damage.unwrap();
    assert!(d.contains("truncated"), "{d}");
    // The bound, whatever the writer thread's speed (see flightlog's writer module): when the
    // close of chunk k returned, every chunk before the two newest was in the file. So the
    // samples of the first `closed - 2` chunks survive; the chunk being filled never does.
    let at_least = (closed - 2) * 200;
    assert!(
        s.samples >= at_least,
        "{} samples, {at_least} expected at least: {d}",
        s.samples
    );
    assert!(s.samples <= closed * 200, "{} samples: {d}", s.samples);
    assert_eq!(s.samples % 200, 0, "whole chunks only: {d}");
    // And at least what the writer had reported in the file.
    assert!(
        s.samples >= reported.samples,
        "{} samples, {} reported flushed: {d}",
        s.samples,
        reported.samples
    );
    assert!(reported.samples <= closed * 200 && reported.samples % 200 == 0);
    // What was recovered re-runs bit for bit.
    match flightlog::check::check_log(&path).unwrap() {
        flightlog::check::CheckOutcome::Match { samples, note } => {
            assert_eq!(samples, s.samples);
            assert!(note.unwrap().contains("truncated"));
        }
        other => panic!("{other:?}"),
    }
}
