//! # flapwing-ffi: the C ABI of flapwing
//!
//! Flapping wings as a force element on a rigid body, for C and C++ hosts (MuJoCo plugins,
//! FMUs, Gazebo, Webots, Drake): a handle holds a [`flapsim::WingSet`] built from a vehicle
//! model (a built-in name, a TOML file or TOML text); each step takes the body's state at t_k
//! and returns the wrench on the body over [t_k, t_k + dt] about its centre of mass, body
//! frame. The host integrates the body. The header `include/flapwing.h` is generated from this
//! crate by cbindgen (see the crate README).
//!
//! All quantities SI; body frame x forward, y left, z up, origin at the centre of mass; world
//! z up; quaternions w, x, y, z (world_from_body).
//!
//! ## Errors
//! Every function that can fail returns a [`FlapwingStatus`]; on anything but `FLAPWING_OK`,
//! [`flapwing_last_error`] returns a message naming what was wrong (the file, field, value and
//! what is allowed). A NULL pointer where one is required is `FLAPWING_NULL_POINTER`, never a
//! crash; no Rust panic crosses the boundary (it is caught and returned as `FLAPWING_PANIC`).
//! A freed handle cannot be detected: using a handle after `flapwing_wings_free` is undefined
//! behaviour, as in any C library.
//!
//! ## Threads
//! A handle is not thread-safe: one thread at a time may call functions on it (a host may
//! move it between threads, with its own synchronisation). Distinct handles on distinct
//! threads are independent. The last-error message is per thread.
//!
//! ## Before the first step
//! `flapwing_wings_term`, `flapwing_wings_inertia` and `flapwing_wings_wing` report zeros
//! (and `FLAPWING_OK`) before the first step, as [`flapsim::WingSet::output`] does.

mod args;
mod error;
mod flight;
mod inflow;
mod rewind;
mod rotation;
mod types;

use std::ffi::{CStr, c_char};

use flapsim::{Controls, FromVehicle};
use nalgebra::Vector3;

use args::{handle, handle_mut, need, put};
pub use error::FlapwingStatus;
use error::{Failure, guard};
pub use flight::{FlapwingTrim, flapwing_wings_body_drag, flapwing_wings_trim};
pub use inflow::{
    FlapwingInflow, flapwing_wings_inflow, flapwing_wings_inflow_pairs, flapwing_wings_set_inflow,
};
pub use rewind::{flapwing_wings_restore, flapwing_wings_save};
pub use rotation::flapwing_wings_set_gyroscopic_host;
pub use types::*;

/// A C string argument as UTF-8.
///
/// # Safety
/// `p` is non-null and points to a NUL-terminated string.
unsafe fn utf8<'a>(function: &str, argument: &str, p: *const c_char) -> Result<&'a str, Failure> {
    // SAFETY: the caller passes a non-null, NUL-terminated string (the contract of every
    // function taking `const char *`).
    let c = unsafe { CStr::from_ptr(p) };
    c.to_str().map_err(|e| {
        Failure::invalid(format!(
            "{function}: `{argument}` is not UTF-8 ({e}): {:?}; allowed: UTF-8 text",
            c.to_string_lossy()
        ))
    })
}

/// Creates a handle, writing it to `*out` (NULL on error).
///
/// # Safety
/// `out` is NULL or valid for a write.
unsafe fn create(
    function: &str,
    out: *mut *mut FlapwingWings,
    make: impl FnOnce() -> Result<FlapwingWings, Failure>,
) -> FlapwingStatus {
    guard(function, || {
        if out.is_null() {
            return Err(Failure::null(function, "out"));
        }
        // SAFETY: `out` is non-null and, by the caller's contract, valid for a write.
        unsafe { out.write(std::ptr::null_mut()) };
        let wings = make()?;
        // SAFETY: as above; the handle is owned by the caller until flapwing_wings_free.
        unsafe { out.write(Box::into_raw(Box::new(wings))) };
        Ok(())
    })
}

