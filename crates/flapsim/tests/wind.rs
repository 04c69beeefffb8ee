//! Wind: Dryden turbulence, the 1 - cosine gust, steady wind and each wing's own air.
//!
//! Physics and statistics:
//! - Dryden turbulence (MIL-F-8785C 3.7.2.1) is a stationary Gaussian process along the
//!   convected coordinate with variance sigma^2 and autocorrelation R_u = sigma^2 e^{-xi/L}
//!   (longitudinal), R_v = sigma^2 (1 - xi/(2L)) e^{-xi/L} (lateral, vertical); its one-sided
//!   PSD is the cosine transform (2/pi) int_0^inf R cos(Omega xi). A record of length X holds
//!   about N = X / (2 L) independent samples: the sample variance of the first-order process
//!   has relative standard deviation sqrt(2 L / X) = 1/sqrt(N) (Var(s^2) = (2 sigma^4 / X)
//!   int rho^2, int rho^2 = L for the exponential; 5L/8 for the lateral form, so the bound
//!   is conservative there). Tolerances are 4 of those standard deviations (a false alarm
//!   about 1 in 16000 for a Gaussian estimate; the seeds are fixed, so a run is repeatable).
//! - The exact discretisation makes every sample's variance sigma^2 whatever the spacing, so
//!   the variance is checked at a spacing equal to the length scale too.
//! - A 1 - cosine gust (A/2)(1 - cos(2 pi tau/T)) peaks at A at tau = T/2.
//! - The wings feel only their motion relative to the air: a body at rest with each wing in
//!   a wind w_i feels what the body moving at -w_i feels in still air, and each wing of a
//!   set in per-wing winds feels what it would alone in its own uniform wind.

use flapsim::control::{Disturbance, HoverController, LqrWeights, run_hover};
use flapsim::wind::{DrydenField, DrydenParams, Gust, GustSpec, TurbulenceSpec, Wind, WindSpec};
use flapsim::{FromVehicle, Mode, Simulation, State, Vehicle, WingSet};
use nalgebra::{UnitQuaternion, Vector3};
use wingforce::Validator;

fn fly() -> Vehicle {
    Vehicle::from_toml(flapsim::DROSOPHILA_TOML, "drosophila").unwrap()
}

const PARAMS: DrydenParams = DrydenParams {
    sigma_m_s: [0.3, 0.2, 0.1],
    length_scale_m: [2.0, 1.0, 0.5],
};

/// Samples k = 0..n of a field.
fn series(f: &mut DrydenField, n: usize) -> Vec<[f64; 3]> {
    (0..n as i64).map(|k| f.sample(k)).collect()
}

#[test]
fn turbulence_variance_is_sigma_squared_at_any_spacing() {
    // Record length X = 20000 L for each component: N = 10000 independent samples, relative
    // standard deviation of the variance 1%, tolerance 4%.
    for (spacing_over_lmin, seed) in [(1.0 / 16.0, 1u64), (1.0, 2), (2.0, 3)] {
        let h = 0.5 * spacing_over_lmin;
        let mut f = DrydenField::new(PARAMS, h, seed);
        let n = (20000.0 * 2.0 / h) as usize;
        let ys = series(&mut f, n);
        for i in 0..3 {
            let l = PARAMS.length_scale_m[i];
            let x_len = 20000.0 * 2.0; // the record, m (>= 20000 L for every component)
            let n_indep = x_len / (2.0 * l);
            let tol = 4.0 / n_indep.sqrt();
            let var = ys.iter().map(|y| y[i] * y[i]).sum::<f64>() / n as f64;
            let s2 = PARAMS.sigma_m_s[i].powi(2);
            let rel = var / s2 - 1.0;
            println!(
                "spacing {h} m, component {i}: variance {var:.5e} vs sigma^2 {s2:.5e}, rel {rel:+.4} (tol {tol:.4})"
            );
            assert!(rel.abs() < tol, "component {i}, spacing {h}: {rel}");
        }
    }
}

