//! `/scene/forces`: each wing's total aerodynamic force as a Foxglove arrow
//! (`foxglove.SceneUpdate` with one `ArrowPrimitive` per wing) on every logged sample, at most
//! `FORCE_ARROWS_MAX_RATE_HZ` times per second, decoded back and compared with the forces the
//! simulation produced.

use crate::common;

use common::{force_arrows, mcap_opts, record_model, wingbeats};
use flapsim::Mode;
use flightlog::Decimator;
use flightlog::schema::{FORCE_ARROWS_MAX_RATE_HZ, TOPIC_SCENE_FORCES, TOPIC_STATE};

/// Records `model` at `rate` and checks every arrow against the logged step's forces: one
/// message per sample (at most 2000 per second) at the sample's time; per wing an arrow in
/// `base_link`, locked to it, at the hinge, whose vector is the total force times body length
/// / weight.
fn arrows_are_the_forces(toml: &str, origin: &str, mode: Mode, rate: Option<f64>) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    let run = record_model(
        &mcap_opts(&path, rate),
        "simulate",
        wingbeats(6.0),
        mode,
        toml,
        origin,
    );
    let mut decimator = Decimator::new(rate);
    let logged: Vec<_> = run.outs.iter().filter(|o| decimator.take(o.t_s)).collect();
    assert_eq!(logged.len() as u64, run.stats.samples);
    let samples = logged.len();
    let mut arrow_decimator = Decimator::new(Some(FORCE_ARROWS_MAX_RATE_HZ));
    let logged: Vec<_> = logged
        .into_iter()
        .filter(|o| arrow_decimator.take(o.t_s))
        .collect();
    // The samples' rate: the log's, or the step's at full rate.
    let steps_hz = run.vehicle.freq_hz() * run.vehicle.sim.steps_per_wingbeat as f64;
    let sample_hz = rate.map_or(steps_hz, |r| r.min(steps_hz));
    if sample_hz <= FORCE_ARROWS_MAX_RATE_HZ {
        assert_eq!(logged.len(), samples, "an arrow on every sample");
    } else {
        // One sample in sample_hz / FORCE_ARROWS_MAX_RATE_HZ carries the arrows.
        let expected = samples as f64 * FORCE_ARROWS_MAX_RATE_HZ / sample_hz;
        assert!(
            (logged.len() as f64 - expected).abs() <= 2.0,
            "{} of {samples}, expected about {expected:.1}",
            logged.len()
        );
    }
    let m_per_n = run.vehicle.length_m / run.vehicle.weight_n();

    let bytes = std::fs::read(&path).unwrap();
    let (mut arrows, mut states) = (0, 0);
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        if m.channel.topic == TOPIC_STATE {
            states += 1;
        }
        if m.channel.topic != TOPIC_SCENE_FORCES {
            continue;
        }
        assert_eq!(
            m.channel.schema.as_ref().unwrap().name,
            "foxglove.SceneUpdate"
        );
        let out = logged[arrows];
        arrows += 1;
        assert_eq!(m.log_time, (out.t_s * 1e9).round() as u64);
        let v = common::decode(&m);
        for (w, a) in force_arrows(&v).iter().enumerate() {
            assert_eq!(a.frame_id, "base_link");
            assert!(a.frame_locked);
            assert_eq!(a.id, ["force_left", "force_right"][w]);
            assert_eq!(a.position, run.vehicle.wings[w].mount().hinge_in_body_m);
            let f = out.wings[w].total.force_n;
            assert!(f.norm() > 0.0);
            assert!(
                (a.vector / m_per_n - f).norm() <= 1e-12 * f.norm(),
                "{origin} step {} wing {w}: arrow {} for {f}",
                out.step,
                a.vector / m_per_n
            );
        }
    }
    assert_eq!(arrows, logged.len());
    assert_eq!(states, samples);
}

#[test]
fn arrows_at_a_low_rate() {
    arrows_are_the_forces(
        flapsim::DROSOPHILA_TOML,
        "drosophila.toml",
        Mode::Free,
        Some(700.0),
    );
}

#[test]
fn arrows_at_the_default_rate_free_flight() {
    arrows_are_the_forces(
        flapsim::DROSOPHILA_TOML,
        "drosophila.toml",
        Mode::Free,
        Some(2000.0),
    );
}

#[test]
fn arrows_at_full_rate_actuated_tethered() {
    arrows_are_the_forces(flapsim::ROBOBEE_TOML, "robobee.toml", Mode::Tethered, None);
}

#[test]
fn arrow_shape_is_documented() {
    // Head 20 % of the length; shaft and head 2 % and 5 % of the body length wide.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    let run = common::record(&mcap_opts(&path, None), "simulate", wingbeats(1.0));
    let bytes = std::fs::read(&path).unwrap();
    let m = mcap::MessageStream::new(&bytes)
        .unwrap()
        .map(Result::unwrap)
        .find(|m| m.channel.topic == TOPIC_SCENE_FORCES)
        .unwrap();
    let v = common::decode(&m);
    let l = run.vehicle.length_m;
    for e in v["entities"].as_array().unwrap() {
        let a = &e["arrows"][0];
        let (shaft, head) = (
            a["shaft_length"].as_f64().unwrap(),
            a["head_length"].as_f64().unwrap(),
        );
        assert!((head / (shaft + head) - 0.2).abs() < 1e-12);
        assert!((a["shaft_diameter"].as_f64().unwrap() - 0.02 * l).abs() < 1e-15);
        assert!((a["head_diameter"].as_f64().unwrap() - 0.05 * l).abs() < 1e-15);
        assert!(a["color"]["a"].as_f64().unwrap() > 0.5);
    }
}
