//! Domain-randomisation files (flapsim::randomize): every field a file can name, in every
//! built-in model, is drawn within its range, scaled exactly, reproducibly per seed, and
//! reported; the issue's categories (mass, inertia, wing geometry, hinge, actuator, sensor
//! noise) reach the built vehicle; a bad file names the file, field, value and what is
//! allowed.

use flapsim::randomize::Randomization;
use flapsim::sensors::Noise;
use flapsim::{Vehicle, VehicleSpec};

const MODELS: [&str; 5] = [
    "drosophila",
    "bumblebee",
    "robobee_kinematic",
    "robobee",
    "hummingbird",
];

/// The dotted paths of every real-valued field (a float or a non-empty array of floats,
/// nested arrays included) of a model: what a randomisation file may name.
fn real_paths(t: &toml::Table, prefix: &str, out: &mut Vec<String>) {
    fn real(v: &toml::Value) -> bool {
        match v {
            toml::Value::Float(_) => true,
            toml::Value::Array(a) => !a.is_empty() && a.iter().all(real),
            _ => false,
        }
    }
    for (k, v) in t {
        let p = format!("{prefix}{k}");
        match v {
            toml::Value::Table(sub) => real_paths(sub, &format!("{p}."), out),
            v if real(v) => out.push(p),
            _ => {}
        }
    }
}

fn at<'a>(t: &'a toml::Table, path: &str) -> &'a toml::Value {
    let mut parts = path.split('.');
    let mut v = &t[parts.next().unwrap()];
    for p in parts {
        v = &v[p];
    }
    v
}

/// The floats of a value, flattened.
fn floats(v: &toml::Value) -> Vec<f64> {
    match v {
        toml::Value::Float(x) => vec![*x],
        toml::Value::Array(a) => a.iter().flat_map(floats).collect(),
        _ => vec![],
    }
}

fn one(path: &str, lo: f64, hi: f64) -> Randomization {
    Randomization::from_toml(
        &format!("[[param]]\npath = \"{path}\"\nscale = [{lo:?}, {hi:?}]\n"),
        "r.toml",
    )
    .unwrap()
}

#[test]
fn every_real_field_of_every_builtin_model_is_drawn_within_range_exactly_and_reproducibly() {
    let (lo, hi) = (0.8, 1.25);
    let mut fields = 0;
    for name in MODELS {
        let text = flapsim::builtin_model(name).unwrap();
        let base: toml::Table = text.parse().unwrap();
        let mut paths = Vec::new();
        real_paths(&base, "", &mut paths);
        assert!(paths.len() >= 10, "{name}: {paths:?}");
        for path in &paths {
            let r = one(path, lo, hi);
            let mut seen = Vec::new();
            for seed in 0..3u64 {
                let (drawn, draws) = r.draw(text, name, &mut Noise::new(seed)).unwrap();
                // Reported: one draw per entry, the path and the factor, within the range.
                assert_eq!(draws.len(), 1);
                let (p, k) = &draws[0];
                assert_eq!(p, path);
                assert!((lo..=hi).contains(k), "{name} {path}: {k}");
                // Reproducible: the same seed gives the same model and factor.
                assert_eq!(
                    r.draw(text, name, &mut Noise::new(seed)).unwrap(),
                    (drawn.clone(), draws.clone()),
                    "{name} {path} seed {seed}"
                );
                // Exact: the field (every element) is the base times k; nothing else moves.
                let t: toml::Table = drawn.parse().unwrap();
                for (a, b) in floats(at(&t, path)).iter().zip(floats(at(&base, path))) {
                    assert_eq!(*a, b * k, "{name} {path}");
                }
                for other in paths.iter().filter(|o| *o != path) {
                    assert_eq!(floats(at(&t, other)), floats(at(&base, other)), "{other}");
                }
                seen.push(*k);
            }
            // Different seeds draw different factors.
            assert!(
                seen[0] != seen[1] && seen[1] != seen[2],
                "{name} {path}: {seen:?}"
            );
            fields += 1;
        }
    }
    assert!(fields > 100, "{fields} fields exercised");
}