#[test]
fn turbulence_autocorrelation_and_psd_are_drydens() {
    let h = 0.5 / 16.0;
    let mut f = DrydenField::new(PARAMS, h, 11);
    let x_len = 20000.0 * 2.0;
    let n = (x_len / h) as usize;
    let ys = series(&mut f, n);
    for i in 0..3 {
        let l = PARAMS.length_scale_m[i];
        let s2 = PARAMS.sigma_m_s[i].powi(2);
        // Autocorrelation at lags 0.25 L .. 2 L: the estimate's standard deviation is at most
        // that of the variance (sigma^2 / sqrt(N)); tolerance 4 of those, in units of sigma^2.
        let tol = 4.0 / (x_len / (2.0 * l)).sqrt();
        for lag_l in [0.25, 0.5, 1.0, 2.0] {
            let m = (lag_l * l / h).round() as usize;
            let r = ys[..n - m]
                .iter()
                .zip(&ys[m..])
                .map(|(a, b)| a[i] * b[i])
                .sum::<f64>()
                / (n - m) as f64;
            let want = PARAMS.autocorrelation(i, m as f64 * h);
            println!(
                "component {i}, lag {lag_l} L: R = {:.4} sigma^2, Dryden {:.4} sigma^2 (tol {tol:.4})",
                r / s2,
                want / s2
            );
            assert!((r - want).abs() / s2 < tol, "component {i} lag {lag_l}");
        }
        // PSD by averaged periodograms over K segments of 64 L (Bartlett): each frequency's
        // estimate has relative standard deviation 1/sqrt(K); tolerance 4/sqrt(K) plus 5% for
        // the rectangular window's leakage (the spectrum's curvature over the kernel's width
        // 2 pi / (64 L)).
        let seg = (64.0 * l / h) as usize;
        let k_segs = n / seg;
        let tol_psd = 4.0 / (k_segs as f64).sqrt() + 0.05;
        for omega_l in [0.25, 1.0, 3.0] {
            let omega = omega_l / l;
            let mut acc = 0.0;
            for s in 0..k_segs {
                let (mut re, mut im) = (0.0, 0.0);
                let (c, sn) = ((omega * h).cos(), (omega * h).sin());
                let (mut pr, mut pi) = (1.0, 0.0); // e^{-i Omega xi}
                for y in &ys[s * seg..(s + 1) * seg] {
                    re += y[i] * pr;
                    im += y[i] * pi;
                    let npr = pr * c + pi * sn;
                    pi = pi * c - pr * sn;
                    pr = npr;
                }
                let seg_len = seg as f64 * h;
                acc += (re * re + im * im) * h * h / (std::f64::consts::PI * seg_len);
            }
            let phi = acc / k_segs as f64;
            let want = PARAMS.psd_spatial(i, omega);
            let rel = phi / want - 1.0;
            println!(
                "component {i}, Omega L = {omega_l}: PSD {phi:.4e}, Dryden {want:.4e}, rel {rel:+.3} (tol {tol_psd:.3})"
            );
            assert!(
                rel.abs() < tol_psd,
                "component {i} Omega L {omega_l}: {rel}"
            );
        }
    }
}

#[test]
fn same_seed_same_turbulence_in_any_query_order_other_seed_differs() {
    let mut a = DrydenField::new(PARAMS, 0.01, 42);
    let mut b = DrydenField::new(PARAMS, 0.01, 42);
    let mut c = DrydenField::new(PARAMS, 0.01, 43);
    let etas: Vec<f64> = (-300..300).map(|k| k as f64 * 0.0137).collect();
    let fwd: Vec<[f64; 3]> = etas.iter().map(|&e| a.at(e)).collect();
    let rev: Vec<[f64; 3]> = etas.iter().rev().map(|&e| b.at(e)).collect();
    let rev: Vec<[f64; 3]> = rev.into_iter().rev().collect();
    assert_eq!(fwd, rev, "the field depends on the seed and eta only");
    let other: Vec<[f64; 3]> = etas.iter().map(|&e| c.at(e)).collect();
    assert!(fwd.iter().zip(&other).all(|(x, y)| x != y));
}

