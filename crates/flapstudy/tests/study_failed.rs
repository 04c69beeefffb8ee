//! Failed cases (issue #40): a case whose analysis fails is a row with its reason; which
//! errors fail a case and which stop the study; the summary; shards and their merge; the
//! optimizer's start when designs fail.
//!
//! The RoboBee's wings must settle into a periodic motion within `[actuation] settle_cycles`
//! drive periods; with 3 of them, 6 of the 9 cases below do not (cheap: a few ms each), at
//! the step-start sampling and 100 steps per wingbeat (`pinned`).

use flapstudy::optimize::{NelderMeadOptions, optimize_hover, start_candidates};
use flapstudy::spec::StudySpec;
use flapstudy::sweep::{
    FailedCase, LISTED_FAILURES, csv_cell_text, failed_rows, failure_summary, is_case_failure,
};
use flapstudy::{CaseOutcome, Study, StudyError, merge_csv};

mod support {
    pub mod pinned;
}

/// A study of an actuated vehicle (in this binary to keep the link count down).
mod study_actuated;
use support::pinned::pinned;

const STUDY: &str = r#"
base_model = "robobee"
design = "full_factorial"
responses = ["lift_over_weight", "aero_power_w"]
[[factor]]
path = "actuation.hinge.stiffness_nm_rad"
levels = [3.0e-6, 4.6e-6, 7.5e-6]
[[factor]]
path = "actuation.drive.freq_hz"
levels = [120.0, 150.0, 170.0]
"#;

/// The study on the built-in RoboBee (pinned) with `settle` drive periods to settle in.
fn robobee_study(settle: usize) -> Study {
    let spec = StudySpec::from_toml(STUDY, "test.toml").unwrap();
    let base = pinned(flapsim::builtin_model("robobee").unwrap());
    let edited = base.replacen(
        "\n[actuation]\n",
        &format!("\n[actuation]\nsettle_cycles = {settle}\n"),
        1,
    );
    assert_ne!(edited, base, "the model's [actuation] table moved");
    spec.resolve("test.toml", "rb", &edited, "robobee").unwrap()
}

#[test]
fn failed_cases_are_rows_with_their_reason_and_survive_the_merge() {
    let s = robobee_study(3);
    let results = s.run(0..9, &|_| ()).unwrap();
    assert_eq!(results.len(), 9);
    let failed: Vec<usize> = results
        .iter()
        .filter(|r| r.failure().is_some())
        .map(|r| r.case)
        .collect();
    assert_eq!(failed, [0, 1, 2, 5, 7, 8]);
    for r in &results {
        match &r.outcome {
            CaseOutcome::Failed(why) => {
                assert!(
                    why.contains("did not settle into a periodic motion in 3 drive periods"),
                    "{why}"
                );
                assert!(r.responses.iter().all(|v| v.is_nan()));
            }
            CaseOutcome::Done(all) => {
                assert!(r.responses.iter().all(|v| v.is_finite()));
                assert!(all.aero_power_w > 0.0);
            }
        }
    }
    let whole = s.csv(&results);
    assert!(whole.starts_with(
        "case,actuation.hinge.stiffness_nm_rad,actuation.drive.freq_hz,lift_over_weight,aero_power_w,reynolds,wake_capture_clamped,status,error\n"
    ));
    let row0 = whole.lines().nth(1).unwrap();
    assert!(
        row0.starts_with("0,3e-6,120.0,,,,,failed,the wings of robobee did not settle"),
        "{row0}"
    );
    let row3 = whole.lines().nth(4).unwrap();
    assert!(
        row3.starts_with("3,4.6e-6,120.0,") && row3.ends_with(",ok,"),
        "{row3}"
    );

    // Shards of it, run apart and merged, give the same table, failed rows and all.
    let parts: Vec<(String, String)> = (1..=3)
        .map(|k| {
            let part = s.run(s.shard_range(k, 3), &|_| ()).unwrap();
            (format!("shard {k}"), s.csv(&part))
        })
        .collect();
    assert_eq!(merge_csv(&parts).unwrap(), whole);

    // The failed rows read back from the table are those of the run.
    let from_table = failed_rows(&whole, "whole.csv").unwrap();
    assert_eq!(from_table, s.failed_cases(&results));
    assert_eq!(
        from_table[0].settings,
        "actuation.hinge.stiffness_nm_rad = 3e-6, actuation.drive.freq_hz = 120"
    );
    let summary = failure_summary(&from_table, 9);
    assert!(
        summary.starts_with(
            "6 of 9 case(s) failed (status = failed; the reason is in the `error` column): case(s) 0, 1, 2, 5, 7, 8\n  case 0 (actuation.hinge.stiffness_nm_rad = 3e-6, actuation.drive.freq_hz = 120): the wings"
        ),
        "{summary}"
    );
    assert_eq!(summary.lines().count(), 7);
    // A table without failures reports none, and a status it does not know is an error.
    assert!(failure_summary(&[], 9).is_empty());
    let bad = whole.replacen(",ok,", ",maybe,", 1);
    let e = failed_rows(&bad, "bad.csv").unwrap_err().to_string();
    assert!(
        e.contains("column `status` (8): `maybe` is not a case status"),
        "{e}"
    );
}

