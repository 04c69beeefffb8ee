//! `flapwing trim --speed-m-s`, `stability --speed-m-s`, `hover --speed-m-s` and `flapwing
//! envelope`, driven through the real binary: outputs, files and bad input.

use crate::common;

use common::{flapwing, flapwing_in};

#[test]
fn trim_and_stability_at_a_forward_speed() {
    let dir = tempfile::tempdir().unwrap();
    let r = flapwing_in(
        dir.path(),
        &["trim", "--model", "bumblebee", "--speed-m-s", "2", "--json"],
    );
    assert_eq!(r.code, 0, "{r:?}");
    let j = r.json();
    assert_eq!(j["forward_speed_m_s"], 2.0);
    let pitch = j["pitch_deg"].as_f64().unwrap();
    let plane = j["stroke_plane_angle_deg"].as_f64().unwrap();
    // The model's stroke plane sits 57.5 deg from the body: pitch + plane = 57.5 deg.
    assert!((pitch + plane - 57.5).abs() < 1e-9, "{pitch} + {plane}");
    assert!(j["aero_power_w"].as_f64().unwrap() > 0.0);
    let r = flapwing_in(
        dir.path(),
        &[
            "stability",
            "--model",
            "bumblebee",
            "--speed-m-s",
            "2",
            "--no-floquet",
        ],
    );
    assert_eq!(r.code, 0, "{r:?}");
    assert!(
        r.stdout
            .starts_with("2.00 m/s forward, 0.00 m/s climb stability"),
        "{r:?}"
    );
    // A hover trim can be written to a model file; a forward one cannot (the file's inflow
    // is the hover downwash).
    let r = flapwing_in(
        dir.path(),
        &[
            "trim",
            "--model",
            "bumblebee",
            "--speed-m-s",
            "2",
            "--write",
            "t.toml",
        ],
    );
    r.assert_bad_input();
    assert!(
        r.stderr.contains("--write t.toml") && r.stderr.contains("hover trim only"),
        "{r:?}"
    );
}

#[test]
fn hover_flies_a_forward_condition_closed_loop() {
    let dir = tempfile::tempdir().unwrap();
    let r = flapwing_in(
        dir.path(),
        &[
            "hover",
            "--model",
            "bumblebee",
            "--speed-m-s",
            "2.5",
            "--duration-s",
            "0.3",
            "--no-log",
            "--json",
        ],
    );
    assert_eq!(r.code, 0, "{r:?}");
    let j = r.json();
    assert_eq!(j["condition"]["forward_speed_m_s"], 2.5);
    let o = &j["outcome"];
    assert!(o["diverged"].is_null(), "{o}");
    // From 5 deg of pitch it comes back within 2 deg and a body length of the moving point.
    assert!(o["recovery_time_s"].as_f64().unwrap() < 0.2, "{o}");
    let r = flapwing_in(
        dir.path(),
        &[
            "hover",
            "--model",
            "bumblebee",
            "--speed-m-s",
            "2.5",
            "--feedback",
            "estimated",
            "--no-log",
        ],
    );
    r.assert_bad_input();
    assert!(r.stderr.contains("--feedback estimated"), "{r:?}");
}

#[test]
fn envelope_writes_its_table_csv_and_plot() {
    let dir = tempfile::tempdir().unwrap();
    let r = flapwing_in(
        dir.path(),
        &[
            "envelope",
            "--model",
            "bumblebee",
            "--speeds-m-s",
            "0,2,9",
            "--csv",
            "e.csv",
            "--plot",
            "e.svg",
        ],
    );
    assert_eq!(r.code, 0, "{r:?}");
    assert!(r.stdout.contains("no trim: no trim at 9.00 m/s"), "{r:?}");
    let csv = std::fs::read_to_string(dir.path().join("e.csv")).unwrap();
    assert_eq!(csv.lines().count(), 4, "{csv}");
    assert!(csv.lines().nth(2).unwrap().starts_with("2,0,1,"), "{csv}");
    let svg = std::fs::read_to_string(dir.path().join("e.svg")).unwrap();
    assert!(
        svg.contains("power required") && svg.contains("mode real part"),
        "svg"
    );
    // The files exist now: without --force they are not replaced.
    let again = flapwing_in(
        dir.path(),
        &[
            "envelope",
            "--model",
            "bumblebee",
            "--speeds-m-s",
            "0",
            "--csv",
            "e.csv",
        ],
    );
    again.assert_bad_input();
    let r = flapwing_in(
        dir.path(),
        &[
            "envelope",
            "--model",
            "bumblebee",
            "--speeds-m-s",
            "0,1",
            "--json",
        ],
    );
    assert_eq!(r.code, 0, "{r:?}");
    let j = r.json();
    assert_eq!(j.as_array().unwrap().len(), 2);
    assert!(j[1]["point"]["point"]["power"]["aero_w"].as_f64().unwrap() > 0.0);
}

