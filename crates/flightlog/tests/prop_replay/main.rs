//! Property tests (issue 7): reading a damaged, foreign or forged MCAP log never panics.
//!
//! `flightlog::replay::read_summary`, `replay::export_csv` and `check::check_log` are given
//! truncated logs (every prefix length on a grid, and random lengths), logs with random bits
//! flipped, random bytes (with and without the MCAP magic), valid MCAP files written with the
//! `mcap` crate without flapwing metadata (random channels, messages, metadata, attachments,
//! chunking and compression), and real logs whose `flapwing` metadata was rewritten (random
//! command, settings, model text and log rate). Each call must return `Ok` (a truncated or
//! damaged log: partial, with `damage` saying what was lost) or an error whose message names
//! the file, and never panic. A truncated log yields more messages the longer the prefix,
//! and `check_log` finds its samples equal to a re-run.
//!
//! Generated inputs per property (the file runs in a few seconds in release):
//!
//! | property / test                                   | inputs |
//! |---------------------------------------------------|--------|
//! | `truncation_grid` (deterministic: 97 grid points, chunk ends +-1, edges) | ~110 (check_log on ~10) |
//! | `truncated_at_random_lengths`                     |     60 |
//! | `flipped_bits`                                    |     80 |
//! | `random_bytes`                                    |    200 |
//! | `foreign_mcap_files`                              |    100 |
//! | `forged_flapwing_metadata`                        |     60 |
//!
//! `FLAPWING_PROP_SCALE=N` multiplies every proptest case count (for long local soak runs).
//!
//! The properties by family: `truncation.rs` (cut logs), `corrupted.rs` (flipped bits and
//! random bytes), `foreign.rs` (valid MCAP files not written by flapwing) and `forged.rs`
//! (real logs with forged `flapwing` metadata), on the recorded logs of `fixture.rs` and the
//! checks of `checks.rs` (every reader returns `Ok` or an error naming the file, never
//! panics, never hangs).

#[path = "../../../wingforce/tests/support/prop_config.rs"]
mod prop_config;

mod checks;
mod corrupted;
mod fixture;
mod foreign;
mod forged;
mod truncation;
