//! `flapwing hover --feedback estimated` through the real binary: the LQR flies on the
//! estimate of flapsim's error-state Kalman filter (the filter's own checks are in
//! crates/flapsim/tests/estimator.rs); bad combinations are refused with exit 2 and a message
//! naming what is missing.

use crate::common;

use common::flapwing_in;

#[test]
fn hover_on_the_estimate_reports_the_filter() {
    let dir = tempfile::tempdir().unwrap();
    let r = flapwing_in(
        dir.path(),
        &[
            "hover",
            "--feedback",
            "estimated",
            "--duration-s",
            "0.3",
            "--mcap",
            "e.mcap",
            "--json",
        ],
    );
    assert_eq!(r.code, 0, "{r:?}");
    let j = r.json();
    assert_eq!(j["feedback"], "estimated");
    // With the model's 5 and 6.5 ms latencies the controller predicts the filter's late
    // state forward (crates/flapsim/tests/estimator.rs): the run holds to its end (before
    // that prediction it diverged within 32 ms), and the filter has fused every 200 Hz frame
    // delivered (6.5 ms late).
    assert!(j["outcome"]["diverged"].is_null(), "{}", j["outcome"]);
    let e = &j["estimator"];
    let t_end = j["outcome"]["duration_s"].as_f64().unwrap();
    assert!((t_end - 0.3).abs() < 1e-3, "{}", j["outcome"]);
    let frames = e["mocap_frames"].as_u64().unwrap() as f64;
    let expected = ((t_end - 6.5e-3) / 5e-3).floor() + 1.0;
    assert!((frames - expected).abs() <= 1.0, "{e} after {t_end} s");
    assert_eq!(e["mocap_dropped"], 0);
    assert_eq!(j["sensors"]["mocap_frames"].as_f64().unwrap(), frames);
    // The readings the filter used are the ones logged.
    assert!(dir.path().join("e.mcap").exists());
    let t = flapwing_in(
        dir.path(),
        &["hover", "--no-log", "--json", "--duration-s", "0.01"],
    );
    assert_eq!(t.code, 0, "{t:?}");
    assert_eq!(t.json()["feedback"], "true");
    assert!(t.json()["estimator"].is_null());
}

#[test]
fn estimated_feedback_without_what_it_needs_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let fly = include_str!("../../../models/drosophila.toml");
    let (head, tail) = fly.split_at(fly.find("# Sensors (flapsim::sensors)").unwrap());
    let bare = format!("{head}{}", &tail[tail.find("[sim]").unwrap()..])
        .replace("name = \"drosophila\"", "name = \"no_sensors\"");
    assert!(!bare.contains("[sensors"));
    std::fs::write(d.join("no_sensors.toml"), bare).unwrap();
    let (head, tail) = fly.split_at(fly.find("[sensors.mocap]").unwrap());
    let no_mocap = format!("{head}{}", &tail[tail.find("[sim]").unwrap()..]);
    assert!(!no_mocap.contains("[sensors.mocap]") && no_mocap.contains("[sensors.imu]"));
    std::fs::write(d.join("no_mocap.toml"), no_mocap).unwrap();
    let cases: [(&[&str], &[&str]); 4] = [
        (
            &["--model", "no_sensors.toml"],
            &["--feedback estimated", "no_sensors", "[sensors]"],
        ),
        (&["--model", "no_mocap.toml"], &["[sensors.mocap]"]),
        (&["--open-loop"], &["--open-loop"]),
        (&["--no-sensors"], &["--no-sensors"]),
    ];
    for (extra, needles) in cases {
        let mut args = vec!["hover", "--feedback", "estimated", "--no-log"];
        args.extend_from_slice(extra);
        let r = flapwing_in(d, &args);
        r.assert_bad_input();
        for n in needles {
            assert!(r.stderr.contains(n), "{args:?}: {}", r.stderr);
        }
    }
    let r = flapwing_in(d, &["hover", "--feedback", "kalman", "--no-log"]);
    assert_eq!(r.code, 2, "{r:?}");
    assert!(r.stderr.contains("estimated"), "{}", r.stderr);
}
