//! Property-test machinery for TOML model files, shared by `wingforce/tests/prop_model.rs`
//! (wing models) and `flapsim/tests/prop_vehicle.rs` (vehicles, which include this file with
//! `#[path]`): walking and editing a parsed TOML tree by path, structural mutations of it
//! (replace a value, delete a value or a section, add an unknown field), text-level
//! mutations of a file, random tabulated kinematics, documented ranges of fields and values
//! outside them, and the proptest configuration (`FLAPWING_PROP_SCALE`).
//!
//! Every item here is used by both test files.

use std::ops::Range as Span;
use std::panic::{AssertUnwindSafe, catch_unwind};

use proptest::prelude::*;
use proptest::sample::Index;
use toml::Value;

/// Parses TOML that the test itself wrote (panics if it is not valid).
pub fn parse(text: &str) -> Value {
    toml::from_str(text).expect("valid TOML")
}

/// `v` as a TOML array of floats.
pub fn list(v: &[f64]) -> Value {
    Value::Array(v.iter().map(|x| Value::Float(*x)).collect())
}

/// A panic's payload as text (empty if it is neither a `String` nor a `&str`).
pub fn panic_message(p: Box<dyn std::any::Any + Send>) -> String {
    p.downcast_ref::<String>()
        .cloned()
        .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_default()
}

/// `load(text)`, a panic turned into a test failure that shows the input (proptest reports
/// panics too; this names the input).
pub fn guarded<T>(text: &str, load: impl FnOnce(&str) -> T) -> Result<T, TestCaseError> {
    catch_unwind(AssertUnwindSafe(|| load(text))).map_err(|p| {
        TestCaseError::fail(format!(
            "loader panicked ({}) on:\n{text}",
            panic_message(p)
        ))
    })
}

/// The property tests' configuration (see `prop_config.rs`).
pub fn config(cases: u32) -> ProptestConfig {
    super::prop_config::scaled_config(cases, 2000)
}

// ---------------------------------------------------------------------------------------------
// Paths into the TOML tree.
// ---------------------------------------------------------------------------------------------

#[derive(Debug, Clone, PartialEq)]
pub enum Seg {
    Key(String),
    Idx(usize),
}

/// The path as the loaders name fields: `a.b.c[2]`.
pub fn path_str(p: &[Seg]) -> String {
    let mut s = String::new();
    for seg in p {
        match seg {
            Seg::Key(k) => {
                if !s.is_empty() {
                    s.push('.');
                }
                s.push_str(k);
            }
            Seg::Idx(i) => s.push_str(&format!("[{i}]")),
        }
    }
    s
}

/// Every non-table value (arrays and their elements included), depth first.
pub fn leaves(v: &Value, prefix: &mut Vec<Seg>, out: &mut Vec<Vec<Seg>>) {
    match v {
        Value::Table(t) => {
            for (k, x) in t {
                prefix.push(Seg::Key(k.clone()));
                leaves(x, prefix, out);
                prefix.pop();
            }
        }
        Value::Array(a) => {
            out.push(prefix.clone());
            for (i, x) in a.iter().enumerate() {
                prefix.push(Seg::Idx(i));
                leaves(x, prefix, out);
                prefix.pop();
            }
        }
        _ => out.push(prefix.clone()),
    }
}

/// Every table, the root (empty path) included.
pub fn tables(v: &Value, prefix: &mut Vec<Seg>, out: &mut Vec<Vec<Seg>>) {
    if let Value::Table(t) = v {
        out.push(prefix.clone());
        for (k, x) in t {
            prefix.push(Seg::Key(k.clone()));
            tables(x, prefix, out);
            prefix.pop();
        }
    }
}

/// The leaves that are scalar numbers (floats and integers; list entries included).
pub fn numeric_leaves(v: &Value) -> Vec<Vec<Seg>> {
    let mut ls = Vec::new();
    leaves(v, &mut Vec::new(), &mut ls);
    let mut probe = v.clone();
    ls.into_iter()
        .filter(|p| matches!(get_mut(&mut probe, p), Value::Float(_) | Value::Integer(_)))
        .collect()
}

