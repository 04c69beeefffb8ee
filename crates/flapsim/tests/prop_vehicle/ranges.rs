//! Targeted ranges: an out-of-range value of each documented field (body, wing, hinge,
//! kinematics, fluid, aero, sim, controls, initial state; integer settings too) is rejected
//! with `Error::Invalid` naming exactly that field.

use flapsim::Error;
use proptest::prelude::*;
use toml::Value;

use crate::bases::bases_cached;
use crate::checks::{check_error, load_guarded};
use crate::toml_mutation::{INF, Range, config, r, range_and_value, set_path};

/// `base` indexes [`bases`]: 0 drosophila, 1 robobee, 2 bumblebee, 3 drosophila-full.
const RANGES: &[Range] = &[
    // Negative or zero mass, length, inertia, area.
    r(0, "body.mass_kg", 0.0, INF, true, true),
    r(1, "body.mass_kg", 0.0, INF, true, true),
    r(2, "body.length_m", 0.0, INF, true, true),
    r(3, "body.length_m", 0.0, INF, true, true),
    Range {
        field: "body.inertia_diag_kg_m2[0]",
        ..r(0, "body.inertia_diag_kg_m2.0", 0.0, INF, true, true)
    },
    Range {
        field: "body.inertia_diag_kg_m2[2]",
        ..r(3, "body.inertia_diag_kg_m2.2", 0.0, INF, true, true)
    },
    r(3, "body.inertia_xz_kg_m2", -INF, INF, true, true),
    r(0, "gravity_m_s2", 0.0, 100.0, false, false),
    r(0, "wing.planform.area_m2", 0.0, INF, true, true),
    r(1, "wing.planform.span_m", 0.0, INF, true, true),
    r(2, "wing.planform.r1_hat", 0.4, 0.6, false, false),
    r(3, "wing.overrides.sqrt_sxx_syy_m4", 0.0, INF, true, true),
    r(3, "wing.overrides.sx_absx_m4", -INF, INF, true, true),
    // Hinge.
    Range {
        field: "hinge.left_in_body_m[1]",
        ..r(0, "hinge.left_in_body_m.1", -1.0, 1.0, false, false)
    },
    r(2, "hinge.stroke_plane_tilt_deg", -90.0, 90.0, false, false),
    // Kinematics: angles beyond range, zero frequency, zero amplitude.
    r(0, "kinematics.freq_hz", 0.0, INF, true, true),
    r(1, "kinematics.freq_hz", 0.0, INF, true, true),
    r(0, "kinematics.amplitude_deg", 0.0, 180.0, true, false),
    r(1, "kinematics.amplitude_deg", 0.0, 180.0, true, false),
    r(2, "kinematics.downstroke_aoa_deg", 0.0, 90.0, false, false),
    r(2, "kinematics.upstroke_aoa_deg", 0.0, 90.0, false, false),
    r(2, "kinematics.flip_duration", 0.01, 0.5, false, false),
    r(2, "kinematics.flip_offset", -0.25, 0.25, false, false),
    r(0, "kinematics.dtau_a", 0.0, 0.5, true, false),
    r(3, "left_kinematics.amplitude_deg", 0.0, 180.0, true, false),
    r(3, "left_kinematics.freq_hz", 0.0, INF, true, true),
    r(
        3,
        "left_kinematics.pitch_phase_deg",
        -90.0,
        90.0,
        false,
        false,
    ),
    Range {
        field: "right_kinematics.stroke_deg[4]",
        ..r(
            3,
            "right_kinematics.stroke_deg.4",
            -360.0,
            360.0,
            false,
            false,
        )
    },
    // Fluid.
    r(0, "fluid.density_kg_m3", 0.0, INF, true, true),
    r(2, "fluid.kinematic_viscosity_m2_s", 0.0, INF, true, true),
    // Aero.
    r(3, "aero.c_rot", 0.0, INF, true, true),
    r(3, "aero.cp_chord_frac", 0.0, 1.0, false, false),
    // Sim.
    r(3, "sim.wing_mass_kg", 0.0, INF, false, true),
    r(3, "sim.max_speed_m_s", 0.0, INF, true, true),
    r(3, "sim.max_angular_speed_rad_s", 0.0, INF, true, true),
    // Controls.
    r(3, "controls.mean_stroke_deg", -60.0, 60.0, false, false),
    r(3, "controls.amplitude_deg", -90.0, 90.0, false, false),
    r(3, "controls.pitch_bias_deg", -30.0, 30.0, false, false),
    r(3, "controls.freq_hz", -INF, INF, true, true),
    r(3, "controls.diff_amplitude_deg", -90.0, 90.0, false, false),
    r(3, "controls.diff_pitch_bias_deg", -30.0, 30.0, false, false),
    r(
        3,
        "controls.diff_mean_stroke_deg",
        -60.0,
        60.0,
        false,
        false,
    ),
    // Initial state.
    Range {
        field: "initial.position_m[2]",
        ..r(3, "initial.position_m.2", -1e4, 1e4, false, false)
    },
    Range {
        field: "initial.attitude_deg[1]",
        ..r(0, "initial.attitude_deg.1", -180.0, 180.0, false, false)
    },
    Range {
        field: "initial.velocity_m_s[0]",
        ..r(3, "initial.velocity_m_s.0", -100.0, 100.0, false, false)
    },
    Range {
        field: "initial.angular_velocity_deg_s[1]",
        ..r(
            3,
            "initial.angular_velocity_deg_s.1",
            -1e5,
            1e5,
            false,
            false,
        )
    },
];

