//! The C ABI reproduces flapsim's own host: `Simulation`'s tethered loads, step by step, from
//! the states it reports, to 1e-12 of the run's largest load.

use std::ptr;

use flapsim::{Mode, Simulation, Vehicle};
use flapwing::{
    FlapwingBodyState, FlapwingStatus, FlapwingWings, FlapwingWrench, flapwing_wings_free,
    flapwing_wings_from_builtin, flapwing_wings_step,
};

fn body_state(s: &flapsim::State) -> FlapwingBodyState {
    let q = s.world_from_body;
    FlapwingBodyState {
        position_m: s.position_m.into(),
        world_from_body_wxyz: [q.w, q.i, q.j, q.k],
        velocity_world_m_s: s.velocity_m_s.into(),
        angular_velocity_body_rad_s: s.angular_velocity_body_rad_s.into(),
    }
}

/// Largest difference of force and moment components over `wingbeats`, relative to the
/// run's largest force and moment component.
fn tethered_deviation(name: &str, wingbeats: u64) -> (f64, f64) {
    let text = flapsim::builtin_model(name).unwrap();
    let vehicle = Vehicle::from_toml(text, &format!("<built-in {name}>")).unwrap();
    let steps = wingbeats * vehicle.sim.steps_per_wingbeat as u64;
    let mut sim = Simulation::new(vehicle, Mode::Tethered);
    let c_name = std::ffi::CString::new(name).unwrap();
    let mut wings: *mut FlapwingWings = ptr::null_mut();
    // SAFETY: a NUL-terminated name and a valid out pointer.
    let s = unsafe { flapwing_wings_from_builtin(c_name.as_ptr(), 0.0, &mut wings) };
    assert_eq!(s, FlapwingStatus::FLAPWING_OK);
    let (mut max_df, mut max_dm, mut max_f, mut max_m) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for _ in 0..steps {
        let out = *sim.step().unwrap();
        let body = body_state(&out.state);
        let mut w = FlapwingWrench::default();
        // SAFETY: a live handle, a valid state and a valid out pointer.
        let s = unsafe { flapwing_wings_step(wings, &body, &mut w) };
        assert_eq!(s, FlapwingStatus::FLAPWING_OK);
        for i in 0..3 {
            max_df = max_df.max((w.force_body_n[i] - out.total.force_n[i]).abs());
            max_dm = max_dm.max((w.moment_body_nm[i] - out.total.moment_nm[i]).abs());
            max_f = max_f.max(out.total.force_n[i].abs());
            max_m = max_m.max(out.total.moment_nm[i].abs());
        }
    }
    // SAFETY: the handle from above, freed once.
    unsafe { flapwing_wings_free(wings) };
    assert!(max_f > 0.0 && max_m > 0.0, "{name}: no loads");
    (max_df / max_f, max_dm / max_m)
}

#[test]
fn fly_tethered_loads_match_simulation() {
    let (df, dm) = tethered_deviation("drosophila", 2);
    assert!(df <= 1e-12 && dm <= 1e-12, "force {df:e}, moment {dm:e}");
}

#[test]
fn actuated_robobee_tethered_loads_match_simulation() {
    let (df, dm) = tethered_deviation("robobee", 2);
    assert!(df <= 1e-12 && dm <= 1e-12, "force {df:e}, moment {dm:e}");
}