/// A built-in model's wings: `name` is one of drosophila, bumblebee, robobee_kinematic,
/// dragonfly, robobee, hummingbird. `dt_s > 0` is the host's fixed step, at most 1/10 of the wingbeat
/// period (1 / (10 f); a longer step is FLAPWING_INVALID_ARGUMENT); `dt_s == 0` takes the
/// model's own (1 / (f sim.steps_per_wingbeat)). On error `*out` is set to NULL.
///
/// # Safety
/// `name` is NULL or a NUL-terminated string; `out` is NULL or valid for a write.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_from_builtin(
    name: *const c_char,
    dt_s: f64,
    out: *mut *mut FlapwingWings,
) -> FlapwingStatus {
    const F: &str = "flapwing_wings_from_builtin";
    let make = || {
        if name.is_null() {
            return Err(Failure::null(F, "name"));
        }
        // SAFETY: non-null, NUL-terminated by the caller's contract.
        let name = unsafe { utf8(F, "name", name) }?;
        let text = flapsim::builtin_model(name).ok_or_else(|| {
            Failure::new(
                FlapwingStatus::FLAPWING_MODEL_ERROR,
                format!(
                    "{F}: no built-in model named {name:?}; allowed: drosophila, bumblebee, robobee_kinematic, dragonfly, robobee, hummingbird (or a TOML file: flapwing_wings_from_file)"
                ),
            )
        })?;
        FlapwingWings::from_toml(F, text, &format!("<built-in {name}>"), dt_s)
    };
    // SAFETY: `out` is NULL or valid for a write (this function's contract).
    unsafe { create(F, out, make) }
}

/// The wings of the vehicle model in a TOML file. The file cannot be read:
/// FLAPWING_IO_ERROR naming the path; a bad model: FLAPWING_MODEL_ERROR naming the file,
/// the field, the value and what is allowed. `dt_s` as in flapwing_wings_from_builtin. On
/// error `*out` is set to NULL.
///
/// # Safety
/// `path` is NULL or a NUL-terminated string; `out` is NULL or valid for a write.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_from_file(
    path: *const c_char,
    dt_s: f64,
    out: *mut *mut FlapwingWings,
) -> FlapwingStatus {
    const F: &str = "flapwing_wings_from_file";
    let make = || {
        if path.is_null() {
            return Err(Failure::null(F, "path"));
        }
        // SAFETY: non-null, NUL-terminated by the caller's contract.
        let path = unsafe { utf8(F, "path", path) }?;
        let text = std::fs::read_to_string(path).map_err(|e| {
            Failure::new(
                FlapwingStatus::FLAPWING_IO_ERROR,
                format!("{F}: cannot read model file {path:?}: {e}"),
            )
        })?;
        FlapwingWings::from_toml(F, &text, path, dt_s)
    };
    // SAFETY: `out` is NULL or valid for a write (this function's contract).
    unsafe { create(F, out, make) }
}

/// The wings of the vehicle model in TOML text; `origin` names it in error messages (a file
/// name or a description; NULL: "<TOML text>"). `dt_s` as in flapwing_wings_from_builtin. On
/// error `*out` is set to NULL.
///
/// # Safety
/// `text` and `origin` are NULL or NUL-terminated strings; `out` is NULL or valid for a write.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_from_toml(
    text: *const c_char,
    origin: *const c_char,
    dt_s: f64,
    out: *mut *mut FlapwingWings,
) -> FlapwingStatus {
    const F: &str = "flapwing_wings_from_toml";
    let make = || {
        if text.is_null() {
            return Err(Failure::null(F, "text"));
        }
        // SAFETY: non-null, NUL-terminated by the caller's contract.
        let text = unsafe { utf8(F, "text", text) }?;
        let origin = if origin.is_null() {
            "<TOML text>"
        } else {
            // SAFETY: non-null, NUL-terminated by the caller's contract.
            unsafe { utf8(F, "origin", origin) }?
        };
        FlapwingWings::from_toml(F, text, origin, dt_s)
    };
    // SAFETY: `out` is NULL or valid for a write (this function's contract).
    unsafe { create(F, out, make) }
}

