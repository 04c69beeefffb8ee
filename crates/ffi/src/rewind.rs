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
    guard(F, || {
        if std::ptr::eq(wings, saved) && !wings.is_null() {
            return Ok(());
        }
        if saved.is_null() {
            return Err(Failure::null(F, "saved"));
        }
        // SAFETY: forwarded from this function's contract; distinct handles (checked above).
        let from = unsafe { handle(F, wings) }?;
        // SAFETY: as above.
        let to = unsafe { handle_mut(F, saved) }?;
        from.set
            .save_state(&mut to.set)
            .map_err(|e| Failure::invalid(format!("{F}: {e}")))?;
        copy_host(to, from);
        Ok(())
    })
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
    guard(F, || {
        if std::ptr::eq(wings, saved) && !wings.is_null() {
            return Ok(());
        }
        if saved.is_null() {
            return Err(Failure::null(F, "saved"));
        }
        // SAFETY: forwarded from this function's contract; distinct handles (checked above).
        let to = unsafe { handle_mut(F, wings) }?;
        // SAFETY: as above.
        let from = unsafe { handle(F, saved) }?;
        to.set
            .restore_state(&from.set)
            .map_err(|e| Failure::invalid(format!("{F}: {e}")))?;
        copy_host(to, from);
        Ok(())
    })
}
