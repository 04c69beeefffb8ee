//! Going back a step through the C ABI: `flapwing_wings_save` and `flapwing_wings_restore`
//! (`wingset::WingSet::save_state`). A host that sets its body back to an earlier step and
//! steps again (MuJoCo's `mjd_transitionFD`, any finite-difference linearisation) saves the
//! wings before a step into a copy made once (`flapwing_wings_clone`) and restores them from
//! it when it goes back: cheaper than a clone per step, since a save leaves out the wingbeat's
//! table of kinematic loads (a cache) and reuses the copy's memory.

use crate::args::{handle, handle_mut};
use crate::error::{Failure, FlapwingStatus, guard};
use crate::types::FlapwingWings;

/// The handle's own settings beside the wing set's state (the body's properties and the
/// host's gyroscopic inertia), copied with it.
fn copy_host(to: &mut FlapwingWings, from: &FlapwingWings) {
    to.body = from.body;
    to.gyroscopic_host = from.gyroscopic_host;
}

/// Copies the state between two handles, copies of one build: `copy` moves the wing set's
/// state (checked), then the handle's own settings follow.
///
/// # Safety
/// `to` and `from` are NULL or live handles used by no other thread during the call.
unsafe fn copy_between<E: std::fmt::Display>(
    function: &str,
    to: *mut FlapwingWings,
    from: *const FlapwingWings,
    copy: impl FnOnce(&mut FlapwingWings, &FlapwingWings) -> Result<(), E>,
) -> FlapwingStatus {
    guard(function, || {
        if std::ptr::eq(to, from) && !to.is_null() {
            return Ok(());
        }
        // SAFETY: forwarded from this function's contract; distinct handles (checked above).
        let src = unsafe { handle(function, from) }?;
        // SAFETY: as above.
        let dst = unsafe { handle_mut(function, to) }?;
        copy(dst, src).map_err(|e| Failure::invalid(format!("{function}: {e}")))?;
        copy_host(dst, src);
        Ok(())
    })
}

/// Saves the state of `wings` (time, wing, actuator and inflow states, controls, wind, host
/// settings, the step memory) into `saved`, a copy of `wings` made with
/// `flapwing_wings_clone` (of it or of a copy of it), for `flapwing_wings_restore`. A handle
/// built apart is FLAPWING_INVALID_ARGUMENT and `saved` is unchanged; `saved == wings` does
/// nothing.
///
/// # Safety
/// `wings` and `saved` are NULL or live handles; neither is used by another thread during
/// the call.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_save(
    wings: *const FlapwingWings,
    saved: *mut FlapwingWings,
) -> FlapwingStatus {
    const F: &str = "flapwing_wings_save";
    if saved.is_null() {
        return guard(F, || Err(Failure::null(F, "saved")));
    }
    // SAFETY: forwarded from this function's contract.
    unsafe { copy_between(F, saved, wings, |to, from| from.set.save_state(&mut to.set)) }
}

/// Puts back into `wings` the state saved in `saved` (`flapwing_wings_save`): the steps that
/// follow repeat, bit for bit, those that followed the save. A handle that is not a copy of
/// `wings` is FLAPWING_INVALID_ARGUMENT and `wings` is unchanged; `saved == wings` does
/// nothing.
///
/// # Safety
/// `wings` and `saved` are NULL or live handles; neither is used by another thread during
/// the call.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_restore(
    wings: *mut FlapwingWings,
    saved: *const FlapwingWings,
) -> FlapwingStatus {
    const F: &str = "flapwing_wings_restore";
    if saved.is_null() {
        return guard(F, || Err(Failure::null(F, "saved")));
    }
    // SAFETY: forwarded from this function's contract.
    unsafe { copy_between(F, wings, saved, |to, from| to.set.restore_state(&from.set)) }
}
