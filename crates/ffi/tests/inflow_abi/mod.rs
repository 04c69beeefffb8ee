//! A wing pair's dynamic inflow through the C ABI (issue #38): a handle built from a model
//! with `[aero] inflow = "dynamic"` steps its pair's states itself, exactly as flapsim's wing
//! set of the same model does (the element, bit for bit), and a host reads and sets them.

use std::ffi::CString;
use std::ptr;

use flapsim::{FromVehicle, Vehicle, WingSet};
use flapwing::{
    FlapwingBodyState, FlapwingInflow, FlapwingStatus, FlapwingWings, FlapwingWrench,
    flapwing_last_error, flapwing_wings_free, flapwing_wings_from_builtin,
    flapwing_wings_from_toml, flapwing_wings_inflow, flapwing_wings_inflow_pairs,
    flapwing_wings_set_inflow, flapwing_wings_step,
};

fn last_error() -> String {
    // SAFETY: the ABI returns a valid NUL-terminated string.
    unsafe { std::ffi::CStr::from_ptr(flapwing_last_error()) }
        .to_string_lossy()
        .into_owned()
}

fn dynamic_fly_toml() -> String {
    let text = flapsim::DROSOPHILA_TOML.replace("inflow = \"frozen\"", "inflow = \"dynamic\"");
    assert!(text.contains("inflow = \"dynamic\""));
    text
}

/// The body at `vehicle`'s initial attitude flying forward (world x) at `speed_m_s`, as the
/// C ABI and flapsim's wing set take it.
fn body_at(vehicle: &Vehicle, speed_m_s: f64) -> (FlapwingBodyState, flapsim::State) {
    let q = vehicle.initial_attitude;
    let body = FlapwingBodyState {
        position_m: [0.0; 3],
        world_from_body_wxyz: [q.w, q.i, q.j, q.k],
        velocity_world_m_s: [speed_m_s, 0.0, 0.0],
        angular_velocity_body_rad_s: [0.0; 3],
    };
    let state = flapsim::State {
        position_m: nalgebra::Vector3::zeros(),
        world_from_body: q,
        velocity_m_s: nalgebra::Vector3::new(speed_m_s, 0.0, 0.0),
        angular_velocity_body_rad_s: nalgebra::Vector3::zeros(),
    };
    (body, state)
}

#[test]
fn the_handle_steps_reads_and_sets_the_pairs_inflow() {
    let text = CString::new(dynamic_fly_toml()).unwrap();
    let mut wings: *mut FlapwingWings = ptr::null_mut();
    // SAFETY: NUL-terminated strings and a valid out pointer.
    let s = unsafe { flapwing_wings_from_toml(text.as_ptr(), c"fly".as_ptr(), 0.0, &mut wings) };
    assert_eq!(s, FlapwingStatus::FLAPWING_OK, "{}", last_error());
    let mut pairs = 9;
    // SAFETY: a live handle and a valid out pointer.
    assert_eq!(
        unsafe { flapwing_wings_inflow_pairs(wings, &mut pairs) },
        FlapwingStatus::FLAPWING_OK
    );
    assert_eq!(pairs, 1);

    let vehicle = Vehicle::from_toml(&dynamic_fly_toml(), "fly").unwrap();
    let mut set = WingSet::from_vehicle_sized(&vehicle).unwrap();
    // The body at the model's initial attitude (its stroke plane level), flying forward at
    // 0.5 m/s.
    let (body, state) = body_at(&vehicle, 0.5);
    for _ in 0..150 {
        let mut w = FlapwingWrench::default();
        // SAFETY: a live handle, a valid state and out pointer.
        let s = unsafe { flapwing_wings_step(wings, &body, &mut w) };
        assert_eq!(s, FlapwingStatus::FLAPWING_OK, "{}", last_error());
        set.step(&state).unwrap();
    }
    let mut got = FlapwingInflow::default();
    // SAFETY: a live handle and a valid out pointer.
    assert_eq!(
        unsafe { flapwing_wings_inflow(wings, 0, &mut got) },
        FlapwingStatus::FLAPWING_OK
    );
    let [w0, fore, left] = set.inflow_states()[0].to_array();
    assert_eq!((got.mean_m_s, got.fore_m_s, got.left_m_s), (w0, fore, left));
    // Forward flight skews the wake back: less downwash at the front (Pitt-Peters).
    assert!(got.fore_m_s < 0.0, "{got:?}");
    assert_eq!(got.left_m_s, 0.0, "a symmetric pair in symmetric flight");

    let new = FlapwingInflow {
        mean_m_s: 0.4,
        fore_m_s: 0.01,
        left_m_s: -0.02,
    };
    // SAFETY: a live handle.
    assert_eq!(
        unsafe { flapwing_wings_set_inflow(wings, 0, new) },
        FlapwingStatus::FLAPWING_OK
    );
    // SAFETY: a live handle and a valid out pointer.
    unsafe { flapwing_wings_inflow(wings, 0, &mut got) };
    assert_eq!(got, new);
    // Bad pair, bad value: invalid arguments, named; nothing changes.
    // SAFETY: a live handle and a valid out pointer.
    let s = unsafe { flapwing_wings_inflow(wings, 1, &mut got) };
    assert_eq!(s, FlapwingStatus::FLAPWING_INVALID_ARGUMENT);
    assert!(last_error().contains("pair 1"), "{}", last_error());
    let nan = FlapwingInflow {
        mean_m_s: f64::NAN,
        ..new
    };
    // SAFETY: a live handle.
    let s = unsafe { flapwing_wings_set_inflow(wings, 0, nan) };
    assert_ne!(s, FlapwingStatus::FLAPWING_OK);
    assert!(last_error().contains("finite"), "{}", last_error());
    // SAFETY: a live handle and a valid out pointer.
    unsafe { flapwing_wings_inflow(wings, 0, &mut got) };
    assert_eq!(got, new);
    // SAFETY: a live handle, freed once.
    unsafe { flapwing_wings_free(wings) };

    // A frozen wake has no pairs to read.
    let mut frozen: *mut FlapwingWings = ptr::null_mut();
    // SAFETY: a NUL-terminated name and a valid out pointer.
    unsafe { flapwing_wings_from_builtin(c"drosophila".as_ptr(), 0.0, &mut frozen) };
    // SAFETY: a live handle and a valid out pointer.
    unsafe { flapwing_wings_inflow_pairs(frozen, &mut pairs) };
    assert_eq!(pairs, 0);
    // SAFETY: a live handle, freed once.
    unsafe { flapwing_wings_free(frozen) };
}

