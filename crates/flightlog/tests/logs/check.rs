//! `replay --check`: a fresh log re-runs bit for bit; an edited model does not.

use crate::common;

use common::{copy_with_metadata, mcap_opts, record, record_mode, wingbeats};
use flapsim::actuated::dynamics::{StageLoads, StrikeShare};
use flightlog::check::{CheckOutcome, check_log};

#[test]
fn fresh_log_matches_and_edited_model_does_not() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    let run = record(&mcap_opts(&path, Some(2000.0)), "simulate", wingbeats(6.0));
    match check_log(&path).unwrap() {
        CheckOutcome::Match { samples, note } => {
            assert_eq!(samples, run.stats.samples);
            assert_eq!(note, None);
        }
        other => panic!("{other:?}"),
    }
    // The copy itself (unchanged) still matches: the copier is faithful.
    let same = dir.path().join("same.mcap");
    copy_with_metadata(&path, &same, |_| {});
    assert!(matches!(
        check_log(&same).unwrap(),
        CheckOutcome::Match { .. }
    ));
    // Heavier vehicle: the trajectory differs.
    let edited = dir.path().join("edited.mcap");
    copy_with_metadata(&path, &edited, |md| {
        let toml = md["model_toml"].replace("mass_kg = 1.0e-6", "mass_kg = 1.1e-6");
        assert_ne!(toml, md["model_toml"], "the edit must change the model");
        md.insert("model_toml".into(), toml);
    });
    match check_log(&edited).unwrap() {
        CheckOutcome::Mismatch {
            samples_matched,
            detail,
        } => {
            // Step 0 is the initial state (identical); the change shows from step 1 on.
            assert!(samples_matched >= 1, "{detail}");
            assert!(samples_matched < run.stats.samples, "{detail}");
            assert!(
                detail.contains("logged") && detail.contains("re-run"),
                "{detail}"
            );
        }
        other => panic!("{other:?}"),
    }
    // A broken embedded model is an error, not a mismatch.
    let broken = dir.path().join("broken.mcap");
    copy_with_metadata(&path, &broken, |md| {
        md.insert("model_toml".into(), "name = ".into());
    });
    let e = check_log(&broken).unwrap_err();
    assert!(e.is_bad_input(), "{e}");
}

#[test]
fn other_modes_and_commands() {
    let dir = tempfile::tempdir().unwrap();
    let tethered = dir.path().join("tethered.mcap");
    let run = record_mode(
        &mcap_opts(&tethered, None),
        "simulate",
        wingbeats(2.0),
        flapsim::Mode::Tethered,
    );
    match check_log(&tethered).unwrap() {
        CheckOutcome::Match { samples, .. } => assert_eq!(samples, run.stats.samples),
        other => panic!("{other:?}"),
    }
    let long = dir.path().join("long.mcap");
    record_mode(
        &mcap_opts(&long, Some(3000.0)),
        "simulate",
        wingbeats(2.0),
        flapsim::Mode::LONGITUDINAL,
    );
    assert!(matches!(
        check_log(&long).unwrap(),
        CheckOutcome::Match { .. }
    ));
    // Another command's log is not re-run; a `hover` log with a simulate's settings is an
    // error naming them (real hover logs re-run: crates/cli/tests/replay.rs).
    let other = dir.path().join("identify.mcap");
    record(&mcap_opts(&other, Some(2000.0)), "identify", wingbeats(1.0));
    match check_log(&other).unwrap() {
        CheckOutcome::NotCheckable { reason } => assert!(
            reason.contains("`flapwing identify`; only `simulate` and `hover` logs"),
            "{reason}"
        ),
        other => panic!("{other:?}"),
    }
    let hover = dir.path().join("hover.mcap");
    record(&mcap_opts(&hover, Some(2000.0)), "hover", wingbeats(1.0));
    let e = check_log(&hover).unwrap_err().to_string();
    assert!(e.contains("the log's hover settings do not load"), "{e}");
}

#[test]
fn a_run_stopped_early_matches_with_a_note() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("stopped.mcap");
    let toml = flapsim::DROSOPHILA_TOML;
    let vehicle = flapsim::Vehicle::from_toml(toml, common::ORIGIN).unwrap();
    let duration = wingbeats(4.0);
    let settings =
        flightlog::SimSettings::new(flapsim::Mode::Free, duration, Some(2000.0), [0.0; 3]);
    let info = flightlog::RunInfo::new(
        "simulate",
        "flapwing simulate",
        toml,
        common::ORIGIN,
        settings.to_json(),
    );
    let mut rec =
        flightlog::Recorder::create(&mcap_opts(&path, Some(2000.0)), &info, &vehicle).unwrap();
    let mut sim = flapsim::Simulation::new(vehicle, flapsim::Mode::Free);
    // Ctrl-C after half the run: the caller stops and finishes the log.
    sim.run_while(duration, |out| {
        rec.record(out).unwrap();
        out.t_s < 0.5 * duration
    })
    .unwrap();
    rec.event(sim.time_s(), flightlog::Level::Warning, "interrupted")
        .unwrap();
    let stats = rec.finish().unwrap();
    match check_log(&path).unwrap() {
        CheckOutcome::Match { samples, note } => {
            assert_eq!(samples, stats.samples);
            assert!(note.unwrap().contains("stopped early"));
        }
        other => panic!("{other:?}"),
    }
}

