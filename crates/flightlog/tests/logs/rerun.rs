//! Rerun output: the .rrd decodes with Rerun's own decoder and holds the entities.
#![cfg(feature = "rerun")]

use crate::common;

use std::collections::BTreeSet;
use std::fs::File;
use std::io::BufReader;
use std::path::Path;

use common::{mcap_opts, record, wingbeats};
use flightlog::LogOptions;
use rerun::external::re_log_encoding::DecoderApp;
use rerun::log::{Chunk, LogMsg};

/// (entity paths, rows, footer present).
fn inspect_rrd(path: &Path) -> (BTreeSet<String>, usize, bool) {
    let mut it = DecoderApp::decode_eager(BufReader::new(File::open(path).unwrap())).unwrap();
    let mut entities = BTreeSet::new();
    let mut rows = 0;
    for msg in &mut it {
        if let LogMsg::ArrowMsg(_, arrow) = &msg.unwrap() {
            let chunk = Chunk::from_arrow_msg(arrow).unwrap();
            entities.insert(chunk.entity_path().to_string());
            rows += chunk.num_rows();
        }
    }
    let finished = !it.rrd_manifests().unwrap().is_empty();
    (entities, rows, finished)
}

const ENTITIES: [&str; 14] = [
    "/world",
    "/world/body",
    "/world/body/axes",
    "/world/body/wing_left",
    "/world/body/wing_right",
    "/world/body/wing_left/mesh",
    "/world/body/wing_right/mesh",
    "/world/body/forces/translational",
    "/world/body/forces/total",
    "/plots/c_l/left",
    "/plots/c_d/right",
    "/plots/lift_over_weight",
    "/plots/position_m",
    "/plots/attitude_deg",
];

#[test]
fn live_rrd_and_converted_rrd_decode() {
    let dir = tempfile::tempdir().unwrap();
    let rrd = dir.path().join("live.rrd");
    let mcap = dir.path().join("run.mcap");
    let opts = LogOptions {
        rrd: Some(rrd.clone()),
        ..mcap_opts(&mcap, Some(2000.0))
    };
    let run = record(&opts, "simulate", wingbeats(5.0));
    assert!(run.stats.samples > 40);
    let (entities, rows, finished) = inspect_rrd(&rrd);
    assert!(finished, "no footer: the recording was not finished");
    for e in ENTITIES {
        assert!(entities.contains(e), "{e} missing from {entities:?}");
    }
    assert!(rows as u64 >= run.stats.samples, "{rows} rows");
    if run.stats.events > 0 {
        assert!(entities.contains("/events"));
    }

    let converted = dir.path().join("converted.rrd");
    let st = flightlog::replay::to_rrd(&mcap, &converted).unwrap();
    assert_eq!(st.frames, run.stats.samples);
    assert_eq!(st.events, run.stats.events);
    let (entities2, rows2, finished2) = inspect_rrd(&converted);
    assert!(finished2);
    assert_eq!(entities2, entities);
    assert_eq!(rows2, rows);
}