pub fn get_mut<'a>(v: &'a mut Value, p: &[Seg]) -> &'a mut Value {
    p.iter().fold(v, |v, seg| match seg {
        Seg::Key(k) => v.get_mut(k.as_str()).unwrap(),
        Seg::Idx(i) => v.get_mut(*i).unwrap(),
    })
}

pub fn remove(v: &mut Value, p: &[Seg]) {
    let (last, parent) = p.split_last().expect("not the root");
    match (get_mut(v, parent), last) {
        (Value::Table(t), Seg::Key(k)) => {
            t.remove(k);
        }
        (Value::Array(a), Seg::Idx(i)) => {
            a.remove(*i);
        }
        _ => unreachable!(),
    }
}

/// Sets the value at a dotted path (list entries as `name.i`).
pub fn set_path(v: &mut Value, dotted: &str, x: Value) {
    let segs: Vec<Seg> = dotted
        .split('.')
        .map(|s| match s.parse::<usize>() {
            Ok(i) => Seg::Idx(i),
            Err(_) => Seg::Key(s.to_owned()),
        })
        .collect();
    *get_mut(v, &segs) = x;
}

// ---------------------------------------------------------------------------------------------
// Structural mutations of the TOML tree.
// ---------------------------------------------------------------------------------------------

/// What a value is replaced with.
#[derive(Debug, Clone)]
pub enum Repl {
    Nan,
    Inf,
    NegInf,
    Zero,
    ZeroInt,
    Negate,
    MinusOneInt,
    Huge,
    NegHuge,
    Tiny,
    HugeInt,
    Float(f64),
    Str(String),
    Bool(bool),
    Array(Vec<f64>),
    EmptyArray,
    Table,
}

impl Repl {
    pub fn value(&self, old: &Value) -> Value {
        match self {
            Repl::Nan => Value::Float(f64::NAN),
            Repl::Inf => Value::Float(f64::INFINITY),
            Repl::NegInf => Value::Float(f64::NEG_INFINITY),
            Repl::Zero => Value::Float(0.0),
            Repl::ZeroInt => Value::Integer(0),
            Repl::Negate => match old {
                Value::Float(x) if *x != 0.0 => Value::Float(-x),
                Value::Integer(i) if *i != 0 => Value::Integer(-i),
                _ => Value::Float(-1.0),
            },
            Repl::MinusOneInt => Value::Integer(-1),
            Repl::Huge => Value::Float(1e300),
            Repl::NegHuge => Value::Float(-1e300),
            Repl::Tiny => Value::Float(1e-300),
            Repl::HugeInt => Value::Integer(i64::MAX),
            Repl::Float(x) => Value::Float(*x),
            Repl::Str(s) => Value::String(s.clone()),
            Repl::Bool(b) => Value::Boolean(*b),
            Repl::Array(a) => Value::Array(a.iter().map(|x| Value::Float(*x)).collect()),
            Repl::EmptyArray => Value::Array(vec![]),
            Repl::Table => parse("a = 1\nb = \"x\""),
        }
    }
}

/// The special values (NaN, +-inf, 0, negated, -1, +-1e300, 1e-300, i64::MAX).
pub const SPECIAL: [Repl; 11] = [
    Repl::Nan,
    Repl::Inf,
    Repl::NegInf,
    Repl::Zero,
    Repl::ZeroInt,
    Repl::Negate,
    Repl::MinusOneInt,
    Repl::Huge,
    Repl::NegHuge,
    Repl::Tiny,
    Repl::HugeInt,
];

