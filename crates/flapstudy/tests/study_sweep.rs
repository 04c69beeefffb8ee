//! Study files, designs, tethered hover responses and sweeps.
//!
//! Physics checks use exact scalings of the quasi-steady model (MODEL.md section 4): every
//! force term is proportional to the fluid density at fixed Re, and with Re held fixed every
//! term scales with the square of the wingbeat frequency (velocities ~ f, accelerations
//! ~ f^2, reference dynamic pressure ~ f^2), so forces ~ f^2 and power = moment x angular
//! velocity ~ f^3. These scalings are of still air: the hover downwash of the built-in fly
//! (`[aero] inflow`) depends on the weight, not on the wingbeat, so the scaling
//! checks switch it off.

use flapstudy::spec::{StudySpec, latin_hypercube, shard_range};
use flapstudy::sweep::merge_csv;
use flapstudy::{Response, Study};

fn study(text: &str) -> Study {
    let spec = StudySpec::from_toml(text, "test.toml").expect("study parses");
    let base = flapsim::builtin_model(&spec.base_model).expect("built-in base");
    spec.resolve("test.toml", "test", base, &spec.base_model)
        .expect("study resolves")
}

/// A study on the built-in fly in still air (no hover downwash).
fn still_air_study(text: &str) -> Study {
    let spec = StudySpec::from_toml(text, "test.toml").expect("study parses");
    let base = flapsim::DROSOPHILA_TOML.replace("inflow = \"frozen\"", "inflow = \"off\"");
    assert_ne!(
        base,
        flapsim::DROSOPHILA_TOML,
        "the fly's downwash switch moved"
    );
    spec.resolve("test.toml", "test", &base, &spec.base_model)
        .expect("study resolves")
}

fn study_err(text: &str) -> String {
    let spec = match StudySpec::from_toml(text, "test.toml") {
        Ok(s) => s,
        Err(e) => return e.to_string(),
    };
    let base = flapsim::builtin_model(&spec.base_model).unwrap();
    spec.resolve("test.toml", "test", base, &spec.base_model)
        .unwrap_err()
        .to_string()
}

const FACTORIAL: &str = r#"
base_model = "drosophila"
design = "full_factorial"
responses = ["lift_over_weight", "aero_power_w", "cl_mean_total", "cl_mean_translational",
             "cl_mean_rotational", "cl_mean_added_mass", "cl_mean_wake_capture",
             "lift_per_power_n_per_w", "mean_pitch_moment_nm", "wake_capture_peak_cl"]
[[factor]]
path = "kinematics.amplitude_deg"
levels = [120.0, 140.0, 160.0]
[[factor]]
path = "kinematics.mid_stroke_aoa_deg"
range = [35.0, 45.0]
count = 2
"#;

#[test]
fn full_factorial_order_and_responses() {
    let s = study(FACTORIAL);
    assert_eq!(s.case_count(), 6);
    // First factor slowest.
    assert_eq!(s.cases[0], [120.0, 35.0]);
    assert_eq!(s.cases[1], [120.0, 45.0]);
    assert_eq!(s.cases[5], [160.0, 45.0]);
    let v = s.vehicle(4).unwrap();
    assert!((v.wings[0].kinematics().amplitude_rad.to_degrees() - 160.0).abs() < 1e-12);
    let results = s.run(0..6, &|_| ()).unwrap();
    for r in &results {
        let get =
            |name: &str| r.responses[s.responses.iter().position(|x| x.name() == name).unwrap()];
        // The total is the sum of the four terms.
        let sum: f64 = ["translational", "rotational", "added_mass", "wake_capture"]
            .iter()
            .map(|t| get(&format!("cl_mean_{t}")))
            .sum();
        assert!((get("cl_mean_total") - sum).abs() < 1e-12);
        assert!(get("aero_power_w") > 0.0);
        let lpp = get("lift_over_weight") * r.done().unwrap().weight_n / get("aero_power_w");
        assert!((get("lift_per_power_n_per_w") - lpp).abs() < 1e-12 * lpp.abs());
        // Eq 23's peak: 0.3 dCL / (mu* sqrt(2 pi)) of the (in-range) regressions.
        let w = s.vehicle(r.case).unwrap().wings[0]
            .wake_capture()
            .copied()
            .unwrap();
        let peak = 0.3 * w.dcl_bar / (w.mu_star * (2.0 * std::f64::consts::PI).sqrt());
        assert!((get("wake_capture_peak_cl") - peak).abs() < 1e-12);
    }
    // More amplitude, more lift (same angle of attack).
    assert!(results[4].responses[0] > results[2].responses[0]);
    assert!(results[2].responses[0] > results[0].responses[0]);
}

