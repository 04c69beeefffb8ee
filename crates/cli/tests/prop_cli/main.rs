//! Property tests (issue 7): the real `flapwing` binary with random flag values and bad model
//! files exits 0, 1 or 2 (never 101, a Rust panic), never prints "panicked", and exits 2 with
//! an `error:` line for bad input; a bad `--model FILE` names the file.
//!
//! Every case runs the binary once (a few milliseconds each: `simulate --duration-s` at most
//! 0.002 s, `hover --duration-s` at most 0.01 s, `forces` at most 3 x 40 steps), so the case
//! counts are small. Generated inputs (binary runs) per property:
//!
//! | property                                  | cases |
//! |-------------------------------------------|-------|
//! | `wake_capture_flags`                      |    48 |
//! | `forces_flags`                            |    24 |
//! | `simulate_flags`                          |    24 |
//! | `hover_flags`                             |    24 |
//! | `bad_model_files_name_the_file`           |    32 |
//! | `replay_of_damaged_logs`                  |    24 |
//!
//! `FLAPWING_PROP_SCALE=N` multiplies every case count (for long local soak runs).
//!
//! The properties by family: `aero_flags.rs` (`wake-capture` and `forces` flags),
//! `flight_flags.rs` (`simulate` and `hover` flags), `model_files.rs` (damaged `--model`
//! files) and `damaged_logs.rs` (damaged logs given to `replay`), on the flag-value
//! generators of `flag_values.rs` and the run harness and exit contract of `harness.rs`.

#[path = "../../../wingforce/tests/support/prop_config.rs"]
mod prop_config;

mod aero_flags;
mod damaged_logs;
mod flag_values;
mod flight_flags;
mod harness;
mod model_files;
