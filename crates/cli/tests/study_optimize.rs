//! `flapwing optimize`: Nelder-Mead over a study's factor box, maximizing lift per
//! aerodynamic power with the weight supported. Checked against the model itself: the
//! optimum must support the weight, stay inside the box, beat the box centre, and no design
//! of the shipped 7 x 5 sweep of the same box that supports the weight may beat it.

use crate::common;

use common::flapwing_in;

const STUDY: &str = include_str!("../../../examples/studies/drosophila_lift_per_power.toml");

#[test]
fn optimum_supports_the_weight_and_beats_the_sweep() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("lpp.toml"), STUDY).unwrap();
    let run = flapwing_in(dir.path(), &["optimize", "lpp.toml", "--json"]);
    assert_eq!(run.code, 0, "{run:?}");
    let j = run.json();
    assert_eq!(j["feasible"], true);
    let best = &j["best"];
    let lw = best["lift_over_weight"].as_f64().unwrap();
    let lpp = best["lift_per_power_n_per_w"].as_f64().unwrap();
    assert!(lw >= 1.0 - 1e-6, "{lw}");
    assert!(lpp > j["start"]["lift_per_power_n_per_w"].as_f64().unwrap());
    for (v, b) in best["values"]
        .as_array()
        .unwrap()
        .iter()
        .zip(j["bounds"].as_array().unwrap())
    {
        let v = v.as_f64().unwrap();
        assert!(v >= b[0].as_f64().unwrap() && v <= b[1].as_f64().unwrap());
    }
    let run = flapwing_in(dir.path(), &["sweep", "lpp.toml"]);
    assert_eq!(run.code, 0, "{run:?}");
    let csv = std::fs::read_to_string(dir.path().join("drosophila_lift_per_power.csv")).unwrap();
    for line in csv.lines().skip(1) {
        // case, amplitude, aoa, the responses, reynolds, wake_capture_clamped, status, error
        let cells: Vec<&str> = line.split(',').collect();
        assert_eq!(cells[cells.len() - 2..], ["ok", ""], "{line}");
        let f: Vec<f64> = cells[..cells.len() - 2]
            .iter()
            .map(|x| x.parse().unwrap())
            .collect();
        // case, amplitude, aoa, lift_per_power, lift_over_weight, ...
        if f[4] >= 1.0 {
            assert!(
                lpp >= f[3],
                "sweep case {} beats the optimum: {} > {lpp}",
                f[0],
                f[3]
            );
        }
    }
    let text = flapwing_in(dir.path(), &["optimize", "lpp.toml"]);
    assert_eq!(text.code, 0, "{text:?}");
    assert!(
        text.stdout.contains("the optimum supports the weight"),
        "{text:?}"
    );
}

#[test]
fn a_factor_without_an_interval_is_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let one = STUDY.replace("range = [15.0, 60.0]\ncount = 5", "levels = [40.0]");
    std::fs::write(dir.path().join("one.toml"), one).unwrap();
    let run = flapwing_in(dir.path(), &["optimize", "one.toml"]);
    run.assert_bad_input();
    assert!(
        run.stderr.contains("kinematics.mid_stroke_aoa_deg"),
        "{run:?}"
    );
}
