//! Failed cases of a study (issue #40): a case whose analysis fails (wings that do not settle,
//! dynamics that diverge) is a row with its reason, the other cases finish, the summary says
//! which failed; shards and their merge keep the failed rows; `optimize` counts failed designs
//! as infeasible; a bad study stays bad input before any case runs.
//!
//! The RoboBee's wings start from rest and must settle into a periodic motion within
//! `[actuation] settle_cycles` drive periods: the shipped study (40 periods, the model's value)
//! has one such case, and a copy of the model with fewer periods has more (cheap cases, well
//! under a second each run).

use crate::common;

use common::flapwing_in;

#[path = "../../flapstudy/tests/support/pinned.rs"]
mod pinned;
use pinned::pinned;

const ROBOBEE_STUDY: &str = include_str!("../../../examples/studies/robobee_hinge_drive.toml");
const ROBOBEE_MODEL: &str = include_str!("../../../models/robobee.toml");

/// A temporary directory with the shipped RoboBee study, and the same study on a copy of the
/// model (pinned) that gives the wings `settle` drive periods (`few.toml`, study name `few`).
fn robobee_dir(settle: usize) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("rb.toml"), ROBOBEE_STUDY).unwrap();
    let model = pinned(ROBOBEE_MODEL).replacen(
        "\n[actuation]\n",
        &format!("\n[actuation]\nsettle_cycles = {settle}\n"),
        1,
    );
    assert_ne!(model, ROBOBEE_MODEL, "the model's [actuation] table moved");
    std::fs::write(dir.path().join("robobee_few.toml"), model).unwrap();
    let study = ROBOBEE_STUDY
        .replace(
            "base_model = \"robobee\"",
            "base_model = \"robobee_few.toml\"",
        )
        .replace("name = \"robobee_hinge_drive\"", "name = \"few\"");
    std::fs::write(dir.path().join("few.toml"), study).unwrap();
    dir
}

fn read(dir: &tempfile::TempDir, path: &str) -> String {
    std::fs::read_to_string(dir.path().join(path)).unwrap()
}

/// (case, status, error, the response cells) of each row of a sweep CSV.
fn rows(csv: &str) -> Vec<(usize, String, String, Vec<String>)> {
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(header[header.len() - 2..], ["status", "error"], "{csv}");
    lines
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            assert_eq!(c.len(), header.len(), "{l}");
            let n = c.len();
            (
                c[0].parse().unwrap(),
                c[n - 2].to_owned(),
                c[n - 1].to_owned(),
                c[3..n - 2].iter().map(|s| s.to_string()).collect(),
            )
        })
        .collect()
}

/// The shipped study on the built-in RoboBee (its step mean at 100 steps per wingbeat): two
/// cases fail. Case 1 (3e-6 N m/rad, 150 Hz): its soft hinge breaks (pitch past its 85 deg
/// limit), as at every step count from 40 to 800 with the step mean and at 400 and 1600 with
/// the step-start sampling (`flapwing frequency-response --steps-per-cycle N` on a copy; at
/// the step-start sampling's 100 steps it settled). Case 2 (3e-6 N m/rad, 170 Hz) does not
/// settle in 40 periods, as before (below, on the pinned copy, the cases the failure
/// handling was written against).
#[test]
fn the_issue_40_robobee_sweep_finishes_with_nine_rows() {
    let dir = robobee_dir(40);
    let shipped = flapwing_in(dir.path(), &["sweep", "rb.toml", "--out", "s", "--strict"]);
    assert_eq!(shipped.code, 1, "{shipped:?}");
    assert!(shipped.stdout.contains(": 9 of 9 cases"), "{shipped:?}");
    assert!(
        shipped.stdout.contains("2 of 9 case(s) failed")
            && shipped.stdout.contains(
                "  case 1 (actuation.hinge.stiffness_nm_rad = 3e-6, actuation.drive.freq_hz = 150): the wings of robobee have no periodic motion"
            )
            && shipped.stdout.contains("is too soft for this drive")
            && shipped.stdout.contains(
                "  case 2 (actuation.hinge.stiffness_nm_rad = 3e-6, actuation.drive.freq_hz = 170): the wings of robobee did not settle"
            ),
        "{shipped:?}"
    );
    let run = flapwing_in(dir.path(), &["sweep", "few.toml", "--out", "a"]);
    assert_eq!(run.code, 0, "{run:?}");
    assert!(run.stdout.contains(": 9 of 9 cases"), "{run:?}");
    assert!(
        run.stdout.contains("1 of 9 case(s) failed")
            && run.stdout.contains(
                "  case 2 (actuation.hinge.stiffness_nm_rad = 3e-6, actuation.drive.freq_hz = 170): the wings of robobee did not settle"
            ),
        "{run:?}"
    );
    let csv = read(&dir, "a/few.csv");
    let rows = rows(&csv);
    assert_eq!(rows.len(), 9, "{csv}");
    for (i, (case, status, error, cells)) in rows.iter().enumerate() {
        assert_eq!(*case, i);
        if i == 2 {
            assert_eq!(status, "failed", "{csv}");
            assert!(
                error.contains("did not settle into a periodic motion in 40 drive periods")
                    && error.contains("raise [actuation] settle_cycles"),
                "{error}"
            );
            assert!(cells.iter().all(String::is_empty), "{csv}");
        } else {
            assert_eq!((status.as_str(), error.as_str()), ("ok", ""), "{csv}");
            for c in cells {
                assert!(c.parse::<f64>().unwrap().is_finite(), "{csv}");
            }
        }
    }
    // --strict: the same table, then exit 1 naming the failures.
    let strict = flapwing_in(dir.path(), &["sweep", "few.toml", "--out", "b", "--strict"]);
    assert_eq!(strict.code, 1, "{strict:?}");
    assert!(
        strict.stderr.contains("--strict: 1 case(s) failed"),
        "{strict:?}"
    );
    assert_eq!(read(&dir, "b/few.csv"), csv);
}

