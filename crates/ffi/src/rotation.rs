//! A host's rotation update made second order through the C ABI:
//! `flapwing_wings_gyroscopic_correction`.

use nalgebra::Matrix3;

use crate::args::{handle, need, put};
use crate::error::{Failure, FlapwingStatus, guard};
use crate::types::FlapwingWings;

/// After a step: the body-frame moment, N m, to add to the step's wrench when the host takes
/// the body's gyroscopic term w x I w at the step's start in the body frame, as MuJoCo does
/// for a free joint (its bias force) and a plain semi-implicit Euler loop does:
/// w_k x I w_k - w_m x I w_m, with w_k the rates the step was given and w_m those the wings
/// took their loads at (a second-order `[sim] load_sampling` predicts them at the step's
/// midpoint). The host's update of the body rates is then the midpoint rule of Euler's
/// equations, second order as the loads are; without it a body turning about more than one
/// principal axis is first order. Zeros before the first step, after
/// `flapwing_wings_restart_motion` and under the step-start sampling.
///
/// `inertia_body_kg_m2`: the body's inertia about its centre of mass, body frame, row-major
/// 3 x 3 (finite); the host's own, so that the term cancels the host's exactly.
///
/// # Safety
/// `wings` is NULL or a live handle; `inertia_body_kg_m2` is NULL or valid for a read of 9
/// doubles; `out_moment_body_nm` is NULL or valid for a write of 3 doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_gyroscopic_correction(
    wings: *const FlapwingWings,
    inertia_body_kg_m2: *const f64,
    out_moment_body_nm: *mut [f64; 3],
) -> FlapwingStatus {
    const F: &str = "flapwing_wings_gyroscopic_correction";
    guard(F, || {
        // SAFETY: forwarded from this function's contract.
        let w = unsafe { handle(F, wings) }?;
        need(F, "inertia_body_kg_m2", inertia_body_kg_m2)?;
        // SAFETY: non-null and valid for a read of 9 doubles (this function's contract).
        let i = unsafe { inertia_body_kg_m2.cast::<[f64; 9]>().read() };
        if let Some(k) = i.iter().position(|x| !x.is_finite()) {
            return Err(Failure::invalid(format!(
                "{F}: inertia_body_kg_m2[{k}] = {}; allowed: finite numbers",
                i[k]
            )));
        }
        let m = w.set.gyroscopic_correction_nm(&Matrix3::from_row_slice(&i));
        // SAFETY: forwarded from this function's contract.
        unsafe { put(F, out_moment_body_nm, m.into()) }
    })
}
