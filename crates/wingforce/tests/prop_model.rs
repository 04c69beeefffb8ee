//! Property tests (issue 7): every bad wing model file gets a clear error and nothing panics.
//!
//! `WingModelSpec::from_toml` + `build` is fed mutated versions of the real model file
//! (`models/robofly.toml`) and of variants of it that use every planform and kinematics family
//! (so that every field the format has is present to be mutated), random tabulated kinematics,
//! garbage and truncated text. Loading must never panic and must either succeed or return an
//! error whose Display starts with `<origin>: `; value errors (`Error::Invalid`) must name the
//! field and say "not allowed". Targeted properties check that out-of-range values of each
//! documented field are rejected with that exact field named.
//!
//! The TOML-tree walkers, the mutation, text-mutation, table and range generators and
//! `config` are in `support/toml_mutation/`, shared with `flapsim/tests/prop_vehicle/`.
//!
//! Generated inputs per property (proptest `cases`; the whole file runs in about 2 s in
//! release). `FLAPWING_PROP_SCALE=N` multiplies every proptest case count (for soak runs).
//!
//! | property                                   | cases |
//! |--------------------------------------------|-------|
//! | `structural_mutations_never_panic`         |  2000 |
//! | `out_of_range_values_name_their_field`     |  1000 |
//! | `unknown_fields_are_named`                 |   300 |
//! | `type_errors_are_parse_errors`             |   500 |
//! | `text_mutations_never_panic`               |  1500 |
//! | `tabulated_kinematics_tables`              |   600 |
//! | `tabulated_planform_tables`                |   400 |
//! | `moderate_values_load_usably_or_fail_cleanly` | 1000 |
//! | `loaded_models_give_finite_forces` (exhaustive, not proptest) | ~2600 |

use proptest::prelude::*;
use proptest::sample::Index;
use toml::Value;
use wingforce::{BodyMotion, Error, Wing, WingModelSpec};

mod support;
use support::toml_mutation::{
    Defect, INF, Mutation, Range, assert_special_values, config, get_mut, guarded, leaves, list,
    mutate_text, mutated, mutation, non_number, parse, path_str, put_table, r, range_and_value,
    repl, replace_numeric_leaf, set_path, table, tabulated_kinematics_toml, text_mutation,
};

const ROBOFLY: &str = include_str!("../../../models/robofly.toml");

/// Origin given to the loader: errors must start with it (spaces and a non-ASCII character
/// make sure it is printed verbatim, not re-quoted).
const ORIGIN: &str = "mut/robofly variant é.toml";

// ---------------------------------------------------------------------------------------------
// Base models: the real file and variants covering every family and every optional field.
// ---------------------------------------------------------------------------------------------

const HARMONIC: &str = r#"
family = "harmonic"
freq_hz = 0.25
amplitude_deg = 150.0
mid_stroke_aoa_deg = 45.0
pitch_phase_deg = 10.0
deviation_amplitude_deg = 5.0
mean_stroke_deg = 2.0
pitch_bias_deg = 1.0
"#;

const TRAPEZOIDAL_FULL: &str = r#"
family = "trapezoidal"
freq_hz = 0.2
amplitude_deg = 155.0
mid_stroke_aoa_deg = 40.0
dtau_a = 0.12
dtau_d = 0.1
mean_stroke_deg = -3.0
pitch_bias_deg = 2.0
"#;

const RECTANGULAR: &str = r#"
shape = "rectangular"
span_m = 0.25
chord_m = 0.09
root_offset_m = 0.1
pitch_axis_from_le_frac = 0.25
"#;

const ELLIPTIC: &str = r#"
shape = "elliptic"
span_m = 0.25
max_chord_m = 0.11
root_offset_m = 0.1
pitch_axis_from_le_frac = 0.3
"#;

const TABULATED_PLANFORM: &str = r#"
shape = "tabulated"
root_offset_m = 0.1
r_from_root_m = [0.0, 0.05, 0.1, 0.15, 0.2, 0.25]
chord_m = [0.03, 0.08, 0.1, 0.1, 0.08, 0.0]
le_offset_m = [0.01, 0.02, 0.025, 0.025, 0.02, 0.0]
"#;