fn expect_invalid(text: &str, field: &str, what: &str) -> Result<(), TestCaseError> {
    let e = load_guarded(text)?.expect_err(&format!("{what} accepted"));
    check_error(&e, text)?;
    match &e {
        Error::Model(wingforce::Error::Invalid { field: f, .. }) => {
            prop_assert_eq!(f, field, "{}: {}", what, e)
        }
        _ => prop_assert!(false, "{}: not a value error: {}", what, e),
    }
    Ok(())
}

proptest! {
    #![proptest_config(config(600))]

    /// Out-of-range body, wing, hinge, kinematics, fluid, aero, sim, controls and initial
    /// values: rejected with `Error::Invalid` naming exactly the field.
    #[test]
    fn out_of_range_values_name_their_field((range, x) in range_and_value(RANGES)) {
        let mut v = bases_cached()[range.base].1.clone();
        set_path(&mut v, range.path, Value::Float(x));
        let text = toml::to_string(&v).unwrap();
        expect_invalid(&text, range.field, &format!("{} = {x:?}", range.path))?;
    }
}

/// Integer settings and their ranges (base drosophila-full).
const INT_RANGES: &[(&str, i64, i64)] = &[
    ("sim.steps_per_wingbeat", 10, 100_000),
    ("sim.solver_iterations", 1, 16),
    ("aero.strips", 1, 1000),
];

proptest! {
    #![proptest_config(config(200))]

    /// Integer settings outside their range (0, just outside, huge) name the field.
    #[test]
    fn out_of_range_integers_name_their_field(
        which in 0..INT_RANGES.len(),
        below in any::<bool>(),
        frac in 0.0f64..1.0,
        huge in any::<bool>(),
    ) {
        let (path, lo, hi) = INT_RANGES[which];
        let x = if below {
            ((lo as f64) * frac) as i64
        } else if huge {
            hi + 1 + ((i64::MAX - hi - 1) as f64 * frac) as i64
        } else {
            hi + 1 + (1000.0 * frac) as i64
        };
        let mut v = bases_cached()[3].1.clone();
        set_path(&mut v, path, Value::Integer(x));
        let text = toml::to_string(&v).unwrap();
        expect_invalid(&text, path, &format!("{path} = {x}"))?;
    }
}
