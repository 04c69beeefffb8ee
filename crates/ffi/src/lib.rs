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

mod error;

use std::ffi::{CStr, c_char};

use flapsim::{Controls, State, Vehicle, WingSet, WingSetOutput};
use nalgebra::{Quaternion, UnitQuaternion, Vector3};

pub use error::FlapwingStatus;
use error::{Failure, guard};

/// Term index: the translational (quasi-steady circulatory) force.
pub const FLAPWING_TERM_TRANSLATIONAL: u32 = 0;
/// Term index: the rotational circulation.
pub const FLAPWING_TERM_ROTATIONAL: u32 = 1;
/// Term index: the added mass.
pub const FLAPWING_TERM_ADDED_MASS: u32 = 2;
/// Term index: the wake capture.
pub const FLAPWING_TERM_WAKE_CAPTURE: u32 = 3;

/// Largest deviation of the body quaternion's norm from 1 that a step accepts (the
/// quaternion is then normalised).
pub const FLAPWING_QUATERNION_NORM_TOLERANCE: f64 = 1e-6;

/// One wing set (opaque): the wings of a vehicle model, their state, and the model's body.
#[derive(Debug)]
pub struct FlapwingWings {
    set: WingSet,
    body: FlapwingBodyProperties,
}

/// The body's state at t_k, from the host.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FlapwingBodyState {
    /// Position of the centre of mass, world, m.
    pub position_m: [f64; 3],
    /// Attitude, world_from_body, unit quaternion w, x, y, z.
    pub world_from_body_wxyz: [f64; 4],
    /// Velocity of the centre of mass, world, m/s.
    pub velocity_world_m_s: [f64; 3],
    /// Angular velocity, body frame, rad/s.
    pub angular_velocity_body_rad_s: [f64; 3],
}

/// Force and moment on the body.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FlapwingWrench {
    /// Force, body frame, N.
    pub force_body_n: [f64; 3],
    /// Moment about the centre of mass, body frame, N m.
    pub moment_body_nm: [f64; 3],
}

/// The model's body, for hosts that build it.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FlapwingBodyProperties {
    /// Mass, kg.
    pub mass_kg: f64,
    /// Inertia tensor about the centre of mass, body frame, row-major, kg m^2.
    pub inertia_body_kg_m2: [f64; 9],
    /// Gravitational acceleration, m/s^2 (along world -z).
    pub gravity_m_s2: f64,
    /// Initial position of the centre of mass, world, m.
    pub initial_position_m: [f64; 3],
    /// Initial attitude, world_from_body, w, x, y, z.
    pub initial_world_from_body_wxyz: [f64; 4],
}

/// Control inputs (flapsim::Controls), SI (rad, Hz, V): offsets on the model's kinematics
/// (prescribed wings) or on its drive (actuated wings).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FlapwingControls {
    /// Mean stroke angle offset, rad.
    pub mean_stroke_rad: f64,
    /// Stroke amplitude offset, rad.
    pub amplitude_rad: f64,
    /// Pitch bias offset, rad.
    pub pitch_bias_rad: f64,
    /// Mid-stroke angle-of-attack offset, rad.
    pub aoa_rad: f64,
    /// Wingbeat frequency offset, Hz.
    pub freq_hz: f64,
    /// Left-minus-right amplitude, rad.
    pub diff_amplitude_rad: f64,
    /// Left-minus-right pitch bias, rad.
    pub diff_pitch_bias_rad: f64,
    /// Left-minus-right mean stroke angle, rad.
    pub diff_mean_stroke_rad: f64,
    /// Drive bias offset, V (actuated wings).
    pub bias_v: f64,
    /// Drive amplitude offset, V (actuated wings).
    pub amplitude_v: f64,
    /// Left-minus-right drive amplitude, V (actuated wings).
    pub diff_amplitude_v: f64,
    /// Left-minus-right drive bias, V (actuated wings).
    pub diff_bias_v: f64,
    /// Left-minus-right second-harmonic fraction (actuated wings).
    pub diff_second_harmonic: f64,
}

