//! Ctrl-C during long calls. Rust loops run with the GIL released; Python's own SIGINT
//! handler only sets a flag, so a loop must come back to the interpreter now and then to run
//! the handlers (`Python::check_signals`) and stop with their exception (KeyboardInterrupt).
//!
//! - [`Signals`]: polled from a loop running on the calling thread with the GIL released
//!   (`py.detach`): every [`EVERY`] it re-attaches for the check.
//! - [`watch`]: runs work that spreads over rayon's threads on a helper thread while the
//!   calling thread checks the signals every [`EVERY`]; on an exception it sets the stop
//!   flag the work polls, waits for it to stop and raises the exception.
//!
//! After an interruption the object keeps what was done before the stop (the steps taken,
//! the tasks' state); an interrupted task's episode has ended (reset it).

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
/// raises, `stop` is set, `work` is waited for (it should poll `stop` and return early) and
/// the exception is raised.
pub fn watch<T: Send>(py: Python<'_>, work: impl FnOnce(&AtomicBool) -> T + Send) -> PyResult<T> {
    let stop = AtomicBool::new(false);
    let (tx, mut rx) = mpsc::channel::<()>();
    std::thread::scope(|s| {
        let stop_ref = &stop;
        let handle = s.spawn(move || {
            let r = work(stop_ref);
            let _ = tx.send(());
            r
        });
        let mut raised = None;
        loop {
            let r = &mut rx;
            let waited = py.detach(move || r.recv_timeout(EVERY));
            match waited {
                Ok(()) | Err(mpsc::RecvTimeoutError::Disconnected) => break,
                Err(mpsc::RecvTimeoutError::Timeout) => {}
            }
            if raised.is_none()
                && let Err(e) = py.check_signals()
            {
                stop.store(true, Ordering::Relaxed);
                raised = Some(e);
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