#[test]
fn forces_scale_with_density_and_frequency_squared() {
    let s = still_air_study(
        r#"
base_model = "drosophila"
design = "full_factorial"
responses = ["lift_over_weight", "aero_power_w", "cl_mean_total", "cd_mean_total"]
[[factor]]
path = "fluid.density_kg_m3"
levels = [1.204, 2.408]
"#,
    );
    let r = s.run(0..2, &|_| ()).unwrap();
    let ratio = |k: usize| r[1].responses[k] / r[0].responses[k];
    assert!((ratio(0) - 2.0).abs() < 1e-12, "lift ratio {}", ratio(0));
    assert!((ratio(1) - 2.0).abs() < 1e-12, "power ratio {}", ratio(1));
    assert!((ratio(2) - 1.0).abs() < 1e-12 && (ratio(3) - 1.0).abs() < 1e-12);

    // Hold Re at the drosophila's own value while doubling the frequency.
    let base = flapsim::Vehicle::from_toml(
        &flapsim::DROSOPHILA_TOML.replace("inflow = \"frozen\"", "inflow = \"off\""),
        "d",
    )
    .unwrap();
    let re0 = base.wings[0].reynolds();
    let s = still_air_study(&format!(
        r#"
base_model = "drosophila"
design = "full_factorial"
responses = ["lift_over_weight", "aero_power_w", "mean_pitch_moment_nm"]
[[factor]]
path = "kinematics.freq_hz"
levels = [218.0, 436.0]
[[factor]]
path = "fluid.reynolds"
levels = [{re0:?}]
"#
    ));
    let r = s.run(0..2, &|_| ()).unwrap();
    assert!((r[0].done().unwrap().reynolds - re0).abs() < 1e-9 * re0);
    assert!((r[1].done().unwrap().reynolds - re0).abs() < 1e-9 * re0);
    let ratio = |k: usize| r[1].responses[k] / r[0].responses[k];
    assert!((ratio(0) - 4.0).abs() < 1e-9, "lift ratio {}", ratio(0));
    assert!((ratio(1) - 8.0).abs() < 1e-9, "power ratio {}", ratio(1));
    assert!((ratio(2) - 4.0).abs() < 1e-9, "moment ratio {}", ratio(2));
}

#[test]
fn merged_shards_equal_one_unsharded_run() {
    let s = study(FACTORIAL);
    let whole = s.csv(&s.run(0..s.case_count(), &|_| ()).unwrap());
    for n in [1, 2, 4, 6] {
        let mut parts = Vec::new();
        // Shards in reverse order: the merge sorts by case index.
        for k in (1..=n).rev() {
            let results = s.run(s.shard_range(k, n), &|_| ()).unwrap();
            parts.push((format!("shard {k}/{n}"), s.csv(&results)));
        }
        assert_eq!(merge_csv(&parts).unwrap(), whole, "{n} shards");
    }
    // Overlapping shards are refused.
    let a = s.csv(&s.run(0..3, &|_| ()).unwrap());
    let b = s.csv(&s.run(2..6, &|_| ()).unwrap());
    let e = merge_csv(&[("a".into(), a), ("b".into(), b)])
        .unwrap_err()
        .to_string();
    assert!(e.contains("case 2 also appears"), "{e}");
    // Shard ranges cover every case once.
    for cases in [0, 1, 7, 100] {
        for n in 1..=9 {
            let covered: Vec<usize> = (1..=n).flat_map(|k| shard_range(cases, k, n)).collect();
            assert_eq!(covered, (0..cases).collect::<Vec<_>>());
        }
    }
}

#[test]
fn thread_count_does_not_change_the_output() {
    let s = study(FACTORIAL);
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let two = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let a = one.install(|| s.csv(&s.run(0..6, &|_| ()).unwrap()));
    let b = two.install(|| s.csv(&s.run(0..6, &|_| ()).unwrap()));
    assert_eq!(a, b);
}

