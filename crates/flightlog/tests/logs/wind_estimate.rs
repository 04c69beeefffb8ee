//! The optional `/wind` and `/estimate` channels: a drosophila flight in Dryden turbulence
//! with the state estimator running on its sensors, recorded with [`Recorder::wind`] and
//! [`Recorder::estimate`], read back value for value; the re-run check compares the winds.

use crate::common;

use std::collections::HashMap;
use std::path::Path;

use common::ORIGIN;
use flapsim::estimator::{EstimatedFeedback, N_ERR, Prior};
use flapsim::{Mode, Simulation, Vehicle, Wind};
use flightlog::check::{CheckOutcome, check_log};
use flightlog::replay::{read_summary, read_table};
use flightlog::schema::{self, TOPIC_ESTIMATE, TOPIC_WIND};
use flightlog::{Decimator, LogOptions, Recorder, RunInfo, SimSettings};
use nalgebra::Vector3;

/// Drosophila in Dryden turbulence (seed `seed`).
fn windy_toml(seed: u64) -> String {
    format!(
        "{}\n[wind]\nmin_convection_speed_m_s = 0.5\n[wind.turbulence]\nintensity_m_s = [0.3, 0.3, 0.2]\nlength_scale_m = [0.05, 0.05, 0.05]\nseed = {seed}\n",
        flapsim::DROSOPHILA_TOML
    )
}

/// One logged sample's expected values.
struct Expected {
    t_ns: u64,
    uniform: Vector3<f64>,
    winds: Vec<Vector3<f64>>,
    /// The filter's time, nominal position and attitude, covariance (row-major), and the
    /// position the controller reads at the sample time.
    t_filter: f64,
    position: Vector3<f64>,
    attitude: [f64; 4],
    covariance: Vec<f64>,
    feedback_position: Vector3<f64>,
}

/// Records `duration_s` of free flight of `toml` as `flapwing simulate` flies a model's
/// `[wind]`, with the estimator fed by the model's sensors; `tamper` changes the winds
/// handed to the recorder. Returns the expected values of each logged sample.
fn record(
    path: &Path,
    toml: &str,
    duration_s: f64,
    opts: LogOptions,
    tamper: impl Fn(&mut Vec<Vector3<f64>>),
) -> Vec<Expected> {
    let vehicle = Vehicle::from_toml(toml, ORIGIN).unwrap();
    let rate = Some(2000.0);
    let settings = SimSettings::new(Mode::Free, duration_s, rate, [0.0; 3]);
    let info = RunInfo::new("simulate", "test", toml, ORIGIN, settings.to_json());
    let opts = LogOptions {
        mcap: Some(path.to_owned()),
        log_rate_hz: rate,
        ..opts
    };
    let mut rec = Recorder::create(&opts, &info, &vehicle).unwrap();
    let wind = Wind::from_spec(
        vehicle.wind.as_ref().unwrap(),
        ORIGIN,
        vehicle.initial_position_m,
    )
    .unwrap();
    let prior = Prior::hover(&vehicle, vehicle.initial_attitude);
    let mut fb = EstimatedFeedback::new(&vehicle, 3, &prior).unwrap();
    let mut sim = Simulation::new(vehicle, Mode::Free);
    sim.set_wind_model(Some(wind));
    let n = (duration_s / sim.dt_s()).round() as u64;
    let mut decimator = Decimator::new(rate);
    let mut expected = Vec::new();
    for _ in 0..n {
        fb.observe(sim.time_s(), &sim.state());
        let out = *sim.step().unwrap();
        rec.record(&out).unwrap();
        let uniform = sim.uniform_wind_m_s();
        let mut winds = sim.wing_winds_m_s().to_vec();
        assert_eq!(winds.len(), 2);
        tamper(&mut winds);
        rec.wind(out.t_s, &uniform, &winds).unwrap();
        if opts.estimate {
            rec.estimate(out.t_s, fb.filter()).unwrap();
        }
        if decimator.take(out.t_s) {
            let (t, x, p) = fb.filter().latest();
            let q = x.world_from_body;
            expected.push(Expected {
                t_ns: (out.t_s * 1e9).round() as u64,
                uniform,
                winds,
                t_filter: t.unwrap_or(0.0),
                position: x.position_world_m,
                attitude: [q.i, q.j, q.k, q.w],
                covariance: p.transpose().iter().copied().collect(),
                feedback_position: fb.filter().state_at(out.t_s).position_m,
            });
        }
    }
    rec.finish().unwrap();
    expected
}