/// The dynamic wake of an actuated vehicle (the RoboBee: its pair's disc the stroke its
/// dynamics sweep) and of a four-winged one (the dragonfly: two pairs, each crossing the
/// other's disc) through the C ABI: one state triple per pair, each stepped exactly as
/// flapsim's wing set of the same model steps it (the element, bit for bit).
#[test]
fn actuated_and_four_winged_handles_carry_every_pairs_inflow() {
    for (name, text, pairs) in [
        ("robobee", flapsim::ROBOBEE_TOML, 1),
        ("dragonfly", flapsim::DRAGONFLY_TOML, 2),
    ] {
        let model = format!("{text}\n[aero]\ninflow = \"dynamic\"\n");
        let c_model = CString::new(model.clone()).unwrap();
        let c_name = CString::new(name).unwrap();
        let mut wings: *mut FlapwingWings = ptr::null_mut();
        // SAFETY: NUL-terminated strings and a valid out pointer.
        let s =
            unsafe { flapwing_wings_from_toml(c_model.as_ptr(), c_name.as_ptr(), 0.0, &mut wings) };
        assert_eq!(s, FlapwingStatus::FLAPWING_OK, "{name}: {}", last_error());
        let mut n = 0;
        // SAFETY: a live handle and a valid out pointer.
        unsafe { flapwing_wings_inflow_pairs(wings, &mut n) };
        assert_eq!(n, pairs, "{name}");
        let vehicle = Vehicle::from_toml(&model, name).unwrap();
        let mut set = WingSet::from_vehicle_sized(&vehicle).unwrap();
        let (body, state) = body_at(&vehicle, 0.0);
        for _ in 0..200 {
            let mut w = FlapwingWrench::default();
            // SAFETY: a live handle, a valid state and out pointer.
            let s = unsafe { flapwing_wings_step(wings, &body, &mut w) };
            assert_eq!(s, FlapwingStatus::FLAPWING_OK, "{name}: {}", last_error());
            set.step(&state).unwrap();
        }
        for (p, expected) in set.inflow_states().iter().enumerate() {
            let mut got = FlapwingInflow::default();
            // SAFETY: a live handle and a valid out pointer.
            let s = unsafe { flapwing_wings_inflow(wings, p, &mut got) };
            assert_eq!(s, FlapwingStatus::FLAPWING_OK);
            let [w0, fore, left] = expected.to_array();
            assert_eq!((got.mean_m_s, got.fore_m_s, got.left_m_s), (w0, fore, left));
            // Each pair pushes air down.
            assert!(got.mean_m_s > 0.0, "{name} pair {p}: {got:?}");
        }
        // SAFETY: a live handle, freed once.
        unsafe { flapwing_wings_free(wings) };
    }
}