#[test]
fn shards_and_their_merge_keep_the_failed_rows() {
    let dir = robobee_dir(3);
    let run = flapwing_in(dir.path(), &["sweep", "few.toml", "--out", "whole"]);
    assert_eq!(run.code, 0, "{run:?}");
    assert!(run.stdout.contains("6 of 9 case(s) failed"), "{run:?}");
    let whole = read(&dir, "whole/few.csv");
    let failed: Vec<usize> = rows(&whole)
        .into_iter()
        .filter(|r| r.1 == "failed")
        .map(|r| r.0)
        .collect();
    assert_eq!(failed, [0, 1, 2, 5, 7, 8], "{whole}");
    for k in 1..=3 {
        let shard = format!("{k}/3");
        let args = ["sweep", "few.toml", "--out", "parts", "--shard", &shard];
        let run = flapwing_in(dir.path(), &args);
        assert_eq!(run.code, 0, "{run:?}");
        assert!(run.stdout.contains("of 3 case(s) failed"), "{run:?}");
        // A complete shard is skipped, and still reports its failed cases.
        let again = flapwing_in(dir.path(), &args);
        assert_eq!(again.code, 0, "{again:?}");
        assert!(
            again.stdout.contains("is already complete") && again.stdout.contains("failed"),
            "{again:?}"
        );
    }
    // `status` counts the shards done, and lists their failed cases.
    let status = flapwing_in(dir.path(), &["status", "parts", "--json"]);
    assert_eq!(status.code, 0, "{status:?}");
    let j = status.json();
    assert_eq!(j["studies"][0]["done"], serde_json::json!([1, 2, 3]), "{j}");
    assert_eq!(
        j["studies"][0]["failed_cases"],
        serde_json::json!([0, 1, 2, 5, 7, 8]),
        "{j}"
    );
    let status = flapwing_in(dir.path(), &["status", "parts"]);
    assert!(
        status
            .stdout
            .contains("  failed cases in done shards: 6 (0,1,2,5,7,8;"),
        "{status:?}"
    );
    let merge = flapwing_in(dir.path(), &["sweep", "merge", "parts"]);
    assert_eq!(merge.code, 0, "{merge:?}");
    assert!(
        merge.stdout.contains("9 cases") && merge.stdout.contains("6 of 9 case(s) failed"),
        "{merge:?}"
    );
    assert!(
        merge.stdout.contains(
            "  case 8 (actuation.hinge.stiffness_nm_rad = 7.5e-6, actuation.drive.freq_hz = 170): the wings of robobee did not settle"
        ),
        "{merge:?}"
    );
    assert_eq!(read(&dir, "parts/few.csv"), whole);
    let strict = flapwing_in(
        dir.path(),
        &["sweep", "merge", "parts", "--force", "--strict"],
    );
    assert_eq!(strict.code, 1, "{strict:?}");
    assert_eq!(read(&dir, "parts/few.csv"), whole);
    // `sweep analyze` of a table with failed rows names the row and why it has no value.
    let analyze = flapwing_in(
        dir.path(),
        &[
            "sweep",
            "analyze",
            "whole/few.csv",
            "--response",
            "lift_over_weight",
        ],
    );
    analyze.assert_bad_input();
    assert!(
        analyze.stderr.contains("line 2") && analyze.stderr.contains("this case failed"),
        "{analyze:?}"
    );
}

