//! Bad vehicle files give errors naming file, field, value and what is allowed.

use flapsim::Vehicle;

fn err(text: &str) -> String {
    Vehicle::from_toml(text, "bad.toml")
        .unwrap_err()
        .to_string()
}

#[test]
fn errors_name_file_field_value_and_range() {
    let good = flapsim::DROSOPHILA_TOML;
    Vehicle::from_toml(good, "ok").unwrap();
    let cases = [
        ("mass_kg = 1.0e-6", "mass_kg = -1.0e-6", "body.mass_kg"),
        ("mass_kg = 1.0e-6", "mass_kg = nan", "body.mass_kg"),
        ("freq_hz = 218.0", "freq_hz = 0.0", "kinematics.freq_hz"),
        (
            "amplitude_deg = 140.0",
            "amplitude_deg = 0.0",
            "kinematics.amplitude_deg",
        ),
        (
            "amplitude_deg = 140.0",
            "amplitude_deg = 1e300",
            "kinematics.amplitude_deg",
        ),
        ("span_m = 2.39e-3", "span_m = inf", "wing.planform.span_m"),
        (
            "\nsteps_per_wingbeat = 20 ",
            "\nsteps_per_wingbeat = 5 ",
            "sim.steps_per_wingbeat",
        ),
        (
            "stroke_plane_tilt_deg = 45.0",
            "stroke_plane_tilt_deg = 400.0",
            "hinge.stroke_plane_tilt_deg",
        ),
        (
            "inertia_diag_kg_m2 = [8.1e-14, 3.53e-13, 3.53e-13]",
            "inertia_diag_kg_m2 = [8.1e-14, 3.53e-13, 9.53e-13]",
            "body.inertia_diag_kg_m2",
        ),
    ];
    for (from, to, field) in cases {
        assert!(good.contains(from), "fixture lost {from}");
        let e = err(&good.replacen(from, to, 1));
        assert!(
            e.starts_with("bad.toml") && e.contains(field) && e.contains("not allowed"),
            "{to}: {e}"
        );
    }
    let unknown = err(&good.replacen("[body]", "[body]\nmass_g = 1.0", 1));
    assert!(
        unknown.contains("bad.toml") && unknown.contains("mass_g"),
        "{unknown}"
    );
    let missing = err(&good.replacen("length_m = 2.5e-3", "", 1));
    assert!(
        missing.contains("bad.toml") && missing.contains("length_m"),
        "{missing}"
    );
    let wrong_type = err(&good.replacen("mass_kg = 1.0e-6", "mass_kg = \"heavy\"", 1));
    assert!(
        wrong_type.contains("bad.toml") && wrong_type.contains("mass_kg"),
        "{wrong_type}"
    );
}

#[test]
fn an_actuated_vehicle_refuses_the_frozen_downwash_and_takes_the_dynamic_wake() {
    // A frozen downwash's disc is a prescribed stroke amplitude, which an actuated wing's
    // dynamics produce rather than take as an input (wingforce::inflow); the dynamic wake
    // measures the stroke they sweep (wingset::set::inflow).
    for line in ["induced_inflow = true", "inflow = \"frozen\""] {
        let text = format!("{}\n[aero]\n{line}\n", flapsim::ROBOBEE_TOML);
        let e = err(&text);
        assert!(
            e.starts_with("bad.toml")
                && e.contains("aero.inflow")
                && e.contains("actuated")
                && e.contains("\"dynamic\""),
            "{line}: {e}"
        );
    }
    let text = format!("{}\n[aero]\ninflow = \"dynamic\"\n", flapsim::ROBOBEE_TOML);
    let v = Vehicle::from_toml(&text, "dynamic.toml").unwrap();
    assert_eq!(v.inflow_model(), wingforce::InflowModel::Dynamic);
}

#[test]
fn an_unknown_or_contradictory_inflow_model_is_named() {
    let fly = flapsim::DROSOPHILA_TOML;
    assert!(fly.contains("induced_inflow = true") || fly.contains("inflow = "));
    let base = fly
        .lines()
        .filter(|l| !l.starts_with("induced_inflow") && !l.starts_with("inflow ="))
        .collect::<Vec<_>>()
        .join("\n");
    let unknown = err(&base.replacen("[aero]", "[aero]\ninflow = \"swirl\"", 1));
    assert!(
        unknown.contains("bad.toml")
            && unknown.contains("swirl")
            && unknown.contains("off")
            && unknown.contains("frozen")
            && unknown.contains("dynamic"),
        "{unknown}"
    );
    let both = err(&base.replacen(
        "[aero]",
        "[aero]\ninflow = \"dynamic\"\ninduced_inflow = true",
        1,
    ));
    assert!(
        both.starts_with("bad.toml") && both.contains("aero.inflow") && both.contains("dynamic"),
        "{both}"
    );
}

/// A spanwise twist (`[kinematics.twist]`, a measured table's feathering along the span) on
/// an actuated vehicle, whose pitch is an output of its hinge dynamics, would go unused: the
/// file is refused, naming the field. The same twist on a prescribed vehicle loads.
#[test]
fn a_twist_on_an_actuated_vehicle_is_refused() {
    let n = 16;
    let list = |f: &dyn Fn(f64) -> f64| {
        (0..=n)
            .map(|i| format!("{:.6}", f(2.0 * std::f64::consts::PI * i as f64 / n as f64)))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let t = list(&|w| w / (2.0 * std::f64::consts::PI) / 120.0);
    let stroke = list(&|w| -45.0 * w.cos());
    let pitch = list(&|w| 90.0 - 45.0 * w.sin());
    let inner = list(&|w| 90.0 - 30.0 * w.sin());
    let table = format!(
        "[kinematics]\nfamily = \"tabulated\"\nt_s = [{t}]\nstroke_deg = [{stroke}]\npitch_deg = [{pitch}]\n\n[kinematics.twist]\nreference_r_frac = 0.75\nstations_r_frac = [0.25]\npitch_deg = [[{inner}]]\n"
    );
    let replace = |model: &str| {
        let start = model.find("\n[kinematics]\n").unwrap() + 1;
        let end = start + model[start..].find("\n\n").unwrap();
        format!("{}{table}{}", &model[..start], &model[end..])
    };
    let e = err(&replace(flapsim::ROBOBEE_TOML));
    assert!(
        e.contains("bad.toml") && e.contains("kinematics.twist") && e.contains("actuated"),
        "{e}"
    );
    Vehicle::from_toml(&replace(flapsim::ROBOBEE_KINEMATIC_TOML), "ok").unwrap();
}