/// A special value 4 times in 11 (each of them equally likely), otherwise a random float,
/// string, boolean, list or table.
pub fn repl() -> impl Strategy<Value = Repl> {
    prop_oneof![
        4 => (0..SPECIAL.len()).prop_map(|i| SPECIAL[i].clone()),
        1 => any::<f64>().prop_map(Repl::Float),
        1 => (-1e4f64..1e4).prop_map(Repl::Float),
        1 => "[a-z0-9 ._-]{0,12}".prop_map(Repl::Str),
        1 => any::<bool>().prop_map(Repl::Bool),
        1 => prop::collection::vec(-1e3f64..1e3, 0..6).prop_map(Repl::Array),
        1 => Just(Repl::EmptyArray),
        1 => Just(Repl::Table),
    ]
}

#[derive(Debug, Clone)]
pub enum Mutation {
    Replace(Index, Repl),
    Delete(Index),
    DeleteSection(Index),
    AddUnknown(Index, Repl),
}

pub fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        6 => (any::<Index>(), repl()).prop_map(|(i, r)| Mutation::Replace(i, r)),
        2 => any::<Index>().prop_map(Mutation::Delete),
        1 => any::<Index>().prop_map(Mutation::DeleteSection),
        1 => (any::<Index>(), repl()).prop_map(|(i, r)| Mutation::AddUnknown(i, r)),
    ]
}

/// Applies a mutation; returns a description (with the path it touched).
pub fn apply(v: &mut Value, m: &Mutation) -> String {
    let mut ls = Vec::new();
    leaves(v, &mut Vec::new(), &mut ls);
    let mut ts = Vec::new();
    tables(v, &mut Vec::new(), &mut ts);
    match m {
        Mutation::Replace(i, r) => {
            let p = i.get(&ls).clone();
            let slot = get_mut(v, &p);
            *slot = r.value(slot);
            format!("replace {} with {r:?}", path_str(&p))
        }
        Mutation::Delete(i) => {
            let p = i.get(&ls).clone();
            remove(v, &p);
            format!("delete {}", path_str(&p))
        }
        Mutation::DeleteSection(i) => {
            let non_root: Vec<_> = ts.iter().filter(|p| !p.is_empty()).cloned().collect();
            let p = i.get(&non_root).clone();
            remove(v, &p);
            format!("delete section [{}]", path_str(&p))
        }
        Mutation::AddUnknown(i, r) => {
            let p = i.get(&ts).clone();
            let t = get_mut(v, &p).as_table_mut().unwrap();
            t.insert("zz_unknown_field".into(), r.value(&Value::Float(1.0)));
            format!("add zz_unknown_field to [{}]", path_str(&p))
        }
    }
}

/// `base` with the mutations applied in turn: their descriptions and the TOML text.
pub fn mutated(base: &Value, muts: &[Mutation]) -> (Vec<String>, String) {
    let mut v = base.clone();
    let what = muts.iter().map(|m| apply(&mut v, m)).collect();
    (what, toml::to_string(&v).unwrap())
}

/// A replacement for a number that is not a number: a string, boolean, list or table.
pub fn non_number() -> impl Strategy<Value = Repl> {
    prop_oneof![
        "[a-z]{1,8}".prop_map(Repl::Str),
        any::<bool>().prop_map(Repl::Bool),
        prop::collection::vec(-10f64..10.0, 0..4).prop_map(Repl::Array),
        Just(Repl::Table),
    ]
}

/// `base` with its numeric leaf `leaf` (see [`numeric_leaves`]) replaced by `r`: the path
/// and the TOML text.
pub fn replace_numeric_leaf(base: &Value, leaf: Index, r: &Repl) -> (String, String) {
    let mut v = base.clone();
    let p = leaf.get(&numeric_leaves(&v)).clone();
    let slot = get_mut(&mut v, &p);
    *slot = r.value(slot);
    (path_str(&p), toml::to_string(&v).unwrap())
}

