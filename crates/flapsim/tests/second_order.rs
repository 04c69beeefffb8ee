//! Second-order stepping (issue 37, `wingset::sampling`).
//!
//! A one-step method of order p has a global error C h^p + O(h^(p+1)) at a fixed time, so
//! halving the step divides the error by 2^p: 4 for a second-order method, 2 for a
//! first-order one (e.g. Hairer, Norsett & Wanner, Solving Ordinary Differential Equations I,
//! 2nd ed., section II.4, Richardson extrapolation). These tests fly a vehicle in free flight
//! from its model's initial state at N, 2N and 4N steps per wingbeat, measure the error of its
//! state at a fixed time against a run at 64N (the reference's own error is then 1/4096 of
//! N's), and check that the error ratios between N and 2N are above 3.5 with the loads taken
//! as the step's means (`load_sampling = "step_mean"`, the default for the prescribed wings),
//! and near 2 with them taken at the step's start (`"step_start"`, the scheme before issue
//! 37), a check that the measure can tell the two apart.
//!
//! Prescribed wings: the fly (its open-loop pitch-up, the main job's unstable mode, over 10
//! wingbeats; the step mean from 400 steps per wingbeat, measured 3.74 and 3.88: from 200
//! they are 3.46 and 3.75, from 100 3.08 and 3.47, the second-order error's own
//! higher-order part still cancelling some of it (the midpoint sampling's were 3.62 and 3.81
//! from 200); the first-order scheme from 200, 2.02 and 2.06). Actuated wings: the RoboBee over
//! three drive periods (below).

/// The wake that answers (issue #38).
#[path = "responsive_wake/mod.rs"]
mod responsive_wake;
/// The hover's setup under the step mean.
#[path = "trim_setup/mod.rs"]
mod trim_setup;

use flapsim::wings::FromVehicle;
use flapsim::{Controls, Mode, Simulation, State, Vehicle};
use wingset::WingSet;

/// A built-in vehicle as its model file has it (for this binary's modules too).
fn builtin(name: &str) -> Vehicle {
    Vehicle::from_toml(flapsim::builtin_model(name).unwrap(), name).unwrap()
}

/// The vehicle with `steps` per wingbeat and the loads taken at `sampling`.
fn vehicle(toml: &str, steps: usize, sampling: &str) -> Vehicle {
    let mut spec = flapsim::VehicleSpec::from_toml(toml, "model").unwrap();
    spec.sim.steps_per_wingbeat = steps;
    spec.sim.load_sampling = wingset::LoadSampling::from_name(sampling);
    spec.build("model").unwrap()
}

/// Control offsets away from the fly's build (`flapwing hover`'s trim and its LQR move the
/// same channels by a few degrees): the steps under the step mean take the held correction
/// (wingset's `held_correction` module).
fn moved() -> Controls {
    Controls {
        amplitude_rad: 5f64.to_radians(),
        mean_stroke_rad: 2f64.to_radians(),
        ..Controls::default()
    }
}

/// The state after `wingbeats` wingbeats of free flight, with `controls` set before the
/// first step.
fn fly_with(
    toml: &str,
    steps: usize,
    sampling: &str,
    wingbeats: usize,
    controls: Option<Controls>,
) -> State {
    let mut sim = Simulation::new(vehicle(toml, steps, sampling), Mode::Free);
    if let Some(c) = controls {
        sim.set_controls(c);
    }
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
    ratios_with(toml, n, sampling, wingbeats, None)
}

