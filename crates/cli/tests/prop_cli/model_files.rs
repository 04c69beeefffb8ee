//! Bad model files given with `--model PATH` (a damaged robofly wing model for `forces`, a
//! damaged drosophila vehicle for `simulate`, `trim`, `stability` and `hover`): when the
//! library rejects the file, the command exits 2 naming the path verbatim (a name with a
//! space and a non-ASCII letter); when it loads, the command exits 0 or 1 (a run can
//! diverge); never a panic (32 cases).

use std::path::PathBuf;

use proptest::prelude::*;
use proptest::sample::Index;

use crate::harness::{check_run, config, flapwing};

const ROBOFLY: &str = include_str!("../../../../models/robofly.toml");

/// A damaged model file.
#[derive(Debug, Clone)]
enum FileMutation {
    /// Cut at a byte.
    Truncate(Index),
    /// Random bytes inserted (may be invalid UTF-8: the file cannot be read as text).
    Splice(Index, Vec<u8>),
    /// The value of a `key = value` line replaced.
    Value(Index, &'static str),
    /// A line removed.
    DeleteLine(Index),
    /// An unknown field added after a line.
    UnknownField(Index),
    /// Random bytes only.
    Garbage(Vec<u8>),
}

fn file_mutation() -> impl Strategy<Value = FileMutation> {
    prop_oneof![
        2 => any::<Index>().prop_map(FileMutation::Truncate),
        1 => (any::<Index>(), prop::collection::vec(any::<u8>(), 1..8))
            .prop_map(|(i, b)| FileMutation::Splice(i, b)),
        4 => (
            any::<Index>(),
            prop::sample::select(vec![
                "nan", "inf", "-inf", "0.0", "0", "-1.0", "1e300", "-1e300", "1e-300",
                "\"abc\"", "true", "[1.0, 2.0]", "{ a = 1 }", "",
            ]),
        )
            .prop_map(|(i, v)| FileMutation::Value(i, v)),
        1 => any::<Index>().prop_map(FileMutation::DeleteLine),
        1 => any::<Index>().prop_map(FileMutation::UnknownField),
        1 => prop::collection::vec(any::<u8>(), 0..64).prop_map(FileMutation::Garbage),
    ]
}

fn mutate(text: &str, m: &FileMutation) -> Vec<u8> {
    let bytes = text.as_bytes();
    let lines: Vec<&str> = text.lines().collect();
    let value_lines: Vec<usize> = lines
        .iter()
        .enumerate()
        .filter(|(_, l)| !l.trim_start().starts_with('#') && l.contains(" = "))
        .map(|(i, _)| i)
        .collect();
    let join = |ls: Vec<String>| (ls.join("\n") + "\n").into_bytes();
    match m {
        FileMutation::Truncate(i) => bytes[..i.index(bytes.len() + 1)].to_vec(),
        FileMutation::Splice(i, g) => {
            let at = i.index(bytes.len() + 1);
            [&bytes[..at], g, &bytes[at..]].concat()
        }
        FileMutation::Value(i, v) => {
            let k = *i.get(&value_lines);
            let mut ls: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
            let key = ls[k].split(" = ").next().unwrap().to_owned();
            ls[k] = format!("{key} = {v}");
            join(ls)
        }
        FileMutation::DeleteLine(i) => {
            let k = i.index(lines.len());
            let ls = lines
                .iter()
                .enumerate()
                .filter(|(j, _)| *j != k)
                .map(|(_, s)| s.to_string())
                .collect();
            join(ls)
        }
        FileMutation::UnknownField(i) => {
            let k = i.index(lines.len());
            let mut ls: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
            ls.insert(k + 1, "zz_unknown = 1.0".into());
            join(ls)
        }
        FileMutation::Garbage(g) => g.clone(),
    }
}

/// Which command reads the file: `forces` takes a wing model, the others a vehicle.
#[derive(Debug, Clone, Copy)]
enum ModelCommand {
    Forces,
    Simulate,
    Trim,
    Stability,
    Hover,
}

impl ModelCommand {
    fn args(self, path: &str) -> Vec<String> {
        let v = |a: &[&str]| a.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let mut args = match self {
            ModelCommand::Forces => v(&["forces", "--cycles", "1", "--steps-per-cycle", "20"]),
            ModelCommand::Simulate => v(&["simulate", "--duration-s", "0.001"]),
            ModelCommand::Trim => v(&["trim"]),
            ModelCommand::Stability => v(&["stability", "--no-floquet"]),
            ModelCommand::Hover => v(&["hover", "--duration-s", "0.005"]),
        };
        args.push(format!("--model={path}"));
        args
    }

    fn base(self) -> &'static str {
        match self {
            ModelCommand::Forces => ROBOFLY,
            _ => flapsim::DROSOPHILA_TOML,
        }
    }

    /// Whether the library loads the file (the CLI must then not call it bad input).
    fn loads(self, bytes: &[u8], origin: &str) -> Result<(), String> {
        let text = std::str::from_utf8(bytes).map_err(|e| e.to_string())?;
        match self {
            ModelCommand::Forces => wingforce::WingModelSpec::from_toml(text, origin)
                .and_then(|s| s.build(origin))
                .map(|_| ())
                .map_err(|e| e.to_string()),
            _ => flapsim::Vehicle::from_toml(text, origin)
                .map(|_| ())
                .map_err(|e| e.to_string()),
        }
    }
}

proptest! {
    #![proptest_config(config(32))]

    /// A damaged model file given with --model PATH: when the library rejects it, the
    /// command exits 2 naming the path; when it loads, the command exits 0 or 1 (a run can
    /// diverge); never a panic.
    #[test]
    fn bad_model_files_name_the_file(
        cmd in prop::sample::select(vec![
            ModelCommand::Forces,
            ModelCommand::Forces,
            ModelCommand::Simulate,
            ModelCommand::Simulate,
            ModelCommand::Trim,
            ModelCommand::Stability,
            ModelCommand::Hover,
        ]),
        m in file_mutation(),
    ) {
        let dir = tempfile::tempdir().unwrap();
        // A name with a space and a non-ASCII letter: it must appear verbatim.
        let path: PathBuf = dir.path().join("my model é.toml");
        let bytes = mutate(cmd.base(), &m);
        std::fs::write(&path, &bytes).unwrap();
        let shown = path.display().to_string();
        let r = flapwing(dir.path(), &cmd.args(&shown));
        check_run(&r)?;
        match cmd.loads(&bytes, &shown) {
            Err(why) => {
                prop_assert_eq!(r.code, 2, "{:?}: library says {}\nstderr: {}", m, why, r.stderr);
                prop_assert!(
                    r.stderr.contains(&shown),
                    "{:?}: stderr does not name `{}`: {}", m, shown, r.stderr
                );
            }
            Ok(()) => prop_assert!(
                r.code == 0 || r.code == 1,
                "{:?}: the library loads the file but the CLI exits {}: {}", m, r.code, r.stderr
            ),
        }
    }
}