#[test]
fn taguchi_l18_study_uses_table_2() {
    let s = study(
        r#"
base_model = "drosophila"
design = "taguchi_l18"
responses = ["cl_mean_wake_capture"]
[[factor]]
path = "fluid.kinematic_viscosity_m2_s"
levels = [6e-5, 3e-5, 1.2e-5, 6e-6, 3e-6, 1.2e-6]
[[factor]]
path = "kinematics.dtau_d"
levels = [0.06, 0.12, 0.18]
[[factor]]
path = "kinematics.dtau_a"
levels = [0.06, 0.12, 0.18]
"#,
    );
    assert_eq!(s.case_count(), 18);
    let oa = flapstudy::OrthogonalArray::l18();
    let idx = |levels: &[f64], x: f64| levels.iter().position(|&l| l == x).unwrap() as u8 + 1;
    for (case, row) in s.cases.iter().zip(&oa.rows) {
        let got = [
            idx(&s.factors[0].levels, case[0]),
            idx(&s.factors[1].levels, case[1]),
            idx(&s.factors[2].levels, case[2]),
        ];
        assert_eq!(got, row[..3]);
    }
    let r = s.run(0..18, &|_| ()).unwrap();
    // Re = V_ref c_bar / nu: tests 1 and 4 of Table 2 share dtau_D and dtau_A (so V_ref)
    // and differ in nu by a factor 2.
    assert_eq!(s.cases[0][1..], s.cases[3][1..]);
    let ratio = r[3].done().unwrap().reynolds / r[0].done().unwrap().reynolds;
    assert!((ratio - 2.0).abs() < 1e-12, "{ratio}");
}

#[test]
fn latin_hypercube_strata_and_seed() {
    // McKay et al. (1979): in each dimension, each of the n strata holds exactly one sample.
    let n = 17;
    let pts = latin_hypercube(&[(0.0, 1.0), (10.0, 20.0), (-5.0, 5.0)], n, 42);
    assert_eq!(pts.len(), n);
    for (d, (lo, hi)) in [(0.0, 1.0), (10.0, 20.0), (-5.0, 5.0)].iter().enumerate() {
        let mut strata: Vec<usize> = pts
            .iter()
            .map(|p| ((p[d] - lo) / (hi - lo) * n as f64).floor() as usize)
            .collect();
        strata.sort();
        assert_eq!(strata, (0..n).collect::<Vec<_>>());
    }
    assert_eq!(
        pts,
        latin_hypercube(&[(0.0, 1.0), (10.0, 20.0), (-5.0, 5.0)], n, 42)
    );
    assert_ne!(
        pts,
        latin_hypercube(&[(0.0, 1.0), (10.0, 20.0), (-5.0, 5.0)], n, 43)
    );
    let s = study(
        r#"
base_model = "drosophila"
design = "latin_hypercube"
samples = 5
seed = 7
responses = ["lift_over_weight"]
[[factor]]
path = "kinematics.amplitude_deg"
range = [120.0, 160.0]
"#,
    );
    assert_eq!(s.case_count(), 5);
    assert!(s.cases.iter().all(|c| (120.0..160.0).contains(&c[0])));
}

#[test]
fn paths_into_defaults_arrays_and_integers() {
    let s = study(
        r#"
base_model = "drosophila"
design = "full_factorial"
responses = ["lift_over_weight"]
[[factor]]
path = "aero.strips"
levels = [10, 40]
[[factor]]
path = "initial.attitude_deg[1]"
levels = [40.0]
[[factor]]
path = "controls.amplitude_deg"
levels = [5.0]
"#,
    );
    let v = s.vehicle(1).unwrap();
    assert_eq!(v.wings[0].geometry().strips.len(), 40);
    assert!((v.controls.amplitude_rad.to_degrees() - 5.0).abs() < 1e-12);
    assert!((v.wings[0].kinematics().amplitude_rad.to_degrees() - 145.0).abs() < 1e-9);
}

