//! Status codes, the per-thread last-error message and the guard every exported function runs
//! its body in (null checks, `catch_unwind`, error to code and message).

use std::cell::RefCell;
use std::ffi::{CString, c_char};
use std::panic::{AssertUnwindSafe, catch_unwind};

/// What a call through the C ABI returned. Every function that can fail returns one; on
/// anything but `FLAPWING_OK`, `flapwing_last_error()` holds a message naming what was wrong.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FlapwingStatus {
    /// Success.
    FLAPWING_OK = 0,
    /// A required pointer argument was NULL.
    FLAPWING_NULL_POINTER = 1,
    /// A bad value: a non-finite or non-unit body state, a wing or term index out of range,
    /// text that is not UTF-8, a time step < 0 or NaN, controls the model does not allow.
    FLAPWING_INVALID_ARGUMENT = 2,
    /// The model file, text or built-in name is bad (the message names the file, the field,
    /// the value and what is allowed).
    FLAPWING_MODEL_ERROR = 3,
    /// The model file cannot be read (the message names the path and the reason).
    FLAPWING_IO_ERROR = 4,
    /// The wings' dynamics diverged (actuated wings).
    FLAPWING_DIVERGED = 5,
    /// A bug: a Rust panic was caught at the boundary (the message says where).
    FLAPWING_PANIC = 6,
}

/// A failure: the code to return and the message to keep.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Failure {
    pub(crate) status: FlapwingStatus,
    pub(crate) message: String,
}

impl Failure {
    pub(crate) fn new(status: FlapwingStatus, message: impl Into<String>) -> Self {
        Self {
            status,
            message: message.into(),
        }
    }

    pub(crate) fn null(function: &str, argument: &str) -> Self {
        Self::new(
            FlapwingStatus::FLAPWING_NULL_POINTER,
            format!("{function}: `{argument}` is NULL; allowed: a valid pointer"),
        )
    }

    pub(crate) fn invalid(message: impl Into<String>) -> Self {
        Self::new(FlapwingStatus::FLAPWING_INVALID_ARGUMENT, message)
    }

    /// A flapsim error with its code, the message prefixed by the function's name.
    pub(crate) fn sim(function: &str, e: impl Into<flapsim::Error>) -> Self {
        let e = e.into();
        let status = match &e {
            flapsim::Error::Model(_) => FlapwingStatus::FLAPWING_MODEL_ERROR,
            flapsim::Error::Diverged { .. } => FlapwingStatus::FLAPWING_DIVERGED,
            flapsim::Error::Input(_) | flapsim::Error::Analysis(_) => {
                FlapwingStatus::FLAPWING_INVALID_ARGUMENT
            }
        };
        Self::new(status, format!("{function}: {e}"))
    }
}

thread_local! {
    /// The message of the last call on this thread ("" after a call that succeeded).
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

fn set_last_error(message: &str) {
    // A message never holds a NUL byte from flapsim, but a caller's text could put one there
    // (a file name); it would cut the C string short, so it is shown as U+FFFD.
    let c = CString::new(message.replace('\0', "\u{fffd}")).unwrap_or_default();
    LAST_ERROR.with(|e| *e.borrow_mut() = c);
}

/// Clears this thread's message after a call that succeeded; already clear (the common case:
/// a host stepping the wings), it is left alone, saving an allocation and a free per call
/// (about 300 instructions of a 4000-instruction step, callgrind).
fn clear_last_error() {
    LAST_ERROR.with(|e| {
        if !e.borrow().is_empty() {
            *e.borrow_mut() = CString::default();
        }
    });
}

/// A pointer to this thread's last message, valid until the next call on this thread.
pub(crate) fn last_error_ptr() -> *const c_char {
    LAST_ERROR.with(|e| e.borrow().as_ptr())
}

/// Runs `body` at the boundary: a panic is caught (FLAPWING_PANIC), an error becomes its code
/// and this thread's last message, success clears the message.
pub(crate) fn guard(function: &str, body: impl FnOnce() -> Result<(), Failure>) -> FlapwingStatus {
    let result = catch_unwind(AssertUnwindSafe(body)).unwrap_or_else(|payload| {
        let what = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "a panic without a message".into());
        Err(Failure::new(
            FlapwingStatus::FLAPWING_PANIC,
            format!("{function}: internal error (a bug in flapwing, please report it): {what}"),
        ))
    });
    match result {
        Ok(()) => {
            clear_last_error();
            FlapwingStatus::FLAPWING_OK
        }
        Err(f) => {
            set_last_error(&f.message);
            f.status
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ffi::CStr;

    fn last() -> String {
        // SAFETY: the pointer is this thread's CString, alive until the next call here.
        unsafe { CStr::from_ptr(last_error_ptr()) }
            .to_string_lossy()
            .into_owned()
    }

    #[test]
    fn a_panic_is_caught_and_named() {
        let s = guard("flapwing_test", || panic!("boom {}", 42));
        assert_eq!(s, FlapwingStatus::FLAPWING_PANIC);
        assert!(last().contains("flapwing_test"), "{}", last());
        assert!(last().contains("boom 42"), "{}", last());
        assert_eq!(
            guard("flapwing_test", || Ok(())),
            FlapwingStatus::FLAPWING_OK
        );
        assert_eq!(last(), "");
    }

    #[test]
    fn a_nul_in_a_message_does_not_cut_it() {
        let s = guard("f", || Err(Failure::invalid("a\0b end")));
        assert_eq!(s, FlapwingStatus::FLAPWING_INVALID_ARGUMENT);
        assert_eq!(last(), "a\u{fffd}b end");
    }

    #[test]
    fn the_last_error_is_per_thread() {
        guard("f", || Err(Failure::invalid("main thread")));
        let other = std::thread::spawn(|| {
            let before = last();
            guard("f", || Err(Failure::invalid("other thread")));
            (before, last())
        })
        .join()
        .unwrap();
        assert_eq!(other, (String::new(), "other thread".to_string()));
        assert_eq!(last(), "main thread");
    }
}