#[test]
fn envelope_refuses_bad_grids_and_fails_when_nothing_trims() {
    let dir = tempfile::tempdir().unwrap();
    for (flag, value, says) in [
        ("--speeds-m-s", "1,nan", "NaN"),
        ("--speeds-m-s", "-2", "-2"),
        ("--climbs-m-s", "inf", "inf"),
    ] {
        let r = flapwing_in(
            dir.path(),
            &["envelope", "--model", "bumblebee", flag, value],
        );
        r.assert_bad_input();
        assert!(
            r.stderr.contains(says) && r.stderr.contains("allowed"),
            "{r:?}"
        );
    }
    let r = flapwing_in(
        dir.path(),
        &["trim", "--model", "bumblebee", "--climb-m-s", "-1"],
    );
    r.assert_bad_input();
    assert!(r.stderr.contains("vortex-ring"), "{r:?}");
    let r = flapwing_in(
        dir.path(),
        &["envelope", "--model", "bumblebee", "--speeds-m-s", "9,10"],
    );
    assert_eq!(r.code, 1, "{r:?}");
    assert!(r.stderr.contains("no point of the envelope trims"), "{r:?}");
}

/// `--inflow` puts another induced flow on the model for `trim`, `stability` and `envelope`,
/// and each names it; a model that cannot take it, or an unknown name, is bad input (exit 2).
#[test]
fn inflow_option_selects_and_names_the_wake() {
    let dir = tempfile::tempdir().unwrap();
    let stability = |inflow: &str| {
        let r = flapwing_in(
            dir.path(),
            &[
                "stability",
                "--model",
                "bumblebee",
                "--no-floquet",
                "--inflow",
                inflow,
            ],
        );
        assert_eq!(r.code, 0, "{r:?}");
        r.stdout
    };
    let z_w = |out: &str| -> f64 {
        let line = out
            .lines()
            .find(|l| l.trim_start().starts_with("Z_w"))
            .unwrap();
        line.split_whitespace().last().unwrap().parse().unwrap()
    };
    let frozen = stability("frozen");
    let dynamic = stability("dynamic");
    assert!(frozen.contains("induced flow: frozen"), "{frozen}");
    assert!(dynamic.contains("induced flow: dynamic"), "{dynamic}");
    // The responsive disc relieves the heave damping (momentum theory: by m / (2m + k),
    // about 0.42 here; crates/flapsim/tests/responsive_wake/mod.rs checks it within 10%).
    let ratio = z_w(&dynamic) / z_w(&frozen);
    assert!((0.3..0.6).contains(&ratio), "Z_w dynamic / frozen {ratio}");
    let r = flapwing_in(
        dir.path(),
        &["trim", "--model", "robobee", "--inflow", "frozen"],
    );
    assert_eq!(r.code, 2, "{r:?}");
    assert!(
        r.stderr.contains("--inflow frozen")
            && r.stderr.contains("allowed")
            && r.stderr.contains("\"dynamic\""),
        "{r:?}"
    );
    let r = flapwing_in(dir.path(), &["trim", "--inflow", "swirl"]);
    assert_eq!(r.code, 2, "{r:?}");
    assert!(r.stderr.contains("off, frozen, dynamic"), "{r:?}");
    // `envelope` takes it too, and names it. The hover power with the downwash exceeds the
    // still air's by the induced power the wings pay to move the air (Ellington 1984, Phil
    // Trans R Soc B 305:145, part V: profile plus induced power).
    let hover_power = |inflow: &str| -> f64 {
        let r = flapwing_in(
            dir.path(),
            &[
                "envelope",
                "--model",
                "bumblebee",
                "--speeds-m-s",
                "0",
                "--inflow",
                inflow,
            ],
        );
        assert_eq!(r.code, 0, "{r:?}");
        assert!(
            r.stdout.contains(&format!("induced flow: {inflow}")),
            "{r:?}"
        );
        let row = r.stdout.lines().nth(3).unwrap();
        row.split_whitespace().nth(5).unwrap().parse().unwrap()
    };
    let (off, frozen) = (hover_power("off"), hover_power("frozen"));
    assert!(frozen > off, "frozen {frozen} W, still air {off} W");
}

/// `envelope --vary angle-of-attack` trims every point on the angle of attack: the stroke
/// amplitude stays the file's 116 deg, and the power at 4.5 m/s is within 15% of hover's
/// (crates/flapsim/tests/forward_flight.rs: Dudley & Ellington 1990a/b).
#[test]
fn envelope_takes_the_trims_lift_variable() {
    let r = flapwing(&[
        "envelope",
        "--model",
        "bumblebee",
        "--speeds-m-s",
        "0,4.5",
        "--vary",
        "angle-of-attack",
        "--json",
    ]);
    assert_eq!(r.code, 0, "{r:?}");
    let j = r.json();
    let point = |i: usize| &j[i]["point"]["point"];
    for i in 0..2 {
        let a = point(i)["stroke_amplitude_rad"]
            .as_f64()
            .unwrap()
            .to_degrees();
        assert!((a - 116.0).abs() < 1e-9, "{a} deg");
    }
    let power = |i: usize| point(i)["power"]["aero_w"].as_f64().unwrap();
    let ratio = power(1) / power(0);
    assert!((ratio - 1.0).abs() < 0.15, "{ratio}");
}
