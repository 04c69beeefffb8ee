//! The output files of one command, checked together before any work: none is a directory,
//! none is one of the command's input files (which writing it would truncate before it is
//! read), no two are the same file, and an existing one is replaced only with `--force`.
//!
//! "The same file" is decided by file identity (device and inode) when both exist, so a
//! hard link, a symbolic link or another spelling of the path (`./log.mcap`, `dir/../log.mcap`)
//! is caught; a path that does not exist yet is compared by its canonical folder and name.

use std::path::{Path, PathBuf};

use crate::error::input_error;

/// One file a command reads or writes: the flag or argument that names it, and its path.
#[derive(Debug, Clone, Copy)]
pub struct Named<'a> {
    /// How the command line names it (`--rrd`, `FILE`, `--model`).
    pub flag: &'a str,
    /// The path as given.
    pub path: &'a Path,
}

impl<'a> Named<'a> {
    /// `flag` naming `path`.
    pub fn new(flag: &'a str, path: &'a Path) -> Self {
        Self { flag, path }
    }
}

/// The model file a command read (`--model`), as an input to protect: none for a built-in
/// model (its origin is not a file).
pub fn model_input(origin: &str) -> Vec<Named<'_>> {
    let path = Path::new(origin);
    if path.is_file() {
        vec![Named::new("--model", path)]
    } else {
        Vec::new()
    }
}

/// The identity of a path: the canonical path of an existing file (with its device and
/// inode on Unix), else the canonical folder joined with the name (the absolute folder when
/// it does not exist yet; `None` for a path without a file name).
#[derive(Debug, Clone, PartialEq, Eq)]
enum Identity {
    Existing {
        canonical: PathBuf,
        id: Option<(u64, u64)>,
    },
    New(PathBuf),
}

fn identity(path: &Path) -> Option<Identity> {
    if let Ok(meta) = std::fs::metadata(path) {
        let canonical = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
        #[cfg(unix)]
        let id = {
            use std::os::unix::fs::MetadataExt;
            Some((meta.dev(), meta.ino()))
        };
        #[cfg(not(unix))]
        let id = {
            let _ = meta;
            None
        };
        return Some(Identity::Existing { canonical, id });
    }
    let name = path.file_name()?;
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let dir = std::fs::canonicalize(parent)
        .or_else(|_| std::path::absolute(parent))
        .ok()?;
    Some(Identity::New(dir.join(name)))
}

/// True when `a` and `b` name the same file (or the same path to be created).
pub fn same_file(a: &Path, b: &Path) -> bool {
    match (identity(a), identity(b)) {
        (
            Some(Identity::Existing {
                canonical: ca,
                id: ia,
            }),
            Some(Identity::Existing {
                canonical: cb,
                id: ib,
            }),
        ) => match (ia, ib) {
            (Some(x), Some(y)) => x == y,
            _ => ca == cb,
        },
        (Some(Identity::New(x)), Some(Identity::New(y))) => x == y,
        _ => false,
    }
}

/// Checks a command's `outputs` against its `inputs` and each other before any work (see
/// the module docs); `force` allows replacing existing outputs. Every error is bad input
/// (exit 2) naming the flags and the path.
pub fn check(inputs: &[Named<'_>], outputs: &[Named<'_>], force: bool) -> anyhow::Result<()> {
    for (k, out) in outputs.iter().enumerate() {
        let shown = out.path.display();
        if out.path.is_dir() {
            return Err(input_error(format!(
                "{} `{shown}` is a directory; give a file name",
                out.flag
            )));
        }
        for input in inputs {
            if same_file(out.path, input.path) {
                return Err(input_error(format!(
                    "{} `{shown}` is the input {} `{}`: writing it would destroy the input; give another output path",
                    out.flag,
                    input.flag,
                    input.path.display()
                )));
            }
        }
        for other in &outputs[..k] {
            if same_file(out.path, other.path) {
                return Err(input_error(format!(
                    "{} and {} are the same file `{shown}`: give each output its own path",
                    other.flag, out.flag
                )));
            }
        }
        if out.path.exists() && !force {
            return Err(input_error(format!(
                "refusing to overwrite the existing {} file `{shown}` (pass --force to replace it)",
                out.flag
            )));
        }
    }
    Ok(())
}

/// Checks a command's `--csv` and `--plot` outputs before any work: the plot's format
/// (`.svg` or `.png`), then both together against `inputs` and each other ([`check`]).
pub fn check_csv_and_plot(
    inputs: &[Named<'_>],
    csv: Option<&Path>,
    plot: Option<&Path>,
    force: bool,
) -> anyhow::Result<()> {
    if let Some(p) = plot {
        crate::plot::check_path("--plot", p)?;
    }
    let mut outputs = Vec::new();
    if let Some(p) = csv {
        outputs.push(Named::new("--csv", p));
    }
    if let Some(p) = plot {
        outputs.push(Named::new("--plot", p));
    }
    check(inputs, &outputs, force)
}

/// A command's one output, `--plot`, beside the model it read from `origin` (a file or a
/// built-in name): checked ([`check_csv_and_plot`]) and created before any work; `None`
/// without a plot.
pub fn create_plot(
    origin: &str,
    plot: Option<&Path>,
    force: bool,
) -> anyhow::Result<Option<std::fs::File>> {
    let Some(p) = plot else {
        return Ok(None);
    };
    check_csv_and_plot(&model_input(origin), None, Some(p), force)?;
    Ok(Some(crate::output::create_output_file(p, force, "plot")?))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::{EXIT_BAD_INPUT, exit_code};

    #[test]
    fn inputs_and_outputs_by_identity() {
        let dir = tempfile::tempdir().unwrap();
        let log = dir.path().join("run.mcap");
        std::fs::write(&log, b"x").unwrap();
        let dotted = dir.path().join("sub/../run.mcap");
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        let linked = dir.path().join("hard.mcap");
        std::fs::hard_link(&log, &linked).unwrap();
        let new = dir.path().join("new.rrd");
        let new_dotted = dir.path().join("sub/../new.rrd");
        assert!(same_file(&log, &dotted));
        assert!(same_file(&log, &linked));
        assert!(same_file(&new, &new_dotted));
        assert!(!same_file(&log, &new));
        let input = [Named::new("FILE", &log)];
        for out in [&log, &dotted, &linked] {
            let e = check(&input, &[Named::new("--rrd", out)], true).unwrap_err();
            assert_eq!(exit_code(&e), EXIT_BAD_INPUT);
            assert!(e.to_string().contains("is the input FILE"), "{e}");
        }
        let e = check(
            &input,
            &[Named::new("--mcap", &new), Named::new("--rrd", &new_dotted)],
            true,
        )
        .unwrap_err();
        assert!(
            e.to_string().contains("--mcap and --rrd are the same file"),
            "{e}"
        );
        check(&input, &[Named::new("--rrd", &new)], false).unwrap();
        std::fs::write(&new, b"y").unwrap();
        let e = check(&input, &[Named::new("--rrd", &new)], false).unwrap_err();
        assert!(e.to_string().contains("--force"), "{e}");
        check(&input, &[Named::new("--rrd", &new)], true).unwrap();
        let e = check(&[], &[Named::new("--csv", dir.path())], true).unwrap_err();
        assert!(e.to_string().contains("is a directory"), "{e}");
    }
}
