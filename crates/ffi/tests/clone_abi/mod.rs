//! `flapwing_wings_clone`: a copy of a handle steps as the original would, bit for bit, from
//! wherever the original was when it was copied. A host that restarts runs (the MuJoCo
//! plugin at `mj_resetData`) keeps a copy made before the first step and clones it at each
//! restart, instead of building and trimming the wings again (the trim alone costs 0.18 s for
//! the dragonfly and 1.5 s for the hummingbird): so the copy must be the rebuilt handle, bit
//! for bit, and carry every state a run moves (time, the actuated wings' hinge and actuator
//! states and the stop strikes shared between steps, the dynamic inflow, the held
//! corrections, the step memory of the second-order sampling).

use std::ptr;

use flapwing::{
    FlapwingBodyState, FlapwingStatus, FlapwingWings, FlapwingWrench, flapwing_wings_clone,
    flapwing_wings_free, flapwing_wings_from_builtin, flapwing_wings_step, flapwing_wings_trim,
};

use super::last_error;

fn built(name: &std::ffi::CStr) -> *mut FlapwingWings {
    let mut wings: *mut FlapwingWings = ptr::null_mut();
    // SAFETY: a NUL-terminated name and a valid out pointer.
    let s = unsafe { flapwing_wings_from_builtin(name.as_ptr(), 0.0, &mut wings) };
    assert_eq!(s, FlapwingStatus::FLAPWING_OK, "{}", last_error());
    wings
}

fn copy(wings: *const FlapwingWings) -> *mut FlapwingWings {
    let mut out: *mut FlapwingWings = ptr::null_mut();
    // SAFETY: a live handle and a valid out pointer.
    let s = unsafe { flapwing_wings_clone(wings, &mut out) };
    assert_eq!(s, FlapwingStatus::FLAPWING_OK, "{}", last_error());
    assert!(!out.is_null());
    out
}

/// The body at step `k` of a made-up manoeuvre: moving, pitching and rolling, so that every
/// state the wings keep (the step memory's prediction included) is exercised.
fn body(k: usize) -> FlapwingBodyState {
    let t = k as f64 * 1e-4;
    // A rotation by a small angle about a tilted axis: a unit quaternion.
    let (s, c) = (0.05 * (30.0 * t).sin()).sin_cos();
    let (ax, ay) = (0.3 / 1.09_f64.sqrt(), 1.0 / 1.09_f64.sqrt());
    FlapwingBodyState {
        position_m: [0.1 * t, 0.0, 0.02 * t],
        world_from_body_wxyz: [c, ax * s, ay * s, 0.0],
        velocity_world_m_s: [0.1, 0.01 * (50.0 * t).cos(), 0.02],
        angular_velocity_body_rad_s: [0.5 * (40.0 * t).cos(), 1.5 * (30.0 * t).cos(), 0.1],
    }
}

/// The wrenches of `steps` steps from step `from` of the manoeuvre.
fn run(wings: *mut FlapwingWings, from: usize, steps: usize) -> Vec<[f64; 6]> {
    (from..from + steps)
        .map(|k| {
            let mut w = FlapwingWrench::default();
            // SAFETY: a live handle, a valid state and a valid out pointer.
            let s = unsafe { flapwing_wings_step(wings, &body(k), &mut w) };
            assert_eq!(s, FlapwingStatus::FLAPWING_OK, "{}", last_error());
            let [fx, fy, fz] = w.force_body_n;
            let [mx, my, mz] = w.moment_body_nm;
            [fx, fy, fz, mx, my, mz]
        })
        .collect()
}

fn bits(w: &[[f64; 6]]) -> Vec<[u64; 6]> {
    w.iter().map(|r| r.map(f64::to_bits)).collect()
}

#[test]
fn a_copy_steps_as_the_original_would_from_where_it_was_copied() {
    // The hummingbird: actuated wings on stops (strikes shared between steps), the most
    // state a wing set carries. Two wingbeats at its 400 steps, strikes included.
    let original = built(c"hummingbird");
    let pristine = copy(original);
    let first = run(original, 0, 800);
    let midway = copy(original);
    let rest = run(original, 800, 400);
    assert!(first.iter().chain(&rest).flatten().all(|x| x.is_finite()));

    let again = copy(pristine);
    assert_eq!(bits(&run(again, 0, 800)), bits(&first));
    assert_eq!(bits(&run(again, 800, 400)), bits(&rest));
    assert_eq!(bits(&run(midway, 800, 400)), bits(&rest));
    // SAFETY: live handles, each freed once.
    unsafe {
        for w in [original, pristine, midway, again] {
            flapwing_wings_free(w);
        }
    }
}

#[test]
fn a_copy_of_a_trimmed_handle_is_the_handle_built_and_trimmed_again() {
    let trimmed = |name: &std::ffi::CStr| {
        let w = built(name);
        // SAFETY: a live handle; the trim's own output is not wanted (NULL).
        let s = unsafe { flapwing_wings_trim(w, 1.0, 0.0, ptr::null_mut()) };
        assert_eq!(s, FlapwingStatus::FLAPWING_OK, "{}", last_error());
        w
    };
    for name in [c"bumblebee", c"dragonfly"] {
        let first = trimmed(name);
        let pristine = copy(first);
        let reference = run(first, 0, 200);
        let rebuilt = trimmed(name);
        let cloned = copy(pristine);
        assert_eq!(bits(&run(rebuilt, 0, 200)), bits(&reference), "{name:?}");
        assert_eq!(bits(&run(cloned, 0, 200)), bits(&reference), "{name:?}");
        // SAFETY: live handles, each freed once.
        unsafe {
            for w in [first, pristine, rebuilt, cloned] {
                flapwing_wings_free(w);
            }
        }
    }
}

#[test]
fn copying_nothing_is_a_null_pointer_error_and_clears_the_output() {
    let mut out: *mut FlapwingWings = 8 as *mut FlapwingWings;
    // SAFETY: NULL is allowed and reported; `out` is valid for a write.
    let s = unsafe { flapwing_wings_clone(ptr::null(), &mut out) };
    assert_eq!(s, FlapwingStatus::FLAPWING_NULL_POINTER);
    assert!(out.is_null());
    assert!(
        last_error().contains("flapwing_wings_clone"),
        "{}",
        last_error()
    );
    // SAFETY: a live handle and a NULL output, which is reported.
    let w = built(c"drosophila");
    let s = unsafe { flapwing_wings_clone(w, ptr::null_mut()) };
    assert_eq!(s, FlapwingStatus::FLAPWING_NULL_POINTER);
    // SAFETY: a live handle, freed once.
    unsafe { flapwing_wings_free(w) };
}
