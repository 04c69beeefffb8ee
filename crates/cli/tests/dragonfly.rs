//! The four-winged built-in dragonfly through the real binary: it flies (`--no-log`), its
//! logs carry every wing (frames, channels, planforms and force arrows) and replay, and it
//! hovers (trim and stability) from its forward-flight file.

use crate::common;

use common::{flapwing, flapwing_in};

#[test]
fn the_dragonfly_flies_without_a_log() {
    let run = flapwing(&[
        "simulate",
        "--model",
        "dragonfly",
        "--no-log",
        "--json",
        "--duration-s",
        "0.08",
    ]);
    assert_eq!(run.code, 0, "{run:?}");
    let j = run.json();
    assert_eq!(j["model"], "<built-in dragonfly>");
    // Free flight from the published 1.5 m/s: the wings carry 0.872 of the weight at the
    // frozen state (docs/models.md; crates/flapsim/tests/four_wings.rs), 0.843 over the first
    // two wingbeats (measured, at 40 and at 400 steps per wingbeat): the net drag of 0.138
    // weights slows the body from 1.5 to 1.37 m/s in those two wingbeats. Tolerance 0.04:
    // the motion's share.
    let lw = j["summary"]["mean_lift_over_weight"].as_f64().unwrap();
    assert!((lw - 0.872).abs() < 0.04, "{lw}");
}

/// The CSV export of one channel of `log`: (header, rows), each a list of cells.
fn csv_of(dir: &std::path::Path, log: &str, channel: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let out = dir.join(format!("{}.csv", channel.replace('/', "_")));
    let run = flapwing_in(
        dir,
        &["replay", log, "--csv", channel, out.to_str().unwrap()],
    );
    assert_eq!(run.code, 0, "{run:?}");
    let text = std::fs::read_to_string(&out).unwrap();
    let mut lines = text
        .lines()
        .map(|l| l.split(',').map(str::to_owned).collect());
    let header: Vec<String> = lines.next().unwrap();
    (header, lines.collect())
}

/// A row's cell in the column named `name`.
fn cell<'a>(header: &[String], row: &'a [String], name: &str) -> &'a str {
    let i = header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no {name}"));
    &row[i]
}

#[test]
fn a_log_of_four_wings_replays_with_every_wing() {
    let dir = tempfile::tempdir().unwrap();
    let run = flapwing_in(
        dir.path(),
        &[
            "simulate",
            "--model",
            "dragonfly",
            "--duration-s",
            "0.04",
            "--mcap",
            "d.mcap",
            "--rrd",
            "d.rrd",
        ],
    );
    assert_eq!(run.code, 0, "{run:?}");
    let labels = ["left", "right", "pairs0_left", "pairs0_right"];
    // The summary names the four wings and lists each one's frame and channels.
    let replay = flapwing_in(dir.path(), &["replay", "d.mcap"]);
    assert_eq!(replay.code, 0, "{replay:?}");
    assert!(
        replay
            .stdout
            .contains("wings      4: left, right, pairs0_left, pairs0_right"),
        "{}",
        replay.stdout
    );
    assert!(
        replay.stdout.contains("(all 4 wings, body frame)"),
        "{}",
        replay.stdout
    );
    let j = flapwing_in(dir.path(), &["replay", "d.mcap", "--json"]).json();
    assert_eq!(j["wings"], serde_json::json!(labels));
    let topics: Vec<&str> = j["channels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["topic"].as_str().unwrap())
        .collect();
    let samples = j["samples"].as_u64().unwrap();
    // 0.04 s at the dragonfly's 400 steps per wingbeat: 450 steps, logged at the log's
    // 2000 samples a second at most (80 measured).
    assert!(samples >= 40, "{samples}");
    for l in labels {
        for t in [
            format!("/tf/wing_{l}"),
            format!("/wing/{l}/kinematics"),
            format!("/wing/{l}/forces"),
        ] {
            let c = j["channels"]
                .as_array()
                .unwrap()
                .iter()
                .find(|c| c["topic"] == t.as_str())
                .unwrap_or_else(|| panic!("no {t} in {topics:?}"));
            assert_eq!(c["message_count"].as_u64(), Some(samples), "{t}");
        }
    }
    // Foxglove's 3D panel: each wing's transform is a child of base_link, its planform is
    // drawn in its frame and its force arrow comes from its hinge.
    let hinges: Vec<f64> = labels
        .iter()
        .map(|l| {
            let (h, rows) = csv_of(dir.path(), "d.mcap", &format!("/tf/wing_{l}"));
            assert_eq!(cell(&h, &rows[0], "parent_frame_id"), "base_link");
            assert_eq!(cell(&h, &rows[0], "child_frame_id"), format!("wing_{l}"));
            cell(&h, &rows[0], "translation.x").parse().unwrap()
        })
        .collect();
    // Forewings ahead of the centre of mass, hindwings behind (models/dragonfly.toml).
    assert!(
        hinges[0] > 0.0 && hinges[1] > 0.0 && hinges[2] < 0.0 && hinges[3] < 0.0,
        "{hinges:?}"
    );
    let (h, rows) = csv_of(dir.path(), "d.mcap", "/scene/wings");
    let (fh, frows) = csv_of(dir.path(), "d.mcap", "/scene/forces");
    assert_eq!(frows.len() as u64, samples);
    for (k, l) in labels.iter().enumerate() {
        assert_eq!(
            cell(&h, &rows[0], &format!("entities.{k}.frame_id")),
            format!("wing_{l}")
        );
        assert_eq!(
            cell(&fh, &frows[0], &format!("entities.{k}.id")),
            format!("force_{l}")
        );
        let x: f64 = cell(
            &fh,
            &frows[0],
            &format!("entities.{k}.arrows.0.pose.position.x"),
        )
        .parse()
        .unwrap();
        assert_eq!(x, hinges[k], "{l}");
    }
    assert!(
        !fh.iter().any(|c| c.starts_with("entities.4.")),
        "four arrows, no more"
    );
    // The log re-runs bit for bit and converts to Rerun with every sample.
    let check = flapwing_in(dir.path(), &["replay", "d.mcap", "--check"]);
    assert_eq!(check.code, 0, "{check:?}");
    assert!(
        check
            .stdout
            .contains(&format!("match: {samples} samples identical")),
        "{check:?}"
    );
    let rrd = flapwing_in(dir.path(), &["replay", "d.mcap", "--rrd", "again.rrd"]);
    assert_eq!(rrd.code, 0, "{rrd:?}");
    assert!(
        rrd.stdout.contains(&format!("wrote {samples} samples")),
        "{rrd:?}"
    );
    assert!(std::fs::metadata(dir.path().join("d.rrd")).unwrap().len() > 10_000);
}

#[test]
fn the_dragonfly_hovers_and_its_stability_runs() {
    // The file holds the body level for forward flight; the hover trim is found from the
    // pitch that levels the stroke planes (crates/flapsim/tests/hover_start.rs). Before
    // 2026-12-06 these commands refused the dragonfly ("no hover trim").
    let run = flapwing(&["trim", "--model", "dragonfly", "--json"]);
    assert_eq!(run.code, 0, "{run:?}");
    let j = run.json();
    for r in [
        "residual_fx_over_weight",
        "residual_fz_over_weight",
        "residual_my_over_weight_length",
    ] {
        assert!(j[r].as_f64().unwrap().abs() < 1e-10, "{r}: {j}");
    }
    let run = flapwing(&["stability", "--model", "dragonfly"]);
    assert_eq!(run.code, 0, "{run:?}");
    assert!(run.stdout.contains("Floquet exponents"), "{run:?}");
}