#[test]
fn viewer_options_fail_clearly_without_a_viewer() {
    let toml = flapsim::DROSOPHILA_TOML;
    let vehicle = flapsim::Vehicle::from_toml(toml, common::ORIGIN).unwrap();
    let info = flightlog::RunInfo::new("simulate", "x", toml, common::ORIGIN, "{}");
    // Port 9 (discard) on localhost: nothing listens there in a test environment.
    let opts = LogOptions {
        rerun_connect: Some("rerun+http://127.0.0.1:9/proxy".into()),
        ..LogOptions::default()
    };
    let e = flightlog::Recorder::create(&opts, &info, &vehicle).unwrap_err();
    assert!(e.to_string().contains("no Rerun viewer"), "{e}");
    let opts = LogOptions {
        rerun_connect: Some("not a url".into()),
        ..LogOptions::default()
    };
    assert!(flightlog::Recorder::create(&opts, &info, &vehicle).is_err());
    // An unwritable MCAP path leaves no .rrd behind.
    let dir = tempfile::tempdir().unwrap();
    let rrd = dir.path().join("x.rrd");
    let opts = LogOptions {
        rrd: Some(rrd.clone()),
        mcap: Some(dir.path().join("no/such/dir/x.mcap")),
        ..LogOptions::default()
    };
    let e = flightlog::Recorder::create(&opts, &info, &vehicle).unwrap_err();
    assert!(e.to_string().contains("cannot create"), "{e}");
    assert!(!rrd.exists());
    // Spawning needs `rerun` on PATH; only check the error when it is absent.
    let on_path = std::env::var_os("PATH")
        .is_some_and(|p| std::env::split_paths(&p).any(|d| d.join("rerun").is_file()));
    if !on_path {
        let opts = LogOptions {
            rerun_spawn: true,
            ..LogOptions::default()
        };
        let e = flightlog::Recorder::create(&opts, &info, &vehicle).unwrap_err();
        assert!(e.to_string().contains("cannot spawn a Rerun viewer"), "{e}");
    }
}

#[test]
fn the_estimate_and_the_winds_show_against_the_truth() {
    use flapsim::estimator::{EstimatedFeedback, Prior};
    use flapsim::{Mode, Simulation, Vehicle, Wind};

    let dir = tempfile::tempdir().unwrap();
    let rrd = dir.path().join("live.rrd");
    let mcap = dir.path().join("run.mcap");
    let toml = format!(
        "{}\n[wind]\n[wind.turbulence]\nintensity_m_s = [0.3, 0.3, 0.2]\nlength_scale_m = [0.05, 0.05, 0.05]\nseed = 1\n",
        flapsim::DROSOPHILA_TOML
    );
    let vehicle = Vehicle::from_toml(&toml, common::ORIGIN).unwrap();
    let info = flightlog::RunInfo::new("hover", "x", toml.as_str(), common::ORIGIN, "{}");
    let opts = LogOptions {
        rrd: Some(rrd.clone()),
        wind: true,
        estimate: true,
        ..mcap_opts(&mcap, Some(2000.0))
    };
    let mut rec = flightlog::Recorder::create(&opts, &info, &vehicle).unwrap();
    let wind = Wind::from_spec(
        vehicle.wind.as_ref().unwrap(),
        "w",
        vehicle.initial_position_m,
    );
    let prior = Prior::hover(&vehicle, vehicle.initial_attitude);
    let mut fb = EstimatedFeedback::new(&vehicle, 1, &prior).unwrap();
    let mut sim = Simulation::new(vehicle, Mode::Free);
    sim.set_wind_model(Some(wind.unwrap()));
    for _ in 0..200 {
        fb.observe(sim.time_s(), &sim.state());
        let out = *sim.step().unwrap();
        rec.record(&out).unwrap();
        rec.wind(out.t_s, &sim.uniform_wind_m_s(), sim.wing_winds_m_s())
            .unwrap();
        rec.estimate(out.t_s, fb.filter()).unwrap();
    }
    let stats = rec.finish().unwrap();
    let (entities, rows, finished) = inspect_rrd(&rrd);
    assert!(finished);
    for e in [
        "/world/estimate",
        "/world/estimate/axes",
        "/plots/estimate/position_m/x",
        "/plots/estimate/position_m/z",
        "/plots/estimate/attitude_deg/pitch",
        "/plots/estimate/position_std_m",
        "/plots/wind_m_s/left",
        "/plots/wind_m_s/right",
    ] {
        assert!(entities.contains(e), "{e} missing from {entities:?}");
    }
    // The conversion of the MCAP log shows the same.
    let converted = dir.path().join("converted.rrd");
    let st = flightlog::replay::to_rrd(&mcap, &converted).unwrap();
    assert_eq!(st.estimates, stats.samples);
    assert_eq!(st.winds, stats.samples);
    let (entities2, rows2, _) = inspect_rrd(&converted);
    assert_eq!(entities2, entities);
    assert_eq!(rows2, rows);
}
