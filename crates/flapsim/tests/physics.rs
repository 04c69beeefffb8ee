//! Physics invariants of the vehicle simulation.
//!
//! - Free fall: rapier integrates a free body with symplectic Euler per substep (h = dt/N:
//!   v += a h, then x += v h), so after n steps (t = n dt) the exact discrete solution is
//!   v = v0 + a t and x = x0 + v0 t + a t (t + h) / 2 (the step-start sampling, rapier's
//!   pose). With the midpoint sampling the simulation moves the pose to the trapezoidal rule,
//!   exact for a constant acceleration: x = x0 + v0 t + a t^2 / 2. With the wings still the
//!   simulation must match each to 1e-9 relative.
//! - One model, two paths: the tethered vehicle's cycle-mean load equals the sum of
//!   wingforce's cycle means of the two wings (same phases, same kinematics) with the
//!   step-start sampling, and wingforce's fine cycle mean to the midpoint sampling's
//!   quadrature with it.
//! - Odd step counts: at 25 steps per wingbeat a reversal falls on a step's midpoint and the
//!   two half strokes see different grids; the step-mean sampling's tethered cycle-mean
//!   pitching moment still equals the fine cycle mean (zero to round-off for the fly's
//!   symmetric half strokes) to a small fraction of what the midpoint sampling made of it
//!   (issue 37; wingforce's `wing::step_mean`).
//! - Symmetry: mirror-image wings give zero mean side force, roll and yaw moment.
//! - Damping: a climbing body feels a restoring (downward) force change and a pitching body
//!   a moment opposing the pitch rate (flapping counter-force and counter-torque; Cheng et al.
//!   2010, Hedrick et al. 2009).

use flapsim::averaged::{FrozenState, mean_loads};
use flapsim::{Mode, Simulation, Vehicle};
use nalgebra::{UnitQuaternion, Vector3};
use wingforce::BodyMotion;
use wingforce::cycle::cycle_mean;

fn drosophila() -> Vehicle {
    Vehicle::from_toml(flapsim::DROSOPHILA_TOML, "models/drosophila.toml").unwrap()
}

/// The vehicle at its initial attitude, not moving.
fn hovering_still(v: &Vehicle) -> FrozenState {
    FrozenState {
        world_from_body: v.initial_attitude,
        velocity_body_m_s: Vector3::zeros(),
        angular_velocity_body_rad_s: Vector3::zeros(),
    }
}

#[test]
fn free_fall_matches_the_discrete_analytic_solution() {
    for sampling in flapsim::LoadSampling::ALL {
        for iterations in [1usize, 4] {
            let mut v = drosophila();
            v.sim.load_sampling = Some(sampling);
            v.sim.solver_iterations = iterations;
            v.initial_velocity_m_s = Vector3::new(0.01, -0.02, 0.3);
            v.initial_angular_velocity_rad_s = Vector3::zeros();
            let x0 = v.initial_position_m;
            let v0 = v.initial_velocity_m_s;
            let mut sim = Simulation::new(v, Mode::Free);
            sim.set_wings_still(true);
            let n = 2000u64;
            for _ in 0..n {
                sim.step().unwrap();
            }
            let dt = sim.dt_s();
            let h = match sampling {
                flapsim::LoadSampling::StepStart => dt / iterations as f64,
                flapsim::LoadSampling::Midpoint | flapsim::LoadSampling::StepMean => 0.0,
            };
            let t = n as f64 * dt;
            let a = Vector3::new(0.0, 0.0, -9.81);
            let x = x0 + v0 * t + 0.5 * a * t * (t + h);
            let vel = v0 + a * t;
            let s = sim.state();
            assert!(
                (s.position_m - x).norm() <= 1e-9 * x.norm(),
                "{sampling:?}, {iterations}: {} vs {x}",
                s.position_m
            );
            assert!((s.velocity_m_s - vel).norm() <= 1e-9 * vel.norm());
        }
    }
}

#[test]
fn tethered_mean_equals_wingforce_cycle_mean() {
    for sampling in flapsim::LoadSampling::ALL {
        let mut v = drosophila();
        v.sim.load_sampling = Some(sampling);
        v.sim.steps_per_wingbeat = 100;
        let steps = v.sim.steps_per_wingbeat;
        // Step-start: the same N phases; midpoint: the step means, against a fine cycle mean
        // (20,000 phases), to 1e-6 (measured: 3e-7 at 100 steps per wingbeat).
        let (phases, tol) = match sampling {
            flapsim::LoadSampling::StepStart => (steps, 1e-9),
            flapsim::LoadSampling::Midpoint | flapsim::LoadSampling::StepMean => (20_000, 1e-6),
        };
        let expected: Vector3<f64> = v
            .wings
            .iter()
            .map(|w| {
                cycle_mean(w, &BodyMotion::default(), 0.0, phases)
                    .total
                    .force_n
            })
            .sum();
        let mut sim = Simulation::new(v, Mode::Tethered);
        let mut mean = Vector3::zeros();
        for _ in 0..steps {
            mean += sim.step().unwrap().total.force_n / steps as f64;
        }
        assert!(
            (mean - expected).norm() < tol * expected.norm(),
            "{sampling:?}: {mean} vs {expected}"
        );
        // The body did not move.
        assert_eq!(sim.state().velocity_m_s, Vector3::zeros());
    }
}