const AERO_FULL: &str = r#"
translational = "dickinson1999"
ar_ro_corrections = false
rotational = true
added_mass = true
wake_capture = true
c_rot = 2.0
strips = 7
cp_chord_frac = 0.3
"#;

/// `base` with `[section.sub]` replaced by the table parsed from `table_text`.
fn with_table(base: &Value, path: &[&str], table_text: &str) -> Value {
    let mut v = base.clone();
    let mut t = &mut v;
    for p in &path[..path.len() - 1] {
        t = t.get_mut(*p).expect("path exists");
    }
    t.as_table_mut()
        .unwrap()
        .insert(path[path.len() - 1].to_owned(), parse(table_text));
    v
}

/// The real file and variants; every one of them loads.
fn bases() -> Vec<(&'static str, Value)> {
    let robofly = parse(ROBOFLY);
    let mut out = vec![("robofly.toml", robofly.clone())];
    out.push((
        "harmonic+rectangular",
        with_table(
            &with_table(&robofly, &["kinematics"], HARMONIC),
            &["wing", "planform"],
            RECTANGULAR,
        ),
    ));
    let mut full = with_table(
        &with_table(&robofly, &["kinematics"], TRAPEZOIDAL_FULL),
        &["wing", "planform"],
        ELLIPTIC,
    );
    full = with_table(&full, &["aero"], AERO_FULL);
    full = with_table(
        &full,
        &["fluid"],
        "density_kg_m3 = 1000.0\nkinematic_viscosity_m2_s = 1e-4\n",
    );
    out.push(("trapezoidal-freq+elliptic+aero", full));
    out.push((
        "tabulated-kinematics+tabulated-planform",
        with_table(
            &with_table(
                &robofly,
                &["kinematics"],
                &tabulated_kinematics_toml(25, 4.0, 45.0, 5.0),
            ),
            &["wing", "planform"],
            TABULATED_PLANFORM,
        ),
    ));
    // A refitted wake-capture model (the paper's, written out): its coefficients and ranges.
    let wake = toml::to_string(&wingforce::WakeCaptureModel::paper()).unwrap();
    let mut with_wake = robofly.clone();
    with_wake["aero"]
        .as_table_mut()
        .unwrap()
        .insert("wake_capture_model".into(), parse(&wake));
    out.push(("robofly+wake_capture_model", with_wake));
    for (name, v) in &out {
        let text = toml::to_string(v).unwrap();
        load(&text).unwrap_or_else(|e| panic!("base {name} must load: {e}"));
    }
    out
}

// ---------------------------------------------------------------------------------------------
// Loading and checking.
// ---------------------------------------------------------------------------------------------

fn load(text: &str) -> Result<Wing, Error> {
    WingModelSpec::from_toml(text, ORIGIN).and_then(|s| s.build(ORIGIN))
}

/// Loads with a `catch_unwind` guard.
fn load_guarded(text: &str) -> Result<Result<Wing, Error>, TestCaseError> {
    guarded(text, load)
}

