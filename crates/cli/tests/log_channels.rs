//! The optional log channels through the real binary: `/wind` in runs with a wind field
//! (each wing's wind as flapsim's simulation gives it, the same for the same seed, absent in
//! still air) and `/estimate` in `hover --feedback estimated` (the filter's estimate beside
//! the truth of `/vehicle/state`).

use crate::common;

use std::collections::HashMap;
use std::path::Path;

use common::flapwing_in;
use flapsim::{Mode, Simulation, Vehicle, Wind};
use flightlog::Decimator;
use flightlog::replay::{read_summary, read_table};

/// The messages of `topic` as rows of numbers by column name.
fn rows(path: &Path, topic: &str) -> Vec<HashMap<String, f64>> {
    let t = read_table(path, topic).unwrap();
    t.rows
        .iter()
        .map(|r| {
            t.columns
                .iter()
                .zip(r)
                .filter_map(|(c, v)| Some((c.clone(), v.as_deref()?.parse().ok()?)))
                .collect()
        })
        .collect()
}

fn topics(path: &Path) -> Vec<String> {
    let s = read_summary(path).unwrap();
    s.channels.into_iter().map(|c| c.topic).collect()
}

/// drosophila in Dryden turbulence of seed `seed`.
fn windy_model(seed: u64) -> String {
    format!(
        "{}\n[wind]\nmin_convection_speed_m_s = 0.5\n[wind.turbulence]\nintensity_m_s = [0.3, 0.3, 0.2]\nlength_scale_m = [0.05, 0.05, 0.05]\nseed = {seed}\n",
        include_str!("../../../models/drosophila.toml")
    )
}

#[test]
fn simulate_logs_the_wing_winds_of_the_simulation() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("windy.toml"), windy_model(4)).unwrap();
    let duration_s = 0.01;
    let sim = |log: &str, extra: &[&str]| {
        let mut args = vec![
            "simulate",
            "--duration-s",
            "0.01",
            "--no-sensors",
            "--mcap",
            log,
        ];
        args.extend_from_slice(extra);
        let r = flapwing_in(d, &args);
        assert_eq!(r.code, 0, "{r:?}");
        d.join(log)
    };
    let a = sim("a.mcap", &["--model", "windy.toml"]);
    assert!(topics(&a).iter().any(|t| t == "/wind"));
    let logged = rows(&a, "/wind");

    // The same run in flapsim: the model's [wind] from the start position, free flight.
    let text = windy_model(4);
    let vehicle = Vehicle::from_toml(&text, "windy.toml").unwrap();
    let wind = Wind::from_spec(
        vehicle.wind.as_ref().unwrap(),
        "windy.toml",
        vehicle.initial_position_m,
    )
    .unwrap();
    let mut s = Simulation::new(vehicle, Mode::Free);
    s.set_wind_model(Some(wind));
    let n = (duration_s / s.dt_s()).round() as u64;
    let mut decimator = Decimator::new(Some(2000.0));
    let mut expected = Vec::new();
    for _ in 0..n {
        let t = s.step().unwrap().t_s;
        if decimator.take(t) {
            expected.push(((t * 1e9).round(), s.wing_winds_m_s().to_vec()));
        }
    }
    assert_eq!(logged.len(), expected.len());
    assert!(logged.len() > 10);
    for (row, (t_ns, winds)) in logged.iter().zip(&expected) {
        assert_eq!(row["log_time_ns"], *t_ns);
        assert_eq!(winds.len(), 2);
        for (i, w) in winds.iter().enumerate() {
            for (k, x) in ["x", "y", "z"].iter().zip(w.iter()) {
                let got = row[&format!("wing_winds_world_m_s.{i}.{k}")];
                assert_eq!(got.to_bits(), x.to_bits(), "wing {i} {k} at {t_ns} ns");
            }
        }
        // simulate flies no uniform wind besides the field.
        assert_eq!(row["uniform_world_m_s.x"], 0.0);
    }
    assert!(expected.iter().any(|(_, w)| w[0].norm() > 0.01));
    // `replay --check` re-runs the log and compares the winds too.
    let c = flapwing_in(d, &["replay", "a.mcap", "--check"]);
    assert_eq!(c.code, 0, "{c:?}");

    // Deterministic per seed (here the flags' seed), another seed another wind, still air
    // no /wind at all.
    let flags = |seed: &'static str| -> Vec<&'static str> {
        vec![
            "--turbulence-intensity-m-s",
            "0.3",
            "--turbulence-length-scale-m",
            "0.05",
            "--wind-seed",
            seed,
        ]
    };
    let b = rows(&sim("b.mcap", &flags("7")), "/wind");
    let b2 = rows(&sim("b2.mcap", &flags("7")), "/wind");
    let c = rows(&sim("c.mcap", &flags("8")), "/wind");
    assert_eq!(b, b2);
    assert_ne!(b, c);
    assert_eq!(b.len(), logged.len());
    let still = sim("still.mcap", &[]);
    assert!(!topics(&still).iter().any(|t| t == "/wind"));
}

