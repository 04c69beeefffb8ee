//! Property tests (issue 7): every bad vehicle file gets a clear error and nothing panics.
//!
//! `flapsim::Vehicle::from_toml` is fed mutated versions of the real vehicle files
//! (`models/drosophila.toml`, `robobee.toml`, `bumblebee.toml`) and of a "full" drosophila that
//! spells out every optional field (gravity, Ixz, overrides, left harmonic and right tabulated
//! kinematics, controls, aero, sim, initial), random tabulated kinematics, garbage and truncated
//! text. Loading must never panic and must either succeed or return an error whose Display
//! starts with `<origin>: `; value errors must name the field and say "not allowed". Targeted
//! properties check that out-of-range values of each documented field are rejected naming
//! exactly that field. A vehicle that loads must also start simulating without a panic.
//!
//! Generated inputs per property (proptest `cases`; the file runs in a few seconds in release):
//!
//! | property                                        | cases |
//! |-------------------------------------------------|-------|
//! | `structural_mutations_never_panic`              |  1500 |
//! | `out_of_range_values_name_their_field`          |   600 |
//! | `out_of_range_integers_name_their_field`        |   200 |
//! | `unknown_fields_are_named`                      |   300 |
//! | `type_errors_are_parse_errors`                  |   400 |
//! | `text_mutations_never_panic`                    |  1500 |
//! | `tabulated_kinematics_tables`                   |   400 |
//! | `moderate_values_load_and_simulate_or_fail_cleanly` | 400 |
//! | `controls_that_break_the_kinematics_name_controls` | 200 |
//! | `loaded_vehicles_simulate` (exhaustive, not proptest) | ~1500 |
//!
//! `FLAPWING_PROP_SCALE=N` multiplies every proptest case count (for long local soak runs).
//!
//! The TOML-tree walkers, the mutation, text-mutation, table and range generators and
//! `config` are shared with `wingforce/tests/prop_model.rs`, in
//! `crates/wingforce/tests/support/toml_mutation.rs` (included here with `#[path]`).

use std::panic::{AssertUnwindSafe, catch_unwind};

use flapsim::{Error, Mode, Simulation, Vehicle};
use proptest::prelude::*;
use proptest::sample::Index;
use toml::Value;

#[path = "../../wingforce/tests/support/prop_config.rs"]
mod prop_config;
#[path = "../../wingforce/tests/support/toml_mutation.rs"]
mod toml_mutation;
use toml_mutation::{
    Defect, INF, Mutation, Range, Seg, assert_special_values, config, get_mut, guarded, leaves,
    mutate_text, mutated, mutation, non_number, numeric_leaves, panic_message, parse, path_str,
    put_table, r, range_and_value, repl, replace_numeric_leaf, set_path, table,
    tabulated_kinematics_toml, text_mutation,
};

const ORIGIN: &str = "mut/vehicle variant é.toml";

// ---------------------------------------------------------------------------------------------
// Base models.
// ---------------------------------------------------------------------------------------------

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

