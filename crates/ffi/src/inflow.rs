//! A wing pair's dynamic inflow through the C ABI (issue #38): `flapwing_wings_inflow_pairs`,
//! `flapwing_wings_inflow`, `flapwing_wings_set_inflow`. The handle's wing set steps the
//! states itself (a model with `[aero] inflow = "dynamic"`); these read and set them.

use wingforce::inflow::InflowState;

use crate::args::{handle, handle_mut, put};
use crate::error::{Failure, FlapwingStatus, guard};
use crate::types::FlapwingWings;

/// One wing pair's dynamic inflow states (`wingforce::inflow::dynamic`): the air comes down
/// through the pair's stroke plane at `mean_m_s + fore_m_s x / R_e + left_m_s y / R_e` (x
/// forward, y left in the stroke plane from the disc's centre; R_e the radius of the disc of
/// the area the pair sweeps), m/s.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FlapwingInflow {
    /// Mean induced velocity through the pair's disc (down), m/s.
    pub mean_m_s: f64,
    /// Extra downwash at the disc's front edge, m/s.
    pub fore_m_s: f64,
    /// Extra downwash at the disc's left edge, m/s.
    pub left_m_s: f64,
}

/// The number of wing pairs whose wake answers (`[aero] inflow = "dynamic"`): 0 for a model
/// whose inflow is frozen or off.
///
/// # Safety
/// `wings` is NULL or a live handle; `out` is NULL or valid for a write.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_inflow_pairs(
    wings: *const FlapwingWings,
    out: *mut usize,
) -> FlapwingStatus {
    const F: &str = "flapwing_wings_inflow_pairs";
    guard(F, || {
        // SAFETY: forwarded from this function's contract.
        let w = unsafe { handle(F, wings) }?;
        // SAFETY: forwarded from this function's contract.
        unsafe { put(F, out, w.set.inflow_states().len()) }
    })
}

/// Pair `pair`'s dynamic inflow states now (after a step: the states the next step starts
/// from). FLAPWING_INVALID_ARGUMENT for a pair beyond `flapwing_wings_inflow_pairs`.
///
/// # Safety
/// `wings` is NULL or a live handle; `out` is NULL or valid for a write.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_inflow(
    wings: *const FlapwingWings,
    pair: usize,
    out: *mut FlapwingInflow,
) -> FlapwingStatus {
    const F: &str = "flapwing_wings_inflow";
    guard(F, || {
        // SAFETY: forwarded from this function's contract.
        let w = unsafe { handle(F, wings) }?;
        let states = w.set.inflow_states();
        let s = states.get(pair).ok_or_else(|| {
            Failure::invalid(format!(
                "{F}: pair {pair}; allowed: below the {} pair(s) whose wake answers",
                states.len()
            ))
        })?;
        let [mean_m_s, fore_m_s, left_m_s] = s.to_array();
        // SAFETY: forwarded from this function's contract.
        unsafe {
            put(
                F,
                out,
                FlapwingInflow {
                    mean_m_s,
                    fore_m_s,
                    left_m_s,
                },
            )
        }
    })
}

/// Sets pair `pair`'s dynamic inflow states (a start where a run left off, a perturbation).
/// FLAPWING_INVALID_ARGUMENT for a pair beyond `flapwing_wings_inflow_pairs` or a non-finite
/// state, and the states unchanged.
///
/// # Safety
/// `wings` is NULL or a live handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_set_inflow(
    wings: *mut FlapwingWings,
    pair: usize,
    state: FlapwingInflow,
) -> FlapwingStatus {
    const F: &str = "flapwing_wings_set_inflow";
    guard(F, || {
        // SAFETY: forwarded from this function's contract.
        let w = unsafe { handle_mut(F, wings) }?;
        let mut states = w.set.inflow_states();
        let n = states.len();
        let slot = states.get_mut(pair).ok_or_else(|| {
            Failure::invalid(format!(
                "{F}: pair {pair}; allowed: below the {n} pair(s) whose wake answers"
            ))
        })?;
        *slot = InflowState::from_array([state.mean_m_s, state.fore_m_s, state.left_m_s]);
        w.set
            .set_inflow_states(&states)
            .map_err(|e| Failure::sim(F, e))
    })
}