/// One wing after the last step.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FlapwingWingState {
    /// Stroke angle phi, rad (wingforce WingAngles).
    pub stroke_rad: f64,
    /// Pitch angle theta, rad.
    pub pitch_rad: f64,
    /// Deviation angle eta, rad.
    pub deviation_rad: f64,
    /// d phi / dt, rad/s.
    pub stroke_rate_rad_s: f64,
    /// d theta / dt, rad/s.
    pub pitch_rate_rad_s: f64,
    /// d eta / dt, rad/s.
    pub deviation_rate_rad_s: f64,
    /// This wing's total aerodynamic force, body frame, N.
    pub force_body_n: [f64; 3],
    /// Hinge spring, damper and stop moment about the pitch axis, N m (actuated wings; 0
    /// otherwise).
    pub hinge_moment_nm: f64,
}

impl From<&FlapwingControls> for Controls {
    fn from(c: &FlapwingControls) -> Self {
        Controls {
            mean_stroke_rad: c.mean_stroke_rad,
            amplitude_rad: c.amplitude_rad,
            pitch_bias_rad: c.pitch_bias_rad,
            aoa_rad: c.aoa_rad,
            freq_hz: c.freq_hz,
            diff_amplitude_rad: c.diff_amplitude_rad,
            diff_pitch_bias_rad: c.diff_pitch_bias_rad,
            diff_mean_stroke_rad: c.diff_mean_stroke_rad,
            bias_v: c.bias_v,
            amplitude_v: c.amplitude_v,
            diff_amplitude_v: c.diff_amplitude_v,
            diff_bias_v: c.diff_bias_v,
            diff_second_harmonic: c.diff_second_harmonic,
        }
    }
}

impl FlapwingControls {
    /// The name of the first field that is not finite, if any.
    fn first_non_finite(&self) -> Option<&'static str> {
        let fields = [
            ("mean_stroke_rad", self.mean_stroke_rad),
            ("amplitude_rad", self.amplitude_rad),
            ("pitch_bias_rad", self.pitch_bias_rad),
            ("aoa_rad", self.aoa_rad),
            ("freq_hz", self.freq_hz),
            ("diff_amplitude_rad", self.diff_amplitude_rad),
            ("diff_pitch_bias_rad", self.diff_pitch_bias_rad),
            ("diff_mean_stroke_rad", self.diff_mean_stroke_rad),
            ("bias_v", self.bias_v),
            ("amplitude_v", self.amplitude_v),
            ("diff_amplitude_v", self.diff_amplitude_v),
            ("diff_bias_v", self.diff_bias_v),
            ("diff_second_harmonic", self.diff_second_harmonic),
        ];
        fields
            .into_iter()
            .find(|(_, x)| !x.is_finite())
            .map(|(name, _)| name)
    }
}

impl FlapwingBodyState {
    /// The body state as flapsim's [`State`], or a message naming the first field that is not
    /// finite or a quaternion that is not of unit norm (within
    /// [`FLAPWING_QUATERNION_NORM_TOLERANCE`]; it is normalised).
    pub fn to_state(&self) -> Result<State, String> {
        let fields: [(&str, &[f64]); 4] = [
            ("position_m", &self.position_m),
            ("world_from_body_wxyz", &self.world_from_body_wxyz),
            ("velocity_world_m_s", &self.velocity_world_m_s),
            (
                "angular_velocity_body_rad_s",
                &self.angular_velocity_body_rad_s,
            ),
        ];
        for (name, v) in fields {
            if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                return Err(format!(
                    "body state: {name}[{i}] = {}; allowed: finite numbers",
                    v[i]
                ));
            }
        }
        let [w, x, y, z] = self.world_from_body_wxyz;
        let q = Quaternion::new(w, x, y, z);
        let norm = q.norm();
        if !((norm - 1.0).abs() <= FLAPWING_QUATERNION_NORM_TOLERANCE) {
            return Err(format!(
                "body state: world_from_body_wxyz = [{w}, {x}, {y}, {z}] has norm {norm}; allowed: a unit quaternion (norm within {FLAPWING_QUATERNION_NORM_TOLERANCE:e} of 1)"
            ));
        }
        Ok(State {
            position_m: Vector3::from(self.position_m),
            world_from_body: UnitQuaternion::from_quaternion(q),
            velocity_m_s: Vector3::from(self.velocity_world_m_s),
            angular_velocity_body_rad_s: Vector3::from(self.angular_velocity_body_rad_s),
        })
    }
}

