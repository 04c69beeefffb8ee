//! Sensors on the CLI, end to end through the real binary: `simulate` and `hover` sample the
//! model's `[sensors]` (models/drosophila.toml) and log every delivered reading to
//! `/sensors/imu` and `/sensors/mocap`, which `replay --csv` exports.
//!
//! The statistics follow flapsim::sensors' noise model (IEEE Std 952, Kalibr's discrete
//! form): a reading is truth + bias + white noise of standard deviation
//! sigma = density x sqrt(rate) per sample, and the bias walks by b sqrt(dt) per sample.
//! The mean of N independent samples has standard deviation sigma / sqrt(N); a random walk's
//! mean over [0, T] strays by b sqrt(T / 3) (one sigma); the sample standard deviation of N
//! normal samples has relative standard deviation 1 / sqrt(2 (N - 1)). Tolerances are five of
//! those sigmas.

use crate::common;

use std::collections::HashMap;
use std::path::Path;

use common::flapwing_in;

/// models/drosophila.toml's [sensors.imu] and [sensors.mocap], in SI units.
const RATE_HZ: f64 = 1000.0;
const LATENCY_S: f64 = 5.0e-3;
const GYRO_DENSITY: f64 = 0.004 * std::f64::consts::PI / 180.0; // rad/s/sqrt(Hz)
const GYRO_WALK: f64 = 0.0012 * std::f64::consts::PI / 180.0; // rad/s/sqrt(s)
const ACCEL_DENSITY: f64 = 100.0e-6 * 9.80665; // m/s^2/sqrt(Hz)
const ACCEL_WALK: f64 = 0.0163e-3 * 9.80665; // m/s^2/sqrt(s)
const MOCAP_RATE_HZ: f64 = 200.0;
const MOCAP_LATENCY_S: f64 = 6.5e-3;
const POSITION_NOISE_M: f64 = 1.5e-4;
/// The model's gravity and initial pitch.
const G: f64 = 9.81;
const PITCH_RAD: f64 = std::f64::consts::FRAC_PI_4;

/// A CSV written by `replay --csv`, as columns of numbers by name.
fn read_csv(path: &Path) -> HashMap<String, Vec<f64>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let names: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let mut cols: HashMap<String, Vec<f64>> = names.iter().map(|n| (n.clone(), vec![])).collect();
    for line in lines {
        for (n, cell) in names.iter().zip(line.split(',')) {
            if let Ok(x) = cell.parse::<f64>() {
                cols.get_mut(n).unwrap().push(x);
            }
        }
    }
    cols
}

fn mean(x: &[f64]) -> f64 {
    x.iter().sum::<f64>() / x.len() as f64
}

fn std(x: &[f64]) -> f64 {
    let m = mean(x);
    (x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (x.len() as f64 - 1.0)).sqrt()
}

fn export(dir: &Path, log: &str, topic: &str, out: &str) -> HashMap<String, Vec<f64>> {
    let r = flapwing_in(dir, &["replay", log, "--csv", topic, out]);
    assert_eq!(r.code, 0, "{r:?}");
    read_csv(&dir.join(out))
}

/// Samples taken at k / rate and delivered `latency` later, up to the last step's time.
fn delivered(last_step_s: f64, rate_hz: f64, latency_s: f64) -> usize {
    ((last_step_s - latency_s) * rate_hz + 1e-6).floor() as usize + 1
}