/// [`ratios`] with `controls` set before the first step.
fn ratios_with(
    toml: &str,
    n: usize,
    sampling: &str,
    wingbeats: usize,
    controls: Option<Controls>,
) -> [f64; 2] {
    let r = fly_with(toml, 64 * n, sampling, wingbeats, controls);
    let e: Vec<f64> = [n, 2 * n, 4 * n]
        .iter()
        .map(|&k| error(&fly_with(toml, k, sampling, wingbeats, controls), &r))
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

/// The fly with its controls moved from the build's, as a controller moves them: its steps
/// take their sampled loads plus the build's quadrature refinement (wingset's
/// `held_correction`), whose error against the step mean at the moved kinematics is
/// O(dt^2 dk), so the scheme stays second order. Measured here: ratios 3.74 and 3.88 from 400
/// steps per wingbeat.
#[test]
fn held_correction_converges_at_second_order() {
    let toml = flapsim::DROSOPHILA_TOML;
    let asym = Controls {
        diff_amplitude_rad: 1f64.to_radians(),
        ..Controls::default()
    };
    let r = ratios_with(toml, 400, "step_mean", 10, Some(asym));
    eprintln!("ASYM {r:?}");
    let held = ratios_with(toml, 400, "step_mean", 10, Some(moved()));
    assert!(held.iter().all(|r| *r > 3.5), "held ratios {held:?}");
}

/// The fly with a left-right asymmetric control (1 deg of amplitude difference: the body rolls
/// and yaws as it pitches up). A turn about more than one axis was first order while rapier
/// advanced the rates with the world inertia and the gyroscopic term at the step's start
/// (1.83x and 1.97x); since the host hands it the midpoint rule's torque (flapsim's
/// `host::midpoint_torque_world`), measured here 3.99x and 4.00x from 400 steps per wingbeat.
#[test]
fn a_rolling_and_yawing_body_converges_at_second_order() {
    let toml = flapsim::DROSOPHILA_TOML;
    let asym = Controls {
        diff_amplitude_rad: 1f64.to_radians(),
        ..Controls::default()
    };
    let r = ratios_with(toml, 400, "step_mean", 10, Some(asym));
    assert!(r.iter().all(|r| *r > 3.5), "ratios {r:?}");
}

/// The held correction against the step mean in full, at one body state: bit for bit the
/// same at the build's controls (the step mean is taken in full there), and after a control
/// change a difference that is not zero (the held correction is taken) and falls as dt^2
/// (the ratio between N and 2N steps per wingbeat near 4; measured 4.0 at 20 and 40). The
/// body is held at its initial state, so only the kinematic loads differ.
#[test]
fn held_correction_differs_from_the_full_step_mean_by_dt_squared() {
    let toml = flapsim::DROSOPHILA_TOML;
    let gap = |steps: usize, controls: Option<Controls>| -> f64 {
        let v = vehicle(toml, steps, "step_mean");
        let body = Simulation::new(v.clone(), Mode::Free).state();
        let mut sets: Vec<WingSet> = (0..2)
            .map(|_| WingSet::from_vehicle_sized(&v).unwrap())
            .collect();
        sets[1].set_held_correction(false);
        let mut worst = 0f64;
        let mut scale = 0f64;
        for set in &mut sets {
            if let Some(c) = controls {
                set.set_controls(c).unwrap();
            }
        }
        for _ in 0..steps {
            let a = sets[0].step(&body).unwrap().total.force_n;
            let b = sets[1].step(&body).unwrap().total.force_n;
            worst = worst.max((a - b).norm());
            scale = scale.max(b.norm());
        }
        worst / scale
    };
    assert_eq!(gap(20, None), 0.0);
    let g: Vec<f64> = [50, 100, 200].map(|n| gap(n, Some(moved()))).to_vec();
    eprintln!(
        "held - full, largest over a wingbeat over the largest force, at 50, 100, 200: {g:?}"
    );
    assert!(g[0] > 0.0, "{g:?}");
    for w in g.windows(2) {
        assert!((3.5..4.5).contains(&(w[0] / w[1])), "{g:?}");
    }
}

/// The RoboBee over three drive periods, so that its measured stroke reference is taken up
/// twice. Measured here: step-mean errors 2.46e-4, 6.19e-5, 1.53e-5 at 200, 400, 800 steps per
/// wingbeat (ratios 3.97 and 4.05; over ten periods 3.95 and 4.13; over thirty from 100: 1.9
/// and 4.6). Before the step mean split actuated steps at stroke reversals (it was the
/// midpoint's), the error fell 4.7x and 2.6x over one period and not at all over three: the
/// wake capture restarts at a reversal, and a Runge-Kutta step or trapezoid across it is
/// first order; a start-up dither of the rate (2e-6 of its peak) counted as reversals only
/// at the finest steps; and the stroke reference was taken up one step late at some step
/// counts, from the round-off in the accumulated time (wingset's `actuated::dynamics::step`).
#[test]
fn actuated_wings_converge_at_second_order() {
    let toml = flapsim::ROBOBEE_TOML;
    let mean = ratios(toml, 200, "step_mean", 3);
    assert!(mean.iter().all(|r| *r > 3.5), "step_mean ratios {mean:?}");
    let start = ratios(toml, 50, "step_start", 1);
    assert!(
        start.iter().all(|r| (1.6..2.6).contains(r)),
        "step_start ratios {start:?}"
    );
}
