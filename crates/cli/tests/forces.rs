//! `flapwing forces`.

use crate::common;

/// Every built-in vehicle's wing.
#[path = "forces_vehicles/mod.rs"]
mod forces_vehicles;

use common::{ROBOFLY, flapwing, flapwing_in};
use serde_json::Value;

const TERMS: [&str; 5] = [
    "translational",
    "rotational",
    "added_mass",
    "wake_capture",
    "total",
];

fn c_l(j: &Value, term: &str) -> f64 {
    j["mean_last_cycle"][term]["c_l"].as_f64().unwrap()
}

fn c_d(j: &Value, term: &str) -> f64 {
    j["mean_last_cycle"][term]["c_d"].as_f64().unwrap()
}

#[test]
fn built_in_robofly_in_json() {
    let run = flapwing(&["forces", "--json"]);
    assert_eq!(run.code, 0, "{run:?}");
    let j = run.json();
    for term in TERMS {
        assert!(
            c_l(&j, term).is_finite() && c_d(&j, term).is_finite(),
            "{term}: {j}"
        );
    }
    assert_eq!(j["source"], "<built-in robofly>");
    assert!((j["reynolds"].as_f64().unwrap() - 1360.0).abs() < 1e-9);
    assert!((j["v_ref_m_s"].as_f64().unwrap() - 0.1905).abs() < 1e-12);
    assert_eq!(j["wake_capture_clamped"], false);
    assert!(
        run.stderr.is_empty(),
        "no warning inside the fitted range: {}",
        run.stderr
    );
    // The wake-capture term is a positive Gaussian at the start of each half stroke holding
    // 0.1 dCL_bar of area (eq 22-23), so it adds about 0.2 dCL_bar = 0.054 to the cycle-mean
    // lift; the rotational term averages to zero over symmetric pitch flips and the
    // added-mass term does not take lift away, so the total exceeds the translational part.
    let dcl = j["wake_capture"]["clamped"]["dcl_bar"].as_f64().unwrap();
    assert!(
        (c_l(&j, "wake_capture") - 0.2 * dcl).abs() < 0.002 * dcl,
        "{j}"
    );
    assert!(c_l(&j, "total") > c_l(&j, "translational"), "{j}");
    let sum: f64 = TERMS[..4].iter().map(|t| c_l(&j, t)).sum();
    assert!((sum - c_l(&j, "total")).abs() < 1e-12);
}

#[test]
fn no_wake_capture_zeroes_the_term_and_changes_nothing_else() {
    let on = flapwing(&["forces", "--json"]).json();
    let run = flapwing(&["forces", "--json", "--no-wake-capture"]);
    assert_eq!(run.code, 0, "{run:?}");
    let off = run.json();
    assert!(off["wake_capture"].is_null());
    assert_eq!(c_l(&off, "wake_capture"), 0.0);
    assert_eq!(c_d(&off, "wake_capture"), 0.0);
    // With the wake term zero the total is the sum of the other three exactly as before. It
    // is not the translational term alone: the added-mass term of eq 7 (normal acceleration
    // only) has a non-zero cycle-mean lift from the pitch accelerations at stroke reversal.
    for term in ["translational", "rotational", "added_mass"] {
        assert_eq!(c_l(&off, term), c_l(&on, term), "{term}");
        assert_eq!(c_d(&off, term), c_d(&on, term), "{term}");
    }
    let others: f64 = ["translational", "rotational", "added_mass"]
        .iter()
        .map(|t| c_l(&off, t))
        .sum();
    assert!((c_l(&off, "total") - others).abs() < 1e-12);
    let wake = c_l(&on, "total") - c_l(&off, "total");
    assert!((wake - c_l(&on, "wake_capture")).abs() < 1e-12);
}

#[test]
fn csv_has_the_header_and_one_row_per_step() {
    let dir = tempfile::tempdir().unwrap();
    let run = flapwing_in(
        dir.path(),
        &[
            "forces",
            "--cycles",
            "2",
            "--steps-per-cycle",
            "50",
            "--csv",
            "series.csv",
        ],
    );
    assert_eq!(run.code, 0, "{run:?}");
    let text = std::fs::read_to_string(dir.path().join("series.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "t_s,cycle,t_star,half_stroke,phi_rad,theta_rad,\
         cl_translational,cd_translational,cl_rotational,cd_rotational,\
         cl_added_mass,cd_added_mass,cl_wake_capture,cd_wake_capture,cl_total,cd_total"
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 2 * 50);
    assert!(
        rows.iter()
            .all(|r| r.len() == 16 && r.iter().all(|x| x.is_finite()))
    );
    // Samples sit mid-step: t = (i + 1/2) T / K.
    let period = 1.0
        / flapwing(&["forces", "--json"]).json()["freq_hz"]
            .as_f64()
            .unwrap();
    assert!((rows[0][0] - 0.5 * period / 50.0).abs() < 1e-12);
    assert!((rows[99][0] - 99.5 * period / 50.0).abs() < 1e-9);
    assert_eq!((rows[49][1], rows[50][1]), (0.0, 1.0), "cycle column");
    assert_eq!(
        (rows[24][3], rows[25][3], rows[99][3]),
        (0.0, 1.0, 3.0),
        "half strokes"
    );
    // Every row's total is the sum of its terms.
    for r in &rows {
        let cl: f64 = (0..4).map(|k| r[6 + 2 * k]).sum();
        assert!((cl - r[14]).abs() < 1e-9, "{r:?}");
    }
}

#[test]
fn csv_is_not_overwritten_without_force() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("series.csv");
    std::fs::write(&path, "precious\n").unwrap();
    let args = ["forces", "--steps-per-cycle", "10", "--csv", "series.csv"];
    let run = flapwing_in(dir.path(), &args);
    run.assert_bad_input();
    assert!(
        run.stderr.contains("series.csv") && run.stderr.contains("--force"),
        "{}",
        run.stderr
    );
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "precious\n");

    let run = flapwing_in(dir.path(), &[&args[..], &["--force"]].concat());
    assert_eq!(run.code, 0, "{run:?}");
    assert_eq!(
        std::fs::read_to_string(&path).unwrap().lines().count(),
        1 + 3 * 10
    );
}

