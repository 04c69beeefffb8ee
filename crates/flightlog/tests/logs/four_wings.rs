//! Logs of any number of wings: the four-winged dragonfly recorded with
//! `Recorder::record_wings` has every wing's channels in the documented order, its cycle
//! mean sums all four wings, it converts to Rerun with every sample and re-runs bit for bit;
//! a two-winged layout is the channel list of before; `record` refuses what a step output
//! cannot hold.

use crate::common;

use common::mcap_opts;
use flapsim::{Mode, Simulation, Vehicle};
use flightlog::check::{CheckOutcome, check_log};
use flightlog::schema::{CHANNELS, WingLayout};
use flightlog::{Recorder, RunInfo, SimSettings};

#[test]
fn two_wings_keep_the_channels_of_before() {
    let two = WingLayout::new(2);
    let names: Vec<(String, &str)> = CHANNELS
        .iter()
        .map(|(t, s)| ((*t).to_owned(), *s))
        .collect();
    assert_eq!(two.channels(), names);
    assert_eq!(two.frame(0), "wing_left");
    assert_eq!(two.frame(1), "wing_right");
    let four = WingLayout::new(4);
    assert_eq!(
        four.labels(),
        ["left", "right", "pairs0_left", "pairs0_right"]
    );
    assert_eq!(four.channel_count(), 19);
    assert_eq!(four.channels()[four.events()].0, "/events");
    assert_eq!(four.channels()[four.scene_forces()].0, "/scene/forces");
}

#[test]
fn a_dragonfly_log_has_every_wing() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("d.mcap");
    let toml = flapsim::DRAGONFLY_TOML;
    let vehicle = Vehicle::from_toml(toml, "dragonfly.toml").unwrap();
    let duration_s = 2.5 / vehicle.freq_hz();
    let settings = SimSettings::new(Mode::Free, duration_s, None, [0.0; 3]);
    let info = RunInfo::new(
        "simulate",
        "flapwing simulate --model dragonfly",
        toml,
        "dragonfly.toml",
        settings.to_json(),
    );
    let mut rec = Recorder::create(&mcap_opts(&path, None), &info, &vehicle).unwrap();
    let mut sim = Simulation::new(vehicle.clone(), Mode::Free);
    let n = (duration_s / sim.dt_s()).round() as u64;
    // Per step: phase and the sum of the four wings' total forces (body frame).
    let mut sums = Vec::new();
    for k in 0..n {
        let out = *sim.step().unwrap();
        if k == 0 {
            // A step output holds the first pair only: refused for four wings.
            let e = rec.record(&out).unwrap_err().to_string();
            assert!(e.contains("dragonfly") && e.contains("record_wings"), "{e}");
        }
        let set = sim.wing_set().output();
        assert_eq!(set.wings.len(), 4);
        let f: nalgebra::Vector3<f64> = set.wings.iter().map(|w| w.total.force_n).sum();
        sums.push((out.phase, f));
        rec.record_wings(&out, set).unwrap();
    }
    // A wing set output of another size is refused.
    let mut short = sim.wing_set().output().clone();
    short.wings.truncate(2);
    let out = *sim.step().unwrap();
    let e = rec.record_wings(&out, &short).unwrap_err().to_string();
    assert!(e.contains("2 wings") && e.contains("4"), "{e}");
    rec.finish().unwrap();

    let s = flightlog::replay::read_summary(&path).unwrap();
    assert_eq!(s.wings, ["left", "right", "pairs0_left", "pairs0_right"]);
    let topics: Vec<&str> = s.channels.iter().map(|c| c.topic.as_str()).collect();
    let want = WingLayout::new(4).channels();
    let want: Vec<&str> = want.iter().map(|c| c.0.as_str()).collect();
    assert_eq!(topics, want);
    assert_eq!(s.samples, n);
    // The cycle mean sums all four wings: the two complete wingbeats' means of the
    // step sums above.
    let m = s.cycle_mean.expect("two complete wingbeats");
    assert_eq!(m.wingbeats, 2);
    let mut by_beat = std::collections::BTreeMap::<i64, (nalgebra::Vector3<f64>, f64)>::new();
    for (phase, f) in &sums {
        let e = by_beat.entry(phase.floor() as i64).or_default();
        e.0 += f;
        e.1 += 1.0;
    }
    let complete: Vec<_> = by_beat.values().take(2).map(|(f, k)| f / *k).collect();
    let mean = (complete[0] + complete[1]) / 2.0;
    for k in 0..3 {
        let rel = (m.force_body_n[k] - mean[k]).abs() / mean.norm();
        assert!(
            rel < 1e-12,
            "axis {k}: {} vs {}",
            m.force_body_n[k],
            mean[k]
        );
    }
    // Rerun gets every sample with all four wings; the log re-runs bit for bit.
    let rrd = flightlog::replay::to_rrd(&path, dir.path().join("d.rrd")).unwrap();
    assert_eq!(rrd.frames, n);
    match check_log(&path).unwrap() {
        CheckOutcome::Match { samples, .. } => assert_eq!(samples, n),
        other => panic!("{other:?}"),
    }
}
