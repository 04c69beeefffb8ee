//! Corrupted logs: random bits flipped in a real log, and random bytes (with and without
//! the MCAP magic, or spliced into a real log's header). The readers return `Ok` or a clear
//! error and never panic; a summary never has more messages than the whole log.

use std::time::Duration;

use flightlog::check::check_log;
use proptest::prelude::*;
use proptest::sample::Index;

use crate::checks::{check_read_error, check_with_limit, config, csv_of, guarded, summary_of};
use crate::fixture::fixture;

// ---------------------------------------------------------------------------------------------
// Bit flips.
// ---------------------------------------------------------------------------------------------

proptest! {
    #![proptest_config(config(80))]

    /// One to four flipped bits anywhere: read_summary and export_csv never panic; a
    /// summary never has more messages than the whole log. With a single flip, check_log is
    /// run too (its re-run is bounded by the log's samples).
    #[test]
    fn flipped_bits(
        flips in prop::collection::vec((any::<Index>(), 0u8..8), 1..5),
        run_check in prop::bool::weighted(0.15),
    ) {
        let f = fixture();
        let mut b = f.bytes.clone();
        let n = b.len();
        for (i, bit) in &flips {
            b[i.index(n)] ^= 1 << bit;
        }
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("flipped.mcap");
        std::fs::write(&path, &b).unwrap();
        if let Some(s) = summary_of(&path)? {
            prop_assert!(s.message_count <= f.summary.message_count);
        }
        csv_of(&path, "/vehicle/state", &dir.path().join("s.csv"))?;
        if run_check && flips.len() == 1 {
            match check_with_limit(&path, Duration::from_secs(60))? {
                None => prop_assert!(false, "check_log hangs"),
                Some(Ok(_)) => {}
                Some(Err(e)) => prop_assert!(!e.to_string().trim().is_empty()),
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Random bytes.
// ---------------------------------------------------------------------------------------------

const MAGIC: &[u8] = b"\x89MCAP0\r\n";

proptest! {
    #![proptest_config(config(200))]

    /// Random bytes, sometimes behind the MCAP magic, sometimes a random splice into the real
    /// log's header: a clear error (or Ok), never a panic.
    #[test]
    fn random_bytes(
        body in prop::collection::vec(any::<u8>(), 0..2000),
        how in 0u8..4,
        at in any::<Index>(),
    ) {
        let f = fixture();
        let bytes = match how {
            0 => body.clone(),
            1 => [MAGIC, &body].concat(),
            2 => [MAGIC, &body, MAGIC].concat(),
            _ => {
                // The real log's first part, then garbage.
                let cut = at.index(f.bytes.len().min(4096) + 1);
                [&f.bytes[..cut], &body].concat()
            }
        };
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("random.mcap");
        std::fs::write(&path, &bytes).unwrap();
        summary_of(&path)?;
        csv_of(&path, "/vehicle/state", &dir.path().join("s.csv"))?;
        match guarded("check_log", || check_log(&path))? {
            Ok(_) => {}
            Err(e) => check_read_error(&e, &path)?,
        }
    }
}
