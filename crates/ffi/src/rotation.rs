//! A host's rotation update made second order through the C ABI:
//! `flapwing_wings_set_gyroscopic_host`.

use nalgebra::Matrix3;

use crate::args::handle_mut;
use crate::error::{Failure, FlapwingStatus, guard};
use crate::types::FlapwingWings;

/// Says that the host takes the body's gyroscopic term w x I w at the step's start in the body
/// frame, as MuJoCo does for a free joint (its bias force) and a plain semi-implicit Euler loop
/// does, with `inertia_body_kg_m2` its inertia of the body about the centre of mass, body
/// frame, row-major 3 x 3 (finite); NULL: it does not (the default). From the next step on,
/// the moment `flapwing_wings_step` returns then includes w_k x I w_k - w_m x I w_m, with w_k
/// the rates the step was given and w_m those the wings took their loads at (a second-order
/// `[sim] load_sampling` predicts them at the step's midpoint): the host's update of the
/// rates becomes the midpoint rule of Euler's equations, second order as the loads are;
/// without it a body turning about more than one principal axis is first order. The term is
/// zero under the step-start sampling, at the first step and after
/// `flapwing_wings_restart_motion`; `flapwing_wings_term`, `_inertia` and `_wing` do not
/// include it.
///
/// # Safety
/// `wings` is NULL or a live handle; `inertia_body_kg_m2` is NULL or valid for a read of 9
/// doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_set_gyroscopic_host(
    wings: *mut FlapwingWings,
    inertia_body_kg_m2: *const f64,
) -> FlapwingStatus {
    const F: &str = "flapwing_wings_set_gyroscopic_host";
    guard(F, || {
        // SAFETY: forwarded from this function's contract.
        let w = unsafe { handle_mut(F, wings) }?;
        if inertia_body_kg_m2.is_null() {
            w.gyroscopic_host = None;
            return Ok(());
        }
        // SAFETY: non-null and valid for a read of 9 doubles (this function's contract).
        let i = unsafe { inertia_body_kg_m2.cast::<[f64; 9]>().read() };
        if let Some(k) = i.iter().position(|x| !x.is_finite()) {
            return Err(Failure::invalid(format!(
                "{F}: inertia_body_kg_m2[{k}] = {}; allowed: finite numbers",
                i[k]
            )));
        }
        w.gyroscopic_host = Some(Matrix3::from_row_slice(&i));
        Ok(())
    })
}