#[test]
fn bad_studies_name_the_factor() {
    let head = "base_model = \"drosophila\"\ndesign = \"full_factorial\"\nresponses = [\"lift_over_weight\"]\n";
    let e = study_err(&format!(
        "{head}[[factor]]\npath = \"kinematics.amplitude_deg\"\nlevels = [140.0, 200.0]\n"
    ));
    assert!(
        e.contains("factor 1 (`kinematics.amplitude_deg`): level 200") && e.contains("(0, 180]"),
        "{e}"
    );
    let e = study_err(&format!(
        "{head}[[factor]]\npath = \"kinematics.amplitude_dg\"\nlevels = [140.0]\n"
    ));
    assert!(
        e.contains("`kinematics.amplitude_dg`") && e.contains("amplitude_dg"),
        "{e}"
    );
    let e = study_err(&format!(
        "{head}[[factor]]\npath = \"aero.strips\"\nlevels = [10.5]\n"
    ));
    assert!(
        e.contains("`aero.strips`") && e.contains("not an integer"),
        "{e}"
    );
    let e = study_err(&format!(
        "{head}[[factor]]\npath = \"name\"\nlevels = [1.0]\n"
    ));
    assert!(e.contains("`name`") && e.contains("string"), "{e}");
    let e = study_err(&format!(
        "{head}[[factor]]\npath = \"initial.attitude_deg[3]\"\nlevels = [1.0]\n"
    ));
    assert!(e.contains("out of range"), "{e}");
    let e = study_err(
        "base_model = \"drosophila\"\ndesign = \"full_factorial\"\nresponses = [\"lift\"]\n[[factor]]\npath = \"kinematics.amplitude_deg\"\nlevels = [140.0]\n",
    );
    assert!(
        e.contains("unknown response `lift`") && e.contains("lift_over_weight"),
        "{e}"
    );
    let e = study_err(
        "base_model = \"drosophila\"\ndesign = \"latin_hypercube\"\nsamples = 3\nresponses = [\"aero_power_w\"]\n[[factor]]\npath = \"kinematics.amplitude_deg\"\nlevels = [140.0]\n",
    );
    assert!(e.contains("needs `range"), "{e}");
    let e = study_err(
        "base_model = \"drosophila\"\ndesign = \"taguchi_l9\"\nresponses = [\"aero_power_w\"]\n[[factor]]\npath = \"kinematics.amplitude_deg\"\nlevels = [140.0, 150.0]\n",
    );
    assert!(e.contains("no free column with 2 levels"), "{e}");
    let e = study_err(
        "base_model = \"drosophila\"\ndesign = \"box_behnken\"\nresponses = []\nfactor = []\n",
    );
    assert!(
        e.starts_with("test.toml:") && e.contains("box_behnken"),
        "{e}"
    );
    assert!(Response::parse("cd_mean_added_mass").is_some());
}

#[test]
fn a_sweep_over_an_actuated_robobee_drive() {
    // The study's factor is a drive parameter; each case runs the wings into their periodic
    // motion (flapsim::actuated::periodic) and averages it. Below the stroke resonance the
    // stroke amplitude, and with it the lift, grows with the drive amplitude. The robobee
    // rebuilt from published sources (issue 24) lifts 0.95 of its weight at its 100 V limit
    // and does not trim (`flapwing validate`'s vehicles section), so trim_feasible is only
    // checked to be a verdict.
    let s = study(
        "name = \"robobee_drive\"\nbase_model = \"robobee\"\ndesign = \"full_factorial\"\nresponses = [\"lift_over_weight\", \"aero_power_w\", \"trim_feasible\"]\n[[factor]]\npath = \"actuation.drive.amplitude_v\"\nlevels = [60.0, 80.0, 100.0]\n",
    );
    let r = s.run(0..3, &|_| ()).unwrap();
    let lw: Vec<f64> = r.iter().map(|c| c.responses[0]).collect();
    assert!(lw[0] < lw[1] && lw[1] < lw[2], "L/W {lw:?}");
    assert!(lw[0] < 1.0, "L/W {lw:?}");
    assert!(
        r.iter().all(|c| c.responses[1] > 0.0),
        "the drive works against the air"
    );
    assert!(
        r.iter()
            .all(|c| c.responses[2] == 0.0 || c.responses[2] == 1.0),
        "each case has a trim verdict"
    );
}