/// The messages of `topic` as rows of numbers by column name.
fn rows(path: &Path, topic: &str) -> Vec<HashMap<String, f64>> {
    let t = read_table(path, topic).unwrap();
    assert_eq!(t.skipped, 0);
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

/// Bit for bit, but for the sign of a zero (proto3 leaves zeros off the wire).
fn same(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a == 0.0 && b == 0.0)
}

fn assert_vec(row: &HashMap<String, f64>, name: &str, v: &Vector3<f64>) {
    for (k, e) in ["x", "y", "z"].iter().zip(v.iter()) {
        let got = row[&format!("{name}.{k}")];
        assert!(same(got, *e), "{name}.{k}: {got} vs {e}");
    }
}

#[test]
fn wind_and_estimate_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("windy.mcap");
    let opts = LogOptions {
        wind: true,
        estimate: true,
        ..LogOptions::default()
    };
    let exp = record(&path, &windy_toml(5), 0.02, opts, |_| {});
    assert!(exp.len() > 30);

    let s = read_summary(&path).unwrap();
    assert!(s.complete, "{:?}", s.damage);
    let topics: Vec<&str> = s.channels.iter().map(|c| c.topic.as_str()).collect();
    let mut want: Vec<&str> = schema::CHANNELS.iter().map(|c| c.0).collect();
    want.extend([TOPIC_WIND, TOPIC_ESTIMATE]);
    assert_eq!(topics, want);
    for (topic, name) in [schema::WIND_CHANNEL, schema::ESTIMATE_CHANNEL] {
        let c = s.channels.iter().find(|c| c.topic == topic).unwrap();
        assert_eq!(c.schema_name, name);
        assert_eq!(c.message_count, exp.len() as u64, "{topic}");
    }

    let wind = rows(&path, TOPIC_WIND);
    assert_eq!(wind.len(), exp.len());
    for (row, e) in wind.iter().zip(&exp) {
        assert_eq!(row["log_time_ns"] as u64, e.t_ns);
        assert_vec(row, "uniform_world_m_s", &e.uniform);
        for (i, w) in e.winds.iter().enumerate() {
            assert_vec(row, &format!("wing_winds_world_m_s.{i}"), w);
        }
        assert!(!row.contains_key("wing_winds_world_m_s.2.x"));
    }
    // Turbulence: the two wings feel different winds, which change with time.
    let w10 = &exp[10].winds;
    assert!(w10[0] != w10[1] && exp[0].winds[0] != w10[0]);

    let est = rows(&path, TOPIC_ESTIMATE);
    assert_eq!(est.len(), exp.len());
    let mut fused = false;
    for (row, e) in est.iter().zip(&exp) {
        assert_eq!(row["log_time_ns"] as u64, e.t_ns);
        assert!(same(row["t_s"], e.t_filter));
        assert_vec(row, "position_world_m", &e.position);
        assert_vec(row, "feedback.position_world_m", &e.feedback_position);
        for (k, q) in ["x", "y", "z", "w"].iter().zip(e.attitude) {
            assert!(same(row[&format!("attitude.{k}")], q));
        }
        assert_eq!(e.covariance.len(), N_ERR * N_ERR);
        for (i, c) in e.covariance.iter().enumerate() {
            assert!(same(row[&format!("covariance.{i}")], *c), "P[{i}]");
        }
        // The standard deviations are the square roots of P's diagonal, in error-state
        // order (position, velocity, attitude, accelerometer bias, gyro bias).
        let parts = [
            "position_world_m",
            "velocity_world_m_s",
            "attitude_body_rad",
            "accel_bias_body_m_s2",
            "gyro_bias_body_rad_s",
        ];
        for (b, part) in parts.iter().enumerate() {
            for (k, axis) in ["x", "y", "z"].iter().enumerate() {
                let i = 3 * b + k;
                let got = row[&format!("std.{part}.{axis}")];
                assert!(
                    same(got, e.covariance[i * N_ERR + i].sqrt()),
                    "{part}.{axis}"
                );
            }
        }
        fused |= row.get("mocap_frames").copied().unwrap_or(0.0) > 0.0;
    }
    assert!(fused, "no motion-capture frame was fused in the run");
    // The covariance is the filter's own: symmetric, not the identity or zero.
    let last = &exp[exp.len() - 1].covariance;
    assert!(last[1] == last[N_ERR] && last[0] > 0.0 && last[0] < 1e-5);
}

