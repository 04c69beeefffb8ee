//! Bad input through the C ABI (the exported functions, called as C would): each gives its
//! code and a message naming what was wrong, changes nothing, and never crashes.

use std::ffi::{CStr, CString, c_char};
use std::ptr;

use flapwing::FlapwingStatus::{self, *};
use flapwing::*;

fn last_error() -> String {
    // SAFETY: flapwing_last_error never returns NULL; the string lives until the next call.
    unsafe { CStr::from_ptr(flapwing_last_error()) }
        .to_string_lossy()
        .into_owned()
}

fn cstr(s: &str) -> CString {
    CString::new(s).unwrap()
}

/// Checks the code and that the message holds each of `parts`.
fn expect(status: FlapwingStatus, code: FlapwingStatus, parts: &[&str]) {
    let message = last_error();
    assert_eq!(status, code, "{message}");
    for p in parts {
        assert!(message.contains(p), "{message:?} lacks {p:?}");
    }
}

struct Handle(*mut FlapwingWings);

impl Drop for Handle {
    fn drop(&mut self) {
        // SAFETY: a handle from flapwing_wings_from_*, freed once.
        unsafe { flapwing_wings_free(self.0) };
    }
}

fn builtin(name: &str, dt_s: f64) -> Handle {
    let mut out = ptr::null_mut();
    // SAFETY: NUL-terminated name, valid out pointer.
    let s = unsafe { flapwing_wings_from_builtin(cstr(name).as_ptr(), dt_s, &mut out) };
    assert_eq!(s, FLAPWING_OK, "{}", last_error());
    Handle(out)
}

fn from_toml(text: &str, origin: &str) -> (FlapwingStatus, *mut FlapwingWings) {
    let mut out = ptr::dangling_mut::<FlapwingWings>();
    // SAFETY: NUL-terminated strings, valid out pointer.
    let s = unsafe {
        flapwing_wings_from_toml(cstr(text).as_ptr(), cstr(origin).as_ptr(), 0.0, &mut out)
    };
    (s, out)
}

fn at_rest() -> FlapwingBodyState {
    FlapwingBodyState {
        world_from_body_wxyz: [1.0, 0.0, 0.0, 0.0],
        ..Default::default()
    }
}

fn step(h: &Handle, body: &FlapwingBodyState) -> (FlapwingStatus, FlapwingWrench) {
    let mut w = FlapwingWrench {
        force_body_n: [7.0; 3],
        moment_body_nm: [7.0; 3],
    };
    // SAFETY: live handle, valid pointers.
    let s = unsafe { flapwing_wings_step(h.0, body, &mut w) };
    (s, w)
}

fn time_s(h: &Handle) -> f64 {
    let mut t = f64::NAN;
    // SAFETY: live handle, valid pointer.
    assert_eq!(unsafe { flapwing_wings_time_s(h.0, &mut t) }, FLAPWING_OK);
    t
}

#[test]
fn a_bad_model_field_names_the_file_field_and_value() {
    let text = flapsim::DROSOPHILA_TOML.replace("mass_kg = 1.0e-6", "mass_kg = -1.0e-6");
    assert_ne!(text, flapsim::DROSOPHILA_TOML);
    let (s, out) = from_toml(&text, "my_fly.toml");
    expect(
        s,
        FLAPWING_MODEL_ERROR,
        &["my_fly.toml", "body.mass_kg", "-0.000001"],
    );
    assert!(out.is_null(), "*out is NULL on error");

    // The same through a file: the message names the path.
    let path = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("bad_fly.toml");
    std::fs::write(&path, &text).unwrap();
    let mut out = ptr::null_mut();
    let c_path = cstr(path.to_str().unwrap());
    // SAFETY: NUL-terminated path, valid out pointer.
    let s = unsafe { flapwing_wings_from_file(c_path.as_ptr(), 0.0, &mut out) };
    expect(
        s,
        FLAPWING_MODEL_ERROR,
        &[path.to_str().unwrap(), "body.mass_kg"],
    );
    assert!(out.is_null());
}

