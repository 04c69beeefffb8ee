//! The four-winged built-in dragonfly through the real binary: it flies (`--no-log`), and
//! what supports one wing pair only (logs, hover trim at forward-flight kinematics) says so
//! with an error, never a panic.

mod common;

use common::flapwing;

#[test]
fn the_dragonfly_flies_without_a_log() {
    let run = flapwing(&[
        "simulate",
        "--model",
        "dragonfly",
        "--no-log",
        "--json",
        "--duration-s",
        "0.08",
    ]);
    assert_eq!(run.code, 0, "{run:?}");
    let j = run.json();
    assert_eq!(j["model"], "<built-in dragonfly>");
    // Free flight from the published 1.5 m/s: the wings carry 0.769 of the weight over the
    // first two wingbeats (docs/models.md; crates/flapsim/tests/four_wings.rs measures it at
    // the frozen state). Tolerance 0.01: the body moves a little in two wingbeats.
    let lw = j["summary"]["mean_lift_over_weight"].as_f64().unwrap();
    assert!((lw - 0.769).abs() < 0.01, "{lw}");
}

#[test]
fn a_log_of_four_wings_is_refused_with_the_way_out() {
    let dir = tempfile::tempdir().unwrap();
    let mcap = dir.path().join("d.mcap");
    let run = flapwing(&[
        "simulate",
        "--model",
        "dragonfly",
        "--duration-s",
        "0.01",
        "--mcap",
        mcap.to_str().unwrap(),
    ]);
    run.assert_bad_input();
    assert!(
        run.stderr.contains("dragonfly")
            && run.stderr.contains("4 wings")
            && run.stderr.contains("--no-log"),
        "{run:?}"
    );
    assert!(!mcap.exists(), "no partial log left behind");
}

#[test]
fn no_hover_trim_at_forward_flight_kinematics_is_an_error() {
    let run = flapwing(&["trim", "--model", "dragonfly"]);
    assert_eq!(run.code, 1, "{run:?}");
    assert!(
        run.stderr.contains("no hover trim") && !run.stderr.contains("panicked"),
        "{run:?}"
    );
}