/// The tethered fly's cycle-mean pitching moment about the centre of mass at `steps` steps
/// per wingbeat under `sampling`, and wingforce's fine cycle mean (20,000 phases), N m.
fn tethered_pitching_moment(steps: usize, sampling: flapsim::LoadSampling) -> (f64, f64) {
    let mut v = drosophila();
    v.sim.load_sampling = Some(sampling);
    v.sim.steps_per_wingbeat = steps;
    let fine: f64 = v
        .wings
        .iter()
        .map(|w| {
            let m = cycle_mean(w, &BodyMotion::default(), 0.0, 20_000);
            m.total.moment_about_com_nm(&w.mount().hinge_in_body_m).y
        })
        .sum();
    let mut sim = Simulation::new(v, Mode::Tethered);
    let mut mean = 0.0;
    for _ in 0..steps {
        mean += sim.step().unwrap().total.moment_nm.y / steps as f64;
    }
    (mean, fine)
}

#[test]
fn an_odd_step_count_does_not_alias_the_mean_pitching_moment() {
    let (midpoint, fine) = tethered_pitching_moment(25, flapsim::LoadSampling::Midpoint);
    let (step_mean, _) = tethered_pitching_moment(25, flapsim::LoadSampling::StepMean);
    // Measured: fine -2.5e-23 N m, midpoint 4.81e-12, step mean 1.28e-13 (the fly's weight
    // times its length is 2.5e-8 N m). Bound: 5e-13 N m, a tenth of the midpoint's.
    assert!(fine.abs() < 1e-20, "fine cycle mean {fine:e} N m");
    assert!(
        (step_mean - fine).abs() < 5e-13,
        "step mean {step_mean:e} N m against {fine:e}"
    );
    assert!(
        (midpoint - fine).abs() > 10.0 * (step_mean - fine).abs(),
        "midpoint {midpoint:e} N m: the aliasing this guards against is gone; revisit the bound"
    );
}

#[test]
fn symmetric_wings_give_no_mean_side_force_roll_or_yaw() {
    let v = drosophila();
    let m = mean_loads(&v, &hovering_still(&v), 200).unwrap();
    let lift = m.total.force_n.norm();
    let arm = v.length_m;
    assert!(m.total.force_n.y.abs() < 1e-12 * lift);
    assert!(m.total.moment_nm.x.abs() < 1e-12 * lift * arm);
    assert!(m.total.moment_nm.z.abs() < 1e-12 * lift * arm);
}

#[test]
fn climbing_and_pitching_are_damped() {
    let v = drosophila();
    let q = v.initial_attitude;
    let at = |vel_world: Vector3<f64>, rate: Vector3<f64>| {
        mean_loads(
            &v,
            &FrozenState {
                world_from_body: q,
                velocity_body_m_s: q.inverse() * vel_world,
                angular_velocity_body_rad_s: rate,
            },
            200,
        )
        .unwrap()
    };
    let rest = at(Vector3::zeros(), Vector3::zeros());
    let climb = at(Vector3::new(0.0, 0.0, 0.2), Vector3::zeros());
    let fz = |m: &flapsim::averaged::MeanLoads| (q * m.total.force_n).z;
    assert!(
        fz(&climb) < fz(&rest),
        "climbing at 0.2 m/s: {} vs {}",
        fz(&climb),
        fz(&rest)
    );
    let pitch = at(Vector3::zeros(), Vector3::new(0.0, 20.0, 0.0));
    let dm = pitch.total.moment_nm.y - rest.total.moment_nm.y;
    assert!(dm < 0.0, "pitch rate +20 rad/s changed M_y by {dm}");
}

#[test]
fn drosophila_lifts_its_weight_within_25_percent() {
    // The flapsim issue: with literature hover kinematics (Fry et al. 2005: 218 Hz, 140 deg)
    // the mean lift is within 25% of the weight.
    let v = drosophila();
    let m = mean_loads(&v, &hovering_still(&v), 400).unwrap();
    let ratio = m.force_world_n(&v.initial_attitude).z / v.weight_n();
    println!("drosophila mean lift / weight = {ratio:.4}");
    assert!((ratio - 1.0).abs() < 0.25, "lift/weight {ratio}");
}

#[test]
fn runs_are_bit_identical() {
    let run = || {
        let mut sim = Simulation::new(drosophila(), Mode::Free);
        let mut trace = Vec::new();
        for _ in 0..300 {
            let o = sim.step().unwrap();
            trace.push((o.state.position_m, o.state.world_from_body, o.total.force_n));
        }
        trace
    };
    assert!(run() == run());
}