#[test]
fn a_toml_syntax_error_and_an_unknown_field_are_model_errors() {
    let (s, out) = from_toml("[body\nmass_kg = 1", "broken.toml");
    expect(s, FLAPWING_MODEL_ERROR, &["broken.toml"]);
    assert!(out.is_null());
    let text = flapsim::DROSOPHILA_TOML.replace("[body]", "[body]\nmass_gk = 2.0");
    let (s, _) = from_toml(&text, "typo.toml");
    expect(s, FLAPWING_MODEL_ERROR, &["typo.toml", "mass_gk"]);
}

#[test]
fn a_missing_file_is_an_io_error_naming_the_path() {
    let mut out = ptr::dangling_mut::<FlapwingWings>();
    let path = cstr("/nonexistent/dir/fly.toml");
    // SAFETY: NUL-terminated path, valid out pointer.
    let s = unsafe { flapwing_wings_from_file(path.as_ptr(), 0.0, &mut out) };
    expect(
        s,
        FLAPWING_IO_ERROR,
        &["/nonexistent/dir/fly.toml", "No such file"],
    );
    assert!(out.is_null());
}

#[test]
fn a_model_file_gives_the_builtin_s_wings() {
    let path = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("good_fly.toml");
    std::fs::write(&path, flapsim::DROSOPHILA_TOML).unwrap();
    let mut out = ptr::null_mut();
    let c_path = cstr(path.to_str().unwrap());
    // SAFETY: NUL-terminated path, valid out pointer.
    let s = unsafe { flapwing_wings_from_file(c_path.as_ptr(), 0.0, &mut out) };
    assert_eq!(s, FLAPWING_OK, "{}", last_error());
    let file = Handle(out);
    let fly = builtin("drosophila", 0.0);
    for _ in 0..5 {
        assert_eq!(step(&file, &at_rest()), step(&fly, &at_rest()));
    }
}

#[test]
fn an_unknown_builtin_and_non_utf8_text_are_refused() {
    let mut out = ptr::dangling_mut::<FlapwingWings>();
    // SAFETY: NUL-terminated name, valid out pointer.
    let s = unsafe { flapwing_wings_from_builtin(cstr("housefly").as_ptr(), 0.0, &mut out) };
    expect(
        s,
        FLAPWING_MODEL_ERROR,
        &["\"housefly\"", "drosophila", "hummingbird"],
    );
    assert!(out.is_null());
    let bad = [0x66u8, 0xff, 0x00];
    // SAFETY: NUL-terminated bytes, valid out pointer.
    let s = unsafe { flapwing_wings_from_builtin(bad.as_ptr().cast::<c_char>(), 0.0, &mut out) };
    expect(s, FLAPWING_INVALID_ARGUMENT, &["`name` is not UTF-8"]);
}

#[test]
fn a_step_that_is_negative_nan_or_infinite_is_refused() {
    for dt in [-1e-5, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let mut out = ptr::dangling_mut::<FlapwingWings>();
        // SAFETY: NUL-terminated name, valid out pointer.
        let s = unsafe { flapwing_wings_from_builtin(cstr("drosophila").as_ptr(), dt, &mut out) };
        expect(
            s,
            FLAPWING_INVALID_ARGUMENT,
            &["dt_s = ", "allowed: a finite step > 0 s"],
        );
        assert!(out.is_null());
    }
    // 0 is the model's own step; a positive one is the host's.
    let own = builtin("drosophila", 0.0);
    let host = builtin("drosophila", 1e-5);
    let (mut a, mut b) = (0.0, 0.0);
    // SAFETY: live handles, valid pointers.
    unsafe {
        assert_eq!(flapwing_wings_dt_s(own.0, &mut a), FLAPWING_OK);
        assert_eq!(flapwing_wings_dt_s(host.0, &mut b), FLAPWING_OK);
    }
    assert_eq!(a, 1.0 / (218.0 * 20.0), "1 / (f sim.steps_per_wingbeat)");
    assert_eq!(b, 1e-5);
}