impl From<&flapsim::BodyLoad> for FlapwingWrench {
    fn from(l: &flapsim::BodyLoad) -> Self {
        Self {
            force_body_n: l.force_n.into(),
            moment_body_nm: l.moment_nm.into(),
        }
    }
}

fn wxyz(q: &UnitQuaternion<f64>) -> [f64; 4] {
    [q.w, q.i, q.j, q.k]
}

fn body_properties(v: &Vehicle) -> FlapwingBodyProperties {
    let i = &v.inertia_kg_m2;
    let mut inertia = [0.0; 9];
    for r in 0..3 {
        for c in 0..3 {
            inertia[3 * r + c] = i[(r, c)];
        }
    }
    FlapwingBodyProperties {
        mass_kg: v.mass_kg,
        inertia_body_kg_m2: inertia,
        gravity_m_s2: v.gravity_m_s2,
        initial_position_m: v.initial_position_m.into(),
        initial_world_from_body_wxyz: wxyz(&v.initial_attitude),
    }
}

impl FlapwingWings {
    /// A handle from TOML text: `dt_s > 0` is the host's step, `dt_s == 0` the model's own.
    fn from_toml(function: &str, text: &str, origin: &str, dt_s: f64) -> Result<Self, Failure> {
        if !(dt_s >= 0.0 && dt_s.is_finite()) {
            return Err(Failure::invalid(format!(
                "{function}: dt_s = {dt_s}; allowed: a finite step > 0 s, or 0 for the model's own step (1 / (f sim.steps_per_wingbeat))"
            )));
        }
        let vehicle = Vehicle::from_toml(text, origin).map_err(|e| Failure::sim(function, e))?;
        let set = if dt_s == 0.0 {
            WingSet::from_vehicle_sized(&vehicle)
        } else {
            WingSet::from_vehicle(&vehicle, dt_s)
        }
        .map_err(|e| Failure::sim(function, e))?;
        Ok(Self {
            body: body_properties(&vehicle),
            set,
        })
    }

    /// The wing set (for Rust callers and tests).
    pub fn wing_set(&self) -> &WingSet {
        &self.set
    }

    fn output(&self) -> &WingSetOutput {
        self.set.output()
    }
}

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
/// robobee, hummingbird. `dt_s > 0` is the host's fixed step; `dt_s == 0` takes the model's
/// own (1 / (f sim.steps_per_wingbeat)). On error `*out` is set to NULL.
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
                    "{F}: no built-in model named {name:?}; allowed: drosophila, bumblebee, robobee_kinematic, robobee, hummingbird (or a TOML file: flapwing_wings_from_file)"
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

/// A handle argument as a reference.
///
/// # Safety
/// `p` is NULL or a live handle, not used mutably elsewhere for `'a`.
unsafe fn handle<'a>(
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
unsafe fn handle_mut<'a>(
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
unsafe fn put<T>(function: &str, out: *mut T, value: T) -> Result<(), Failure> {
    if out.is_null() {
        return Err(Failure::null(function, "out"));
    }
    // SAFETY: non-null and valid for a write (the caller's contract).
    unsafe { out.write(value) };
    Ok(())
}

/// Checks an out pointer before any work is done.
fn need<T>(function: &str, argument: &str, out: *const T) -> Result<(), Failure> {
    if out.is_null() {
        Err(Failure::null(function, argument))
    } else {
        Ok(())
    }
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
/// (aerodynamic and the wings' inertial reaction, about the CoM, body frame) and advances the
/// wings. A body state with a non-finite value or a quaternion off unit norm is
/// FLAPWING_INVALID_ARGUMENT naming the field and changes nothing. On error `*total_out` is
/// set to zeros.
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
            w.set
                .step(&state)
                .map(|o| FlapwingWrench::from(&o.total))
                .map_err(|e| Failure::sim(F, e))
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
        if let Some(v) = w.set.vehicle() {
            if v.controls != c {
                let mut v = v.clone();
                v.apply_controls(&c).map_err(|e| Failure::sim(F, e))?;
            }
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