#[test]
fn turbulence_behind_the_start_has_the_same_statistics() {
    // Samples at negative eta come from the time-reversed process: variance sigma^2 and the
    // same correlation across eta = 0 (checked at one lag, tolerance as above).
    let h = 0.5 / 16.0;
    let mut f = DrydenField::new(PARAMS, h, 5);
    let n = (20000.0 * 2.0 / h) as i64;
    let ys: Vec<[f64; 3]> = (-n..0).map(|k| f.sample(k)).collect();
    for i in 0..3 {
        let tol = 4.0 / (20000.0 * 2.0 / (2.0 * PARAMS.length_scale_m[i])).sqrt();
        let var = ys.iter().map(|y| y[i] * y[i]).sum::<f64>() / ys.len() as f64;
        let rel = var / PARAMS.sigma_m_s[i].powi(2) - 1.0;
        println!("behind, component {i}: rel variance error {rel:+.4} (tol {tol:.4})");
        assert!(rel.abs() < tol);
        let m = (PARAMS.length_scale_m[i] / h) as usize;
        let r = ys[..ys.len() - m]
            .iter()
            .zip(&ys[m..])
            .map(|(a, b)| a[i] * b[i])
            .sum::<f64>()
            / (ys.len() - m) as f64;
        let want = PARAMS.autocorrelation(i, m as f64 * h);
        assert!((r - want).abs() / PARAMS.sigma_m_s[i].powi(2) < tol, "{i}");
    }
}

#[test]
fn low_altitude_forms_at_insect_heights() {
    // MIL-F-8785C 3.7.2.3 at 1 m (3.28 ft): L_w = 1 m, L_u = L_v = h / (0.177 + 0.000823 h)^1.2
    // = 7.84 m, sigma_u / sigma_w = (0.177 + 0.000823 h)^-0.4 = 1.99 (hand calculation).
    let p = DrydenParams::low_altitude(1.0, 5.0);
    assert!((p.length_scale_m[2] - 1.0).abs() < 1e-12);
    assert!((p.length_scale_m[0] - 7.84).abs() < 0.01, "{:?}", p);
    assert!((p.sigma_m_s[2] - 0.5).abs() < 1e-12);
    assert!(
        (p.sigma_m_s[0] / p.sigma_m_s[2] - 1.99).abs() < 0.01,
        "{:?}",
        p
    );
    let p3 = DrydenParams::low_altitude(3.0, 5.0);
    assert!((p3.length_scale_m[0] - 22.7).abs() < 0.1, "{:?}", p3);
}

#[test]
fn one_minus_cosine_gust_peaks_at_its_amplitude() {
    let g = Gust {
        amplitude_m_s: 0.7,
        direction_world: Vector3::new(0.0, 0.6, 0.8),
        start_s: 0.1,
        duration_s: 0.04,
    };
    // Analytic: at tau = T/2, cos(pi) = -1, speed A (to the rounding of cos(pi) in f64).
    assert!((g.speed_m_s(0.02) - 0.7).abs() <= 1e-15);
    let max = (0..=10_000)
        .map(|k| g.speed_m_s(k as f64 * 0.04 / 10_000.0))
        .fold(0.0, f64::max);
    assert!((max - 0.7).abs() <= 1e-15, "{max}");
    assert_eq!(g.speed_m_s(-1e-9), 0.0);
    assert_eq!(g.speed_m_s(0.0), 0.0);
    assert_eq!(g.speed_m_s(0.040_000_001), 0.0);
    // Through a wind field: at the reference point the peak comes at start + T/2, along the
    // direction; a point 1 cm downstream (along e_u = +x) sees it 0.01 / U_c later.
    let spec = WindSpec {
        steady_world_m_s: [0.5, 0.0, 0.0],
        gusts: vec![GustSpec {
            amplitude_m_s: 0.7,
            direction_world: [0.0, 3.0, 4.0],
            start_s: 0.1,
            duration_s: None,
            length_m: Some(0.02),
        }],
        ..WindSpec::default()
    };
    let mut w = Wind::from_spec(&spec, "test", Vector3::zeros()).unwrap();
    let t_peak = 0.1 + 0.5 * 0.02 / 0.5;
    let v = w.sample(&Vector3::zeros(), t_peak);
    assert!(
        (v.gusts_m_s - Vector3::new(0.0, 0.42, 0.56)).norm() < 1e-12,
        "{v:?}"
    );
    assert_eq!(v.steady_m_s, Vector3::new(0.5, 0.0, 0.0));
    let v = w.sample(&Vector3::new(0.01, 0.0, 0.0), t_peak + 0.01 / 0.5);
    assert!((v.gusts_m_s.norm() - 0.7).abs() < 1e-12, "{v:?}");
}