#[test]
fn overrides_out_of_the_fitted_range_warn_once() {
    // Run V2's conditions: dtau_D = 0.03 is below the fitted range and gets clamped.
    let run = flapwing(&[
        "forces", "--json", "--re", "408", "--dtau-a", "0.12", "--dtau-d", "0.03",
    ]);
    assert_eq!(run.code, 0, "{run:?}");
    let j = run.json();
    assert!((j["reynolds"].as_f64().unwrap() - 408.0).abs() < 1e-9);
    assert_eq!(j["wake_capture_clamped"], true);
    assert_eq!(j["wake_capture"]["inputs"]["dtau_d"]["value"], 0.03);
    assert_eq!(j["wake_capture"]["inputs"]["dtau_d"]["clamped_value"], 0.06);
    assert_eq!(run.stderr.matches("warning:").count(), 1, "{}", run.stderr);
    assert!(run.stderr.contains("dtau_D 0.03 -> 0.06"), "{}", run.stderr);
}

#[test]
fn dtau_overrides_need_trapezoidal_kinematics() {
    let dir = tempfile::tempdir().unwrap();
    let (head, _) = ROBOFLY.split_once("[kinematics]").unwrap();
    let harmonic = format!(
        "{head}[kinematics]\nfamily = \"harmonic\"\nfreq_hz = 0.1\namplitude_deg = 155.0\n\
         mid_stroke_aoa_deg = 40.0\n"
    );
    std::fs::write(dir.path().join("harmonic.toml"), harmonic).unwrap();
    let ok = flapwing_in(
        dir.path(),
        &["forces", "--model", "harmonic.toml", "--json"],
    );
    assert_eq!(ok.code, 0, "{ok:?}");
    let run = flapwing_in(
        dir.path(),
        &["forces", "--model", "harmonic.toml", "--dtau-a", "0.1"],
    );
    run.assert_bad_input();
    assert!(
        run.stderr.contains("harmonic.toml") && run.stderr.contains("trapezoidal"),
        "{}",
        run.stderr
    );
}

#[test]
fn text_report_lists_every_term() {
    let run = flapwing(&["forces", "--cycles", "1", "--steps-per-cycle", "200"]);
    assert_eq!(run.code, 0, "{run:?}");
    for needle in TERMS
        .iter()
        .chain(&["Re = V_ref c_bar / nu", "V_ref", "robofly"])
    {
        assert!(run.stdout.contains(needle), "{needle}: {}", run.stdout);
    }
}

#[test]
fn nan_coefficients_of_a_refitted_model_are_bad_input() {
    // wingforce validates a refitted wake-capture model's coefficients (finite, mu* > 0):
    // a NaN is bad input (exit 2) naming the file and the field, never NaN means.
    let dir = tempfile::tempdir().unwrap();
    let text = format!(
        "{ROBOFLY}\n[aero.wake_capture_model]\nsource = \"refit\"\n\
         dcl = {{ c0 = nan, c1 = 0.0, c2 = 0.0, c3 = 0.0, c4 = 0.0 }}\n\
         dcd = {{ c0 = 0.9, c1 = 0.0, c2 = 0.0, c3 = 0.0, c4 = 0.0 }}\n\
         mu_star = {{ m0 = 0.05, m1 = 0.0, m2 = 0.0 }}\n\
         re_range = {{ min = 136.0, max = 6800.0 }}\n\
         dtau_a_range = {{ min = 0.06, max = 0.18 }}\n\
         dtau_d_range = {{ min = 0.06, max = 0.18 }}\n"
    );
    std::fs::write(dir.path().join("refit.toml"), text).unwrap();
    let run = flapwing_in(dir.path(), &["forces", "--model", "refit.toml", "--json"]);
    assert_eq!(run.code, 2, "{run:?}");
    assert!(run.stdout.is_empty(), "{run:?}");
    assert!(
        run.stderr.contains("refit.toml") && run.stderr.contains("aero.wake_capture_model.dcl.c0"),
        "{}",
        run.stderr
    );
    assert!(!run.stderr.contains("panicked"));
}

#[test]
fn every_wingbeat_has_the_same_mean() {
    // A fixed mount has no memory: the last wingbeat's means do not depend on how many came
    // before (the mid-step samples never land on the pitch-acceleration jumps of the flip).
    let one = flapwing(&["forces", "--json", "--cycles", "1"]).json();
    let five = flapwing(&["forces", "--json", "--cycles", "5"]).json();
    for term in TERMS {
        assert!((c_l(&one, term) - c_l(&five, term)).abs() < 1e-12, "{term}");
        assert!((c_d(&one, term) - c_d(&five, term)).abs() < 1e-12, "{term}");
    }
}
