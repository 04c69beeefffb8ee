//! Logs written by flapwing before issue #16, with JSON messages (the fixtures in
//! tests/fixtures/, made by `scripts/make-json-log-fixtures` with the last such version),
//! still replay: summary, CSV export, the re-run check and (feature `rerun`) the Rerun
//! conversion, with the same numbers as today's protobuf logs of the same run.

use crate::common;

use std::path::PathBuf;

use flightlog::check::{CheckOutcome, check_log};
use flightlog::replay::{export_csv, read_summary};
use flightlog::schema::CHANNELS;

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name)
}

#[test]
fn old_json_logs_replay_and_check() {
    for (name, samples) in [
        ("json-drosophila-free.mcap", 40),
        ("json-robobee-tethered.mcap", 20),
    ] {
        let path = fixture(name);
        let s = read_summary(&path).unwrap();
        assert!(s.complete, "{name}: {:?}", s.damage);
        assert_eq!(s.samples, samples, "{name}");
        // Every channel of today but /scene/wings and /scene/forces, which came with the
        // protobuf logs.
        assert_eq!(s.channels.len(), CHANNELS.len() - 2);
        for c in &s.channels {
            assert_eq!(c.message_encoding, "json", "{name}");
            assert_eq!(c.schema_encoding, "jsonschema", "{name}");
        }
        assert!(s.cycle_mean.is_some() || samples < 40, "{name}");
        match check_log(&path).unwrap() {
            CheckOutcome::Match { samples: n, note } => {
                assert_eq!(n, samples, "{name}");
                assert_eq!(note, None, "{name}");
            }
            other => panic!("{name}: {other:?}"),
        }
        let dir = tempfile::tempdir().unwrap();
        let csv = dir.path().join("kin.csv");
        let st = export_csv(&path, "/wing/left/kinematics", &csv).unwrap();
        assert_eq!((st.rows, st.skipped), (samples, 0), "{name}");
        let header = std::fs::read_to_string(&csv).unwrap();
        let header = header.lines().next().unwrap();
        assert!(header.contains("angles_deg.phi"), "{header}");
        assert_eq!(
            header.contains("actuation.voltage_v"),
            name.contains("robobee")
        );
    }
}

/// The old log and a protobuf log of the same run hold the same trajectory.
#[test]
fn old_and_new_logs_of_one_run_agree() {
    let old = read_summary(fixture("json-drosophila-free.mcap")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("new.mcap");
    let settings = old.settings().unwrap();
    // The run of the model the old log embeds (models change between versions: the fly
    // gained its hover downwash after the JSON logs), with the added-mass form of its day:
    // eq 7-8, the only one before MODEL.md 4.3 was revised (the impulse form is the default
    // now).
    assert!(!old.metadata.contains_key("added_mass_form"));
    let embedded = &old.metadata["model_toml"];
    assert!(!embedded.contains("[aero]") && !embedded.contains("added_mass"));
    // And the loads taken at each step's start, the only sampling before issue 37.
    assert!(!old.metadata.contains_key("load_sampling") && !embedded.contains("load_sampling"));
    let model = format!("{embedded}\n[aero]\nadded_mass = \"paper\"\n",).replacen(
        "[sim]",
        "[sim]\nload_sampling = \"step_start\"",
        1,
    );
    assert!(
        model.contains("load_sampling"),
        "the old model has a [sim] table"
    );
    let run = common::record_model(
        &common::mcap_opts(&path, settings.log_rate_hz),
        "simulate",
        settings.duration_s,
        flapsim::Mode::Free,
        &model,
        &old.metadata["model_origin"],
    );
    assert_eq!(run.stats.samples, old.samples);
    let new = read_summary(&path).unwrap();
    assert_eq!(new.final_position_m, old.final_position_m);
    assert_eq!(new.max_excursion_m, old.max_excursion_m);
    let (a, b) = (old.cycle_mean.unwrap(), new.cycle_mean.unwrap());
    assert_eq!(a.wingbeats, b.wingbeats);
    for i in 0..3 {
        assert!(
            (a.force_body_n[i] - b.force_body_n[i]).abs()
                <= 1e-12 * a.force_body_n[i].abs().max(1e-12)
        );
    }
}

#[cfg(feature = "rerun")]
#[test]
fn old_json_log_converts_to_rrd() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("old.rrd");
    let st = flightlog::replay::to_rrd(fixture("json-drosophila-free.mcap"), &out).unwrap();
    assert_eq!(st.frames, 40);
    assert!(std::fs::metadata(&out).unwrap().len() > 1000);
}