/// The wing set's loads at a body state with the given per-wing winds.
fn set_loads(winds: Option<&[Vector3<f64>]>, body: &State) -> flapsim::WingSetOutput {
    let mut set = WingSet::from_vehicle_sized(&fly()).unwrap();
    if let Some(w) = winds {
        set.set_wing_winds(w).unwrap();
    }
    for _ in 0..37 {
        set.step(body).unwrap();
    }
    set.output().clone()
}

#[test]
fn wings_in_wind_feel_what_wings_moving_through_still_air_feel() {
    let q = UnitQuaternion::from_euler_angles(0.1, -0.7, 0.3);
    let omega = Vector3::new(1.0, -2.0, 0.5);
    let wind = Vector3::new(0.3, -0.1, 0.2);
    let at_rest_in_wind = State {
        position_m: Vector3::new(0.01, 0.0, 0.0),
        world_from_body: q,
        velocity_m_s: Vector3::zeros(),
        angular_velocity_body_rad_s: omega,
    };
    let moving = State {
        velocity_m_s: -wind,
        ..at_rest_in_wind
    };
    let a = set_loads(Some(&[wind, wind][..]), &at_rest_in_wind);
    let b = set_loads(None, &moving);
    // 0 - w and -w - 0 are the same number: bit for bit.
    assert_eq!(a, b);
    // Per-wing winds: each wing of the pair feels what it feels alone in its own wind (the
    // pair is then evaluated wing by wing).
    let (wl, wr) = (Vector3::new(0.4, 0.0, 0.1), Vector3::new(-0.2, 0.3, 0.0));
    let both = set_loads(Some(&[wl, wr][..]), &at_rest_in_wind);
    let left_alone = set_loads(
        None,
        &State {
            velocity_m_s: -wl,
            ..at_rest_in_wind
        },
    );
    let right_alone = set_loads(
        None,
        &State {
            velocity_m_s: -wr,
            ..at_rest_in_wind
        },
    );
    assert_eq!(both.wings[0], left_alone.wings[0]);
    assert_eq!(both.wings[1], right_alone.wings[1]);
    assert_ne!(both.wings[0], both.wings[1]);
    // An actuated set too (each wing's dynamics in its own air).
    let robobee = Vehicle::from_toml(flapsim::ROBOBEE_TOML, "robobee").unwrap();
    let run = |winds: Option<[Vector3<f64>; 2]>, v: Vector3<f64>| {
        let mut set = WingSet::from_vehicle_sized(&robobee).unwrap();
        if let Some(w) = winds {
            set.set_wing_winds(&w).unwrap();
        }
        let body = State {
            velocity_m_s: v,
            ..at_rest_in_wind
        };
        for _ in 0..50 {
            set.step(&body).unwrap();
        }
        set.output().clone()
    };
    assert_eq!(run(Some([wind, wind]), Vector3::zeros()), run(None, -wind));
}

#[test]
fn a_steady_wind_field_per_hinge_is_the_uniform_wind() {
    // The wind field's per-hinge path (wing by wing) gives bit for bit the uniform wind's
    // loads when the field is uniform, in free flight.
    let w = Vector3::new(0.2, 0.1, -0.05);
    let mut a = Simulation::new(fly(), Mode::Free);
    a.set_wind(w);
    let mut b = Simulation::new(fly(), Mode::Free);
    b.set_wind_model(Some(Wind::steady(w)));
    for _ in 0..300 {
        let (oa, ob) = (*a.step().unwrap(), *b.step().unwrap());
        assert_eq!(oa, ob);
    }
    assert_eq!(b.wing_winds_m_s(), &[w, w]);
}

