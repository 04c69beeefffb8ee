//! Writing results: the stdout report or JSON document, and output files that are never
//! overwritten by accident.

use std::fs::{File, OpenOptions};
use std::io::{self, Write};
use std::path::Path;

use serde::Serialize;

use crate::error::input_error;

/// Writes `text` to stdout. A closed pipe (`flapwing validate | head`) is not an error.
pub fn print_stdout(text: &str) -> anyhow::Result<()> {
    let mut out = io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != io::ErrorKind::BrokenPipe => {
            Err(anyhow::Error::new(e).context("cannot write to stdout"))
        }
        _ => Ok(()),
    }
}

/// Prints `value` as the one JSON document on stdout (pretty, newline-terminated).
pub fn print_json(value: &impl Serialize) -> anyhow::Result<()> {
    let mut text = serde_json::to_string_pretty(value)?;
    text.push('\n');
    print_stdout(&text)
}

/// `x` rounded to `digits` significant digits, printed without trailing zeros
/// (0.19049999999999997 -> "0.1905", 1360.0 -> "1360").
pub fn fmt_sig(x: f64, digits: usize) -> String {
    let rounded = format!("{:.*e}", digits.saturating_sub(1), x);
    rounded.parse::<f64>().unwrap_or(x).to_string()
}

/// Creates the output file `path` (`what` names it in messages, e.g. "CSV file"). An existing
/// file is replaced only when `force` is set; otherwise, and when the path cannot be created
/// (missing directory, no permission), the error is bad input.
pub fn create_output_file(path: &Path, force: bool, what: &str) -> anyhow::Result<File> {
    let shown = path.display();
    if path.is_dir() {
        return Err(input_error(format!(
            "{what} `{shown}` is a directory; give a file name"
        )));
    }
    let mut options = OpenOptions::new();
    options.write(true);
    if force {
        options.create(true).truncate(true);
    } else {
        options.create_new(true);
    }
    options.open(path).map_err(|e| {
        if e.kind() == io::ErrorKind::AlreadyExists {
            input_error(format!(
                "refusing to overwrite the existing {what} `{shown}` (pass --force to replace it)"
            ))
        } else {
            input_error(format!("cannot create {what} `{shown}`: {e}"))
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::{EXIT_BAD_INPUT, exit_code};

    #[test]
    fn significant_digits() {
        assert_eq!(fmt_sig(0.19049999999999997, 6), "0.1905");
        assert_eq!(fmt_sig(1360.0000000002, 6), "1360");
        assert_eq!(fmt_sig(0.11177512345, 6), "0.111775");
        assert_eq!(fmt_sig(f64::NAN, 6), "NaN");
    }

    #[test]
    fn existing_files_need_force() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.csv");
        create_output_file(&path, false, "CSV file").unwrap();
        let e = create_output_file(&path, false, "CSV file").unwrap_err();
        assert_eq!(exit_code(&e), EXIT_BAD_INPUT);
        assert!(e.to_string().contains("--force"), "{e}");
        create_output_file(&path, true, "CSV file").unwrap();
        let e = create_output_file(dir.path(), true, "CSV file").unwrap_err();
        assert!(e.to_string().contains("is a directory"), "{e}");
        let missing = dir.path().join("no/such/dir/out.csv");
        let e = create_output_file(&missing, false, "CSV file").unwrap_err();
        assert_eq!(exit_code(&e), EXIT_BAD_INPUT);
    }
}

/// Writes one line to stderr (warnings, "logging to ..."); a closed or full stderr is ignored,
/// never a panic.
pub fn note(line: &str) {
    let mut err = io::stderr().lock();
    let _ = writeln!(err, "{line}");
}
