//! The CLI's integration tests, one binary: each module below was a test file of its own and
//! keeps its module doc; all drive the real `flapwing` binary (`common`). One link instead of
//! one a file (Cargo.toml sets `autotests = false`). The signal and pacing tests (`kill.rs`,
//! `interrupt.rs`, `live_pace.rs`) stay binaries of their own, out of this one's parallel
//! load, and `prop_cli/` is the property tests'. `every_test_file_is_a_test` fails when a file
//! in tests/ is left out.

mod actuated;
mod bad_input;
mod bad_input_surfaces;
mod common;
mod contour;
mod divergence;
mod dragonfly;
mod envelope;
mod estimated_feedback;
mod exit_codes;
mod forces;
mod forces_plot;
mod identify;
mod log_channels;
mod log_paths;
mod replay;
mod sensors;
mod study_failed_cases;
mod study_fit_wake;
mod study_optimize;
mod study_submit;
mod study_sweep;
mod validate;
mod wake_capture;
mod wind;

#[path = "../../../tests/support/test_files.rs"]
mod test_files;

/// Every file in this folder runs: see [`test_files::assert_every_test_file_runs`].
#[test]
fn every_test_file_is_a_test() {
    test_files::assert_every_test_file_runs(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests"),
        "cli.rs",
        include_str!("cli.rs"),
        Some(include_str!("../Cargo.toml")),
    );
}