#[test]
fn a_step_longer_than_a_tenth_of_the_wingbeat_is_refused() {
    // The fly flaps at 218 Hz: 1 / (10 f) is the longest step; one wingbeat, 1 s (218
    // wingbeats) and 1e300 s are refused with the bound.
    let longest = 1.0 / (10.0 * 218.0);
    drop(builtin("drosophila", longest));
    for dt in [1.01 * longest, 1.0 / 218.0, 1.0, 1e300] {
        let mut out = ptr::dangling_mut::<FlapwingWings>();
        // SAFETY: NUL-terminated name, valid out pointer.
        let s = unsafe { flapwing_wings_from_builtin(cstr("drosophila").as_ptr(), dt, &mut out) };
        expect(
            s,
            FLAPWING_INVALID_ARGUMENT,
            &[
                &format!("dt_s = {dt:?}"),
                "at most 1/10 of the wingbeat period",
            ],
        );
        assert!(out.is_null());
    }
}

#[test]
fn a_finite_state_or_wind_whose_loads_overflow_is_refused_and_changes_nothing() {
    let h = builtin("drosophila", 0.0);
    let fresh = builtin("drosophila", 0.0);
    let mut body = at_rest();
    body.velocity_world_m_s[0] = 1e300;
    let (s, w) = step(&h, &body);
    expect(
        s,
        FLAPWING_INVALID_ARGUMENT,
        &[
            "flapwing_wings_step",
            "the loads overflow",
            "1e300",
            "allowed",
        ],
    );
    assert_eq!(
        w,
        FlapwingWrench::default(),
        "the wrench is zeroed on error"
    );
    let mut body = at_rest();
    body.angular_velocity_body_rad_s[2] = -1e300;
    expect(
        step(&h, &body).0,
        FLAPWING_INVALID_ARGUMENT,
        &["angular velocity", "-1e300"],
    );
    let wind = [0.0, 0.0, 1e300];
    // SAFETY: a live handle and 3 doubles.
    assert_eq!(
        unsafe { flapwing_wings_set_wind(h.0, wind.as_ptr()) },
        FLAPWING_OK
    );
    expect(
        step(&h, &at_rest()).0,
        FLAPWING_INVALID_ARGUMENT,
        &["wind", "1e300"],
    );
    assert_eq!(
        time_s(&h),
        0.0,
        "a refused state does not advance the wings"
    );
    // SAFETY: a live handle and 3 doubles.
    assert_eq!(
        unsafe { flapwing_wings_set_wind(h.0, [0.0; 3].as_ptr()) },
        FLAPWING_OK
    );
    for _ in 0..3 {
        assert_eq!(step(&h, &at_rest()), step(&fresh, &at_rest()));
    }
}

#[test]
fn a_non_finite_body_state_names_the_field_and_changes_nothing() {
    let h = builtin("drosophila", 0.0);
    let fresh = builtin("drosophila", 0.0);
    type Setter = fn(&mut FlapwingBodyState);
    let setters: [(&str, Setter); 4] = [
        ("position_m[2]", |b| b.position_m[2] = f64::NAN),
        ("world_from_body_wxyz[0]", |b| {
            b.world_from_body_wxyz[0] = f64::INFINITY
        }),
        ("velocity_world_m_s[0]", |b| {
            b.velocity_world_m_s[0] = f64::NAN
        }),
        ("angular_velocity_body_rad_s[1]", |b| {
            b.angular_velocity_body_rad_s[1] = f64::NEG_INFINITY
        }),
    ];
    for (field, set) in setters {
        let mut body = at_rest();
        set(&mut body);
        let (s, w) = step(&h, &body);
        expect(
            s,
            FLAPWING_INVALID_ARGUMENT,
            &["flapwing_wings_step", field, "finite"],
        );
        assert_eq!(
            w,
            FlapwingWrench::default(),
            "the wrench is zeroed on error"
        );
        assert_eq!(
            time_s(&h),
            0.0,
            "a refused state does not advance the wings"
        );
    }
    let mut body = at_rest();
    body.world_from_body_wxyz = [2.0, 0.0, 0.0, 0.0];
    expect(
        step(&h, &body).0,
        FLAPWING_INVALID_ARGUMENT,
        &["world_from_body_wxyz", "norm 2", "unit quaternion"],
    );
    // The refused steps left no trace.
    for _ in 0..3 {
        assert_eq!(step(&h, &at_rest()), step(&fresh, &at_rest()));
    }
}