/// The exhaustive test `test`: each of the `paths` of every base set to each [`SPECIAL`]
/// value, except the pairs listed in `known` (see [`known_bug_extreme`]). `check(text)` says
/// what is wrong with the result, appended to `<base>: <path> = <value>` (`" loads but ..."`,
/// `": ..."`). Asserts that more than 1000 inputs were tried and that none failed.
pub fn assert_special_values(
    test: &str,
    bases: &[(&str, Value)],
    paths: impl Fn(&Value) -> Vec<Vec<Seg>>,
    known: &[(&str, &[&str])],
    mut check: impl FnMut(&str) -> Option<String>,
) {
    let mut failures = Vec::new();
    let mut tried = 0;
    for (name, v0) in bases {
        for p in paths(v0) {
            for r in &SPECIAL {
                let path = path_str(&p);
                if known_bug_extreme(known, &path, r) {
                    continue;
                }
                let mut v = v0.clone();
                let slot = get_mut(&mut v, &p);
                *slot = r.value(slot);
                let text = toml::to_string(&v).unwrap();
                tried += 1;
                if let Some(why) = check(&text) {
                    failures.push(format!("{name}: {path} = {r:?}{why}"));
                }
            }
        }
    }
    assert!(tried > 1000, "only {tried} inputs");
    eprintln!("{test}: {tried} inputs");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Whether `(path, r)` is listed in a `KNOWN_BUG_EXTREME` table of (field, names of `Repl`
/// values) pairs; a field `name[*]` stands for every entry of the list `name`.
fn known_bug_extreme(known: &[(&str, &[&str])], path: &str, r: &Repl) -> bool {
    let generic = match path.find('[') {
        Some(i) => format!("{}[*]", &path[..i]),
        None => path.to_owned(),
    };
    let name = format!("{r:?}");
    known
        .iter()
        .any(|(p, rs)| (*p == path || *p == generic) && rs.contains(&name.as_str()))
}

// ---------------------------------------------------------------------------------------------
// Targeted ranges: an out-of-range value of a field is rejected naming exactly that field.
// ---------------------------------------------------------------------------------------------

/// A field with its documented range.
#[derive(Debug, Clone, Copy)]
pub struct Range {
    /// Index into the including test's `bases()`.
    pub base: usize,
    /// Dotted path; list entries as `name.i`.
    pub path: &'static str,
    pub lo: f64,
    pub hi: f64,
    pub lo_open: bool,
    pub hi_open: bool,
    /// The field as the error names it (`name[i]` for list entries, `path` otherwise).
    pub field: &'static str,
}

pub const fn r(
    base: usize,
    path: &'static str,
    lo: f64,
    hi: f64,
    lo_open: bool,
    hi_open: bool,
) -> Range {
    Range {
        base,
        path,
        lo,
        hi,
        lo_open,
        hi_open,
        field: path,
    }
}

pub const INF: f64 = f64::INFINITY;

/// A value outside `[lo, hi]` (outside the open ends too): below or above by a relative
/// amount from 1e-6 to 1e6 (or absolute huge), the open bound itself, NaN or +-inf (an
/// infinite bound excludes its infinity only if it is closed).
pub fn outside(r: Range) -> BoxedStrategy<f64> {
    let mut s: Vec<BoxedStrategy<f64>> = vec![Just(f64::NAN).boxed()];
    if r.lo.is_finite() || r.lo_open {
        s.push(Just(f64::NEG_INFINITY).boxed());
    }
    if r.hi.is_finite() || r.hi_open {
        s.push(Just(f64::INFINITY).boxed());
    }
    let scale = |b: f64| b.abs().max(1.0);
    if r.lo.is_finite() {
        let lo = r.lo;
        s.push(
            (-6.0f64..6.0)
                .prop_map(move |e| lo - scale(lo) * 10f64.powf(e))
                .boxed(),
        );
        s.push(Just(lo - 1e300).boxed());
        if r.lo_open {
            s.push(Just(lo).boxed());
        }
    }
    if r.hi.is_finite() {
        let hi = r.hi;
        s.push(
            (-6.0f64..6.0)
                .prop_map(move |e| hi + scale(hi) * 10f64.powf(e))
                .boxed(),
        );
        s.push(Just(hi + 1e300).boxed());
        if r.hi_open {
            s.push(Just(hi).boxed());
        }
    }
    proptest::strategy::Union::new(s).boxed()
}

/// One of `ranges` and a value outside it.
pub fn range_and_value(ranges: &'static [Range]) -> impl Strategy<Value = (Range, f64)> {
    (0..ranges.len()).prop_flat_map(move |i| (Just(ranges[i]), outside(ranges[i])))
}

// ---------------------------------------------------------------------------------------------
// Text-level mutations: garbage, truncation, byte flips.
// ---------------------------------------------------------------------------------------------

#[derive(Debug, Clone)]
pub enum TextMutation {
    Truncate(Index),
    FlipBit(Index, u8),
    Splice(Index, Vec<u8>),
    Garbage(Vec<u8>),
    Text(String),
    Tomlish(String),
}

pub fn text_mutation() -> impl Strategy<Value = TextMutation> {
    prop_oneof![
        3 => any::<Index>().prop_map(TextMutation::Truncate),
        2 => (any::<Index>(), 0u8..8).prop_map(|(i, b)| TextMutation::FlipBit(i, b)),
        2 => (any::<Index>(), prop::collection::vec(any::<u8>(), 1..16))
            .prop_map(|(i, b)| TextMutation::Splice(i, b)),
        1 => prop::collection::vec(any::<u8>(), 0..400).prop_map(TextMutation::Garbage),
        1 => any::<String>().prop_map(TextMutation::Text),
        2 => "[\\[\\]=\"'a-z_.0-9 \n#+-]{0,300}".prop_map(TextMutation::Tomlish),
    ]
}

pub fn mutate_text(base: &str, m: &TextMutation) -> String {
    let bytes = base.as_bytes();
    let out: Vec<u8> = match m {
        TextMutation::Truncate(i) => bytes[..i.index(bytes.len() + 1)].to_vec(),
        TextMutation::FlipBit(i, b) => {
            let mut v = bytes.to_vec();
            v[i.index(bytes.len())] ^= 1 << b;
            v
        }
        TextMutation::Splice(i, g) => {
            let at = i.index(bytes.len() + 1);
            let mut v = bytes[..at].to_vec();
            v.extend_from_slice(g);
            v.extend_from_slice(&bytes[at..]);
            v
        }
        TextMutation::Garbage(g) => g.clone(),
        TextMutation::Text(s) | TextMutation::Tomlish(s) => s.clone().into_bytes(),
    };
    // The loaders take text: invalid UTF-8 becomes U+FFFD, as a caller's lossy read would.
    String::from_utf8_lossy(&out).into_owned()
}

// ---------------------------------------------------------------------------------------------
// Tabulated kinematics.
// ---------------------------------------------------------------------------------------------

/// A smooth periodic table of `n` rows over `period_s` (one downstroke and one upstroke,
/// last row repeating the first): stroke -70 cos, pitch 90 - `pitch_amp_deg` sin, deviation
/// `deviation_amp_deg` sin 2x.
pub fn tabulated_kinematics_toml(
    n: usize,
    period_s: f64,
    pitch_amp_deg: f64,
    deviation_amp_deg: f64,
) -> String {
    let m = n - 1;
    let col = |f: &dyn Fn(f64) -> f64| {
        let v: Vec<String> = (0..n)
            .map(|i| {
                let p = (i % m) as f64 / m as f64 * std::f64::consts::TAU;
                format!("{:?}", f(p))
            })
            .collect();
        format!("[{}]", v.join(", "))
    };
    let t: Vec<String> = (0..n)
        .map(|i| format!("{:?}", period_s * i as f64 / m as f64))
        .collect();
    format!(
        "family = \"tabulated\"\nt_s = [{}]\nstroke_deg = {}\npitch_deg = {}\ndeviation_deg = {}\n",
        t.join(", "),
        col(&|p| -70.0 * p.cos()),
        col(&|p| 90.0 - pitch_amp_deg * p.sin()),
        col(&|p| deviation_amp_deg * (2.0 * p).sin()),
    )
}

/// Puts the table's times, stroke and pitch into a kinematics section (and drops its
/// deviation).
pub fn put_table(kinematics: &mut Value, t: &Table) {
    let k = kinematics.as_table_mut().unwrap();
    k.insert("t_s".into(), list(&t.t_s));
    k.insert("stroke_deg".into(), list(&t.stroke));
    k.insert("pitch_deg".into(), list(&t.pitch));
    k.remove("deviation_deg");
}

#[derive(Debug, Clone)]
pub struct Table {
    pub t_s: Vec<f64>,
    pub stroke: Vec<f64>,
    pub pitch: Vec<f64>,
    /// What the generator did to a valid table (and so which error must come first).
    pub defect: Defect,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Defect {
    None,
    /// t_s[i] <= t_s[i-1].
    NotMonotonic(usize),
    /// stroke's last value differs from the first.
    NotPeriodic,
    /// Values are random (any outcome, but no panic).
    Random,
}

/// Tabulated kinematics: smooth tables of `rows` rows over a period in `period_s` and a
/// stroke amplitude in `amplitude_deg`, the same with one time moved back to or behind its
/// predecessor, or with the stroke's last value differing from the first, and random tables
/// (times random, or cumulative steps, drawn from `random_time_s` or any float).
pub fn table(
    rows: Span<usize>,
    period_s: Span<f64>,
    amplitude_deg: Span<f64>,
    random_time_s: Span<f64>,
) -> impl Strategy<Value = Table> {
    let smooth =
        (rows, period_s, amplitude_deg, 0.0f64..1.0).prop_map(|(n, period, amp, phase0)| {
            let m = n - 1;
            let ang = |i: usize| ((i % m) as f64 / m as f64 + phase0) * std::f64::consts::TAU;
            Table {
                t_s: (0..n).map(|i| period * i as f64 / m as f64).collect(),
                stroke: (0..n).map(|i| -0.5 * amp * ang(i).cos()).collect(),
                pitch: (0..n).map(|i| 90.0 - 40.0 * ang(i).sin()).collect(),
                defect: Defect::None,
            }
        });
    prop_oneof![
        2 => smooth.clone(),
        3 => (smooth.clone(), any::<Index>(), 0.0f64..2.0).prop_map(|(mut t, i, back)| {
            // Move one time (after the first) back to or behind its predecessor.
            let k = 1 + i.index(t.t_s.len() - 1);
            let step = t.t_s[k] - t.t_s[k - 1];
            t.t_s[k] = t.t_s[k - 1] - back * step;
            t.defect = Defect::NotMonotonic(k);
            t
        }),
        3 => (smooth.clone(), prop_oneof![1e-5f64..100.0, -100.0f64..-1e-5]).prop_map(
            |(mut t, d)| {
                let n = t.stroke.len();
                t.stroke[n - 1] = t.stroke[0] + d;
                t.defect = Defect::NotPeriodic;
                t
            }
        ),
        3 => (
            prop::collection::vec(prop_oneof![random_time_s, Just(0.0), any::<f64>()], 0..30),
            prop::collection::vec(prop_oneof![-400.0f64..400.0, any::<f64>()], 0..30),
            prop::collection::vec(-400.0f64..400.0, 0..30),
            any::<bool>(),
        )
            .prop_map(|(mut t, stroke, pitch, cumulative)| {
                if cumulative {
                    // Increasing times from 0 with random (possibly tiny) steps.
                    let mut acc = 0.0;
                    for x in t.iter_mut() {
                        acc += x.abs().min(1e6);
                        *x = acc;
                    }
                    if let Some(first) = t.first_mut() {
                        *first = 0.0;
                    }
                }
                Table { t_s: t, stroke, pitch, defect: Defect::Random }
            }),
    ]
}
