//! Truncated logs (every prefix length on a grid, each chunk end +-1, and random lengths):
//! `read_summary` is `Ok` (partial, with damage) or a clear error; a truncated log yields
//! more messages the longer the prefix, never more than the whole log; only the whole file
//! is complete; and `check_log` finds its samples equal to a re-run (never a mismatch).

use std::time::Duration;

use flightlog::check::CheckOutcome;
use proptest::prelude::*;
use proptest::sample::Index;

use crate::checks::{check_read_error, check_with_limit, config, csv_of, ok, summary_of};
use crate::fixture::fixture;

/// End offsets of the chunk records of a whole log.
fn chunk_ends(bytes: &[u8]) -> Vec<usize> {
    let summary = mcap::Summary::read(bytes).unwrap().unwrap();
    let mut v: Vec<usize> = summary
        .chunk_indexes
        .iter()
        .map(|c| (c.chunk_start_offset + c.chunk_length) as usize)
        .collect();
    v.sort();
    v
}

/// Every prefix length on a grid (97 points) plus each chunk end +-1: read_summary is Ok
/// (partial, with damage) or a clear error; the message count never decreases as the prefix
/// grows; only the whole file is complete; export_csv never panics; check_log (on every
/// twelfth cut) finds a match, nothing to check, or a clear error, never a mismatch.
#[test]
fn truncation_grid() {
    ok((|| {
        let f = fixture();
        let len = f.bytes.len();
        let ends = chunk_ends(&f.bytes);
        prop_assert!(ends.len() >= 3, "only {} chunks", ends.len());
        let mut cuts: Vec<usize> = (0..=96).map(|i| i * len / 96).collect();
        for e in &ends {
            cuts.extend([e - 1, *e, e + 1]);
        }
        cuts.extend([1, 7, 8, 9, len - 1]);
        cuts.sort();
        cuts.dedup();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cut.mcap");
        let csv = dir.path().join("state.csv");
        let mut last_count = 0;
        let mut checked = 0;
        for (k, &cut) in cuts.iter().enumerate() {
            std::fs::write(&path, &f.bytes[..cut]).unwrap();
            let s = summary_of(&path)
                .map_err(|e| TestCaseError::fail(format!("cut at {cut} of {len}: {e}")))?;
            if let Some(s) = &s {
                prop_assert!(
                    s.message_count >= last_count,
                    "cut at {cut}: {} messages, fewer than {last_count} at a shorter cut",
                    s.message_count
                );
                prop_assert!(s.message_count <= f.summary.message_count);
                prop_assert_eq!(s.complete, cut == len, "cut at {} of {}", cut, len);
                last_count = s.message_count;
            }
            csv_of(&path, "/vehicle/state", &csv)?;
            if k % 12 == 0 || cut == len {
                checked += 1;
                match check_with_limit(&path, Duration::from_secs(60))? {
                    None => prop_assert!(false, "check_log of a cut at {cut} hangs"),
                    Some(Ok(CheckOutcome::Mismatch { detail, .. })) => {
                        prop_assert!(false, "cut at {cut}: the re-run differs: {detail}")
                    }
                    Some(Ok(_)) => {}
                    Some(Err(e)) => check_read_error(&e, &path)?,
                }
            }
        }
        prop_assert_eq!(last_count, f.summary.message_count);
        eprintln!(
            "truncation_grid: {} cuts, check_log on {checked}",
            cuts.len()
        );
        Ok(())
    })());
}

proptest! {
    #![proptest_config(config(60))]

    /// Random prefix lengths: Ok (partial, with damage) or a clear error; never more
    /// messages than the whole log.
    #[test]
    fn truncated_at_random_lengths(at in any::<Index>()) {
        let f = fixture();
        let cut = at.index(f.bytes.len() + 1);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cut.mcap");
        std::fs::write(&path, &f.bytes[..cut]).unwrap();
        if let Some(s) = summary_of(&path)? {
            prop_assert!(s.message_count <= f.summary.message_count);
        }
        csv_of(&path, "/wing/left/forces", &dir.path().join("f.csv"))?;
    }
}
