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

/// Every `.rs` file in tests/ is a module above or a test target in Cargo.toml, and every
/// folder with a `main.rs` is a test target: with `autotests = false` cargo would not find a
/// new file by itself.
#[test]
fn every_test_file_is_a_test() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests");
    let root = include_str!("cli.rs");
    let manifest = include_str!("../Cargo.toml");
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_str().unwrap().to_owned();
        if let Some(stem) = name.strip_suffix(".rs") {
            let module = root.contains(&format!("\nmod {stem};\n"));
            let target = manifest.contains(&format!("path = \"tests/{name}\""));
            assert!(
                module || target,
                "tests/{name} is neither a module of tests/cli.rs nor a [[test]]"
            );
        } else if path.join("main.rs").is_file() {
            let target = format!("path = \"tests/{name}/main.rs\"");
            assert!(
                manifest.contains(&target),
                "tests/{name}/main.rs is not a [[test]] in Cargo.toml"
            );
        }
    }
}