#[test]
fn hover_on_the_estimate_logs_it_beside_the_truth() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A push of 0.2 m/s: the body travels about 6 mm in the run, so an estimate that does
    // not follow it is far from the truth. (The LQR on the estimate diverges soon after,
    // a known limitation, see estimated_feedback.rs.)
    let r = flapwing_in(
        d,
        &[
            "hover",
            "--feedback",
            "estimated",
            "--duration-s",
            "0.03",
            "--disturbance",
            "vx_m_s=0.2,pitch_deg=0",
            "--mcap",
            "e.mcap",
            "--rrd",
            "e.rrd",
            "--json",
        ],
    );
    assert_eq!(r.code, 0, "{r:?}");
    let log = d.join("e.mcap");
    let t = topics(&log);
    assert!(t.iter().any(|t| t == "/estimate"), "{t:?}");
    assert!(!t.iter().any(|t| t == "/wind"), "still air: {t:?}");
    let est = rows(&log, "/estimate");
    let truth = rows(&log, "/vehicle/state");
    assert_eq!(est.len(), truth.len());
    assert!(est.len() > 50);
    let dist = |a: &HashMap<String, f64>, pa: &str, b: &HashMap<String, f64>, pb: &str| {
        ["x", "y", "z"]
            .iter()
            .map(|k| (a[&format!("{pa}.{k}")] - b[&format!("{pb}.{k}")]).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    let mut checked = 0;
    for (e, s) in est.iter().zip(&truth) {
        assert_eq!(e["log_time_ns"], s["log_time_ns"]);
        // Once three motion-capture frames are in: the controller's view (the estimate
        // predicted to the log time) within 1 mm of the truth, the filter's own state (an
        // IMU latency, 5 ms, behind: 1 mm at 0.2 m/s) within 2 mm.
        if e.get("mocap_frames").copied().unwrap_or(0.0) >= 3.0 {
            let fb = dist(e, "feedback.position_world_m", s, "position_m");
            let nominal = dist(e, "position_world_m", s, "position_m");
            assert!(fb < 1e-3, "feedback {fb} m off at {} ns", e["log_time_ns"]);
            assert!(nominal < 2e-3, "estimate {nominal} m off");
            // Its own uncertainty says so: a position standard deviation below 1 mm.
            assert!(e["std.position_world_m.x"] > 0.0 && e["std.position_world_m.x"] < 1e-3);
            checked += 1;
        }
        assert!(e.contains_key("covariance.224") && !e.contains_key("covariance.225"));
    }
    assert!(checked > 10, "{checked} samples after the filter converged");
    let moved = dist(
        &truth[truth.len() - 1],
        "position_m",
        &truth[0],
        "position_m",
    );
    assert!(moved > 4e-3, "the body moved only {moved} m");
    assert!(d.join("e.rrd").exists());
}

#[test]
fn hover_logs_the_wind_it_flies_in() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let hover = |log: &str, extra: &[&str]| {
        let mut args = vec![
            "hover",
            "--duration-s",
            "0.01",
            "--no-sensors",
            "--mcap",
            log,
            "--rrd",
            "h.rrd",
            "--force",
        ];
        args.extend_from_slice(extra);
        let r = flapwing_in(d, &args);
        assert_eq!(r.code, 0, "{r:?}");
        d.join(log)
    };
    // Turbulence: a wind per wing, no uniform part.
    let t = rows(
        &hover("t.mcap", &["--turbulence-intensity-m-s", "0.3"]),
        "/wind",
    );
    assert!(t.len() > 10);
    assert!(t.iter().any(|r| r["wing_winds_world_m_s.0.x"] != 0.0));
    assert!(t.iter().all(|r| r["uniform_world_m_s.z"] == 0.0));
    // The disturbance's gust alone: the uniform wind at both wings while it blows.
    let g = rows(
        &hover(
            "g.mcap",
            &[
                "--disturbance",
                "gust_z_m_s=0.4,gust_start_s=0.004,gust_duration_s=0.004",
            ],
        ),
        "/wind",
    );
    assert_eq!(g.len(), t.len());
    let mut blowing = 0;
    for r in &g {
        let w = r["uniform_world_m_s.z"];
        assert!(w == 0.0 || w == 0.4, "{w}");
        assert_eq!(r["wing_winds_world_m_s.0.z"], w);
        assert_eq!(r["wing_winds_world_m_s.1.z"], w);
        blowing += usize::from(w == 0.4);
    }
    assert!(
        blowing > 3 && blowing < g.len() - 3,
        "{blowing} of {}",
        g.len()
    );
    // Still air: no /wind.
    assert!(!topics(&hover("s.mcap", &[])).iter().any(|t| t == "/wind"));
}