#[test]
fn draws_of_the_issue_categories_reach_the_built_vehicle() {
    // Mass, inertia, wing geometry, hinge, sensor noise (drosophila) and the actuated hinge
    // and actuator (robobee), each over a range, many seeds: the built vehicle carries
    // exactly the drawn value.
    let r = Randomization::from_toml(
        include_str!("../../../examples/python/randomize.toml"),
        "randomize.toml",
    )
    .unwrap();
    let base = Vehicle::from_toml(flapsim::DROSOPHILA_TOML, "drosophila").unwrap();
    let bs = base.sensors.unwrap();
    for seed in 0..20u64 {
        let (text, draws) = r
            .draw(
                flapsim::DROSOPHILA_TOML,
                "drosophila",
                &mut Noise::new(seed),
            )
            .unwrap();
        let v = VehicleSpec::from_toml(&text, "drawn")
            .unwrap()
            .build("drawn")
            .unwrap();
        let k = |p: &str| draws.iter().find(|(q, _)| q == p).unwrap().1;
        for (p, k) in &draws {
            let range = r.param.iter().find(|q| &q.path == p).unwrap().scale;
            assert!(
                range[0] <= *k && *k <= range[1],
                "{p}: {k} outside {range:?}"
            );
        }
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs();
        assert!(close(v.mass_kg, base.mass_kg * k("body.mass_kg")));
        for i in 0..3 {
            let ki = k("body.inertia_diag_kg_m2");
            assert!(close(
                v.inertia_kg_m2[(i, i)],
                base.inertia_kg_m2[(i, i)] * ki
            ));
            let kh = k("hinge.left_in_body_m");
            let (h, h0) = (
                v.wings[0].mount().hinge_in_body_m[i],
                base.wings[0].mount().hinge_in_body_m[i],
            );
            assert!(close(h, h0 * kh), "hinge {i}: {h} vs {h0} x {kh}");
        }
        let span = |v: &Vehicle| v.wings[0].geometry().span_m;
        assert!(close(span(&v), span(&base) * k("wing.planform.span_m")));
        let s = v.sensors.unwrap();
        assert!(close(
            s.imu.gyro_noise_density,
            bs.imu.gyro_noise_density * k("sensors.imu.gyro_noise_density_deg_s_sqrt_hz")
        ));
        assert!(close(
            s.imu.accel_noise_density,
            bs.imu.accel_noise_density * k("sensors.imu.accel_noise_density_ug_sqrt_hz")
        ));
    }
    // The actuated RoboBee's hinge stiffness and flexure.
    let r = Randomization::from_toml(
        include_str!("../../../examples/python/randomize_robobee.toml"),
        "randomize_robobee.toml",
    )
    .unwrap();
    let base: toml::Table = flapsim::ROBOBEE_TOML.parse().unwrap();
    for seed in 0..5u64 {
        let (text, draws) = r
            .draw(flapsim::ROBOBEE_TOML, "robobee", &mut Noise::new(seed))
            .unwrap();
        VehicleSpec::from_toml(&text, "drawn")
            .unwrap()
            .build("drawn")
            .unwrap();
        let t: toml::Table = text.parse().unwrap();
        for (p, k) in &draws {
            assert_eq!(floats(at(&t, p))[0], floats(at(&base, p))[0] * k, "{p}");
        }
    }
}

fn bad_file(text: &str) -> String {
    Randomization::from_toml(text, "bad.toml")
        .unwrap_err()
        .to_string()
}

fn bad_path(path: &str) -> String {
    one(path, 0.9, 1.1)
        .check(flapsim::DROSOPHILA_TOML, "drosophila.toml")
        .unwrap_err()
        .to_string()
}

#[test]
fn bad_files_name_the_file_field_value_and_what_is_allowed() {
    let entry =
        |path: &str, scale: &str| format!("[[param]]\npath = \"{path}\"\nscale = {scale}\n");
    for (text, field, value, allowed) in [
        (
            entry("body.mass_kg", "[0.0, 1.1]"),
            "param[0].scale[0] (body.mass_kg)",
            "= 0 ",
            "a finite number > 0",
        ),
        (
            entry("body.mass_kg", "[-1.0, 1.1]"),
            "param[0].scale[0] (body.mass_kg)",
            "= -1 ",
            "a finite number > 0",
        ),
        (
            entry("body.mass_kg", "[1.1, 0.9]"),
            "param[0].scale (body.mass_kg)",
            "[1.1, 0.9]",
            "0 < low <= high",
        ),
        (
            entry("body.mass_kg", "[0.9, inf]"),
            "param[0].scale (body.mass_kg)",
            "[0.9, inf]",
            "0 < low <= high",
        ),
        (
            entry("body.mass_kg", "[nan, 1.1]"),
            "param[0].scale[0] (body.mass_kg)",
            "NaN",
            "a finite number > 0",
        ),
        (
            format!(
                "{}{}",
                entry("body.mass_kg", "[0.9, 1.1]"),
                entry("body.mass_kg", "[0.8, 1.2]")
            ),
            "param[1].path",
            "\"body.mass_kg\"",
            "not named by an earlier entry",
        ),
    ] {
        let e = bad_file(&text);
        assert!(e.starts_with("bad.toml:"), "{e}");
        for part in [field, value, allowed] {
            assert!(e.contains(part), "`{part}` missing from: {e}");
        }
    }
    // The file's shape: a missing or unknown key, a range of the wrong length.
    for (text, says) in [
        ("[[param]]\nscale = [0.9, 1.1]\n".to_owned(), "path"),
        (
            entry("body.mass_kg", "[0.9, 1.1]") + "scales = 1.0\n",
            "scales",
        ),
        (entry("body.mass_kg", "[0.9]"), "scale"),
        ("[[parm]]\n".to_owned(), "parm"),
    ] {
        let e = bad_file(&text);
        assert!(
            e.starts_with("bad.toml:") && e.contains(says),
            "{says}: {e}"
        );
    }
    // Paths the model cannot scale: each says which, and what a path must be.
    for (path, why) in [
        ("body.no_such", "no such field"),
        ("no_such.table", "no such field"),
        ("body", "a table"),
        ("name", "not a number"),
        ("kinematics.family", "not a number"),
        ("sim.steps_per_wingbeat", "an integer field"),
    ] {
        let e = bad_path(path);
        for part in [
            "r.toml",
            "param[0].path",
            &format!("\"{path}\" ({why} in drosophila.toml)"),
            "a real-valued field",
        ] {
            assert!(e.contains(part), "`{part}` missing from: {e}");
        }
    }
}