/// Frees a handle. NULL is a no-op; freeing a handle twice, or using it after, is undefined.
///
/// # Safety
/// `wings` is NULL or a handle from a flapwing_wings_from_* function not yet freed.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_free(wings: *mut FlapwingWings) {
    // Dropping a WingSet does not panic; the guard keeps that so if it ever did.
    guard("flapwing_wings_free", || {
        if !wings.is_null() {
            // SAFETY: a live handle from Box::into_raw (the caller's contract), freed once.
            drop(unsafe { Box::from_raw(wings) });
        }
        Ok(())
    });
}

/// A copy of a handle, in the state it is in now (time, wing and inflow states, controls,
/// wind, trim, host settings): each steps on its own from there, as the original would. A host
/// that restarts runs keeps a copy made before the first step and clones it at each restart
/// instead of building (and trimming) the wings again: the same handle, bit for bit, at the
/// cost of a copy. On error `*out` is set to NULL.
///
/// # Safety
/// `wings` is NULL or a live handle; `out` is NULL or valid for a write.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_clone(
    wings: *const FlapwingWings,
    out: *mut *mut FlapwingWings,
) -> FlapwingStatus {
    const F: &str = "flapwing_wings_clone";
    // SAFETY: `wings` is NULL or live (this function's contract).
    let make = || unsafe { handle(F, wings) }.map(FlapwingWings::clone);
    // SAFETY: `out` is NULL or valid for a write (this function's contract).
    unsafe { create(F, out, make) }
}

/// Number of wings.
///
/// # Safety
/// `wings` is NULL or a live handle; `out` is NULL or valid for a write.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_count(
    wings: *const FlapwingWings,
    out: *mut usize,
) -> FlapwingStatus {
    const F: &str = "flapwing_wings_count";
    guard(F, || {
        // SAFETY: forwarded from this function's contract.
        let w = unsafe { handle(F, wings) }?;
        // SAFETY: forwarded from this function's contract.
        unsafe { put(F, out, w.set.len()) }
    })
}

/// The fixed time step, s.
///
/// # Safety
/// `wings` is NULL or a live handle; `out` is NULL or valid for a write.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_dt_s(
    wings: *const FlapwingWings,
    out: *mut f64,
) -> FlapwingStatus {
    const F: &str = "flapwing_wings_dt_s";
    guard(F, || {
        // SAFETY: forwarded from this function's contract.
        let w = unsafe { handle(F, wings) }?;
        // SAFETY: forwarded from this function's contract.
        unsafe { put(F, out, w.set.dt_s()) }
    })
}

/// The controls last set (`flapwing_wings_set_controls`, or the model's `[controls]` for a
/// new handle): those waiting for the next wingbeat, else those in force. A host that sets
/// some fields reads these first and changes only its own.
///
/// # Safety
/// `wings` is NULL or a live handle; `out` is NULL or valid for a write.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_controls(
    wings: *const FlapwingWings,
    out: *mut FlapwingControls,
) -> FlapwingStatus {
    const F: &str = "flapwing_wings_controls";
    guard(F, || {
        // SAFETY: forwarded from this function's contract.
        let w = unsafe { handle(F, wings) }?;
        // SAFETY: forwarded from this function's contract.
        unsafe { put(F, out, FlapwingControls::from(&w.set.requested_controls())) }
    })
}

/// Time of the next step's start, t_k = k dt, s (0 before the first step).
///
/// # Safety
/// `wings` is NULL or a live handle; `out` is NULL or valid for a write.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_time_s(
    wings: *const FlapwingWings,
    out: *mut f64,
) -> FlapwingStatus {
    const F: &str = "flapwing_wings_time_s";
    guard(F, || {
        // SAFETY: forwarded from this function's contract.
        let w = unsafe { handle(F, wings) }?;
        // SAFETY: forwarded from this function's contract.
        unsafe { put(F, out, w.set.time_s()) }
    })
}

