//! `flapwing validate`: the paper's cases and the operating points here, the vehicles section
//! in `validate/vehicles.rs`. The whole command runs once as text and once as JSON for all
//! of them (a run takes seconds: most of it the vehicles).

use crate::common;
#[path = "validate/vehicles.rs"]
mod vehicles;

use std::sync::OnceLock;

use common::{Run, flapwing};

/// `flapwing validate`, run once for every test that reads the text report.
fn full_text() -> &'static Run {
    static RUN: OnceLock<Run> = OnceLock::new();
    RUN.get_or_init(|| {
        let run = flapwing(&["validate"]);
        assert_eq!(run.code, 0, "{run:?}");
        run
    })
}

/// `flapwing validate --json`'s document, parsed once.
fn full_json() -> &'static serde_json::Value {
    static DOC: OnceLock<serde_json::Value> = OnceLock::new();
    DOC.get_or_init(|| {
        let run = flapwing(&["validate", "--json"]);
        assert_eq!(run.code, 0, "{run:?}");
        run.json()
    })
}

#[test]
fn every_case_passes_and_exits_0() {
    let run = full_text();
    assert!(run.stdout.contains("all 28 cases pass"), "{}", run.stdout);
    assert!(!run.stdout.contains("FAIL"));
}

#[test]
fn json_rows_all_pass() {
    let j = full_json();
    let cases = j["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 28);
    // 28 reproduction cases and 6 published operating points (issue 17).
    assert_eq!(j["total"], 34);
    assert_eq!(j["failed"], 0);
    let points = j["operating_points"].as_array().unwrap();
    assert_eq!(points.len(), 6);
    for p in points {
        let verdict = p["verdict"].as_str().unwrap();
        // A known limitation always carries its note; a pass never does.
        match verdict {
            "pass" => assert!(p["limitation"].is_null(), "{p}"),
            "known limitation" => assert!(p["limitation"].as_str().unwrap().len() > 20, "{p}"),
            _ => panic!("{p}"),
        }
        let err = p["relative_error"].as_f64().unwrap();
        let tol = p["relative_tolerance"].as_f64().unwrap();
        assert_eq!(verdict == "pass", err.abs() <= tol, "{p}");
    }
    assert_eq!(j["all_passed"], true);
    for c in cases {
        assert_eq!(c["pass"], true, "{c}");
        let error = c["error"].as_f64().unwrap();
        assert!(error.abs() <= c["tolerance"].as_f64().unwrap(), "{c}");
        for field in ["case", "source", "published", "computed", "rule"] {
            assert!(!c[field].is_null(), "{field} missing: {c}");
        }
    }
    // The published cases named in the brief are all there.
    let names: Vec<&str> = cases.iter().map(|c| c["case"].as_str().unwrap()).collect();
    for needle in [
        "V1 dCL_bar",
        "V4 mu*",
        "C_D,trans",
        "f_AR",
        "f_Ro",
        "Dickinson C_L(90",
        "C_L,WC",
        "R_g",
    ] {
        assert!(names.iter().any(|n| n.contains(needle)), "{needle}");
    }
}

/// `--section` runs only the sections named: the JSON leaves the others out and the totals
/// count what ran; the text prints only those tables. An unknown section is bad input naming
/// the flag and what is allowed.
#[test]
fn sections_run_alone() {
    let run = flapwing(&["validate", "--section", "cases", "--json"]);
    assert_eq!(run.code, 0, "{run:?}");
    let j = run.json();
    assert_eq!(j["cases"].as_array().unwrap().len(), 28);
    for absent in ["operating_points", "vehicles", "vehicles_passed"] {
        assert!(j.get(absent).is_none(), "{absent}: {j}");
    }
    assert_eq!(j["total"], 28);
    assert_eq!(j["passed"], 28);
    assert_eq!(j["all_passed"], true);
    // The full run's rows, unchanged.
    assert_eq!(j["cases"], full_json()["cases"]);

    let run = flapwing(&["validate", "--section", "cases,operating-points"]);
    assert_eq!(run.code, 0, "{run:?}");
    assert!(run.stdout.contains("all 28 cases pass"), "{}", run.stdout);
    assert!(
        !run.stdout
            .contains("built-in vehicles against measured data"),
        "{}",
        run.stdout
    );
    let full = &full_text().stdout;
    assert!(full.starts_with(&run.stdout), "{}", run.stdout);

    let run = flapwing(&["validate", "--section", "operating-points", "--json"]);
    assert_eq!(run.code, 0, "{run:?}");
    let j = run.json();
    assert_eq!(j["operating_points"], full_json()["operating_points"]);
    for absent in ["cases", "vehicles", "vehicles_passed", "vehicles_missed"] {
        assert!(j.get(absent).is_none(), "{absent}: {j}");
    }
    assert_eq!(j["total"], 6);

    let bad = flapwing(&["validate", "--section", "paper"]);
    bad.assert_bad_input();
    for needle in [
        "--section",
        "paper",
        "cases",
        "operating-points",
        "vehicles",
    ] {
        assert!(bad.stderr.contains(needle), "{needle}: {}", bad.stderr);
    }
}