/// A log written with the midpoint load sampling before the step mean became the default
/// (issue 37; `scripts/make-midpoint-log-fixture` writes it with commit 56fbda5's flapwing)
/// re-runs with the sampling it records, bit for bit: today's midpoint is that day's.
#[test]
fn a_midpoint_log_of_before_the_step_mean_matches() {
    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/midpoint-drosophila-free.mcap");
    let s = flightlog::replay::read_summary(&path).unwrap();
    assert_eq!(s.metadata["load_sampling"], "midpoint");
    match check_log(&path).unwrap() {
        CheckOutcome::Match { samples, note } => {
            assert_eq!(samples, 20);
            assert_eq!(note, None);
        }
        other => panic!("{other:?}"),
    }
}

/// A RoboBee log under the step mean (its actuated wings split their steps at stroke
/// reversals since issue 37's last change) re-runs bit for bit, and one written before that
/// change still does: then the actuated wings' step mean was the midpoint sampling's, and a
/// log without the `actuated_step_mean` metadata re-runs with it. The old log is made as it
/// was: a midpoint run labelled `step_mean`, without the key.
#[test]
fn an_actuated_step_mean_log_of_before_the_reversal_split_matches() {
    let dir = tempfile::tempdir().unwrap();
    let write = |path: &std::path::Path, sampling: &str| {
        let toml: String = flapsim::ROBOBEE_TOML
            .lines()
            .map(|l| match l.starts_with("load_sampling = ") {
                true => format!("load_sampling = \"{sampling}\"\n"),
                false => format!("{l}\n"),
            })
            .collect();
        assert!(toml.contains(&format!("\nload_sampling = \"{sampling}\"\n")));
        let duration = 3.0
            / flapsim::Vehicle::from_toml(&toml, common::ORIGIN)
                .unwrap()
                .freq_hz();
        let opts = mcap_opts(path, None);
        common::record_model(
            &opts,
            "simulate",
            duration,
            flapsim::Mode::Free,
            &toml,
            common::ORIGIN,
        )
        .stats
        .samples
    };
    let new = dir.path().join("step_mean.mcap");
    let samples = write(&new, "step_mean");
    match check_log(&new).unwrap() {
        CheckOutcome::Match { samples: n, note } => {
            assert_eq!((n, note), (samples, None));
        }
        other => panic!("{other:?}"),
    }
    let midpoint = dir.path().join("midpoint.mcap");
    write(&midpoint, "midpoint");
    let old = dir.path().join("old.mcap");
    copy_with_metadata(&midpoint, &old, |md| {
        assert_eq!(
            md.remove("actuated_step_mean").as_deref(),
            Some("split_at_reversals")
        );
        md.insert("load_sampling".into(), "step_mean".into());
        let toml = md["model_toml"].replace("\"midpoint\"", "\"step_mean\"");
        md.insert("model_toml".into(), toml);
    });
    assert!(matches!(
        check_log(&old).unwrap(),
        CheckOutcome::Match { .. }
    ));
    // The two samplings do differ on this run, so the match above says something.
    let relabelled = dir.path().join("relabelled.mcap");
    copy_with_metadata(&new, &relabelled, |md| {
        md.remove("actuated_step_mean");
    });
    assert!(matches!(
        check_log(&relabelled).unwrap(),
        CheckOutcome::Mismatch { .. }
    ));
}