#[test]
fn indices_out_of_range_are_refused_and_readings_before_a_step_are_zero() {
    let h = builtin("drosophila", 0.0);
    let mut w = FlapwingWrench {
        force_body_n: [1.0; 3],
        moment_body_nm: [1.0; 3],
    };
    let mut ws = FlapwingWingState {
        stroke_rad: 1.0,
        ..Default::default()
    };
    // SAFETY: live handle, valid pointers.
    unsafe {
        assert_eq!(
            flapwing_wings_term(h.0, FLAPWING_TERM_ADDED_MASS, &mut w),
            FLAPWING_OK
        );
        assert_eq!(w, FlapwingWrench::default());
        assert_eq!(flapwing_wings_wing(h.0, 1, &mut ws), FLAPWING_OK);
        assert_eq!(ws, FlapwingWingState::default());
        expect(
            flapwing_wings_wing(h.0, 2, &mut ws),
            FLAPWING_INVALID_ARGUMENT,
            &["wing index 2", "0..2"],
        );
        expect(
            flapwing_wings_wing(h.0, usize::MAX, &mut ws),
            FLAPWING_INVALID_ARGUMENT,
            &["wing index"],
        );
        expect(
            flapwing_wings_term(h.0, 4, &mut w),
            FLAPWING_INVALID_ARGUMENT,
            &["term = 4"],
        );
    }
    assert_eq!(step(&h, &at_rest()).0, FLAPWING_OK);
    // SAFETY: live handle, valid pointers.
    unsafe {
        assert_eq!(flapwing_wings_wing(h.0, 0, &mut ws), FLAPWING_OK);
    }
    assert_ne!(ws.stroke_rad, 0.0, "a step fills the wing state");
    assert!(time_s(&h) > 0.0);
}

