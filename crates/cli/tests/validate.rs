//! `flapwing validate`.

mod common;

use common::flapwing;

#[test]
fn every_case_passes_and_exits_0() {
    let run = flapwing(&["validate"]);
    assert_eq!(run.code, 0, "{run:?}");
    assert!(run.stdout.contains("all 28 cases pass"), "{}", run.stdout);
    assert!(!run.stdout.contains("FAIL"));
}

#[test]
fn json_rows_all_pass() {
    let run = flapwing(&["validate", "--json"]);
    assert_eq!(run.code, 0, "{run:?}");
    let j = run.json();
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
