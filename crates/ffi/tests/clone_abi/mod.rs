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
    FlapwingBodyState, FlapwingControls, FlapwingStatus, FlapwingWings, FlapwingWrench,
    flapwing_wings_clone, flapwing_wings_controls, flapwing_wings_free,
    flapwing_wings_from_builtin, flapwing_wings_from_toml, flapwing_wings_inflow_pairs,
    flapwing_wings_restore, flapwing_wings_save, flapwing_wings_set_controls, flapwing_wings_step,
    flapwing_wings_trim,
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

/// `flapwing_wings_save` and `flapwing_wings_restore`: a host's finite differences (MuJoCo's
/// `mjd_transitionFD`) step from a state, go back, and step again from a perturbed one. On
/// every built-in vehicle: at each step the handle is saved, stepped from a perturbed body,
/// restored and stepped from the manoeuvre's body, and it must give the wrench of a run that
/// never went back, bit for bit (every state the wings carry comes back: a missing one, e.g.
/// the dynamic inflow or the midpoint prediction's memory, moves the next wrench).
#[test]
fn a_restored_handle_repeats_the_steps_that_followed_the_save() {
    for name in flapsim::BUILTIN_MODELS {
        // The hummingbird strikes its stops twice a wingbeat (of its 200 steps): 440 steps
        // pass several strikes.
        let steps = if name == "hummingbird" { 440 } else { 60 };
        for wake in ["as built", "dynamic"] {
            let original = match wake {
                "as built" => built(&std::ffi::CString::new(name).unwrap()),
                // Each pair's dynamic inflow (issue #38), states the save must carry; the
                // dragonfly's two pairs cross each other's discs.
                _ => from_toml(name, &dynamic_wake(flapsim::builtin_model(name).unwrap())),
            };
            let mut pairs = 0;
            // SAFETY: a live handle and a valid out pointer.
            unsafe { flapwing_wings_inflow_pairs(original, &mut pairs) };
            assert_eq!(pairs > 0, wake == "dynamic", "{name} ({wake})");
            let handle = copy(original);
            let saved = copy(original);
            let reference = run(original, 0, steps);
            let mut again = Vec::new();
            for k in 0..steps {
                // SAFETY: live, distinct handles.
                let s = unsafe { flapwing_wings_save(handle, saved) };
                assert_eq!(s, FlapwingStatus::FLAPWING_OK, "{}", last_error());
                let mut pushed = body(k);
                pushed.velocity_world_m_s[2] += 0.05;
                pushed.angular_velocity_body_rad_s[1] += 2.0;
                let mut w = FlapwingWrench::default();
                // SAFETY: a live handle, a valid state and out pointer.
                let s = unsafe { flapwing_wings_step(handle, &pushed, &mut w) };
                assert_eq!(s, FlapwingStatus::FLAPWING_OK, "{}", last_error());
                // SAFETY: live, distinct handles.
                let s = unsafe { flapwing_wings_restore(handle, saved) };
                assert_eq!(s, FlapwingStatus::FLAPWING_OK, "{}", last_error());
                again.extend(run(handle, k, 1));
            }
            assert_eq!(bits(&again), bits(&reference), "{name} ({wake})");
            // SAFETY: live handles, each freed once.
            unsafe {
                for w in [original, handle, saved] {
                    flapwing_wings_free(w);
                }
            }
        }
    }
}

/// A model's text with its wake answering: `[aero] inflow = "dynamic"`.
fn dynamic_wake(text: &str) -> String {
    if let Some(i) = text.find("inflow = \"") {
        let end = i + text[i..].find('\n').unwrap();
        format!("{}inflow = \"dynamic\"{}", &text[..i], &text[end..])
    } else if let Some(i) = text.find("[aero]\n") {
        format!(
            "{}[aero]\ninflow = \"dynamic\"\n{}",
            &text[..i],
            &text[i + 7..]
        )
    } else {
        format!("{text}\n[aero]\ninflow = \"dynamic\"\n")
    }
}