#[test]
fn every_function_reports_a_null_handle_and_null_out_pointers() {
    let null: *mut FlapwingWings = ptr::null_mut();
    let (mut n, mut x) = (0usize, 0.0f64);
    let mut b = FlapwingBodyProperties::default();
    let mut w = FlapwingWrench::default();
    let mut ws = FlapwingWingState::default();
    let c = FlapwingControls::default();
    let body = at_rest();
    let wind = [0.0; 3];
    // SAFETY: NULL handles are reported before anything is read or written.
    unsafe {
        let calls = [
            ("flapwing_wings_count", flapwing_wings_count(null, &mut n)),
            ("flapwing_wings_dt_s", flapwing_wings_dt_s(null, &mut x)),
            ("flapwing_wings_time_s", flapwing_wings_time_s(null, &mut x)),
            (
                "flapwing_wings_body_properties",
                flapwing_wings_body_properties(null, &mut b),
            ),
            (
                "flapwing_wings_step",
                flapwing_wings_step(null, &body, &mut w),
            ),
            ("flapwing_wings_term", flapwing_wings_term(null, 0, &mut w)),
            (
                "flapwing_wings_inertia",
                flapwing_wings_inertia(null, &mut w),
            ),
            (
                "flapwing_wings_body_drag",
                flapwing_wings_body_drag(null, &mut w),
            ),
            ("flapwing_wings_wing", flapwing_wings_wing(null, 0, &mut ws)),
            (
                "flapwing_wings_set_controls",
                flapwing_wings_set_controls(null, &c),
            ),
            (
                "flapwing_wings_set_wind",
                flapwing_wings_set_wind(null, wind.as_ptr()),
            ),
            (
                "flapwing_wings_restart_motion",
                flapwing_wings_restart_motion(null),
            ),
        ];
        for (name, s) in calls {
            assert_eq!(s, FLAPWING_NULL_POINTER, "{name}");
        }
        expect(
            flapwing_wings_inertia(null, &mut w),
            FLAPWING_NULL_POINTER,
            &["flapwing_wings_inertia", "`wings` is NULL"],
        );
        flapwing_wings_free(null);
    }
    let h = builtin("robobee", 0.0);
    // SAFETY: a live handle; NULL out pointers are reported before any write.
    unsafe {
        expect(
            flapwing_wings_count(h.0, ptr::null_mut()),
            FLAPWING_NULL_POINTER,
            &["`out`"],
        );
        expect(
            flapwing_wings_dt_s(h.0, ptr::null_mut()),
            FLAPWING_NULL_POINTER,
            &["`out`"],
        );
        expect(
            flapwing_wings_time_s(h.0, ptr::null_mut()),
            FLAPWING_NULL_POINTER,
            &["`out`"],
        );
        expect(
            flapwing_wings_body_properties(h.0, ptr::null_mut()),
            FLAPWING_NULL_POINTER,
            &["`out`"],
        );
        expect(
            flapwing_wings_step(h.0, &body, ptr::null_mut()),
            FLAPWING_NULL_POINTER,
            &["`total_out`"],
        );
        expect(
            flapwing_wings_step(h.0, ptr::null(), &mut w),
            FLAPWING_NULL_POINTER,
            &["`body`"],
        );
        expect(
            flapwing_wings_term(h.0, 0, ptr::null_mut()),
            FLAPWING_NULL_POINTER,
            &["`out`"],
        );
        expect(
            flapwing_wings_inertia(h.0, ptr::null_mut()),
            FLAPWING_NULL_POINTER,
            &["`out`"],
        );
        expect(
            flapwing_wings_body_drag(h.0, ptr::null_mut()),
            FLAPWING_NULL_POINTER,
            &["`out`"],
        );
        expect(
            flapwing_wings_wing(h.0, 0, ptr::null_mut()),
            FLAPWING_NULL_POINTER,
            &["`out`"],
        );
        expect(
            flapwing_wings_set_controls(h.0, ptr::null()),
            FLAPWING_NULL_POINTER,
            &["`controls`"],
        );
        expect(
            flapwing_wings_set_wind(h.0, ptr::null()),
            FLAPWING_NULL_POINTER,
            &["`wind_world_m_s`"],
        );
        let mut out = ptr::null_mut();
        expect(
            flapwing_wings_from_toml(ptr::null(), ptr::null(), 0.0, &mut out),
            FLAPWING_NULL_POINTER,
            &["`text`"],
        );
        expect(
            flapwing_wings_from_file(ptr::null(), 0.0, &mut out),
            FLAPWING_NULL_POINTER,
            &["`path`"],
        );
        // A NULL origin is allowed: the text is named "<TOML text>".
        let text = cstr("[body]\n");
        expect(
            flapwing_wings_from_toml(text.as_ptr(), ptr::null(), 0.0, &mut out),
            FLAPWING_MODEL_ERROR,
            &["<TOML text>"],
        );
    }
    // After all that, the handle still works and the message is cleared by a success.
    assert_eq!(step(&h, &at_rest()).0, FLAPWING_OK);
    assert_eq!(last_error(), "");
}

