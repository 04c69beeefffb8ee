//! The parsed TOML tree: parsing the TOML a test wrote, paths into the tree as the loaders
//! name fields (`a.b.c[2]`), walking its leaves and tables, and editing it by path.

use toml::Value;

/// Parses TOML that the test itself wrote (panics if it is not valid).
pub fn parse(text: &str) -> Value {
    toml::from_str(text).expect("valid TOML")
}

/// `v` as a TOML array of floats.
pub fn list(v: &[f64]) -> Value {
    Value::Array(v.iter().map(|x| Value::Float(*x)).collect())
}

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