/// A vehicle whose wake answers (`[aero] inflow = "dynamic"`) logs its pair's inflow states
/// to `/inflow`, each logged step's as flapsim's simulation takes its loads at them, and
/// `replay --check` re-runs the log bit for bit; a frozen wake logs no `/inflow`; an actuated
/// vehicle's dynamic wake is logged and re-run alike.
#[test]
fn simulate_logs_the_dynamic_inflow() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let text = include_str!("../../../models/drosophila.toml")
        .replace("inflow = \"frozen\"", "inflow = \"dynamic\"");
    assert!(text.contains("inflow = \"dynamic\""));
    std::fs::write(d.join("fly.toml"), &text).unwrap();
    let run = |model: &str, log: &str| {
        let r = flapwing_in(
            d,
            &[
                "simulate",
                "--model",
                model,
                "--duration-s",
                "0.01",
                "--no-sensors",
                "--mcap",
                log,
            ],
        );
        assert_eq!(r.code, 0, "{r:?}");
        assert!(
            r.stdout.contains("induced flow: dynamic") || model != "fly.toml",
            "{r:?}"
        );
        d.join(log)
    };
    let a = run("fly.toml", "a.mcap");
    assert!(topics(&a).iter().any(|t| t == "/inflow"));
    let logged = rows(&a, "/inflow");

    let vehicle = Vehicle::from_toml(&text, "fly.toml").unwrap();
    let mut s = Simulation::new(vehicle, Mode::Free);
    let n = (0.01 / s.dt_s()).round() as u64;
    let mut decimator = Decimator::new(Some(2000.0));
    let mut expected = Vec::new();
    for _ in 0..n {
        let t = s.step().unwrap().t_s;
        if decimator.take(t) {
            expected.push(((t * 1e9).round(), s.wing_set().output().inflow[0]));
        }
    }
    assert_eq!(logged.len(), expected.len());
    assert!(logged.len() > 10);
    for (row, (t_ns, state)) in logged.iter().zip(&expected) {
        assert_eq!(row["log_time_ns"], *t_ns);
        let [w0, fore, left] = state.to_array();
        assert_eq!(row["pairs.0.mean_m_s"].to_bits(), w0.to_bits());
        assert_eq!(row["pairs.0.fore_m_s"].to_bits(), fore.to_bits());
        assert_eq!(row["pairs.0.left_m_s"].to_bits(), left.to_bits());
    }
    // The inflow answers the wingbeat: it is not held.
    let means: Vec<f64> = logged.iter().map(|r| r["pairs.0.mean_m_s"]).collect();
    assert!(means.iter().any(|&m| m != means[0]));
    let c = flapwing_in(d, &["replay", "a.mcap", "--check"]);
    assert_eq!(c.code, 0, "{c:?}");
    let frozen = run("drosophila", "frozen.mcap");
    assert!(!topics(&frozen).iter().any(|t| t == "/inflow"));
    // Actuated wings too (their disc the stroke they sweep): logged, and re-run bit for bit.
    let bee = format!(
        "{}\n[aero]\ninflow = \"dynamic\"\n",
        include_str!("../../../models/robobee.toml")
    );
    std::fs::write(d.join("bee.toml"), &bee).unwrap();
    let b = run("bee.toml", "bee.mcap");
    let means: Vec<f64> = rows(&b, "/inflow")
        .iter()
        .map(|r| r["pairs.0.mean_m_s"])
        .collect();
    assert!(means.len() > 10 && means.iter().any(|&m| m != means[0]));
    let c = flapwing_in(d, &["replay", "bee.mcap", "--check"]);
    assert_eq!(c.code, 0, "{c:?}");
}
