//! Nelder-Mead and the hover design optimization.
//!
//! Analytic bases: Rosenbrock's function (1 - x)^2 + 100 (y - x^2)^2 has its only minimum,
//! 0, at (1, 1) (the classic Nelder-Mead test from (-1.2, 1); Lagarias et al. 1998); a
//! convex quadratic's minimum is where its gradient vanishes. The hover optimum is checked
//! against a brute-force grid of the same model: no feasible grid design may beat it.

use flapstudy::StudySpec;
use flapstudy::optimize::{NelderMeadOptions, nelder_mead, optimize_hover};
use nalgebra::DVector;

#[test]
fn nelder_mead_finds_the_rosenbrock_minimum() {
    let rosen = |x: &DVector<f64>| (1.0 - x[0]).powi(2) + 100.0 * (x[1] - x[0] * x[0]).powi(2);
    let opts = NelderMeadOptions {
        max_evals: 2000,
        x_tol: 1e-10,
        f_tol: 1e-14,
        initial_step: 0.5,
    };
    let r = nelder_mead(rosen, &DVector::from_vec(vec![-1.2, 1.0]), &opts);
    assert!(r.converged, "{r:?}");
    assert!(
        (r.x[0] - 1.0).abs() < 1e-5 && (r.x[1] - 1.0).abs() < 1e-5,
        "{r:?}"
    );
    assert!(r.f < 1e-10);
}

#[test]
fn nelder_mead_finds_a_quadratic_minimum_and_handles_infinities() {
    // f = (x - 1)^2 + 2 (y + 2)^2 + 3 (z - 0.5)^2 + x y: gradient zero at the solution of
    // [2 1 0; 1 4 0; 0 0 6] [x y z] = [2 -8 3], i.e. x = 16/7, y = -18/7, z = 0.5.
    let f = |v: &DVector<f64>| {
        let (x, y, z) = (v[0], v[1], v[2]);
        if x > 10.0 {
            return f64::INFINITY; // a forbidden region the simplex must avoid
        }
        (x - 1.0).powi(2) + 2.0 * (y + 2.0).powi(2) + 3.0 * (z - 0.5).powi(2) + x * y
    };
    let opts = NelderMeadOptions {
        max_evals: 3000,
        x_tol: 1e-9,
        f_tol: 1e-14,
        initial_step: 1.0,
    };
    let r = nelder_mead(f, &DVector::from_vec(vec![0.0, 0.0, 0.0]), &opts);
    assert!(r.converged, "{r:?}");
    for (got, want) in r.x.iter().zip([16.0 / 7.0, -18.0 / 7.0, 0.5]) {
        assert!((got - want).abs() < 1e-6, "{:?}", r.x);
    }
}

#[test]
fn hover_optimum_beats_every_feasible_grid_design() {
    let text = r#"
base_model = "drosophila"
design = "full_factorial"
responses = ["lift_per_power_n_per_w"]
[[factor]]
path = "kinematics.amplitude_deg"
range = [110.0, 170.0]
count = 2
[[factor]]
path = "kinematics.mid_stroke_aoa_deg"
range = [20.0, 60.0]
count = 2
"#;
    let spec = StudySpec::from_toml(text, "opt.toml").unwrap();
    let study = spec
        .resolve("opt.toml", "opt", flapsim::DROSOPHILA_TOML, "drosophila")
        .unwrap();
    let opt = optimize_hover(&study, 1.0, &NelderMeadOptions::default()).unwrap();
    assert!(opt.feasible, "{opt:?}");
    assert!(opt.best.lift_over_weight >= 1.0 - 1e-6);
    assert!(opt.best.lift_per_power_n_per_w > opt.start.lift_per_power_n_per_w);
    // Brute force on a 13 x 13 grid of the same box.
    let mut grid_best: f64 = 0.0;
    for i in 0..13 {
        for j in 0..13 {
            let a = 110.0 + 60.0 * i as f64 / 12.0;
            let aoa = 20.0 + 40.0 * j as f64 / 12.0;
            let v = study.vehicle_at(&[a, aoa]).unwrap();
            let r = flapstudy::hover_responses(&v, study.steps_per_wingbeat).unwrap();
            if r.vertical_force_n / r.weight_n >= 1.0 {
                grid_best = grid_best.max(r.vertical_force_n / r.aero_power_w);
            }
        }
    }
    assert!(
        opt.best.lift_per_power_n_per_w >= grid_best * (1.0 - 1e-3),
        "optimum {} vs grid {grid_best}",
        opt.best.lift_per_power_n_per_w
    );
}
