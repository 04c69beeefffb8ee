//! `flapwing replay`: summary, JSON, CSV, Rerun conversion, `--check` and exit codes.

use std::path::Path;
use std::process::Command;

use flapsim::{Mode, Simulation, Vehicle};
use flightlog::{LogOptions, Recorder, RunInfo, SimSettings};

#[derive(Debug)]
struct Out {
    code: i32,
    stdout: String,
    stderr: String,
}

fn flapwing(args: &[&str]) -> Out {
    let out = Command::new(env!("CARGO_BIN_EXE_flapwing"))
        .args(args)
        .output()
        .expect("run flapwing");
    Out {
        code: out.status.code().expect("exit code"),
        stdout: String::from_utf8(out.stdout).unwrap(),
        stderr: String::from_utf8(out.stderr).unwrap(),
    }
}

/// Records a free drosophila flight as `flapwing simulate` would, with `embedded` as the
/// model text written into the log (the real model is always the built-in drosophila).
fn record(path: &Path, command: &str, embedded: &str, wingbeats: f64) -> u64 {
    let toml = flapsim::DROSOPHILA_TOML;
    let vehicle = Vehicle::from_toml(toml, "drosophila").unwrap();
    let duration = wingbeats / vehicle.freq_hz();
    let settings = SimSettings::new(Mode::Free, duration, Some(2000.0), [0.0; 3]);
    let info = RunInfo::new(
        command,
        format!("flapwing {command}"),
        embedded,
        "drosophila",
        settings.to_json(),
    );
    let opts = LogOptions {
        mcap: Some(path.to_owned()),
        log_rate_hz: Some(2000.0),
        ..LogOptions::default()
    };
    let mut rec = Recorder::create(&opts, &info, &vehicle).unwrap();
    let mut sim = Simulation::new(vehicle, Mode::Free);
    sim.run_for(duration, |out| rec.record(out).unwrap())
        .unwrap();
    rec.finish().unwrap().samples
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn assert_bad_input(o: &Out) {
    assert_eq!(o.code, 2, "{}{}", o.stdout, o.stderr);
    assert!(o.stderr.starts_with("error:"), "{}", o.stderr);
    assert!(!o.stderr.contains("panicked"), "{}", o.stderr);
}

#[test]
fn summary_json_csv_rrd_and_check() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("run.mcap");
    let samples = record(&log, "simulate", flapsim::DROSOPHILA_TOML, 4.0);

    let o = flapwing(&["replay", s(&log)]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(o.stdout.contains("/vehicle/state"), "{}", o.stdout);
    assert!(o.stdout.contains("foxglove.PoseInFrame"), "{}", o.stdout);
    assert!(o.stdout.contains("complete"), "{}", o.stdout);

    let o = flapwing(&["replay", s(&log), "--json"]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let v: serde_json::Value = serde_json::from_str(&o.stdout).unwrap();
    assert_eq!(v["samples"], samples);
    assert_eq!(v["complete"], true);
    assert_eq!(v["metadata"]["command"], "simulate");

    let o = flapwing(&["replay", s(&log), "--check"]);
    assert_eq!(o.code, 0, "{}{}", o.stdout, o.stderr);
    assert!(
        o.stdout
            .starts_with(&format!("match: {samples} samples identical")),
        "{}",
        o.stdout
    );

    let csv = dir.path().join("state.csv");
    let o = flapwing(&["replay", s(&log), "--csv", "/vehicle/state", s(&csv)]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(text.starts_with("log_time_ns,"), "{text}");
    assert_eq!(text.lines().count() as u64, samples + 1);
    // No silent overwrite; unknown channel is bad input.
    assert_bad_input(&flapwing(&[
        "replay",
        s(&log),
        "--csv",
        "/vehicle/state",
        s(&csv),
    ]));
    let o = flapwing(&[
        "replay",
        s(&log),
        "--csv",
        "/vehicle/state",
        s(&csv),
        "--force",
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let o = flapwing(&[
        "replay",
        s(&log),
        "--csv",
        "/nope",
        s(&dir.path().join("n.csv")),
    ]);
    assert_bad_input(&o);
    assert!(o.stderr.contains("/vehicle/state"), "{}", o.stderr);
    assert!(!dir.path().join("n.csv").exists());

    let rrd = dir.path().join("run.rrd");
    let o = flapwing(&["replay", s(&log), "--rrd", s(&rrd)]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(
        o.stdout.contains(&format!("wrote {samples} samples")),
        "{}",
        o.stdout
    );
    assert!(std::fs::metadata(&rrd).unwrap().len() > 1000);

    // A truncated copy still replays and says what was lost.
    let bytes = std::fs::read(&log).unwrap();
    let cut = dir.path().join("cut.mcap");
    // Half the file: inside the data section (the summary repeats every schema, each the
    // whole flapwing descriptor set, so it is a large part of a short log).
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    let o = flapwing(&["replay", s(&cut)]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(
        o.stdout.contains("DAMAGED") && o.stdout.contains("truncated"),
        "{}",
        o.stdout
    );
}

#[test]
fn check_fails_on_an_edited_model() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("edited.mcap");
    let edited = flapsim::DROSOPHILA_TOML.replace("mass_kg = 1.0e-6", "mass_kg = 1.05e-6");
    assert_ne!(edited, flapsim::DROSOPHILA_TOML);
    record(&log, "simulate", &edited, 3.0);
    let o = flapwing(&["replay", s(&log), "--check"]);
    assert_eq!(o.code, 1, "{}{}", o.stdout, o.stderr);
    assert!(o.stdout.starts_with("mismatch"), "{}", o.stdout);
    assert!(o.stderr.starts_with("error:"), "{}", o.stderr);
}

#[test]
fn bad_input_exits_2() {
    let dir = tempfile::tempdir().unwrap();
    assert_bad_input(&flapwing(&["replay", s(&dir.path().join("missing.mcap"))]));
    let text = dir.path().join("text.mcap");
    std::fs::write(&text, "hello").unwrap();
    let o = flapwing(&["replay", s(&text)]);
    assert_bad_input(&o);
    assert!(o.stderr.contains("not an MCAP file"), "{}", o.stderr);
    assert_bad_input(&flapwing(&["replay", s(&text), "--check"]));
    // A log of another command cannot be re-run.
    let other = dir.path().join("identify.mcap");
    record(&other, "identify", flapsim::DROSOPHILA_TOML, 1.0);
    let o = flapwing(&["replay", s(&other), "--check"]);
    assert_bad_input(&o);
    assert!(
        o.stderr
            .contains("written by `flapwing identify`; only `simulate` and `hover` logs"),
        "{}",
        o.stderr
    );
    // A `hover` log whose settings are not a hover's names them.
    let hover = dir.path().join("hover.mcap");
    record(&hover, "hover", flapsim::DROSOPHILA_TOML, 1.0);
    let o = flapwing(&["replay", s(&hover), "--check"]);
    assert_bad_input(&o);
    assert!(
        o.stderr.contains("the log's hover settings do not load"),
        "{}",
        o.stderr
    );
}

/// `flapwing hover` logs re-run bit for bit (`replay --check`): the logged trim, the LQR of
/// the default weights designed there, the disturbance (an initial roll and sideslip and a
/// gust) and the wind field, on the true state, closed loop and open loop, and on the state
/// estimate of the model's sensors (the seed of their noise is in the log).
#[test]
fn hover_logs_re_run_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    for (name, extra) in [
        (
            "closed.mcap",
            &[
                "--disturbance",
                "roll_deg=3,vy_m_s=0.05,gust_x_m_s=0.3,gust_start_s=0.05,gust_duration_s=0.05",
                "--wind-world-m-s",
                "0.2,0,0",
            ][..],
        ),
        ("open.mcap", &["--open-loop", "--model", "bumblebee"][..]),
    ] {
        let log = dir.path().join(name);
        let rrd = log.with_extension("rrd");
        let mut args = vec![
            "hover",
            "--duration-s",
            "0.15",
            "--mcap",
            s(&log),
            "--rrd",
            s(&rrd),
        ];
        args.extend_from_slice(extra);
        let run = flapwing(&args);
        assert_eq!(run.code, 0, "{run:?}");
        let o = flapwing(&["replay", s(&log), "--check"]);
        assert_eq!(o.code, 0, "{name}: {o:?}");
        assert!(
            o.stdout.contains("samples identical"),
            "{name}: {}",
            o.stdout
        );
    }
    // On the state estimate: re-run from the logged seed of the sensors' noise; a seed
    // other than the default too.
    for seed in ["0", "7"] {
        let log = dir.path().join(format!("estimated_{seed}.mcap"));
        let rrd = log.with_extension("rrd");
        let run = flapwing(&[
            "hover",
            "--duration-s",
            "0.1",
            "--feedback",
            "estimated",
            "--sensor-seed",
            seed,
            "--mcap",
            s(&log),
            "--rrd",
            s(&rrd),
        ]);
        assert_eq!(run.code, 0, "{run:?}");
        let o = flapwing(&["replay", s(&log), "--check"]);
        assert_eq!(o.code, 0, "seed {seed}: {o:?}");
        assert!(o.stdout.contains("samples identical"), "{}", o.stdout);
    }
}

/// A run with the second-order load sampling (`[sim] load_sampling = "midpoint"`, issue 37)
/// records it in the log's metadata, and `--check` re-runs it with it: bit for bit. (A log
/// without the metadata, written before issue 37, re-runs with the step-start sampling of
/// its time: `crates/flightlog/tests/fixtures` hold two, checked there.)
#[test]
fn a_midpoint_run_replays_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("mid.toml");
    let text = flapsim::DROSOPHILA_TOML.replace(
        "\nsteps_per_wingbeat = 20 ",
        "\nload_sampling = \"midpoint\"\nsteps_per_wingbeat = 40 ",
    );
    assert_ne!(text, flapsim::DROSOPHILA_TOML);
    std::fs::write(&model, text).unwrap();
    let log = dir.path().join("mid.mcap");
    let o = flapwing(&[
        "simulate",
        "--model",
        s(&model),
        "--duration-s",
        "0.02",
        "--mcap",
        s(&log),
    ]);
    assert_eq!(o.code, 0, "{}{}", o.stdout, o.stderr);
    let o = flapwing(&["replay", s(&log), "--check"]);
    assert_eq!(o.code, 0, "{}{}", o.stdout, o.stderr);
    assert!(o.stdout.starts_with("match"), "{}", o.stdout);
    let o = flapwing(&["replay", s(&log), "--json"]);
    assert!(
        o.stdout.contains("\"load_sampling\": \"midpoint\""),
        "{}",
        o.stdout
    );
}

/// `replay --resimulate` of a log flown by the same model restarts every segment from the
/// logged state with the wing set's logged step memory (the midpoint sampling's history),
/// so the simulated body retraces the logged one to round-off: positions to 4e-35 m (exactly
/// until the body's rates were advanced by the midpoint rule, whose torque goes through the
/// attitude rapier holds, which a restart sets afresh), attitudes and rates to the round-off of
/// comparing them (1e-28 deg, 1e-29 rad/s) (the segments after the first start mid-flight, where a restart
/// without that memory is off by about 2e-10 m after four wingbeats). The comparison MCAP
/// holds both bodies as frames, their poses and the residuals, and the summary.
#[test]
fn resimulating_a_log_of_the_same_model_retraces_it() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("s.mcap");
    // 30 wingbeats at 2000 Hz: states at the first step of several wingbeats.
    record(&log, "simulate", flapsim::DROSOPHILA_TOML, 30.0);
    let cmp = dir.path().join("cmp.mcap");
    let o = flapwing(&[
        "replay",
        s(&log),
        "--resimulate",
        "--json",
        "--mcap",
        s(&cmp),
    ]);
    assert_eq!(o.code, 0, "{}{}", o.stdout, o.stderr);
    let v: serde_json::Value = serde_json::from_str(&o.stdout).unwrap();
    assert_eq!(v["reference"], "logged state");
    let segments = v["segments"].as_array().unwrap();
    assert!(segments.len() >= 2, "{v}");
    for seg in segments {
        assert!(seg["samples"].as_u64().unwrap() >= 5, "{seg}");
        assert!(seg["position_rms_m"].as_f64().unwrap() < 1e-30, "{seg}");
        assert!(seg["attitude_rms_deg"].as_f64().unwrap() < 1e-12, "{seg}");
        assert!(seg["rate_rms_rad_s"].as_f64().unwrap() < 1e-12, "{seg}");
    }
    // The comparison log: both frames, poses, residuals and the summary.
    let summary = flapwing(&["replay", s(&cmp), "--json"]);
    assert_bad_input(&summary);
    assert!(
        summary.stderr.contains("not a flapwing log"),
        "{}",
        summary.stderr
    );
    let bytes = std::fs::read(&cmp).unwrap();
    let mut topics = std::collections::BTreeSet::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        topics.insert(m.channel.topic.clone());
    }
    let want = [
        "/real/pose",
        "/residual",
        "/sim/pose",
        "/tf/real",
        "/tf/sim",
    ];
    assert_eq!(topics.into_iter().collect::<Vec<_>>(), want);
    // Outputs and flags that do not go together.
    let o = flapwing(&["replay", s(&log), "--mcap", s(&dir.path().join("x.mcap"))]);
    assert_bad_input(&o);
    assert!(o.stderr.contains("--resimulate"), "{}", o.stderr);
    let o = flapwing(&["replay", s(&log), "--resimulate", "--check"]);
    assert_bad_input(&o);
    let o = flapwing(&["replay", s(&log), "--pose-topic", "/p"]);
    assert_bad_input(&o);
    let o = flapwing(&["replay", s(&log), "--resimulate", "--mcap", s(&cmp)]);
    assert_bad_input(&o);
    assert!(o.stderr.contains("--force"), "{}", o.stderr);
}
