//! The checks every reading of a damaged log passes: `read_summary`, `export_csv` and
//! `check_log` return `Ok` (a damaged log: partial, with `damage` saying what was lost) or an
//! error whose message names the file and is classed as bad input; a panic is a test failure
//! naming the call; `check_log` runs in a thread with a time limit (a re-run must not hang on
//! any input). Also the proptest configuration.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;
use std::time::Duration;

use flightlog::Error;
use flightlog::check::{CheckOutcome, check_log};
use flightlog::replay::{ReplaySummary, export_csv, read_summary};
use proptest::prelude::*;

use crate::prop_config;

fn panic_message(p: Box<dyn std::any::Any + Send>) -> String {
    p.downcast_ref::<String>()
        .cloned()
        .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_default()
}

/// Runs `f`, turning a panic into a test failure naming `what`.
pub(crate) fn guarded<T>(what: &str, f: impl FnOnce() -> T) -> Result<T, TestCaseError> {
    catch_unwind(AssertUnwindSafe(f))
        .map_err(|p| TestCaseError::fail(format!("{what} panicked: {}", panic_message(p))))
}

/// An error from reading `path`: a message that names the file (all but JSON/Rerun errors).
pub(crate) fn check_read_error(e: &Error, path: &Path) -> Result<(), TestCaseError> {
    let s = e.to_string();
    let name = path.file_name().unwrap().to_string_lossy();
    prop_assert!(!s.trim().is_empty(), "empty error message");
    prop_assert!(
        s.contains(name.as_ref()),
        "the error does not name the file `{}`: {} ({:?})",
        name,
        s,
        e
    );
    prop_assert!(
        e.is_bad_input(),
        "a bad file is not classed as bad input: {s} ({e:?})"
    );
    Ok(())
}

/// `read_summary` of a damaged log: Ok with a damage note unless whole, or a clear error.
/// Returns the summary.
pub(crate) fn summary_of(path: &Path) -> Result<Option<ReplaySummary>, TestCaseError> {
    match guarded("read_summary", || read_summary(path))? {
        Ok(s) => {
            prop_assert!(
                s.complete || s.damage.is_some(),
                "an incomplete log without a damage note"
            );
            // The text and JSON forms of the summary (what `flapwing replay` prints).
            guarded("Display of the summary", || s.to_string())?;
            guarded("JSON of the summary", || serde_json::to_string(&s))?
                .map_err(|e| TestCaseError::fail(format!("summary is not JSON: {e}")))?;
            Ok(Some(s))
        }
        Err(e) => {
            check_read_error(&e, path)?;
            Ok(None)
        }
    }
}

/// `export_csv` of one topic: Ok, or a clear error (an unknown topic lists the others).
pub(crate) fn csv_of(path: &Path, topic: &str, out: &Path) -> Result<(), TestCaseError> {
    match guarded("export_csv", || export_csv(path, topic, out))? {
        Ok(stats) => prop_assert!(stats.columns >= 1),
        Err(Error::UnknownTopic { .. }) => {}
        Err(e) => check_read_error(&e, path)?,
    }
    Ok(())
}

/// `check_log` in a thread with a time limit (a re-run must not hang on any input).
pub(crate) fn check_with_limit(
    path: &Path,
    limit: Duration,
) -> Result<Option<flightlog::Result<CheckOutcome>>, TestCaseError> {
    let p = path.to_owned();
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let r = catch_unwind(AssertUnwindSafe(|| check_log(&p)));
        let _ = tx.send(r);
    });
    match rx.recv_timeout(limit) {
        Ok(Ok(r)) => Ok(Some(r)),
        Ok(Err(p)) => Err(TestCaseError::fail(format!(
            "check_log panicked: {}",
            panic_message(p)
        ))),
        Err(_) => Ok(None),
    }
}

pub(crate) fn config(cases: u32) -> ProptestConfig {
    prop_config::scaled_config(cases, 500)
}

/// Maps a `Result<(), TestCaseError>` of a plain test to a panic.
pub(crate) fn ok(r: Result<(), TestCaseError>) {
    if let Err(e) = r {
        panic!("{e}");
    }
}