/// The wingbeat frequency now (the model's, with the controls' offset in force), Hz.
///
/// # Safety
/// `wings` is NULL or a live handle; `out` is NULL or valid for a write.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_freq_hz(
    wings: *const FlapwingWings,
    out: *mut f64,
) -> FlapwingStatus {
    const F: &str = "flapwing_wings_freq_hz";
    guard(F, || {
        // SAFETY: forwarded from this function's contract.
        let w = unsafe { handle(F, wings) }?;
        // SAFETY: forwarded from this function's contract.
        unsafe { put(F, out, w.set.freq_hz()) }
    })
}

/// The wingbeat phase at the next step's start, cycles (0 before the first step).
///
/// # Safety
/// `wings` is NULL or a live handle; `out` is NULL or valid for a write.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_phase(
    wings: *const FlapwingWings,
    out: *mut f64,
) -> FlapwingStatus {
    const F: &str = "flapwing_wings_phase";
    guard(F, || {
        // SAFETY: forwarded from this function's contract.
        let w = unsafe { handle(F, wings) }?;
        // SAFETY: forwarded from this function's contract.
        unsafe { put(F, out, w.set.phase()) }
    })
}

/// The model's body: mass, inertia, gravity, initial pose.
///
/// # Safety
/// `wings` is NULL or a live handle; `out` is NULL or valid for a write.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_body_properties(
    wings: *const FlapwingWings,
    out: *mut FlapwingBodyProperties,
) -> FlapwingStatus {
    const F: &str = "flapwing_wings_body_properties";
    guard(F, || {
        // SAFETY: forwarded from this function's contract.
        let w = unsafe { handle(F, wings) }?;
        // SAFETY: forwarded from this function's contract.
        unsafe { put(F, out, w.body) }
    })
}

/// One step from the body's state at t_k: writes the total wrench over [t_k, t_k + dt]
/// (aerodynamic, the wings' inertial reaction and the body's parasite drag,
/// `flapwing_wings_body_drag`; about the CoM, body frame) and advances the wings. A body
/// state with a non-finite value or a quaternion off unit norm is FLAPWING_INVALID_ARGUMENT
/// naming the field and changes nothing; so is a finite state or wind whose loads overflow
/// (a speed through the air far beyond flight: the message names the velocities and says
/// what is allowed). On error `*total_out` is set to zeros.
///
/// # Safety
/// `wings` is NULL or a live handle; `body` is NULL or valid for a read; `total_out` is NULL
/// or valid for a write.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_step(
    wings: *mut FlapwingWings,
    body: *const FlapwingBodyState,
    total_out: *mut FlapwingWrench,
) -> FlapwingStatus {
    const F: &str = "flapwing_wings_step";
    guard(F, || {
        // SAFETY: forwarded from this function's contract.
        let w = unsafe { handle_mut(F, wings) }?;
        need(F, "total_out", total_out)?;
        // SAFETY: NULL or valid for a read (this function's contract).
        let body = unsafe { body.as_ref() }.ok_or_else(|| Failure::null(F, "body"));
        let r = body.and_then(|b| {
            let state = b
                .to_state()
                .map_err(|m| Failure::invalid(format!("{F}: {m}")))?;
            let mut total = w
                .set
                .step(&state)
                .map(|o| FlapwingWrench::from(&o.total))
                .map_err(|e| match e.is_load_overflow() {
                    // The host's state or wind, not a run of ours: a bad argument.
                    true => Failure::invalid(format!("{F}: wing set: {}", e.reason())),
                    false => Failure::sim(F, e),
                })?;
            if let Some(i) = &w.gyroscopic_host {
                let g = w.set.gyroscopic_correction_nm(i);
                for (m, g) in total.moment_body_nm.iter_mut().zip(g.iter()) {
                    *m += g;
                }
            }
            Ok(total)
        });
        // SAFETY: non-null (checked) and valid for a write (this function's contract).
        unsafe { total_out.write(r.as_ref().copied().unwrap_or_default()) };
        r.map(|_| ())
    })
}