#[test]
fn tethered_simulate_logs_imu_readings_with_the_model_noise_bias_and_gravity() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let duration_s = 0.2;
    let r = flapwing_in(
        d,
        &[
            "simulate",
            "--tethered",
            "--duration-s",
            "0.2",
            "--sensor-seed",
            "7",
            "--mcap",
            "run.mcap",
            "--json",
        ],
    );
    assert_eq!(r.code, 0, "{r:?}");
    let j = r.json();
    let s = &j["sensors"];
    assert_eq!(s["seed"], 7);
    let last_step_s = (j["summary"]["steps"].as_f64().unwrap() - 1.0) * j["dt_s"].as_f64().unwrap();
    let n = delivered(last_step_s, RATE_HZ, LATENCY_S);
    assert_eq!(s["imu_samples"].as_u64().unwrap() as usize, n);
    let imu = export(d, "run.mcap", "/sensors/imu", "imu.csv");
    assert_eq!(imu["gyro_rad_s.x"].len(), n);

    // Timing: sample k at k / rate, delivered a latency later.
    for (k, (ts, td)) in imu["t_sample_s"]
        .iter()
        .zip(&imu["t_delivered_s"])
        .enumerate()
    {
        assert!(
            (ts - k as f64 / RATE_HZ).abs() < 1e-12,
            "sample {k} at {ts}"
        );
        assert!((td - ts - LATENCY_S).abs() < 1e-12);
    }

    // Tethered: the body does not turn, and the tether holds the weight, so the
    // accelerometer reads the reaction R^T (0, 0, g) = (g sin(pitch), 0, g cos(pitch)).
    let truth_f = [G * PITCH_RAD.sin(), 0.0, G * PITCH_RAD.cos()];
    let gyro_bias = &s["gyro_turn_on_bias_rad_s"];
    let accel_bias = &s["accel_turn_on_bias_m_s2"];
    let sigma_g = GYRO_DENSITY * RATE_HZ.sqrt();
    let sigma_a = ACCEL_DENSITY * RATE_HZ.sqrt();
    assert!((s["gyro_noise_std_rad_s"].as_f64().unwrap() - sigma_g).abs() < 1e-12 * sigma_g);
    assert!((s["accel_noise_std_m_s2"].as_f64().unwrap() - sigma_a).abs() < 1e-12 * sigma_a);
    let nf = n as f64;
    let walk = |b: f64| 5.0 * b * (duration_s / 3.0_f64).sqrt();
    for (i, axis) in ["x", "y", "z"].into_iter().enumerate() {
        let g = &imu[&format!("gyro_rad_s.{axis}")];
        let a = &imu[&format!("accel_m_s2.{axis}")];
        // Mean = true rate (0) + bias, within the noise of the mean and the bias walk.
        let bg = gyro_bias[i].as_f64().unwrap();
        let tol_g = 5.0 * sigma_g / nf.sqrt() + walk(GYRO_WALK);
        assert!(
            (mean(g) - bg).abs() < tol_g,
            "gyro {axis}: mean {} vs bias {bg} (tolerance {tol_g})",
            mean(g)
        );
        let ba = accel_bias[i].as_f64().unwrap();
        let tol_a = 5.0 * sigma_a / nf.sqrt() + walk(ACCEL_WALK);
        assert!(
            (mean(a) - truth_f[i] - ba).abs() < tol_a,
            "accel {axis}: mean {} vs {} + {ba} (tolerance {tol_a})",
            mean(a),
            truth_f[i]
        );
        // Per-sample scatter = density x sqrt(rate).
        let rel = 5.0 / (2.0 * (nf - 1.0)).sqrt();
        assert!(
            (std(g) / sigma_g - 1.0).abs() < rel,
            "gyro {axis} std {}",
            std(g)
        );
        assert!(
            (std(a) / sigma_a - 1.0).abs() < rel,
            "accel {axis} std {}",
            std(a)
        );
        // The logged truth.
        for (w, f) in imu[&format!("true_angular_velocity_rad_s.{axis}")]
            .iter()
            .zip(&imu[&format!("true_specific_force_m_s2.{axis}")])
        {
            assert_eq!(*w, 0.0);
            assert!((f - truth_f[i]).abs() < 1e-12 * G, "{f} vs {}", truth_f[i]);
        }
        // The first sample carries the turn-on bias itself (to serde_json's parsing, which
        // is not always correctly rounded: 1e-15).
        let same = |a: f64, b: f64| (a - b).abs() <= 1e-15 * b.abs();
        assert!(same(imu[&format!("gyro_bias_rad_s.{axis}")][0], bg));
        assert!(same(imu[&format!("accel_bias_m_s2.{axis}")][0], ba));
    }

    // Motion capture: frames at 200 Hz, 6.5 ms late, about the held position.
    let nm = delivered(last_step_s, MOCAP_RATE_HZ, MOCAP_LATENCY_S);
    assert_eq!(s["mocap_frames"].as_u64().unwrap() as usize, nm);
    let mocap = export(d, "run.mcap", "/sensors/mocap", "mocap.csv");
    assert_eq!(mocap["position_m.x"].len(), nm);
    for axis in ["x", "y", "z"] {
        let p = &mocap[&format!("position_m.{axis}")];
        let tol = 5.0 * POSITION_NOISE_M / (nm as f64).sqrt();
        assert!(mean(p).abs() < tol, "mocap {axis}: mean {}", mean(p));
    }
    let pitch = mean(&mocap["euler_deg.pitch"]);
    assert!(
        (pitch - 45.0).abs() < 5.0 * 3.4 / (nm as f64).sqrt(),
        "{pitch}"
    );
}

#[test]
fn the_sensor_seed_makes_readings_reproducible() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (log, seed) in [("a.mcap", "11"), ("b.mcap", "11"), ("c.mcap", "12")] {
        let r = flapwing_in(
            d,
            &[
                "simulate",
                "--tethered",
                "--duration-s",
                "0.02",
                "--sensor-seed",
                seed,
                "--mcap",
                log,
            ],
        );
        assert_eq!(r.code, 0, "{r:?}");
        assert!(
            r.stdout.contains(&format!("sensors (seed {seed}):")),
            "{}",
            r.stdout
        );
    }
    let csv = |log: &str| {
        let out = format!("{log}.csv");
        assert_eq!(
            flapwing_in(d, &["replay", log, "--csv", "/sensors/imu", &out]).code,
            0
        );
        std::fs::read_to_string(d.join(out)).unwrap()
    };
    let (a, b, c) = (csv("a.mcap"), csv("b.mcap"), csv("c.mcap"));
    assert_eq!(a, b, "the same seed gives the same readings");
    assert_ne!(a, c, "another seed gives other readings");
}

