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
    assert_eq!(j["total"], 28);
    assert_eq!(j["failed"], 0);
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