#[test]
fn each_wing_sees_the_field_at_its_hinge() {
    // Turbulence convected along +x; the body yawed 90 deg so the wings (hinges at +-y in the
    // body) lie along x: they see the field at different eta.
    let spec = WindSpec {
        turbulence: Some(TurbulenceSpec {
            intensity_m_s: [0.2, 0.2, 0.2],
            length_scale_m: [0.05, 0.05, 0.05],
            seed: 9,
            sample_spacing_m: None,
        }),
        ..WindSpec::default()
    };
    let mut v = fly();
    v.initial_attitude = UnitQuaternion::from_euler_angles(0.0, 0.0, std::f64::consts::FRAC_PI_2)
        * v.initial_attitude;
    let reference = v.initial_position_m;
    let hinges: Vec<Vector3<f64>> = v.wings.iter().map(|w| w.mount().hinge_in_body_m).collect();
    let mut sim = Simulation::new(v, Mode::Tethered);
    sim.set_wind_model(Some(Wind::from_spec(&spec, "test", reference).unwrap()));
    let mut probe = Wind::from_spec(&spec, "test", reference).unwrap();
    let mut differ = 0;
    for _ in 0..200 {
        let s = sim.state();
        let t = sim.time_s();
        let out = *sim.step().unwrap();
        let winds = sim.wing_winds_m_s().to_vec();
        for (i, h) in hinges.iter().enumerate() {
            let p = s.position_m + s.world_from_body * h;
            assert_eq!(winds[i], probe.velocity_world_m_s(&p, t));
        }
        if winds[0] != winds[1] {
            differ += 1;
        }
        // The loads are those of a wing set given the same winds at the same state.
        assert!(out.total.is_finite());
    }
    assert!(
        differ > 190,
        "the wings' winds differ at {differ} of 200 steps"
    );
}

#[test]
fn hover_in_turbulence_is_deterministic_per_seed() {
    let text = |seed: u64| {
        format!(
            "{}\n[wind]\nmin_convection_speed_m_s = 0.5\n[wind.turbulence]\nintensity_m_s = [0.1, 0.1, 0.05]\nlength_scale_m = [0.5, 0.5, 0.5]\nseed = {seed}\n",
            flapsim::DROSOPHILA_TOML
        )
    };
    let run = |seed: u64| {
        let v = Vehicle::from_toml(&text(seed), "drosophila+wind").unwrap();
        let trim = flapsim::trim::trim(&v).unwrap();
        let trimmed = flapsim::trim::trimmed_vehicle(&v, &trim).unwrap();
        let c = HoverController::design(&trimmed, &trim, &LqrWeights::default(), 0).unwrap();
        let mut states = Vec::new();
        let d = Disturbance::default();
        run_hover(&trimmed, &trim, Some(c), &d, 0.1, |o| {
            states.push(o.state);
            true
        })
        .unwrap();
        states
    };
    let (a, b, c) = (run(1), run(1), run(2));
    assert_eq!(a, b);
    assert_ne!(a, c);
}

