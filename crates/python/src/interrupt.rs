//! Ctrl-C during long calls. Rust loops run with the GIL released; Python's own SIGINT
//! handler only sets a flag, so a loop must come back to the interpreter now and then to run
//! the handlers (`Python::check_signals`) and stop with their exception (KeyboardInterrupt).
//!
//! - [`Signals`]: polled from a loop running on the calling thread with the GIL released
//!   (`py.detach`): every [`EVERY`] it re-attaches for the check.
//! - [`watch_token`]: runs work that spreads over rayon's threads on a helper thread while
//!   the calling thread checks the signals every [`EVERY`]; on an exception it sets the stop
//!   flag the work polls (a `flapsim::cancel` token), waits for it to stop and raises the
//!   exception.
//! - [`analysis`]: the same for flapsim's trim, stability and LQR design, whose loops check
//!   the token.
//!
//! After an interruption the object keeps what was done before the stop (the steps taken,
//! the tasks' state); an interrupted task's episode has ended (reset it).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

/// How often a long call runs Python's signal handlers.
pub const EVERY: Duration = Duration::from_millis(50);

/// A signal poller for a loop running on the calling thread with the GIL released.
pub struct Signals {
    next: Instant,
    count: u32,
    err: Option<PyErr>,
}

impl Default for Signals {
    fn default() -> Self {
        Self::new()
    }
}

impl Signals {
    pub fn new() -> Self {
        Self {
            next: Instant::now() + EVERY,
            count: 0,
            err: None,
        }
    }

    /// False once a signal handler has raised (the loop should stop); cheap: the clock is
    /// read every 16th call and the interpreter visited every [`EVERY`].
    pub fn keep_going(&mut self) -> bool {
        if self.err.is_some() {
            return false;
        }
        self.count = self.count.wrapping_add(1);
        if !self.count.is_multiple_of(16) || Instant::now() < self.next {
            return true;
        }
        match Python::attach(|py| py.check_signals()) {
            Ok(()) => {
                self.next = Instant::now() + EVERY;
                true
            }
            Err(e) => {
                self.err = Some(e);
                false
            }
        }
    }

    /// The exception a signal handler raised, if any.
    pub fn result(self) -> PyResult<()> {
        match self.err {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }
}

/// Runs `work` on a helper thread with the GIL released (work that fans out over rayon);
/// the calling thread runs Python's signal handlers every [`EVERY`] meanwhile. When one
/// raises, the stop flag is set, `work` is waited for (it should poll the flag and return
/// early) and the exception is raised. The flag is a shareable `flapsim::cancel` token: work
/// that runs flapsim analyses on rayon's threads installs it in each job
/// (`flapsim::cancel::with_cancel`), so that Ctrl-C stops an analysis in flight too.
pub fn watch_token<T: Send>(
    py: Python<'_>,
    work: impl FnOnce(&Arc<AtomicBool>) -> T + Send,
) -> PyResult<T> {
    let stop = Arc::new(AtomicBool::new(false));
    let flag = stop.clone();
    watch_flag(py, stop, move || work(&flag))
}

/// A flapsim analysis (trim, stability, LQR design) under [`watch_token`]'s scheme: it runs with a
/// `flapsim::cancel` token installed, which Ctrl-C sets, so that it stops at its next
/// checkpoint (well within a second) and the KeyboardInterrupt is raised.
pub fn analysis<T: Send>(py: Python<'_>, work: impl FnOnce() -> T + Send) -> PyResult<T> {
    let stop = Arc::new(AtomicBool::new(false));
    let token = stop.clone();
    watch_flag(py, stop, move || flapsim::cancel::with_cancel(token, work))
}

/// Imports numpy and its C API before a long call that returns arrays. rust-numpy imports
/// the API capsule at the first array it makes and panics if that import raises, which a
/// pending KeyboardInterrupt does (the import runs Python code, and so the signal handlers):
/// imported here first, where an interrupt is an ordinary exception.
pub fn numpy_ready(py: Python<'_>) -> PyResult<()> {
    py.import("numpy")?;
    numpy::PyArray1::<f64>::zeros(py, 0, false);
    Ok(())
}

fn watch_flag<T: Send>(
    py: Python<'_>,
    stop: Arc<AtomicBool>,
    work: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    let (tx, mut rx) = mpsc::channel::<()>();
    std::thread::scope(|s| {
        let handle = s.spawn(move || {
            let r = work();
            let _ = tx.send(());
            r
        });
        let mut raised = None;
        loop {
            let r = &mut rx;
            let waited = py.detach(move || r.recv_timeout(EVERY));
            let finished = !matches!(waited, Err(mpsc::RecvTimeoutError::Timeout));
            // Checked once more after the work has finished: a signal that came in its last
            // moments is raised here, not by whatever Python code runs next.
            if raised.is_none()
                && let Err(e) = py.check_signals()
            {
                stop.store(true, Ordering::Relaxed);
                raised = Some(e);
            }
            if finished {
                break;
            }
        }
        let out = py.detach(move || handle.join());
        match (raised, out) {
            (Some(e), _) => Err(e),
            (None, Ok(v)) => Ok(v),
            (None, Err(_)) => Err(PyRuntimeError::new_err("a flapwing worker thread panicked")),
        }
    })
}