/// A log written since a stepping change, keyed by metadata `key` = `value`, re-runs bit for
/// bit, and one written before it still does: the old log is a run of `toml` over
/// `wingbeats` with the old stepping (`old` sets it on the spec), its metadata made as the
/// recorder wrote it then (`old_metadata`: without the key, or with the value it had).
/// The two steppings differ on the run, so the new log relabelled as old mismatches.
fn a_log_from_before_matches(
    toml: &str,
    wingbeats: f64,
    old: fn(&mut flapsim::VehicleSpec),
    key: &str,
    value: &str,
    old_metadata: fn(&mut std::collections::BTreeMap<String, String>),
) {
    let dir = tempfile::tempdir().unwrap();
    let write = |path: &std::path::Path, before: bool| {
        let mut spec = flapsim::VehicleSpec::from_toml(toml, common::ORIGIN).unwrap();
        if before {
            old(&mut spec);
        }
        let vehicle = spec.build(common::ORIGIN).unwrap();
        let duration = wingbeats / vehicle.freq_hz();
        let opts = mcap_opts(path, None);
        let mode = flapsim::Mode::Free;
        common::record_vehicle(
            &opts,
            "simulate",
            duration,
            mode,
            toml,
            common::ORIGIN,
            vehicle,
        )
        .stats
        .samples
    };
    let new = dir.path().join("new.mcap");
    let samples = write(&new, false);
    match check_log(&new).unwrap() {
        CheckOutcome::Match { samples: n, note } => assert_eq!((n, note), (samples, None)),
        other => panic!("{other:?}"),
    }
    let before = dir.path().join("before.mcap");
    write(&before, true);
    let old_log = dir.path().join("old.mcap");
    copy_with_metadata(&before, &old_log, old_metadata);
    assert!(matches!(
        check_log(&old_log).unwrap(),
        CheckOutcome::Match { .. }
    ));
    let relabelled = dir.path().join("relabelled.mcap");
    copy_with_metadata(&new, &relabelled, |md| {
        assert_eq!(md.get(key).map(String::as_str), Some(value));
        old_metadata(md);
    });
    assert!(matches!(
        check_log(&relabelled).unwrap(),
        CheckOutcome::Mismatch { .. }
    ));
}

/// A fly log since the midpoint rotation (flapsim's `host::midpoint_torque_world`): a
/// second-order log without the `body_rotation` metadata re-runs with rapier's own update of
/// the body's rates. The fly's run is symmetric, but the two updates still differ in its last
/// bits.
#[test]
fn a_log_of_before_the_midpoint_rotation_matches() {
    a_log_from_before_matches(
        flapsim::DROSOPHILA_TOML,
        10.0,
        |spec| spec.sim.rotation_at_step_start = true,
        "body_rotation",
        "midpoint",
        |md| {
            md.remove("body_rotation");
        },
    );
}

/// A hummingbird log since its stops' strikes were shared between steps for flapsim's
/// trapezoidal pose (wingset's `actuated::dynamics`, `strike.rs`, 2026-12-07): a log without
/// the `strike_impulse` metadata re-runs with each strike's impulse whole in its step. The
/// two differ (the body moves by the impulse's share a step later).
#[test]
fn a_log_of_before_the_strikes_were_shared_matches() {
    a_log_from_before_matches(
        flapsim::HUMMINGBIRD_TOML,
        3.0,
        |spec| spec.sim.strike_share = Some(StrikeShare::WholeInStep),
        "strike_impulse",
        "shared_for_the_trapezoidal_pose",
        |md| {
            md.remove("strike_impulse");
        },
    );
}

/// A hummingbird log since its stops' steps are split at stroke reversals (wingset's
/// `actuated::dynamics::stage_loads`): a log without the
/// `actuated_stage_loads` metadata re-runs with the loads taken afresh at every Runge-Kutta
/// stage. The two differ at the scheme's second-order error.
#[test]
fn a_log_of_before_the_stage_loads_were_interpolated_matches() {
    a_log_from_before_matches(
        flapsim::HUMMINGBIRD_TOML,
        3.0,
        |spec| spec.sim.actuated_stage_loads = StageLoads::EveryStage,
        "actuated_stage_loads",
        "interpolated_split_at_reversals",
        |md| {
            md.remove("actuated_stage_loads");
        },
    );
}

/// A hummingbird log of the morning of 2026-12-07, its stops' loads interpolated within
/// each step and its strikes shared for a semi-implicit pose (`actuated_stage_loads` =
/// `interpolated_between_segment_ends`, `strike_impulse` = `shared_with_next_step`), re-runs
/// as it was written; the split scheme and the trapezoid's shares differ from it.
#[test]
fn a_log_of_before_the_steps_were_split_matches() {
    a_log_from_before_matches(
        flapsim::HUMMINGBIRD_TOML,
        3.0,
        |spec| {
            spec.sim.actuated_stage_loads = StageLoads::Interpolated;
            spec.sim.strike_share = Some(StrikeShare::SemiImplicitPose);
        },
        "actuated_stage_loads",
        "interpolated_split_at_reversals",
        |md| {
            md.insert(
                "actuated_stage_loads".into(),
                "interpolated_between_segment_ends".into(),
            );
            md.insert("strike_impulse".into(), "shared_with_next_step".into());
        },
    );
}
