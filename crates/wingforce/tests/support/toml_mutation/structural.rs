//! Structural mutations of the TOML tree: what a value is replaced with (the special values
//! NaN, +-inf, 0, negated, -1, +-1e300, 1e-300, i64::MAX, or a random float, string,
//! boolean, list or table), replacing or deleting a value, deleting a section, adding an
//! unknown field; a number replaced by a non-number; and the exhaustive test that sets each
//! path of every base to each special value.

use proptest::prelude::*;
use proptest::sample::Index;
use toml::Value;

use super::tree::{Seg, get_mut, leaves, numeric_leaves, parse, path_str, remove, tables};

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