/// After a step: one aerodynamic term's wrench, all wings (`term` a FLAPWING_TERM_* index).
/// Zeros before the first step.
///
/// # Safety
/// `wings` is NULL or a live handle; `out` is NULL or valid for a write.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_term(
    wings: *const FlapwingWings,
    term: u32,
    out: *mut FlapwingWrench,
) -> FlapwingStatus {
    const F: &str = "flapwing_wings_term";
    guard(F, || {
        // SAFETY: forwarded from this function's contract.
        let w = unsafe { handle(F, wings) }?;
        need(F, "out", out)?;
        let terms = &w.output().terms;
        let load = terms.get(term as usize).ok_or_else(|| {
            Failure::invalid(format!(
                "{F}: term = {term}; allowed: 0..{} (FLAPWING_TERM_TRANSLATIONAL, _ROTATIONAL, _ADDED_MASS, _WAKE_CAPTURE)",
                terms.len()
            ))
        })?;
        // SAFETY: forwarded from this function's contract.
        unsafe { put(F, out, FlapwingWrench::from(load)) }
    })
}

/// After a step: the inertial reaction of the wings (and actuators) on the body. Zeros before
/// the first step and for massless prescribed wings.
///
/// # Safety
/// `wings` is NULL or a live handle; `out` is NULL or valid for a write.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_inertia(
    wings: *const FlapwingWings,
    out: *mut FlapwingWrench,
) -> FlapwingStatus {
    const F: &str = "flapwing_wings_inertia";
    guard(F, || {
        // SAFETY: forwarded from this function's contract.
        let w = unsafe { handle(F, wings) }?;
        // SAFETY: forwarded from this function's contract.
        unsafe { put(F, out, FlapwingWrench::from(&w.output().wing_inertia)) }
    })
}

/// After a step: wing `index`'s angles and rates at t_k, its aerodynamic force and (actuated
/// wings) hinge moment. Zeros before the first step.
///
/// # Safety
/// `wings` is NULL or a live handle; `out` is NULL or valid for a write.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_wing(
    wings: *const FlapwingWings,
    index: usize,
    out: *mut FlapwingWingState,
) -> FlapwingStatus {
    const F: &str = "flapwing_wings_wing";
    guard(F, || {
        // SAFETY: forwarded from this function's contract.
        let w = unsafe { handle(F, wings) }?;
        need(F, "out", out)?;
        let o = w.output();
        let n = w.set.len();
        let f = o.wings.get(index).filter(|_| index < n).ok_or_else(|| {
            Failure::invalid(format!(
                "{F}: wing index {index}; allowed: 0..{n} (flapwing_wings_count)"
            ))
        })?;
        let a = &f.angles;
        let state = FlapwingWingState {
            stroke_rad: a.phi,
            pitch_rad: a.theta,
            deviation_rad: a.eta,
            stroke_rate_rad_s: a.phi_dot,
            pitch_rate_rad_s: a.theta_dot,
            deviation_rate_rad_s: a.eta_dot,
            force_body_n: f.total.force_n.into(),
            hinge_moment_nm: o.actuated.get(index).map_or(0.0, |s| s.hinge_moment_nm),
        };
        // SAFETY: forwarded from this function's contract.
        unsafe { put(F, out, state) }
    })
}