#[test]
fn optimize_counts_failed_designs_as_infeasible_and_says_when_all_fail() {
    // 4 drive periods: the centre of this box (3.8e-6 N m/rad, 155 Hz) does not settle.
    let dir = robobee_dir(4);
    let boxed = read(&dir, "few.toml")
        .replace(
            "levels = [3.0e-6, 4.6e-6, 7.5e-6]",
            "levels = [3.0e-6, 4.6e-6]",
        )
        .replace("levels = [120.0, 150.0, 170.0]", "levels = [140.0, 170.0]");
    std::fs::write(dir.path().join("box.toml"), boxed).unwrap();
    let run = flapwing_in(
        dir.path(),
        &["optimize", "box.toml", "--max-evals", "40", "--json"],
    );
    assert_eq!(run.code, 0, "{run:?}");
    let j = run.json();
    assert!(j["starts_tried"].as_u64().unwrap() > 1, "{j}");
    assert!(j["failed_evals"].as_u64().unwrap() >= 1, "{j}");
    assert!(
        j["first_failure"]
            .as_str()
            .unwrap()
            .contains("did not settle"),
        "{j}"
    );
    assert_eq!(j["feasible"], true, "{j}");
    assert!(j["best"]["lift_over_weight"].as_f64().unwrap() >= 1.0 - 1e-6);
    let text = flapwing_in(dir.path(), &["optimize", "box.toml", "--max-evals", "40"]);
    assert_eq!(text.code, 0, "{text:?}");
    assert!(
        text.stdout
            .contains("the box centre failed: the search started from design")
            && text
                .stdout
                .contains("design(s) failed and counted as infeasible"),
        "{text:?}"
    );

    // One drive period: no design settles.
    let none = robobee_dir(1);
    let run = flapwing_in(none.path(), &["optimize", "few.toml", "--max-evals", "40"]);
    assert_eq!(run.code, 1, "{run:?}");
    assert!(
        run.stderr.contains("every design tried failed (25 designs")
            && run
                .stderr
                .contains("did not settle into a periodic motion in 1 drive periods"),
        "{run:?}"
    );
}

#[test]
fn a_bad_study_is_bad_input_before_any_case_runs() {
    let dir = robobee_dir(40);
    let cases = [
        // A typo'd field.
        (
            ROBOBEE_STUDY.replace("hinge.stiffness_nm_rad", "hinge.stifness_nm_rad"),
            "stifness_nm_rad",
        ),
        // A level the model refuses.
        (
            ROBOBEE_STUDY.replace("levels = [3.0e-6,", "levels = [-3.0e-6,"),
            "stiffness_nm_rad",
        ),
    ];
    for (i, (study, named)) in cases.iter().enumerate() {
        let file = format!("bad{i}.toml");
        std::fs::write(dir.path().join(&file), study).unwrap();
        let run = flapwing_in(dir.path(), &["sweep", &file, "--out", "bad"]);
        run.assert_bad_input();
        assert!(run.stderr.contains(named), "{run:?}");
        assert!(
            !dir.path().join("bad/robobee_hinge_drive.csv").exists(),
            "{run:?}"
        );
    }
    // A combination of valid levels the model refuses: the first such case, before any runs.
    let combo = "base_model = \"drosophila\"\ndesign = \"full_factorial\"\nresponses = [\"lift_over_weight\"]\n[[factor]]\npath = \"kinematics.dtau_a\"\nlevels = [0.1, 0.3]\n[[factor]]\npath = \"kinematics.dtau_d\"\nlevels = [0.1, 0.3]\n";
    std::fs::write(dir.path().join("combo.toml"), combo).unwrap();
    let run = flapwing_in(dir.path(), &["sweep", "combo.toml", "--out", "bad"]);
    run.assert_bad_input();
    assert!(
        run.stderr
            .contains("case 3 (kinematics.dtau_a = 0.3, kinematics.dtau_d = 0.3)"),
        "{run:?}"
    );
    assert!(!dir.path().join("bad/combo.csv").exists());
}
