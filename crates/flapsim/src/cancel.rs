//! Cancelling a long analysis (trim, stability, LQR design) from another thread.
//!
//! The analyses run for seconds on an actuated vehicle (every trim residual settles the
//! wings' dynamics) and call each other deep down, so the cancel token is not threaded
//! through their signatures: [`with_cancel`] installs it for the calling thread while it
//! runs a closure, and the analyses' loops call [`check`] at their checkpoints (each cycle
//! average in [`crate::averaged::mean_loads`], each Newton iteration of the trim, each
//! wingbeat of the Floquet analysis, every 64 Riccati iterations of the LQR design). Once the
//! token is set, `check` returns an [`Error::Analysis`] whose message is [`INTERRUPTED`], and
//! the analysis returns it (possibly wrapped in its own context). Code that installs no token
//! (the CLI, the plugins) is never cancelled; `check` then costs one thread-local read.
//!
//! The Python bindings use it for Ctrl-C: the analysis runs on a helper thread under the
//! token while the calling thread runs Python's signal handlers, and sets the token when one
//! raises KeyboardInterrupt.

use std::cell::RefCell;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use crate::error::{Error, Result};

/// The message of the error a cancelled analysis returns.
pub const INTERRUPTED: &str = "interrupted (cancelled by the caller)";

thread_local! {
    static TOKEN: RefCell<Option<Arc<AtomicBool>>> = const { RefCell::new(None) };
}

/// Restores the token that was installed before [`with_cancel`] (also on a panic).
struct Restore(Option<Arc<AtomicBool>>);

impl Drop for Restore {
    fn drop(&mut self) {
        let previous = self.0.take();
        TOKEN.with(|t| *t.borrow_mut() = previous);
    }
}

/// Runs `work` on this thread with `token` installed: the analyses it calls stop at their
/// next checkpoint once `token` is set (see the module documentation).
pub fn with_cancel<T>(token: Arc<AtomicBool>, work: impl FnOnce() -> T) -> T {
    let previous = TOKEN.with(|t| t.borrow_mut().replace(token));
    let _restore = Restore(previous);
    work()
}

/// Installs `token` on this thread for the rest of its life: for the threads of a pool
/// built for one cancellable job (`rayon::ThreadPoolBuilder::start_handler`), whose analyses
/// fan out over the pool where [`with_cancel`] on the calling thread does not reach.
pub fn install(token: Arc<AtomicBool>) {
    TOKEN.with(|t| *t.borrow_mut() = Some(token));
}

/// The token installed on this thread (by [`with_cancel`] or [`install`]), for work this
/// thread fans out over rayon's pool: each task runs under it with [`carry`], so that the
/// analyses' parallel loops (the trim's and the averaged model's Jacobian columns) stop as
/// their caller would.
pub fn current() -> Option<Arc<AtomicBool>> {
    TOKEN.with(|t| t.borrow().clone())
}

/// Runs `work` with `token` ([`current`] of the thread that fanned it out) installed, and
/// as it was without one.
pub fn carry<T>(token: &Option<Arc<AtomicBool>>, work: impl FnOnce() -> T) -> T {
    match token {
        Some(token) => with_cancel(token.clone(), work),
        None => work(),
    }
}

/// `f(0)`, ..., `f(n - 1)` on rayon's pool, each under this thread's token ([`carry`]),
/// collected in order: the same values bit for bit as one by one, and the first error in
/// order (not the first to happen) is the one returned. For the analyses' finite-difference
/// columns (the trim's Jacobian, the averaged model's A and B), independent evaluations.
pub fn par_in_order<T: Send>(n: usize, f: impl Fn(usize) -> Result<T> + Sync) -> Result<Vec<T>> {
    use rayon::prelude::*;
    let token = current();
    (0..n)
        .into_par_iter()
        .map(|j| carry(&token, || f(j)))
        .collect::<Vec<Result<T>>>()
        .into_iter()
        .collect()
}

/// `Err` ([`INTERRUPTED`]) once the token of the enclosing [`with_cancel`] is set; `Ok`
/// without one.
pub fn check() -> Result<()> {
    let cancelled = TOKEN.with(|t| {
        t.borrow()
            .as_ref()
            .is_some_and(|c| c.load(Ordering::Relaxed))
    });
    if cancelled {
        Err(Error::Analysis(INTERRUPTED.to_owned()))
    } else {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn check_fails_only_inside_a_set_token() {
        assert!(check().is_ok());
        let token = Arc::new(AtomicBool::new(false));
        with_cancel(token.clone(), || {
            assert!(check().is_ok());
            token.store(true, Ordering::Relaxed);
            let e = check().unwrap_err();
            assert_eq!(e.to_string(), INTERRUPTED);
        });
        assert!(check().is_ok(), "the token is removed after the work");
    }

    #[test]
    fn a_cancelled_trim_stops_with_the_interrupted_error() {
        let v =
            crate::Vehicle::from_toml(crate::builtin_model("hummingbird").unwrap(), "h").unwrap();
        let token = Arc::new(AtomicBool::new(true));
        let t0 = std::time::Instant::now();
        let r = with_cancel(token, || crate::trim::trim(&v));
        let e = r.unwrap_err().to_string();
        assert!(e.contains(INTERRUPTED), "{e}");
        assert!(t0.elapsed().as_secs_f64() < 0.5, "{:?}", t0.elapsed());
    }

    #[test]
    fn a_cancelled_linearisation_floquet_analysis_and_lqr_design_stop() {
        let v =
            crate::Vehicle::from_toml(crate::builtin_model("drosophila").unwrap(), "d").unwrap();
        let t = crate::trim::trim(&v).unwrap();
        let tv = crate::trim::trimmed_vehicle(&v, &t).unwrap();
        let token = Arc::new(AtomicBool::new(true));
        let is_interrupted = |r: Result<()>| {
            let e = r.unwrap_err().to_string();
            assert!(e.contains(INTERRUPTED), "{e}");
        };
        with_cancel(token, || {
            is_interrupted(crate::stability::analyze_trim(&v, &t, false).map(|_| ()));
            is_interrupted(crate::stability::floquet_analysis(&tv, &t).map(|_| ()));
            let w = crate::control::LqrWeights::default();
            is_interrupted(crate::control::HoverController::design(&tv, &t, &w, 0).map(|_| ()));
        });
    }
}