fn from_toml(name: &str, text: &str) -> *mut FlapwingWings {
    let (c_text, c_name) = (
        std::ffi::CString::new(text).unwrap(),
        std::ffi::CString::new(name).unwrap(),
    );
    let mut wings: *mut FlapwingWings = ptr::null_mut();
    // SAFETY: NUL-terminated strings and a valid out pointer.
    let s = unsafe { flapwing_wings_from_toml(c_text.as_ptr(), c_name.as_ptr(), 0.0, &mut wings) };
    assert_eq!(s, FlapwingStatus::FLAPWING_OK, "{name}: {}", last_error());
    wings
}

/// A save leaves out the wingbeat's table of kinematic loads, a cache tagged with the
/// kinematics it was computed under. A branch that changes the kinematics (new controls at a
/// wingbeat) fills the table under its own tag; after the restore, other controls must not
/// find the branch's entries valid: the fly's run equals one that never branched.
#[test]
fn a_branch_with_other_controls_leaves_nothing_behind() {
    let controls = |wings: *mut FlapwingWings, amplitude_rad: f64| {
        let mut c = FlapwingControls::default();
        // SAFETY: a live handle and valid pointers.
        unsafe {
            assert_eq!(
                flapwing_wings_controls(wings, &mut c),
                FlapwingStatus::FLAPWING_OK
            );
            c.amplitude_rad = amplitude_rad;
            let s = flapwing_wings_set_controls(wings, &c);
            assert_eq!(s, FlapwingStatus::FLAPWING_OK, "{}", last_error());
        }
    };
    let original = built(c"drosophila");
    let unbranched = copy(original);
    let saved = copy(original);
    // Two wingbeats (20 steps each) at the model's controls fill the table.
    let start = run(original, 0, 40);
    assert_eq!(bits(&run(unbranched, 0, 40)), bits(&start));
    // SAFETY: live, distinct handles.
    assert_eq!(
        unsafe { flapwing_wings_save(original, saved) },
        FlapwingStatus::FLAPWING_OK
    );
    controls(original, 0.1);
    run(original, 40, 60);
    // SAFETY: live, distinct handles.
    assert_eq!(
        unsafe { flapwing_wings_restore(original, saved) },
        FlapwingStatus::FLAPWING_OK
    );
    controls(original, -0.05);
    controls(unbranched, -0.05);
    assert_eq!(bits(&run(original, 40, 60)), bits(&run(unbranched, 40, 60)));
    // SAFETY: live handles, each freed once.
    unsafe {
        for w in [original, unbranched, saved] {
            flapwing_wings_free(w);
        }
    }
}

#[test]
fn saving_into_a_handle_built_apart_or_null_is_refused_and_changes_nothing() {
    let a = built(c"drosophila");
    let b = built(c"drosophila");
    run(a, 0, 7);
    // SAFETY: live, distinct handles.
    let s = unsafe { flapwing_wings_save(a, b) };
    assert_eq!(s, FlapwingStatus::FLAPWING_INVALID_ARGUMENT);
    assert!(
        last_error().contains("flapwing_wings_save") && last_error().contains("not a copy"),
        "{}",
        last_error()
    );
    // SAFETY: live, distinct handles.
    let s = unsafe { flapwing_wings_restore(b, a) };
    assert_eq!(s, FlapwingStatus::FLAPWING_INVALID_ARGUMENT);
    // b was neither saved into nor restored: it starts at step 0 as a fresh handle does.
    let fresh = built(c"drosophila");
    assert_eq!(bits(&run(b, 0, 5)), bits(&run(fresh, 0, 5)));
    // SAFETY: NULL arguments are reported, naming the argument.
    let s = unsafe { flapwing_wings_save(a, ptr::null_mut()) };
    assert_eq!(s, FlapwingStatus::FLAPWING_NULL_POINTER);
    assert!(last_error().contains("`saved`"), "{}", last_error());
    // SAFETY: as above.
    let s = unsafe { flapwing_wings_restore(ptr::null_mut(), a) };
    assert_eq!(s, FlapwingStatus::FLAPWING_NULL_POINTER);
    // SAFETY: live handles, each freed once.
    unsafe {
        for w in [a, b, fresh] {
            flapwing_wings_free(w);
        }
    }
}
