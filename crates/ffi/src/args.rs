//! The arguments of the exported functions: handles and out pointers checked for NULL (a
//! `FLAPWING_NULL_POINTER` naming the argument) before they are used.

use crate::error::Failure;
use crate::types::FlapwingWings;

/// A handle argument as a reference.
///
/// # Safety
/// `p` is NULL or a live handle, not used mutably elsewhere for `'a`.
pub(crate) unsafe fn handle<'a>(
    function: &str,
    p: *const FlapwingWings,
) -> Result<&'a FlapwingWings, Failure> {
    // SAFETY: NULL or a live handle (the caller's contract).
    unsafe { p.as_ref() }.ok_or_else(|| Failure::null(function, "wings"))
}

/// A handle argument as a mutable reference.
///
/// # Safety
/// `p` is NULL or a live handle used by this thread only for `'a`.
pub(crate) unsafe fn handle_mut<'a>(
    function: &str,
    p: *mut FlapwingWings,
) -> Result<&'a mut FlapwingWings, Failure> {
    // SAFETY: NULL or a live handle used by one thread at a time (the caller's contract).
    unsafe { p.as_mut() }.ok_or_else(|| Failure::null(function, "wings"))
}

/// Writes `value` to an out pointer.
///
/// # Safety
/// `out` is NULL or valid for a write of `T`.
pub(crate) unsafe fn put<T>(function: &str, out: *mut T, value: T) -> Result<(), Failure> {
    if out.is_null() {
        return Err(Failure::null(function, "out"));
    }
    // SAFETY: non-null and valid for a write (the caller's contract).
    unsafe { out.write(value) };
    Ok(())
}

/// Checks an out pointer before any work is done.
pub(crate) fn need<T>(function: &str, argument: &str, out: *const T) -> Result<(), Failure> {
    if out.is_null() {
        Err(Failure::null(function, argument))
    } else {
        Ok(())
    }
}