#[test]
fn what_fails_a_case_and_what_stops_the_study() {
    assert!(is_case_failure(&flapsim::Error::Analysis("no trim".into())));
    assert!(is_case_failure(&flapsim::Error::Diverged {
        t_s: 0.1,
        step: 10,
        reason: "hinge past its stops".into()
    }));
    assert!(!is_case_failure(&flapsim::Error::Input("4 wings".into())));
    assert!(!is_case_failure(&flapsim::Error::Model(
        wingforce::Error::Parse {
            origin: "m.toml".into(),
            message: "unknown field".into()
        }
    )));

    // A combination of valid levels the model refuses: an error before any case runs.
    let text = r#"
base_model = "drosophila"
design = "full_factorial"
responses = ["lift_over_weight"]
[[factor]]
path = "kinematics.dtau_a"
levels = [0.1, 0.3]
[[factor]]
path = "kinematics.dtau_d"
levels = [0.1, 0.3]
"#;
    let spec = StudySpec::from_toml(text, "combo.toml").unwrap();
    let s = spec
        .resolve(
            "combo.toml",
            "combo",
            flapsim::DROSOPHILA_TOML,
            "drosophila",
        )
        .unwrap();
    let e = s.check_cases(0..4).unwrap_err();
    assert!(
        matches!(e, StudyError::Case { case: 3, .. }),
        "{e}: the first refused case"
    );
    let ran = std::sync::atomic::AtomicUsize::new(0);
    let e = s
        .run(0..4, &|_| {
            ran.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        })
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("case 3 (kinematics.dtau_a = 0.3, kinematics.dtau_d = 0.3): "),
        "{e}"
    );
    assert_eq!(ran.into_inner(), 0, "no case runs before the check");
    // The cases that make valid vehicles pass.
    s.check_cases(0..3).unwrap();
}

#[test]
fn reasons_fit_one_cell_and_long_lists_are_cut() {
    assert_eq!(csv_cell_text("a, b\nc\r"), "a; b c ");
    let many: Vec<FailedCase> = (0..LISTED_FAILURES + 2)
        .map(|case| FailedCase {
            case,
            settings: format!("x = {case}"),
            reason: "no".into(),
        })
        .collect();
    let text = failure_summary(&many, 100);
    let lines: Vec<&str> = text.lines().collect();
    assert!(
        lines[0].starts_with("12 of 100 case(s) failed") && lines[0].ends_with("8, 9, ..."),
        "{text}"
    );
    assert_eq!(lines.len(), 1 + LISTED_FAILURES + 1, "{text}");
    assert_eq!(
        lines[LISTED_FAILURES + 1],
        "  ... and 2 more failed case(s)"
    );
}

#[test]
fn the_optimizer_starts_where_a_design_works_and_says_when_none_does() {
    let c = start_candidates(2);
    assert_eq!(c.len(), 25);
    assert_eq!(c[0].as_slice(), [0.5, 0.5]);
    assert_eq!(
        c[1].as_slice(),
        [0.5, 0.25],
        "nearest first, ties in a fixed order"
    );
    assert!(
        c[24].iter().all(|&x| x == 0.0 || x == 1.0),
        "a corner last: {}",
        c[24]
    );
    let d = |p: &[f64]| p.iter().map(|x| (x - 0.5) * (x - 0.5)).sum::<f64>();
    assert!(
        c.windows(2)
            .all(|w| d(w[0].as_slice()) <= d(w[1].as_slice()))
    );
    let five = start_candidates(5);
    assert_eq!(five.len(), flapstudy::optimize::MAX_START_CANDIDATES);
    assert_eq!(five[0].as_slice(), [0.5; 5]);

    // One drive period: no design settles, and the search says so.
    let none = robobee_study(1);
    let opts = NelderMeadOptions {
        max_evals: 40,
        ..NelderMeadOptions::default()
    };
    match optimize_hover(&none, 1.0, &opts) {
        Err(StudyError::AllFailed {
            tried,
            settings,
            reason,
        }) => {
            assert_eq!(tried, 25);
            assert_eq!(
                settings,
                "actuation.hinge.stiffness_nm_rad = 5.2500000000000006e-6, actuation.drive.freq_hz = 145"
            );
            assert!(reason.contains("did not settle"), "{reason}");
        }
        other => panic!("expected AllFailed, got {other:?}"),
    }
}
