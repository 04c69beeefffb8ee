//! `flapwing wake-capture`.

use crate::common;

use common::{argv, flapwing, sig5};

#[test]
fn v1_row_of_table5_in_json() {
    // Seed paper Table 5, run V1: Re 272, dtau_D 0.06, dtau_A 0.09.
    let run = flapwing(&argv(
        "wake-capture --re 272 --dtau-a 0.09 --dtau-d 0.06 --json",
    ));
    assert_eq!(run.code, 0, "{run:?}");
    let j = run.json();
    let raw = &j["raw"];
    assert!(
        (sig5(raw["dcl_bar"].as_f64().unwrap()) - 0.43986).abs() < 1e-12,
        "{j}"
    );
    assert!(
        (sig5(raw["dcd_bar"].as_f64().unwrap()) - 0.50261).abs() < 1e-12,
        "{j}"
    );
    assert!(
        (raw["mu_star"].as_f64().unwrap() - 0.04703).abs() < 5e-6,
        "{j}"
    );
    // All three inputs lie in the fitted range, so the simulator uses the same values.
    for input in ["re", "dtau_a", "dtau_d"] {
        let i = &j["inputs"][input];
        assert_eq!(i["inside"], true, "{input}: {j}");
        assert_eq!(i["clamped_value"], i["value"], "{input}: {j}");
    }
    assert_eq!(j["any_clamped"], false);
    assert_eq!(j["clamped"], j["raw"]);
}

#[test]
fn v2_row_reports_the_clamped_deceleration() {
    // Run V2 has dtau_D = 0.03, below the fitted 0.06-0.18: the raw formula still gives the
    // published 0.65305, the simulator evaluates it at 0.06.
    let run = flapwing(&argv(
        "wake-capture --re 408 --dtau-a 0.12 --dtau-d 0.03 --json",
    ));
    assert_eq!(run.code, 0, "{run:?}");
    let j = run.json();
    assert!((sig5(j["raw"]["dcl_bar"].as_f64().unwrap()) - 0.65305).abs() < 1e-12);
    assert_eq!(j["inputs"]["dtau_d"]["inside"], false);
    assert_eq!(j["inputs"]["dtau_d"]["clamped_value"], 0.06);
    assert_eq!(j["inputs"]["re"]["inside"], true);
    assert_eq!(j["any_clamped"], true);
    assert_ne!(j["clamped"]["dcl_bar"], j["raw"]["dcl_bar"]);
    assert_eq!(j["clamped"]["mu_star"], j["raw"]["mu_star"]);
}

#[test]
fn text_report_shows_both_columns() {
    let run = flapwing(&argv("wake-capture --re 1360 --dtau-a 0.12 --dtau-d 0.12"));
    assert_eq!(run.code, 0, "{run:?}");
    for needle in [
        "dCL_bar",
        "0.27107",
        "0.27139",
        "0.04942",
        "raw formula",
        "clamped",
    ] {
        assert!(run.stdout.contains(needle), "{needle}: {}", run.stdout);
    }
}

#[test]
fn bad_values_exit_2() {
    for (flag, value) in [
        ("--re", "-5"),
        ("--re", "0"),
        ("--re", "nan"),
        ("--re", "inf"),
        ("--dtau-a", "0.5"),
        ("--dtau-d", "0"),
        ("--dtau-d", "abc"),
    ] {
        let mut args = argv("wake-capture --re 272 --dtau-a 0.09 --dtau-d 0.06");
        let i = args.iter().position(|a| *a == flag).unwrap();
        args[i + 1] = value;
        let run = flapwing(&args);
        run.assert_bad_input();
        assert!(run.stderr.contains(flag), "{flag} {value}: {}", run.stderr);
    }
    flapwing(&["wake-capture", "--re", "272"]).assert_bad_input();
}