/// Sets the controls (absolute offsets on the model's own, SI), in force from the start of
/// the next wingbeat (immediately before the first step). Checked now: a non-finite value, an
/// offset of the other kind (kinematic offsets on actuated wings, drive offsets on
/// prescribed ones) or one the model does not allow is FLAPWING_INVALID_ARGUMENT naming it,
/// and the controls in force stay.
///
/// # Safety
/// `wings` is NULL or a live handle; `controls` is NULL or valid for a read.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_set_controls(
    wings: *mut FlapwingWings,
    controls: *const FlapwingControls,
) -> FlapwingStatus {
    const F: &str = "flapwing_wings_set_controls";
    guard(F, || {
        // SAFETY: forwarded from this function's contract.
        let w = unsafe { handle_mut(F, wings) }?;
        // SAFETY: NULL or valid for a read (this function's contract).
        let c = unsafe { controls.as_ref() }.ok_or_else(|| Failure::null(F, "controls"))?;
        if let Some(field) = c.first_non_finite() {
            return Err(Failure::invalid(format!(
                "{F}: controls.{field} is not finite; allowed: finite numbers"
            )));
        }
        let c = Controls::from(c);
        // Checked on a copy of the model now, rather than failing the step that applies them.
        if let Some(v) = w.set.vehicle().filter(|v| v.controls != c) {
            let mut v = v.clone();
            v.apply_controls(&c).map_err(|e| Failure::sim(F, e))?;
        }
        w.set.set_controls(c).map_err(|e| Failure::sim(F, e))
    })
}

/// Sets a uniform wind, world frame, m/s (in force from the next step).
///
/// # Safety
/// `wings` is NULL or a live handle; `wind_world_m_s` is NULL or valid for a read of 3
/// doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_set_wind(
    wings: *mut FlapwingWings,
    wind_world_m_s: *const f64,
) -> FlapwingStatus {
    const F: &str = "flapwing_wings_set_wind";
    guard(F, || {
        // SAFETY: forwarded from this function's contract.
        let w = unsafe { handle_mut(F, wings) }?;
        need(F, "wind_world_m_s", wind_world_m_s)?;
        // SAFETY: non-null and valid for a read of 3 doubles (this function's contract).
        let v = unsafe { wind_world_m_s.cast::<[f64; 3]>().read() };
        if let Some(i) = v.iter().position(|x| !x.is_finite()) {
            return Err(Failure::invalid(format!(
                "{F}: wind_world_m_s[{i}] = {}; allowed: finite numbers",
                v[i]
            )));
        }
        w.set.set_wind(Vector3::from(v));
        Ok(())
    })
}

/// Forgets the body states earlier steps were given: call it after moving the body other
/// than by integrating the returned loads (a reset, a disturbance set by hand). A model with
/// a second-order `[sim] load_sampling` ("step_mean", the default for prescribed wings, or
/// "midpoint") predicts the body's state at each step's midpoint from
/// the last two states; after this the next step takes the state it is given.
///
/// # Safety
/// `wings` is NULL or a live handle.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_restart_motion(
    wings: *mut FlapwingWings,
) -> FlapwingStatus {
    const F: &str = "flapwing_wings_restart_motion";
    guard(F, || {
        // SAFETY: forwarded from this function's contract.
        let w = unsafe { handle_mut(F, wings) }?;
        w.set.restart_motion();
        Ok(())
    })
}

/// The message of the last call on this thread that failed, "" after a call that succeeded
/// (every function but this one and flapwing_version sets it). Valid until the next call on
/// this thread; never NULL.
#[unsafe(no_mangle)]
pub extern "C" fn flapwing_last_error() -> *const c_char {
    error::last_error_ptr()
}

const VERSION: &CStr =
    match CStr::from_bytes_with_nul(concat!(env!("CARGO_PKG_VERSION"), "\0").as_bytes()) {
        Ok(v) => v,
        Err(_) => panic!("the package version holds a NUL byte"),
    };

/// The library version, e.g. "0.1.0" (static; never NULL).
#[unsafe(no_mangle)]
pub extern "C" fn flapwing_version() -> *const c_char {
    VERSION.as_ptr()
}