#[test]
fn bad_controls_and_wind_are_refused_and_the_controls_in_force_stay() {
    let h = builtin("robobee", 0.0);
    let fresh = builtin("robobee", 0.0);
    let c = FlapwingControls {
        bias_v: f64::NAN,
        ..Default::default()
    };
    // SAFETY: live handles, valid pointers.
    unsafe {
        expect(
            flapwing_wings_set_controls(h.0, &c),
            FLAPWING_INVALID_ARGUMENT,
            &["controls.bias_v", "finite"],
        );
        let kinematic = FlapwingControls {
            amplitude_rad: 0.1,
            ..Default::default()
        };
        expect(
            flapwing_wings_set_controls(h.0, &kinematic),
            FLAPWING_INVALID_ARGUMENT,
            &["actuated", "bias_v"],
        );
        let over = FlapwingControls {
            amplitude_v: 1e6,
            ..Default::default()
        };
        expect(
            flapwing_wings_set_controls(h.0, &over),
            FLAPWING_INVALID_ARGUMENT,
            &["flapwing_wings_set_controls"],
        );
        expect(
            flapwing_wings_set_wind(h.0, [0.0, f64::NAN, 0.0].as_ptr()),
            FLAPWING_INVALID_ARGUMENT,
            &["wind_world_m_s[1] = NaN"],
        );
    }
    for _ in 0..20 {
        assert_eq!(step(&h, &at_rest()), step(&fresh, &at_rest()));
    }
    let fly = builtin("drosophila", 0.0);
    let drive = FlapwingControls {
        amplitude_v: 1.0,
        ..Default::default()
    };
    // SAFETY: live handle, valid pointer.
    let s = unsafe { flapwing_wings_set_controls(fly.0, &drive) };
    expect(s, FLAPWING_INVALID_ARGUMENT, &["prescribed kinematics"]);
}

#[test]
fn the_last_error_is_per_thread_and_handles_work_on_their_own_threads() {
    let mut out = ptr::null_mut();
    // SAFETY: NUL-terminated name, valid out pointer.
    let s = unsafe { flapwing_wings_from_builtin(cstr("nope").as_ptr(), 0.0, &mut out) };
    assert_eq!(s, FLAPWING_MODEL_ERROR);
    let results: Vec<(String, FlapwingWrench)> = (0..2)
        .map(|_| {
            std::thread::spawn(|| {
                let before = last_error();
                let h = builtin("drosophila", 0.0);
                let mut w = FlapwingWrench::default();
                for _ in 0..10 {
                    w = step(&h, &at_rest()).1;
                }
                (before, w)
            })
        })
        .collect::<Vec<_>>()
        .into_iter()
        .map(|t| t.join().unwrap())
        .collect();
    assert_eq!(results[0].0, "", "another thread's error is not seen here");
    assert_eq!(results[0].1, results[1].1);
    assert!(last_error().contains("nope"), "this thread's error stays");
}

#[test]
fn version_and_body_properties() {
    // SAFETY: a static NUL-terminated string.
    let v = unsafe { CStr::from_ptr(flapwing_version()) };
    assert_eq!(v.to_str().unwrap(), env!("CARGO_PKG_VERSION"));
    let h = builtin("drosophila", 0.0);
    let mut b = FlapwingBodyProperties::default();
    // SAFETY: live handle, valid pointer.
    assert_eq!(
        unsafe { flapwing_wings_body_properties(h.0, &mut b) },
        FLAPWING_OK
    );
    assert_eq!(b.mass_kg, 1.0e-6);
    assert_eq!(b.gravity_m_s2, 9.81);
    assert_eq!(
        [
            b.inertia_body_kg_m2[0],
            b.inertia_body_kg_m2[4],
            b.inertia_body_kg_m2[8]
        ],
        [8.1e-14, 3.53e-13, 3.53e-13]
    );
    let q = b.initial_world_from_body_wxyz;
    assert!((q.iter().map(|x| x * x).sum::<f64>() - 1.0).abs() < 1e-15);
}