#[test]
fn divergence_stops_with_time_and_reason() {
    let mut v = drosophila();
    v.sim.max_angular_speed_rad_s = 100.0;
    v.initial_angular_velocity_rad_s = Vector3::new(0.0, 0.0, 0.0);
    let mut sim = Simulation::new(v, Mode::Free);
    let mut s = sim.state();
    s.angular_velocity_body_rad_s = Vector3::new(200.0, 0.0, 0.0);
    sim.set_state(&s);
    let mut seen = 0;
    let err = sim.run_for(0.1, |_| seen += 1).unwrap_err();
    let msg = err.to_string();
    assert!(
        msg.contains("diverged at t = 0.000000 s") && msg.contains("angular speed"),
        "{msg}"
    );
    assert_eq!(seen, 0);
}

#[test]
fn controls_change_at_wingbeat_boundaries() {
    let v = drosophila();
    let steps = v.sim.steps_per_wingbeat;
    let mut sim = Simulation::new(v, Mode::Tethered);
    for _ in 0..10 {
        sim.step().unwrap();
    }
    let c = flapsim::Controls {
        amplitude_rad: 0.1,
        ..Default::default()
    };
    sim.set_controls(c);
    for _ in 10..steps {
        let o = sim.step().unwrap();
        assert_eq!(
            o.controls.amplitude_rad, 0.0,
            "changed mid-wingbeat at step {}",
            o.step
        );
    }
    let o = sim.step().unwrap();
    assert_eq!(o.controls.amplitude_rad, 0.1);
    let _ = UnitQuaternion::<f64>::identity();
}

#[test]
fn wing_inertia_has_zero_cycle_mean_force() {
    // The wing's centre of mass moves periodically, so its acceleration averages to zero over
    // a wingbeat ((v(T) - v(0)) / T = 0): the inertial reaction has zero mean force but a
    // large peak.
    let mut v = drosophila();
    v.sim.wing_mass_kg = 2.4e-9; // about 0.24% of the body mass per wing (Ellington 1984: Diptera wings 0.1-0.5%)
    let steps = v.sim.steps_per_wingbeat;
    let mut sim = Simulation::new(v, Mode::Tethered);
    let (mut mean, mut peak) = (Vector3::zeros(), 0.0f64);
    for _ in 0..steps {
        let o = sim.step().unwrap();
        mean += o.wing_inertia.force_n / steps as f64;
        peak = peak.max(o.wing_inertia.force_n.norm());
    }
    assert!(peak > 0.0);
    assert!(mean.norm() < 1e-6 * peak, "mean {mean} vs peak {peak}");
}

#[test]
fn ground_plane_catches_a_falling_body() {
    // Wings still, ground on: the body falls from 5 mm and comes to rest on its contact sphere
    // (radius half the body length) instead of falling through z = 0.
    let mut v = drosophila();
    v.sim.ground = true;
    v.sim.solver_iterations = 4;
    v.initial_position_m = Vector3::new(0.0, 0.0, 5e-3);
    v.initial_angular_velocity_rad_s = Vector3::zeros();
    let radius = 0.5 * v.length_m;
    let mut sim = Simulation::new(v, Mode::Free);
    sim.set_wings_still(true);
    sim.run_for(0.3, |_| {}).unwrap();
    let s = sim.state();
    assert!(
        (s.position_m.z - radius).abs() < 0.1 * radius,
        "resting at z = {}",
        s.position_m.z
    );
    assert!(
        s.velocity_m_s.norm() < 1e-2,
        "still moving at {}",
        s.velocity_m_s
    );
}

#[test]
fn a_zero_eigenvalue_is_a_neutral_mode_without_a_doubling_time() {
    // Heading in hover: nothing restores the yaw angle, while the yaw rate is damped, so
    // A = [[0, 1], [0, -2]] (yaw angle, yaw rate) has eigenvalues 0 and -2 exactly. The zero
    // one is neutral: no time to double or to half, and the report says what it is.
    let a = nalgebra::DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 0.0, -2.0]);
    let m = flapsim::stability::modes(&a, &["yaw_err_rad", "r_rad_s"]);
    assert_eq!(m.len(), 2);
    let neutral = m.iter().find(|m| m.re_per_s.abs() < 1e-12).unwrap();
    assert_eq!(neutral.time_to_half_or_double_s, None);
    assert!(!neutral.stable);
    assert!(
        neutral.description.contains("heading"),
        "{}",
        neutral.description
    );
    let damped = m.iter().find(|m| m.re_per_s < -1.0).unwrap();
    let t = damped.time_to_half_or_double_s.unwrap();
    assert!((t - std::f64::consts::LN_2 / 2.0).abs() < 1e-12, "{t}");
}
