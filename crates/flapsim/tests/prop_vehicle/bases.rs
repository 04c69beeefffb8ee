//! The base models that every property mutates: the real vehicle files
//! (`models/drosophila.toml`, `robobee.toml`, `bumblebee.toml`) and a "full" drosophila that
//! spells out every optional field (gravity, Ixz, overrides, left harmonic and right tabulated
//! kinematics, controls, aero, sim, initial), each checked to load; and the test that they
//! cover every section of the format.

use toml::Value;

use crate::checks::load;
use crate::toml_mutation::{leaves, parse, path_str, tabulated_kinematics_toml};

/// Every optional section and field of the vehicle format, at values that load.
const FULL_EXTRAS: &str = r#"
gravity_m_s2 = 9.81

[body]
mass_kg = 1.0e-6
inertia_diag_kg_m2 = [8.1e-14, 3.53e-13, 3.53e-13]
inertia_xz_kg_m2 = 1.0e-15
length_m = 2.5e-3

[wing.overrides]
sqrt_sxx_syy_m4 = 1.0e-12
sx_absx_m4 = -1.0e-13

[left_kinematics]
family = "harmonic"
freq_hz = 218.0
amplitude_deg = 140.0
mid_stroke_aoa_deg = 40.0
pitch_phase_deg = 5.0
deviation_amplitude_deg = 3.0
mean_stroke_deg = 1.0
pitch_bias_deg = 1.0

[controls]
mean_stroke_deg = 1.0
amplitude_deg = 2.0
pitch_bias_deg = 1.0
freq_hz = 1.0
diff_amplitude_deg = 1.0
diff_pitch_bias_deg = 0.5
diff_mean_stroke_deg = 0.5

[aero]
translational = "lee2016"
ar_ro_corrections = true
rotational = true
added_mass = true
wake_capture = true
c_rot = 2.08
strips = 9
cp_chord_frac = 0.25

[sim]
steps_per_wingbeat = 40
solver_iterations = 2
ground = true
wing_mass_kg = 1.0e-9
max_speed_m_s = 40.0
max_angular_speed_rad_s = 4000.0

[initial]
position_m = [0.0, 0.0, 0.1]
attitude_deg = [1.0, 45.0, 2.0]
velocity_m_s = [0.01, 0.0, 0.0]
angular_velocity_deg_s = [0.0, 1.0, 0.0]
"#;

/// Merges the tables of `extra` into `base` (replacing leaves).
fn merge(base: &mut Value, extra: &Value) {
    match (base, extra) {
        (Value::Table(b), Value::Table(e)) => {
            for (k, v) in e {
                match b.get_mut(k) {
                    Some(slot @ Value::Table(_)) if v.is_table() => merge(slot, v),
                    _ => {
                        b.insert(k.clone(), v.clone());
                    }
                }
            }
        }
        (b, e) => *b = e.clone(),
    }
}

fn bases() -> Vec<(&'static str, Value)> {
    let mut out = vec![
        ("drosophila.toml", parse(flapsim::DROSOPHILA_TOML)),
        ("robobee.toml", parse(flapsim::ROBOBEE_KINEMATIC_TOML)),
        ("bumblebee.toml", parse(flapsim::BUMBLEBEE_TOML)),
    ];
    let mut full = parse(flapsim::DROSOPHILA_TOML);
    merge(&mut full, &parse(FULL_EXTRAS));
    full.as_table_mut().unwrap().insert(
        "right_kinematics".into(),
        parse(&tabulated_kinematics_toml(31, 1.0 / 218.0, 50.0, 2.0)),
    );
    out.push(("drosophila-full", full));
    for (name, v) in &out {
        let text = toml::to_string(v).unwrap();
        load(&text).unwrap_or_else(|e| panic!("base {name} must load: {e}"));
    }
    out
}

pub(crate) fn bases_cached() -> &'static [(&'static str, Value)] {
    static BASES: std::sync::OnceLock<Vec<(&'static str, Value)>> = std::sync::OnceLock::new();
    BASES.get_or_init(bases)
}

#[test]
fn bases_load_and_cover_every_section() {
    let mut names = Vec::new();
    for (_, v) in bases_cached() {
        let mut ls = Vec::new();
        leaves(v, &mut Vec::new(), &mut ls);
        names.extend(ls.iter().map(|p| path_str(p)));
    }
    for needle in [
        "gravity_m_s2",
        "body.inertia_xz_kg_m2",
        "wing.overrides.sx_absx_m4",
        "left_kinematics.pitch_phase_deg",
        "right_kinematics.t_s[3]",
        "controls.diff_mean_stroke_deg",
        "aero.strips",
        "sim.max_angular_speed_rad_s",
        "initial.angular_velocity_deg_s[2]",
        "kinematics.dtau_d",
    ] {
        assert!(names.iter().any(|n| n == needle), "{needle} not covered");
    }
}