#[test]
fn the_optional_channels_must_be_declared() {
    let dir = tempfile::tempdir().unwrap();
    let vehicle = Vehicle::from_toml(flapsim::DROSOPHILA_TOML, ORIGIN).unwrap();
    let info = RunInfo::new("simulate", "t", flapsim::DROSOPHILA_TOML, ORIGIN, "{}");
    let opts = common::mcap_opts(&dir.path().join("plain.mcap"), None);
    let mut rec = Recorder::create(&opts, &info, &vehicle).unwrap();
    let mut sim = Simulation::new(vehicle.clone(), Mode::Free);
    let out = *sim.step().unwrap();
    rec.record(&out).unwrap();
    let e = rec.wind(out.t_s, &Vector3::zeros(), &[]).unwrap_err();
    assert!(e.to_string().contains("LogOptions::wind"), "{e}");
    let prior = Prior::hover(&vehicle, vehicle.initial_attitude);
    let fb = EstimatedFeedback::new(&vehicle, 0, &prior).unwrap();
    let e = rec.estimate(out.t_s, fb.filter()).unwrap_err();
    assert!(e.to_string().contains("LogOptions::estimate"), "{e}");
    // A step that was not logged writes nothing (and needs no channel).
    rec.wind(out.t_s + 1.0, &Vector3::zeros(), &[]).unwrap();
    let stats = rec.finish().unwrap();
    let s = read_summary(dir.path().join("plain.mcap")).unwrap();
    assert_eq!(s.channels.len(), schema::CHANNELS.len());
    assert_eq!(s.message_count, stats.mcap_messages);
}

#[test]
fn the_rerun_check_compares_the_logged_winds() {
    let dir = tempfile::tempdir().unwrap();
    let toml = windy_toml(9);
    let opts = LogOptions {
        wind: true,
        ..LogOptions::default()
    };
    let good = dir.path().join("good.mcap");
    record(&good, &toml, 0.01, opts.clone(), |_| {});
    match check_log(&good).unwrap() {
        CheckOutcome::Match { samples, .. } => assert!(samples > 10),
        other => panic!("{other:?}"),
    }
    // The same run with one wind component changed from the 5th step on.
    let bad = dir.path().join("bad.mcap");
    let step = std::cell::Cell::new(0);
    record(&bad, &toml, 0.01, opts, |w| {
        step.set(step.get() + 1);
        if step.get() >= 5 {
            w[1].y += 1e-12;
        }
    });
    match check_log(&bad).unwrap() {
        CheckOutcome::Mismatch { detail, .. } => {
            assert!(detail.contains("/wind wing 1 y"), "{detail}")
        }
        other => panic!("{other:?}"),
    }
}