#[test]
fn bad_wind_input_is_an_error_naming_the_field() {
    let load = |wind: &str| {
        Vehicle::from_toml(&format!("{}\n{wind}", flapsim::DROSOPHILA_TOML), "fly.toml")
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default()
    };
    let e = load(
        "[wind.turbulence]\nintensity_m_s = [-0.1, 0.1, 0.1]\nlength_scale_m = [1.0, 1.0, 1.0]\n",
    );
    assert!(
        e.contains("fly.toml")
            && e.contains("wind.turbulence.intensity_m_s[0]")
            && e.contains("-0.1"),
        "{e}"
    );
    let e = load(
        "[wind.turbulence]\nintensity_m_s = [0.1, 0.1, 0.1]\nlength_scale_m = [1.0, 0.0, 1.0]\n",
    );
    assert!(e.contains("wind.turbulence.length_scale_m[1]"), "{e}");
    // Issue #40: a length scale far below the Kolmogorov microscale (1e-12 m) asked for
    // ~1e13 samples a metre and ran the process out of memory; it is refused with the range.
    let e = load(
        "[wind.turbulence]\nintensity_m_s = [0.1, 0.1, 0.1]\nlength_scale_m = [1.0, 1e-12, 1.0]\n",
    );
    assert!(
        e.contains("wind.turbulence.length_scale_m[1]") && e.contains("0.001"),
        "{e}"
    );
    let e = load(
        "[wind.turbulence]\nintensity_m_s = [0.1, 0.1, 0.1]\nlength_scale_m = [0.01, 0.01, 0.01]\nsample_spacing_m = 2e-6\n",
    );
    assert!(
        e.contains("wind.turbulence.sample_spacing_m") && e.contains("0.00001"),
        "{e}"
    );
    let e = load(
        "[[wind.gusts]]\namplitude_m_s = 1.0\ndirection_world = [0.0, 0.0, 0.0]\nstart_s = 0.0\nduration_s = 0.1\n",
    );
    assert!(e.contains("wind.gusts[0].direction_world"), "{e}");
    let e = load(
        "[[wind.gusts]]\namplitude_m_s = 1.0\ndirection_world = [0.0, 0.0, 1.0]\nstart_s = 0.0\nduration_s = 0.1\nlength_m = 0.1\n",
    );
    assert!(
        e.contains("wind.gusts[0]") && e.contains("exactly one"),
        "{e}"
    );
    let e = load("[wind]\nsteady_world_m_s = [0.0, 0.0, 0.0]\ngust = 1\n");
    assert!(e.contains("fly.toml") && e.contains("gust"), "{e}");
    let e = load("[wind]\nmin_convection_speed_m_s = 0.0\n");
    assert!(e.contains("wind.min_convection_speed_m_s"), "{e}");
    // A gust longer than the run.
    let spec = WindSpec {
        gusts: vec![GustSpec {
            amplitude_m_s: 1.0,
            direction_world: [1.0, 0.0, 0.0],
            start_s: 0.05,
            duration_s: Some(0.1),
            length_m: None,
        }],
        ..WindSpec::default()
    };
    let v = Validator::new("run");
    let p = spec.build(&v, "wind").unwrap();
    assert!(p.check_run(&v, "wind", 0.2).is_ok());
    let e = p.check_run(&v, "wind", 0.1).unwrap_err().to_string();
    assert!(e.contains("wind.gusts[0]") && e.contains("0.15"), "{e}");
    // Per-wing winds: one per wing, finite.
    let mut set = WingSet::from_vehicle_sized(&fly()).unwrap();
    assert!(set.set_wing_winds(&[Vector3::zeros()]).is_err());
    let e = set
        .set_wing_winds(&[Vector3::zeros(), Vector3::new(f64::NAN, 0.0, 0.0)])
        .unwrap_err()
        .to_string();
    assert!(e.contains("wing 1"), "{e}");
    assert_eq!(set.wing_winds(), vec![Vector3::zeros(); 2]);
}

#[test]
fn gym_task_episodes_fly_the_models_wind_seeded_per_episode() {
    use flapsim::task::{Task, TaskSpec};
    let text = format!(
        "{}\n[wind]\n[wind.turbulence]\nintensity_m_s = [0.2, 0.2, 0.2]\nlength_scale_m = [0.3, 0.3, 0.3]\n",
        flapsim::DROSOPHILA_TOML
    );
    let mut t = Task::new(&text, "fly+wind", TaskSpec::hover(), None).unwrap();
    let run = |t: &mut Task, seed: u64| {
        t.reset(seed).unwrap();
        for _ in 0..3 {
            t.step(&[0.0; 4]).unwrap();
        }
        (
            t.simulation().state(),
            t.simulation().wing_winds_m_s().to_vec(),
        )
    };
    let (a, b, c) = (run(&mut t, 4), run(&mut t, 4), run(&mut t, 5));
    assert_eq!(a, b, "same episode seed, same wind and flight");
    assert_ne!(a.1, c.1, "another episode seed, other turbulence");
    assert!(a.1.iter().all(|w| w.norm() > 0.0));
}