fn bases_cached() -> &'static [(&'static str, Value)] {
    static BASES: std::sync::OnceLock<Vec<(&'static str, Value)>> = std::sync::OnceLock::new();
    BASES.get_or_init(bases)
}

// ---------------------------------------------------------------------------------------------
// Loading and checking.
// ---------------------------------------------------------------------------------------------

fn load(text: &str) -> Result<Vehicle, Error> {
    Vehicle::from_toml(text, ORIGIN)
}

/// Loads with a `catch_unwind` guard.
fn load_guarded(text: &str) -> Result<Result<Vehicle, Error>, TestCaseError> {
    guarded(text, load)
}

fn check_error(e: &Error, text: &str) -> Result<(), TestCaseError> {
    let s = e.to_string();
    if KNOWN_BUG_CONTROLS && is_known_bug_controls(e) {
        return Ok(());
    }
    prop_assert!(
        s.starts_with(&format!("{ORIGIN}: ")),
        "error does not start with the origin: {s}\ninput:\n{text}"
    );
    match e {
        Error::Model(wingforce::Error::Invalid {
            origin,
            field,
            value,
            allowed,
        }) => {
            prop_assert_eq!(origin, ORIGIN);
            prop_assert!(!field.is_empty() && !value.is_empty() && !allowed.is_empty());
            prop_assert!(
                s.contains(&format!("field `{field}`")) && s.contains("not allowed"),
                "{}",
                s
            );
        }
        Error::Model(wingforce::Error::Parse { origin, message }) => {
            prop_assert_eq!(origin, ORIGIN);
            prop_assert!(!message.trim().is_empty());
        }
        other => prop_assert!(false, "loading returned a non-model error: {other}"),
    }
    Ok(())
}

/// Builds a simulation of a vehicle that loaded and runs up to `steps` steps: must not
/// panic; a step either succeeds or reports a divergence. Returns the first step's error.
fn simulate_briefly(v: Vehicle, steps: usize) -> Result<Option<String>, String> {
    catch_unwind(AssertUnwindSafe(|| {
        let mut sim = Simulation::new(v, Mode::Free);
        for _ in 0..steps {
            match sim.step() {
                Ok(_) => {}
                Err(e @ Error::Diverged { .. }) => return Some(e.to_string()),
                Err(e) => return Some(format!("non-divergence error: {e}")),
            }
        }
        None
    }))
    .map_err(panic_message)
}

// ---------------------------------------------------------------------------------------------
// Structural mutations of the TOML tree.
// ---------------------------------------------------------------------------------------------

proptest! {
    #![proptest_config(config(1500))]

    /// One to three structural mutations of a base vehicle: loading never panics and errors
    /// follow the contract.
    #[test]
    fn structural_mutations_never_panic(
        base in any::<Index>(),
        muts in prop::collection::vec(mutation(), 1..4),
    ) {
        let (what, text) = mutated(&base.get(bases_cached()).1, &muts);
        if let Err(e) = load_guarded(&text)? {
            check_error(&e, &text)
                .map_err(|f| TestCaseError::fail(format!("{f}\nmutations: {what:?}")))?;
        }
    }
}

proptest! {
    #![proptest_config(config(300))]

    /// An unknown field in any table (root, body, wing.planform, kinematics, sim, ...) is a
    /// parse error naming it.
    #[test]
    fn unknown_fields_are_named(base in any::<Index>(), table in any::<Index>(), r in repl()) {
        let (what, text) = mutated(&base.get(bases_cached()).1, &[Mutation::AddUnknown(table, r)]);
        let e = load_guarded(&text)?.expect_err("unknown field accepted");
        check_error(&e, &text)?;
        prop_assert!(
            matches!(e, Error::Model(wingforce::Error::Parse { .. })),
            "{:?}", what
        );
        prop_assert!(e.to_string().contains("zz_unknown_field"), "{what:?}: {e}");
    }
}

proptest! {
    #![proptest_config(config(400))]

    /// A number replaced by a string, boolean, array or table is a parse error.
    #[test]
    fn type_errors_are_parse_errors(
        base in any::<Index>(),
        leaf in any::<Index>(),
        r in non_number(),
    ) {
        let (path, text) = replace_numeric_leaf(&base.get(bases_cached()).1, leaf, &r);
        let e = load_guarded(&text)?.expect_err(&format!("{path} = {r:?} accepted"));
        check_error(&e, &text)?;
        prop_assert!(
            matches!(e, Error::Model(wingforce::Error::Parse { .. })),
            "{} = {:?}: {}", path, r, e
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Targeted ranges.
// ---------------------------------------------------------------------------------------------

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
    ("sim.steps_per_wingbeat", 20, 100_000),
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

// ---------------------------------------------------------------------------------------------
// Text-level mutations.
// ---------------------------------------------------------------------------------------------

proptest! {
    #![proptest_config(config(1500))]

    /// Truncated, bit-flipped, spliced, random-byte and random-text files (the real files
    /// with their comments, and the full variant).
    #[test]
    fn text_mutations_never_panic(which in 0usize..4, m in text_mutation()) {
        let base = match which {
            0 => flapsim::DROSOPHILA_TOML.to_owned(),
            1 => flapsim::ROBOBEE_KINEMATIC_TOML.to_owned(),
            2 => flapsim::BUMBLEBEE_TOML.to_owned(),
            _ => toml::to_string(&bases_cached()[3].1).unwrap(),
        };
        let text = mutate_text(&base, &m);
        if let Err(e) = load_guarded(&text)? {
            check_error(&e, &text)?;
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Tabulated kinematics (as the right wing's kinematics: errors must say `right_kinematics`).
// ---------------------------------------------------------------------------------------------

proptest! {
    #![proptest_config(config(400))]

    /// Not monotonic in time: names `right_kinematics.t_s[i]` and says "increase"; not
    /// periodic: names the stroke's last entry and says "periodic"; smooth tables load and
    /// simulate; random tables never panic.
    #[test]
    fn tabulated_kinematics_tables(
        t in table(6..50, 1e-4..1.0, 5.0..170.0, 0.0..0.01),
    ) {
        let mut v = bases_cached()[3].1.clone();
        put_table(&mut v["right_kinematics"], &t);
        let text = toml::to_string(&v).unwrap();
        let result = load_guarded(&text)?;
        let s = match &result {
            Err(e) => {
                check_error(e, &text)?;
                e.to_string()
            }
            Ok(_) => String::new(),
        };
        match t.defect {
            Defect::None => {
                prop_assert!(result.is_ok(), "smooth table rejected: {}", s);
                let r = simulate_briefly(result.unwrap(), 3);
                prop_assert!(r.is_ok(), "simulation panicked: {:?}", r);
            }
            Defect::NotMonotonic(i) => {
                let field = format!("field `right_kinematics.t_s[{i}]`");
                prop_assert!(s.contains(&field) && s.contains("increase"), "{}", s);
            }
            Defect::NotPeriodic => {
                let field =
                    format!("field `right_kinematics.stroke_deg[{}]`", t.stroke.len() - 1);
                prop_assert!(s.contains(&field) && s.contains("periodic"), "{}", s);
            }
            Defect::Random => {
                if let Ok(vehicle) = result {
                    let r = simulate_briefly(vehicle, 2);
                    prop_assert!(r.is_ok(), "simulation panicked: {:?}", r);
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// A vehicle that loads can be simulated.
// ---------------------------------------------------------------------------------------------

/// KNOWN BUG (issue 7, reported to the lead): these fields are checked only for sign and
/// finiteness, so finite but extreme values load without error and the first simulation step
/// then stops with "the aerodynamic load is not finite" / "the body state is not finite"
/// (`flapwing simulate` exits 1 "diverged" instead of 2 naming the field). Exactly these
/// (field, replacement) pairs are excluded from `loaded_vehicles_simulate`; remove each once
/// the loader rejects it. `Huge` = 1e300, `HugeInt` = i64::MAX, `Tiny` = 1e-300; `*` is any
/// list index.
const KNOWN_BUG_EXTREME: &[(&str, &[&str])] = &[];

/// What is wrong with a vehicle that loaded: a non-finite Re, a panic in the first steps,
/// or a first few steps that stop because a load or the state is not finite. (Stopping
/// because the speed exceeds `sim.max_speed_m_s` is a legitimate outcome of a run: a hinge
/// 1 m from a 1 mg body flips it at once; `flapwing simulate` exits 1 "diverged".)
fn unusable(v: Vehicle) -> Option<String> {
    for w in &v.wings {
        if !(w.reynolds().is_finite() && w.reynolds() > 0.0) {
            return Some(format!("Re = {}", w.reynolds()));
        }
    }
    match simulate_briefly(v, 3) {
        Err(panic) => Some(format!("simulation PANICKED: {panic}")),
        Ok(Some(e)) if e.contains("not finite") || e.contains("non-divergence") => Some(e),
        Ok(_) => None,
    }
}

/// Every numeric leaf of every base set to each special value (NaN, +-inf, 0, negated, -1,
/// +-1e300, 1e-300, i64::MAX): a vehicle that loads simulates three steps without a panic
/// or a non-finite load or state (exhaustive, not random).
#[test]
fn loaded_vehicles_simulate() {
    // List entries: the first two and the last stand for the rest (time budget).
    let some_numeric_leaves = |v0: &Value| {
        let mut probe = v0.clone();
        numeric_leaves(v0)
            .into_iter()
            .filter(|p| match p.last() {
                Some(Seg::Idx(i)) => {
                    let len = get_mut(&mut probe, &p[..p.len() - 1])
                        .as_array()
                        .unwrap()
                        .len();
                    *i < 2 || *i + 1 == len
                }
                _ => true,
            })
            .collect()
    };
    assert_special_values(
        "loaded_vehicles_simulate",
        bases_cached(),
        some_numeric_leaves,
        KNOWN_BUG_EXTREME,
        |text| match catch_unwind(AssertUnwindSafe(|| load(text))) {
            Err(p) => Some(format!(": loader PANICKED: {}", panic_message(p))),
            Ok(Ok(vehicle)) => unusable(vehicle).map(|why| format!(" loads but {why}")),
            Ok(Err(e)) => check_error(&e, text).err().map(|f| format!(": {f}")),
        },
    );
}

proptest! {
    #![proptest_config(config(400))]

    /// Any numeric leaf set to a moderate value (+-1e-6 .. 1e6): the vehicle either fails to
    /// load with a proper error, or loads and its simulation starts without a panic (a
    /// divergence is allowed: e.g. a huge initial velocity beyond sim.max_speed_m_s).
    #[test]
    fn moderate_values_load_and_simulate_or_fail_cleanly(
        base in any::<Index>(),
        leaf in any::<Index>(),
        exp in -6.0f64..6.0,
        negative in any::<bool>(),
    ) {
        let (_, v) = base.get(bases_cached());
        let mut v = v.clone();
        let p = leaf.get(&numeric_leaves(&v)).clone();
        let x = if negative { -1.0 } else { 1.0 } * 10f64.powf(exp);
        *get_mut(&mut v, &p) = Value::Float(x);
        let text = toml::to_string(&v).unwrap();
        match load_guarded(&text)? {
            Ok(vehicle) => {
                let r = simulate_briefly(vehicle, 2);
                prop_assert!(r.is_ok(), "{} = {:?}: simulation panicked: {:?}", path_str(&p), x, r);
            }
            Err(e) => check_error(&e, &text)?,
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Control offsets whose sum with the base kinematics is out of range.
// ---------------------------------------------------------------------------------------------

/// KNOWN BUG (issue 7, reported to the lead): `VehicleSpec::build` calls
/// `Vehicle::apply_controls` before its own checks of the resulting amplitude and frequency
/// (the `controls (resulting left amplitude, deg)` errors), so a `[controls]` section whose
/// offsets are each within range but push the kinematics out of range (e.g. drosophila with
/// `[controls] amplitude_deg = 50.0`: 140 + 50 > 180) fails with `Error::Analysis("controls
/// give wing 0 an amplitude of 190.00 deg ...")`: no origin, no field, and the CLI exits 1
/// instead of 2. While this is `true`, such inputs are only checked to be rejected without a
/// panic; set it to `false` once fixed (the full contract below then applies).
const KNOWN_BUG_CONTROLS: bool = false;

/// The error of `KNOWN_BUG_CONTROLS` (`check_error` lets exactly it through while the flag is
/// set: random values of `controls.*` reach it in the structural and exhaustive tests too).
fn is_known_bug_controls(e: &Error) -> bool {
    matches!(e, Error::Analysis(m) if m.starts_with("controls give wing"))
}

proptest! {
    #![proptest_config(config(200))]

    /// Controls each within their own range: when the resulting amplitude of either wing
    /// leaves (0, 180] deg or the frequency is not > 0, loading fails with a value error on a
    /// `controls` field; otherwise the vehicle loads and simulates.
    #[test]
    fn controls_that_break_the_kinematics_name_controls(
        amp in -90.0f64..=90.0,
        diff_amp in -90.0f64..=90.0,
        freq in prop_oneof![-1e3f64..1e3, -300.0f64..-100.0],
    ) {
        // drosophila-full: left harmonic and right tabulated wings, both 140 deg and 218 Hz.
        let (left, right) = (140.0 + amp + 0.5 * diff_amp, 140.0 + amp - 0.5 * diff_amp);
        let f = 218.0 + freq;
        // Stay clear of the boundaries (the library sums in radians).
        for x in [left, right, left - 180.0, right - 180.0, f] {
            prop_assume!(x.abs() > 1e-6);
        }
        let bad = !(left > 0.0 && left <= 180.0 && right > 0.0 && right <= 180.0 && f > 0.0);
        let mut v = bases_cached()[3].1.clone();
        let c = v["controls"].as_table_mut().unwrap();
        c.insert("amplitude_deg".into(), Value::Float(amp));
        c.insert("diff_amplitude_deg".into(), Value::Float(diff_amp));
        c.insert("freq_hz".into(), Value::Float(freq));
        let text = toml::to_string(&v).unwrap();
        let result = load_guarded(&text)?;
        if bad {
            let e = result.expect_err("out-of-range resulting kinematics accepted");
            if KNOWN_BUG_CONTROLS {
                return Ok(());
            }
            check_error(&e, &text)?;
            match &e {
                Error::Model(wingforce::Error::Invalid { field, .. }) => {
                    prop_assert!(field.starts_with("controls"), "{}", e)
                }
                _ => prop_assert!(false, "not a value error: {}", e),
            }
        } else {
            let vehicle = result.map_err(|e| TestCaseError::fail(format!("rejected: {e}")))?;
            prop_assert_eq!(unusable(vehicle), None);
        }
    }
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