#[test]
fn hover_logs_sensor_readings_whose_residuals_are_the_white_noise() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let r = flapwing_in(
        d,
        &[
            "hover",
            "--duration-s",
            "0.1",
            "--sensor-seed",
            "3",
            "--mcap",
            "hover.mcap",
            "--json",
        ],
    );
    assert_eq!(r.code, 0, "{r:?}");
    let j = r.json();
    assert_eq!(j["sensors"]["seed"], 3);
    let imu = export(d, "hover.mcap", "/sensors/imu", "imu.csv");
    let n = imu["gyro_rad_s.x"].len();
    assert_eq!(j["sensors"]["imu_samples"].as_u64().unwrap() as usize, n);
    assert!(n > 90, "{n} samples in 0.1 s at 1 kHz");
    let sigma_g = GYRO_DENSITY * RATE_HZ.sqrt();
    let sigma_a = ACCEL_DENSITY * RATE_HZ.sqrt();
    let nf = n as f64;
    let mut turning = 0.0_f64;
    for axis in ["x", "y", "z"] {
        let col = |k: &str| &imu[&format!("{k}.{axis}")];
        // Reading - truth - bias is the white noise alone: zero mean, density x sqrt(rate).
        let res = |read: &str, truth: &str, bias: &str| -> Vec<f64> {
            (0..n)
                .map(|k| col(read)[k] - col(truth)[k] - col(bias)[k])
                .collect()
        };
        let rg = res(
            "gyro_rad_s",
            "true_angular_velocity_rad_s",
            "gyro_bias_rad_s",
        );
        let ra = res("accel_m_s2", "true_specific_force_m_s2", "accel_bias_m_s2");
        assert!(mean(&rg).abs() < 5.0 * sigma_g / nf.sqrt(), "gyro {axis}");
        assert!(mean(&ra).abs() < 5.0 * sigma_a / nf.sqrt(), "accel {axis}");
        let rel = 5.0 / (2.0 * (nf - 1.0)).sqrt();
        assert!(
            (std(&rg) / sigma_g - 1.0).abs() < rel,
            "gyro {axis}: {}",
            std(&rg)
        );
        assert!(
            (std(&ra) / sigma_a - 1.0).abs() < rel,
            "accel {axis}: {}",
            std(&ra)
        );
        turning = turning.max(
            col("true_angular_velocity_rad_s")
                .iter()
                .fold(0.0, |m, w| m.max(w.abs())),
        );
    }
    // Free flight from a 5 deg pitch error: the body turns, so the truth is not all zero.
    assert!(
        turning > 10.0 * sigma_g,
        "largest true rate {turning} rad/s"
    );
    // Over whole wingbeats the wings carry the weight and the body barely accelerates, so
    // the mean specific force is +g along the body's mean "up" (attitude errors of a few
    // degrees change its magnitude by under 1%): |mean f| = g within 5%.
    let f: Vec<f64> = ["x", "y", "z"]
        .iter()
        .map(|a| mean(&imu[&format!("true_specific_force_m_s2.{a}")]))
        .collect();
    let norm = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
    assert!((norm / G - 1.0).abs() < 0.05, "|mean f| = {norm}");
}

#[test]
fn sensor_flags_without_sensors_are_refused_or_skipped() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A model without a [sensors] table (every built-in vehicle has one; this is
    // models/drosophila.toml without it): asking for a seed is bad input naming it.
    let fly = include_str!("../../../models/drosophila.toml");
    let (head, tail) = fly.split_at(fly.find("# Sensors (flapsim::sensors)").unwrap());
    let bare = format!("{head}{}", &tail[tail.find("[sim]").unwrap()..])
        .replace("name = \"drosophila\"", "name = \"no_sensors\"");
    assert!(!bare.contains("[sensors"));
    std::fs::write(d.join("no_sensors.toml"), bare).unwrap();
    let r = flapwing_in(
        d,
        &[
            "simulate",
            "--model",
            "no_sensors.toml",
            "--duration-s",
            "0.001",
            "--sensor-seed",
            "1",
            "--no-log",
        ],
    );
    r.assert_bad_input();
    assert!(
        r.stderr.contains("--sensor-seed")
            && r.stderr.contains("no_sensors")
            && r.stderr.contains("[sensors]"),
        "{}",
        r.stderr
    );
    // Without the flag it simply has none; --no-sensors leaves the drosophila's out.
    for args in [
        &[
            "simulate",
            "--model",
            "no_sensors.toml",
            "--duration-s",
            "0.001",
            "--mcap",
            "b.mcap",
            "--json",
        ][..],
        &[
            "simulate",
            "--no-sensors",
            "--duration-s",
            "0.001",
            "--mcap",
            "d.mcap",
            "--json",
        ][..],
    ] {
        let r = flapwing_in(d, args);
        assert_eq!(r.code, 0, "{r:?}");
        assert!(r.json()["sensors"].is_null());
        let log = args[args.len() - 2];
        let x = flapwing_in(
            d,
            &["replay", log, "--csv", "/sensors/imu", "x.csv", "--force"],
        );
        assert_eq!(x.code, 2, "{x:?}");
        assert!(x.stderr.contains("/sensors/imu"), "{}", x.stderr);
    }
}
