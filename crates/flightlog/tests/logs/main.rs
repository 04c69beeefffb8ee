//! flightlog's integration tests, one binary: each module is one idea (its own module doc),
//! linked once against the logging stack (Rerun's and Foxglove's crates) instead of once a
//! file. The property tests are `prop_replay/`. `every_test_file_is_a_module` fails when a file
//! here is left out.

mod check;
mod common;
mod foreign;
mod four_wings;
mod json_logs;
mod mcap_format;
// Not `rerun`: the module would shadow the `rerun` crate its tests use.
#[path = "rerun.rs"]
mod rerun_output;
mod roundtrip;
mod scene_forces;
mod truncation;
mod wind_estimate;

#[path = "../../../../tests/support/test_files.rs"]
mod test_files;

/// Every file in this folder is a module above: see
/// [`test_files::assert_every_test_file_runs`].
#[test]
fn every_test_file_is_a_module() {
    test_files::assert_every_test_file_runs(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/logs"),
        "main.rs",
        include_str!("main.rs"),
        None,
    );
}
