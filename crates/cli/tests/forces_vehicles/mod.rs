//! `flapwing forces --model VEHICLE`: every built-in vehicle's wing on a fixed mount.
//!
//! `forces` read only wing model files: it refused every built-in vehicle by name ("cannot
//! read model file `drosophila`") and every vehicle model file (a parse error at `[body]`).
//! A vehicle's wing is now evaluated with the vehicle's own aerodynamic options and induced
//! flow, one pair at a time (`--pair`); an actuated vehicle's wing, whose `[kinematics]` is
//! only nominal, on the periodic motion its drive gives it with the body held still.
//! MODEL.md's force is the sum of its four terms (translational, rotational, added mass,
//! wake capture), so the totals are checked against the terms' sum, and switching the
//! wake-capture term off on prescribed kinematics removes exactly that term.

use super::common::flapwing;
use serde_json::Value;

const TERMS: [&str; 4] = ["translational", "rotational", "added_mass", "wake_capture"];

fn coefficient(j: &Value, term: &str, which: &str) -> f64 {
    j["mean_last_cycle"][term][which].as_f64().unwrap()
}

fn forces_json(args: &[&str]) -> Value {
    let mut all = vec!["forces", "--json"];
    all.extend_from_slice(args);
    let run = flapwing(&all);
    assert_eq!(run.code, 0, "{run:?}");
    assert!(!run.stderr.contains("panicked"), "{run:?}");
    run.json()
}

#[test]
fn every_built_in_vehicle_reports_its_wings_terms() {
    for (name, pairs, actuated) in [
        ("drosophila", 1, false),
        ("bumblebee", 1, false),
        ("robobee_kinematic", 1, false),
        ("dragonfly", 2, false),
        ("robobee", 1, true),
        ("hummingbird", 1, true),
    ] {
        for pair in 1..=pairs {
            let p = pair.to_string();
            let j = forces_json(&["--model", name, "--pair", &p]);
            assert_eq!(j["source"], format!("<built-in {name}>"));
            let wing = j["wing"].as_str().unwrap();
            assert!(wing.contains(&format!("pair {pair} of {pairs}")), "{wing}");
            assert_eq!(wing.contains("periodic motion"), actuated, "{wing}");
            for which in ["c_l", "c_d"] {
                let sum: f64 = TERMS.iter().map(|t| coefficient(&j, t, which)).sum();
                let total = coefficient(&j, "total", which);
                assert!(total.is_finite() && total != 0.0, "{name} {which}: {j}");
                assert!((sum - total).abs() <= 1e-12 * total.abs(), "{name} {which}");
            }
            // A fixed mount in still air or the hover downwash: the wing lifts.
            assert!(coefficient(&j, "total", "c_l") > 0.2, "{name}: {j}");
        }
    }
    // A vehicle model file (a `[body]` table) is a vehicle too.
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../models/dragonfly_azuma1985.toml"
    );
    let j = forces_json(&["--model", path, "--pair", "2"]);
    assert_eq!(j["model"], "dragonfly_azuma1985");
    assert!(j["wing"].as_str().unwrap().contains("pair 2 of 2"));
}

#[test]
fn the_vehicles_own_wing_and_motion_are_the_ones_evaluated() {
    // Prescribed: the mean of the vehicle's own left wing, sampled at the step midpoints.
    let v = flapsim::Vehicle::from_toml(
        flapsim::builtin_model("drosophila").unwrap(),
        "<built-in drosophila>",
    )
    .unwrap();
    let still = wingforce::BodyMotion::default();
    let n = 1000;
    let mean_c_l = (0..n)
        .map(|k| {
            v.wings[0]
                .evaluate((k as f64 + 0.5) / n as f64, &still)
                .total
                .c_l
        })
        .sum::<f64>()
        / n as f64;
    let j = forces_json(&["--model", "drosophila"]);
    assert!((coefficient(&j, "total", "c_l") - mean_c_l).abs() < 1e-12);
    assert_eq!(j["reynolds"].as_f64().unwrap(), v.wings[0].reynolds());
    assert_eq!(j["induced_flow"], "frozen");

    // Actuated: the same periodic motion as a study's hover responses, which average both
    // wings' samples on their own; Re and V_ref from the measured stroke, the frequency the
    // drive's.
    let v = flapsim::Vehicle::from_toml(
        flapsim::builtin_model("robobee").unwrap(),
        "<built-in robobee>",
    )
    .unwrap();
    let r = flapstudy::hover_responses(&v, v.sim.steps_per_wingbeat).unwrap();
    let j = forces_json(&["--model", "robobee"]);
    for (i, term) in TERMS.iter().chain(&["total"]).enumerate() {
        assert!(
            (coefficient(&j, term, "c_l") - r.cl_mean[i]).abs() < 1e-12,
            "{term}"
        );
        assert!(
            (coefficient(&j, term, "c_d") - r.cd_mean[i]).abs() < 1e-12,
            "{term}"
        );
    }
    assert_eq!(j["reynolds"].as_f64().unwrap(), r.reynolds);
    assert!(
        r.reynolds < 0.8 * v.wings[0].reynolds(),
        "measured, not nominal"
    );
    assert_eq!(j["freq_hz"].as_f64().unwrap(), 120.0);
    assert_eq!(
        j["steps_per_cycle"].as_u64().unwrap() as usize,
        v.sim.steps_per_wingbeat
    );
}

#[test]
fn switching_wake_capture_off_removes_exactly_its_term() {
    for name in ["drosophila", "dragonfly"] {
        let on = forces_json(&["--model", name]);
        let off = forces_json(&["--model", name, "--no-wake-capture"]);
        assert_eq!(coefficient(&off, "wake_capture", "c_l"), 0.0);
        for which in ["c_l", "c_d"] {
            let removed = coefficient(&on, "total", which) - coefficient(&off, "total", which);
            let term = coefficient(&on, "wake_capture", which);
            assert!(term > 0.01, "{name} {which}: {term}");
            assert!((removed - term).abs() < 1e-12, "{name} {which}");
        }
    }
}

#[test]
fn flags_a_vehicle_cannot_take_are_refused_by_name() {
    for (args, says) in [
        (
            &["--model", "dragonfly", "--pair", "3"][..],
            "--pair 3: `<built-in dragonfly>` has 2 wing pair(s); allowed: 1 to 2",
        ),
        (
            &["--model", "drosophila", "--pair", "0"][..],
            "--pair 0: `<built-in drosophila>` has 1 wing pair(s); allowed: 1 to 1",
        ),
        (
            &["--pair", "2"][..],
            "--pair chooses a vehicle's wing pair: give the vehicle with --model",
        ),
        (
            &["--model", "robofly", "--pair", "1"][..],
            "`robofly` is a wing model file (one wing)",
        ),
        (
            &["--model", "robobee", "--re", "1000"][..],
            "--re: `<built-in robobee>` has actuated wings",
        ),
        (
            &["--model", "hummingbird", "--steps-per-cycle", "50"][..],
            "--steps-per-cycle: `<built-in hummingbird>` has actuated wings",
        ),
        (
            &["--model", "drosophila", "--dtau-a", "0.1"][..],
            "`<built-in drosophila>` is a vehicle",
        ),
        (
            &["--model", "no_such_vehicle"][..],
            "cannot read model file `no_such_vehicle` (give a wing model file, the built-in robofly, or a vehicle",
        ),
    ] {
        let mut all = vec!["forces"];
        all.extend_from_slice(args);
        let run = flapwing(&all);
        run.assert_bad_input();
        assert!(run.stderr.contains(says), "{args:?}: {}", run.stderr);
    }
}