/// The error contract: `<origin>: ...`; value errors name the field and say "not allowed".
fn check_error(e: &Error, text: &str) -> Result<(), TestCaseError> {
    let s = e.to_string();
    prop_assert!(
        s.starts_with(&format!("{ORIGIN}: ")),
        "error does not start with the origin: {s}\ninput:\n{text}"
    );
    match e {
        Error::Invalid {
            origin,
            field,
            value,
            allowed,
        } => {
            prop_assert_eq!(origin, ORIGIN);
            prop_assert!(!field.is_empty() && !value.is_empty() && !allowed.is_empty());
            prop_assert!(
                s.contains(&format!("field `{field}`")) && s.contains("not allowed"),
                "{}",
                s
            );
        }
        Error::Parse { origin, message } => {
            prop_assert_eq!(origin, ORIGIN);
            prop_assert!(!message.trim().is_empty(), "empty parse message");
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Structural mutations of the TOML tree.
// ---------------------------------------------------------------------------------------------

proptest! {
    #![proptest_config(config(2000))]

    /// One to three structural mutations of a base model: loading never panics and errors
    /// follow the contract.
    #[test]
    fn structural_mutations_never_panic(
        base in any::<Index>(),
        muts in prop::collection::vec(mutation(), 1..4),
    ) {
        let (what, text) = mutated(&base.get(bases_cached()).1, &muts);
        if let Err(e) = load_guarded(&text)? {
            check_error(&e, &text).map_err(|f| {
                TestCaseError::fail(format!("{f}\nmutations: {what:?}"))
            })?;
        }
    }
}

proptest! {
    #![proptest_config(config(300))]

    /// An unknown field in any table is a parse error that names it.
    #[test]
    fn unknown_fields_are_named(base in any::<Index>(), table in any::<Index>(), r in repl()) {
        let (what, text) = mutated(&base.get(bases_cached()).1, &[Mutation::AddUnknown(table, r)]);
        let e = load_guarded(&text)?.expect_err("unknown field accepted");
        check_error(&e, &text)?;
        prop_assert!(matches!(e, Error::Parse { .. }), "{:?}", what);
        prop_assert!(e.to_string().contains("zz_unknown_field"), "{what:?}: {e}");
    }
}

proptest! {
    #![proptest_config(config(500))]

    /// A number replaced by a string, boolean, array or table is a parse error.
    #[test]
    fn type_errors_are_parse_errors(
        base in any::<Index>(),
        leaf in any::<Index>(),
        r in non_number(),
    ) {
        // Only scalar numbers: strings (name, family, shape) and lists have other rules.
        let (path, text) = replace_numeric_leaf(&base.get(bases_cached()).1, leaf, &r);
        let e = load_guarded(&text)?.expect_err(&format!("{path} = {r:?} accepted"));
        check_error(&e, &text)?;
        prop_assert!(matches!(e, Error::Parse { .. }), "{} = {:?}: {}", path, r, e);
    }
}

// ---------------------------------------------------------------------------------------------
// Targeted ranges: an out-of-range value of a field is rejected naming exactly that field.
// ---------------------------------------------------------------------------------------------

/// Base 0 robofly (peak_rg_speed, ellington_beta, reynolds), 1 harmonic + rectangular,
/// 2 trapezoidal with freq_hz + elliptic + full aero + viscosity, 3 tabulated + tabulated.
const RANGES: &[Range] = &[
    // Angles beyond their range.
    r(0, "kinematics.amplitude_deg", 0.0, 180.0, true, false),
    r(1, "kinematics.amplitude_deg", 0.0, 180.0, true, false),
    r(2, "kinematics.amplitude_deg", 0.0, 180.0, true, false),
    r(0, "kinematics.mid_stroke_aoa_deg", 0.0, 90.0, false, false),
    r(1, "kinematics.mid_stroke_aoa_deg", 0.0, 90.0, false, false),
    r(2, "kinematics.mean_stroke_deg", -90.0, 90.0, false, false),
    r(2, "kinematics.pitch_bias_deg", -45.0, 45.0, false, false),
    r(1, "kinematics.mean_stroke_deg", -90.0, 90.0, false, false),
    r(1, "kinematics.pitch_bias_deg", -45.0, 45.0, false, false),
    r(1, "kinematics.pitch_phase_deg", -90.0, 90.0, false, false),
    r(
        1,
        "kinematics.deviation_amplitude_deg",
        0.0,
        45.0,
        false,
        false,
    ),
    // Zero or negative frequency and stroke speed.
    r(1, "kinematics.freq_hz", 0.0, INF, true, true),
    r(2, "kinematics.freq_hz", 0.0, INF, true, true),
    r(0, "kinematics.peak_rg_speed_m_s", 0.0, INF, true, true),
    r(0, "kinematics.dtau_a", 0.0, 0.5, true, false),
    r(2, "kinematics.dtau_d", 0.0, 0.5, true, false),
    // Negative or zero lengths and areas.
    r(0, "wing.planform.span_m", 0.0, INF, true, true),
    r(0, "wing.planform.area_m2", 0.0, INF, true, true),
    r(0, "wing.planform.r1_hat", 0.4, 0.6, false, false),
    r(0, "wing.planform.root_offset_m", 0.0, INF, false, true),
    r(
        0,
        "wing.planform.pitch_axis_from_le_frac",
        0.0,
        1.0,
        false,
        false,
    ),
    r(1, "wing.planform.span_m", 0.0, INF, true, true),
    r(1, "wing.planform.chord_m", 0.0, INF, true, true),
    r(2, "wing.planform.max_chord_m", 0.0, INF, true, true),
    r(2, "wing.planform.span_m", 0.0, INF, true, true),
    r(3, "wing.planform.root_offset_m", 0.0, INF, false, true),
    Range {
        field: "wing.planform.chord_m[2]",
        ..r(3, "wing.planform.chord_m.2", 0.0, INF, false, true)
    },
    r(0, "wing.overrides.sqrt_sxx_syy_m4", 0.0, INF, true, true),
    // Fluid.
    r(0, "fluid.density_kg_m3", 0.0, INF, true, true),
    r(0, "fluid.reynolds", 0.0, INF, true, true),
    r(2, "fluid.kinematic_viscosity_m2_s", 0.0, INF, true, true),
    // Aerodynamic options.
    r(0, "aero.c_rot", 0.0, INF, true, true),
    r(2, "aero.cp_chord_frac", 0.0, 1.0, false, false),
    // Tabulated kinematics values are angles within +-360 deg.
    Range {
        field: "kinematics.stroke_deg[3]",
        ..r(3, "kinematics.stroke_deg.3", -360.0, 360.0, false, false)
    },
    Range {
        field: "kinematics.pitch_deg[0]",
        ..r(3, "kinematics.pitch_deg.0", -360.0, 360.0, false, false)
    },
];

proptest! {
    #![proptest_config(config(1000))]

    /// Angles beyond range, zero frequency, zero amplitude, negative/zero lengths and areas,
    /// bad fluid: rejected with `Error::Invalid` naming exactly the field.
    #[test]
    fn out_of_range_values_name_their_field((range, x) in range_and_value(RANGES)) {
        let (_, v) = &bases_cached()[range.base];
        let mut v = v.clone();
        set_path(&mut v, range.path, Value::Float(x));
        let text = toml::to_string(&v).unwrap();
        let e = load_guarded(&text)?
            .expect_err(&format!("{} = {x:?} accepted", range.path));
        check_error(&e, &text)?;
        match &e {
            Error::Invalid { field, .. } => prop_assert_eq!(field, range.field, "{}", e),
            _ => prop_assert!(false, "{} = {:?}: not a value error: {}", range.path, x, e),
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Text-level mutations: garbage, truncation, byte flips.
// ---------------------------------------------------------------------------------------------

proptest! {
    #![proptest_config(config(1500))]

    /// Truncated (at any byte), bit-flipped, spliced, random-byte and random-text files.
    #[test]
    fn text_mutations_never_panic(which in 0usize..3, m in text_mutation()) {
        // The real file with its comments, and two serialized variants.
        let base = match which {
            0 => ROBOFLY.to_owned(),
            k => toml::to_string(&bases_cached()[k + 1].1).unwrap(),
        };
        let text = mutate_text(&base, &m);
        if let Err(e) = load_guarded(&text)? {
            check_error(&e, &text)?;
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Tabulated kinematics and planforms.
// ---------------------------------------------------------------------------------------------

proptest! {
    #![proptest_config(config(600))]

    /// Tables not monotonic in time name the first bad time; tables whose last row does not
    /// repeat the first name the stroke's last entry and say "periodic"; smooth tables load;
    /// random tables never panic.
    #[test]
    fn tabulated_kinematics_tables(
        t in table(5..60, 1e-3..1e3, 1.0..170.0, 0.0..1.0),
    ) {
        let (_, v) = &bases_cached()[3];
        let mut v = v.clone();
        put_table(&mut v["kinematics"], &t);
        let text = toml::to_string(&v).unwrap();
        let result = load_guarded(&text)?;
        if let Err(e) = &result {
            check_error(e, &text)?;
        }
        let s = result.as_ref().err().map(|e| e.to_string()).unwrap_or_default();
        match t.defect {
            Defect::None => {
                prop_assert!(result.is_ok(), "smooth table rejected: {}", s);
                let w = result.unwrap();
                let period = t.t_s[t.t_s.len() - 1];
                prop_assert!((w.kinematics().freq_hz * period - 1.0).abs() < 1e-9);
            }
            Defect::NotMonotonic(i) => {
                let field = format!("field `kinematics.t_s[{i}]`");
                prop_assert!(s.contains(&field) && s.contains("increase"), "{}", s);
            }
            Defect::NotPeriodic => {
                let field = format!("field `kinematics.stroke_deg[{}]`", t.stroke.len() - 1);
                prop_assert!(s.contains(&field) && s.contains("periodic"), "{}", s);
            }
            Defect::Random => {}
        }
    }
}

proptest! {
    #![proptest_config(config(400))]

    /// Tabulated planforms with random stations, chords and leading-edge offsets.
    #[test]
    fn tabulated_planform_tables(
        r in prop::collection::vec(prop_oneof![0.0f64..0.3, any::<f64>()], 0..12),
        chord in prop::collection::vec(prop_oneof![-0.1f64..0.2, Just(0.0), any::<f64>()], 0..12),
        le in prop::collection::vec(prop_oneof![-0.1f64..0.1, any::<f64>()], 0..12),
        root in prop_oneof![0.0f64..1.0, any::<f64>()],
        cumulative in any::<bool>(),
        strips in 1i64..60,
    ) {
        let mut r = r;
        if cumulative {
            let mut acc = 0.0;
            for x in r.iter_mut() {
                acc += x.abs().min(1e3);
                *x = acc;
            }
            if let Some(f) = r.first_mut() {
                *f = 0.0;
            }
        }
        let (_, v) = &bases_cached()[3];
        let mut v = v.clone();
        let p = v["wing"]["planform"].as_table_mut().unwrap();
        p.insert("r_from_root_m".into(), list(&r));
        p.insert("chord_m".into(), list(&chord));
        p.insert("le_offset_m".into(), list(&le));
        p.insert("root_offset_m".into(), Value::Float(root));
        v["aero"].as_table_mut().unwrap().insert("strips".into(), Value::Integer(strips));
        let text = toml::to_string(&v).unwrap();
        if let Err(e) = load_guarded(&text)? {
            check_error(&e, &text)?;
        }
    }
}

// ---------------------------------------------------------------------------------------------
// A model that loads is usable: finite Re, V_ref and forces.
// ---------------------------------------------------------------------------------------------

/// KNOWN BUG (issue 7, reported to the lead): the loader checks only the sign and finiteness
/// of these fields, so finite but extreme values load without error and the wing then has a
/// NaN/inf Reynolds number, V_ref or forces (`flapwing forces` exits 1 "non-finite forces"
/// instead of 2 naming the field). Exactly these (field, replacement) pairs are excluded from
/// `loaded_models_give_finite_forces`; remove each once the loader rejects it.
/// `Huge` = 1e300, `HugeInt` = i64::MAX, `Tiny` = 1e-300.
const KNOWN_BUG_EXTREME: &[(&str, &[&str])] = &[];

/// KNOWN BUG (issue 7, reported to the lead): a refitted `aero.wake_capture_model` is checked
/// for finite coefficients and mu* > 0, but not for finite dCL/dCD over its fitted range: with
/// `dcl.c2` or `dcd.c2` > ln(f64::MAX) / re_range.max (about 0.104 for the paper's range,
/// e.g. `dcd.c2 = 1.0`), `c1 exp(c2 Re)` overflows and every force is NaN. Exactly these
/// inputs are skipped in `moderate_values_load_usably_or_fail_cleanly`; remove once rejected.
fn known_bug_wake_exp_overflow(path: &str, x: f64) -> bool {
    let re_max = wingforce::WakeCaptureModel::paper().re_range.max;
    // Fixed: the loader now rejects such models; nothing is skipped any more.
    let _ = (path, x, re_max);
    false
}

/// The checks on a wing that loaded; `Err` describes what is not finite.
fn usable(wing: &Wing) -> Result<(), String> {
    if !(wing.reynolds().is_finite() && wing.reynolds() > 0.0) {
        return Err(format!("Re = {}", wing.reynolds()));
    }
    if !(wing.v_ref_m_s().is_finite() && wing.v_ref_m_s() > 0.0) {
        return Err(format!("V_ref = {}", wing.v_ref_m_s()));
    }
    for phase in [0.1, 0.25, 0.6] {
        let f = wing.evaluate(phase, &BodyMotion::default());
        if !(f.total.c_l.is_finite() && f.total.c_d.is_finite()) {
            return Err(format!(
                "C_L = {}, C_D = {} at phase {phase}",
                f.total.c_l, f.total.c_d
            ));
        }
    }
    Ok(())
}

/// Every numeric leaf of every base replaced by each special value: a model that loads gives
/// a finite Re, V_ref and forces (exhaustive: 5 bases x every leaf x 11 values).
#[test]
fn loaded_models_give_finite_forces() {
    let all_leaves = |v: &Value| {
        let mut ls = Vec::new();
        leaves(v, &mut Vec::new(), &mut ls);
        ls
    };
    assert_special_values(
        "loaded_models_give_finite_forces",
        bases_cached(),
        all_leaves,
        KNOWN_BUG_EXTREME,
        |text| match load(text) {
            Ok(w) => usable(&w).err().map(|why| format!(" loads but {why}")),
            Err(e) => check_error(&e, text).err().map(|f| format!(": {f}")),
        },
    );
}

proptest! {
    #![proptest_config(config(1000))]

    /// Any numeric leaf set to a moderate value (+-1e-6 .. 1e6): the model either fails to load
    /// with a proper error or gives finite Re, V_ref and forces.
    #[test]
    fn moderate_values_load_usably_or_fail_cleanly(
        base in any::<Index>(),
        leaf in any::<Index>(),
        exp in -6.0f64..6.0,
        negative in any::<bool>(),
    ) {
        let (_, v) = base.get(bases_cached());
        let mut v = v.clone();
        let mut ls = Vec::new();
        leaves(&v, &mut Vec::new(), &mut ls);
        let p = leaf.get(&ls).clone();
        let x = if negative { -1.0 } else { 1.0 } * 10f64.powf(exp);
        prop_assume!(!known_bug_wake_exp_overflow(&path_str(&p), x));
        *get_mut(&mut v, &p) = Value::Float(x);
        let text = toml::to_string(&v).unwrap();
        match load_guarded(&text)? {
            Ok(w) => {
                if let Err(why) = usable(&w) {
                    prop_assert!(false, "{} = {:?} loads but {}", path_str(&p), x, why);
                }
            }
            Err(e) => check_error(&e, &text)?,
        }
    }
}

fn bases_cached() -> &'static [(&'static str, Value)] {
    static BASES: std::sync::OnceLock<Vec<(&'static str, Value)>> = std::sync::OnceLock::new();
    BASES.get_or_init(bases)
}

#[test]
fn bases_load_and_cover_every_family() {
    let b = bases_cached();
    assert_eq!(b.len(), 5);
    let mut paths = Vec::new();
    for (_, v) in b {
        leaves(v, &mut Vec::new(), &mut paths);
    }
    let names: Vec<String> = paths.iter().map(|p| path_str(p)).collect();
    for needle in [
        "kinematics.peak_rg_speed_m_s",
        "kinematics.freq_hz",
        "kinematics.pitch_phase_deg",
        "kinematics.t_s",
        "wing.planform.chord_m[2]",
        "wing.planform.max_chord_m",
        "wing.overrides.sx_absx_m4",
        "aero.strips",
        "aero.wake_capture_model.dcl.c0",
        "fluid.kinematic_viscosity_m2_s",
    ] {
        assert!(names.iter().any(|n| n == needle), "{needle} not covered");
    }
}
