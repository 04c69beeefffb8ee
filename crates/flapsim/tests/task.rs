//! flapsim::task on every built-in vehicle: each has a `[sensors]` table, so each that
//! hovers runs in both tasks (the RoboBee has no hover, and the task says so); and the first observation of an episode is a delivered sensor reading of the
//! initial state (the sensors' pre-roll), which shows a recovery task's disturbance.

use flapsim::task::{Task, TaskSpec, preroll_s};
use flapsim::{Vehicle, builtin_model};

const BUILTIN_VEHICLES: [&str; 6] = [
    "drosophila",
    "bumblebee",
    "robobee_kinematic",
    "robobee",
    "hummingbird",
    "dragonfly",
];

fn text(name: &str) -> &'static str {
    builtin_model(name).unwrap()
}

#[test]
fn every_builtin_vehicle_has_sensors_and_runs_in_every_task() {
    for name in BUILTIN_VEHICLES {
        let v = Vehicle::from_toml(text(name), name).unwrap();
        let p = v.sensors.unwrap_or_else(|| panic!("{name}: no [sensors]"));
        assert!(p.mocap.is_some(), "{name}: no [sensors.mocap]");
        for (kind, spec) in [
            ("hover", TaskSpec::hover()),
            ("recover", TaskSpec::recover()),
        ] {
            let t = Task::new(text(name), name, spec, None);
            if name == "robobee" {
                // Rebuilt from its published parameter set (issue #24), the RoboBee lifts
                // 0.95 W at its 100 V limit: no hover to start a task from, and it says so.
                let e = t.err().map(|e| e.to_string()).unwrap_or_default();
                assert!(e.contains("no hover trim"), "{name} {kind}: {e}");
                continue;
            }
            let mut t = t.unwrap_or_else(|e| panic!("{name} {kind}: {e}"));
            assert_eq!(t.observation_len(), 12);
            let o = t.reset(3).unwrap();
            assert_eq!(o.len(), 12);
            assert!(o.iter().all(|x| x.is_finite()), "{name} {kind}: {o:?}");
            // Delivered readings at reset: the IMU's noise and motion capture's noise at
            // least (every built-in model has non-zero noise on both).
            assert!(o[..6].iter().any(|x| *x != 0.0), "{name} {kind}: IMU {o:?}");
            assert!(
                o[6..].iter().any(|x| *x != 0.0),
                "{name} {kind}: mocap {o:?}"
            );
            for _ in 0..3 {
                let s = t.step(&[0.0; 4]).unwrap();
                assert!(s.observation.iter().all(|x| x.is_finite()));
                assert!(s.reward.is_finite());
                if s.terminated || s.truncated {
                    break;
                }
            }
        }
    }
}

#[test]
fn the_preroll_is_the_longest_sensor_latency() {
    let v = Vehicle::from_toml(text("drosophila"), "drosophila").unwrap();
    let p = v.sensors.unwrap();
    // models/drosophila.toml: IMU 5 ms, motion capture 6.5 ms.
    assert_eq!(preroll_s(&p), 6.5e-3);
    let v = Vehicle::from_toml(text("hummingbird"), "hummingbird").unwrap();
    assert_eq!(preroll_s(&v.sensors.unwrap()), 0.030);
}

/// Pearson correlation.
fn corr(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let cov: f64 = a.iter().zip(b).map(|(x, y)| (x - ma) * (y - mb)).sum();
    let va: f64 = a.iter().map(|x| (x - ma).powi(2)).sum();
    let vb: f64 = b.iter().map(|y| (y - mb).powi(2)).sum();
    cov / (va * vb).sqrt()
}

#[test]
fn the_first_recover_observation_shows_the_disturbance() {
    let mut t = Task::new(text("drosophila"), "drosophila", TaskSpec::recover(), None).unwrap();
    let (mut obs_att, mut true_att) = ([Vec::new(), Vec::new()], [Vec::new(), Vec::new()]);
    let (mut obs_acc, mut true_tilt) = (Vec::new(), Vec::new());
    for seed in 0..60 {
        let o = t.reset(seed).unwrap();
        assert_eq!(t.simulation().time_s(), 0.0);
        let s = t.simulation().state();
        let e = (t.trim().attitude().inverse() * s.world_from_body).scaled_axis();
        for k in 0..2 {
            obs_att[k].push(o[9 + k]);
            true_att[k].push(e[k]);
        }
        obs_acc.push((o[3] * o[3] + o[4] * o[4] + o[5] * o[5]).sqrt());
        true_tilt.push(9.81 * (e[0] * e[0] + e[1] * e[1]).sqrt());
    }
    // Motion capture: the disturbance (uniform +-10 deg, std 5.8 deg) plus 3.4 deg of noise.
    for k in 0..2 {
        let c = corr(&obs_att[k], &true_att[k]);
        assert!(c > 0.7, "attitude axis {k}: correlation {c}");
    }
    // The held accelerometer reads gravity in the tilted frame: g times the tilt, against a
    // 25 mg turn-on bias and 3 mg of noise.
    let c = corr(&obs_acc, &true_tilt);
    assert!(c > 0.7, "specific force: correlation {c}");
}

/// `observe = estimate`: the agent sees the error-state Kalman filter's state (position
/// error, velocity, attitude error, rate) instead of the raw readings. The filter starts
/// from the trim pose at rest (prior 10 degrees, 1 body length) and fuses 200 Hz motion
/// capture with 3.4 degrees of attitude noise per frame (models/drosophila.toml) and the
/// 1 kHz IMU. Over recovery episodes of zero actions (20 wingbeats, 18 frames each, from
/// disturbances of up to 10 degrees, the uncontrolled fly tumbling on) the observed
/// attitude error follows the true one: its rms error is below half the rms of the true
/// attitude error (an observation of the trim, or of nothing, would give 1; measured 2.7
/// degrees against 11.1: the filter's state is its newest IMU sample's, 5 ms behind the
/// truth it is compared with, plus the filter's 2 degree rms at 1 kHz, tests/estimator.rs);
/// the position error is observed within half a body length (measured 0.26).
#[test]
fn an_estimate_observing_task_sees_the_filter_state() {
    use flapsim::task::Observation;
    let spec = TaskSpec {
        observe: Observation::Estimate,
        ..TaskSpec::recover()
    };
    let mut t = Task::new(text("drosophila"), "drosophila", spec, None).unwrap();
    let q_trim = t.trim().attitude();
    let l = t.vehicle().length_m;
    let (mut err2, mut truth2, mut n, mut worst_p) = (0.0, 0.0, 0.0, 0.0f64);
    for seed in 1u64..=6 {
        let o = t.reset(seed).unwrap();
        assert_eq!(o.len(), 12);
        for _ in 0..20 {
            let st = t.step(&[0.0; 4]).unwrap();
            let s = t.simulation().state();
            let truth = (q_trim.inverse() * s.world_from_body).scaled_axis();
            let o = &st.observation;
            let seen = nalgebra::Vector3::new(o[6], o[7], o[8]);
            err2 += (seen - truth).norm_squared();
            truth2 += truth.norm_squared();
            n += 1.0;
            let p = nalgebra::Vector3::new(o[0], o[1], o[2]);
            let p_true = s.position_m - t.vehicle().initial_position_m;
            worst_p = worst_p.max((p - p_true).norm() / l);
            if st.terminated || st.truncated {
                break;
            }
        }
    }
    let (rms_err, rms_truth) = (
        (err2 / n).sqrt().to_degrees(),
        (truth2 / n).sqrt().to_degrees(),
    );
    eprintln!(
        "observed attitude error: rms error {rms_err:.2} deg against a true rms {rms_truth:.2} deg; worst position error {worst_p:.3} body lengths"
    );
    assert!(
        rms_err < 0.5 * rms_truth,
        "{rms_err} deg against {rms_truth} deg"
    );
    assert!(worst_p < 0.5, "{worst_p} body lengths");
    // Without motion capture the filter cannot see position: refused, naming the table.
    let fly = text("drosophila");
    let (head, tail) = fly.split_at(fly.find("[sensors.mocap]").unwrap());
    let no_mocap = format!("{head}{}", &tail[tail.find("[sim]").unwrap()..]);
    let e = Task::new(&no_mocap, "fly_no_mocap.toml", spec, None);
    let e = e.err().map(|e| e.to_string()).unwrap_or_default();
    assert!(
        e.contains("fly_no_mocap.toml") && e.contains("[sensors.mocap]"),
        "{e}"
    );
}

/// An actuated vehicle's wings start every episode on their periodic motion at the trim,
/// which depends on the vehicle and its trim only: the task settles them once and reuses them
/// (the hummingbird's take 40 drive periods per reset otherwise). An episode after others,
/// from the wings settled for the first, must then be the episode a fresh task flies from the
/// same seed, bit for bit (it fails if the settled wings depended on an episode's disturbance
/// or were changed by a flight).
#[test]
fn an_actuated_episode_after_others_is_a_fresh_tasks_episode() {
    let name = "hummingbird";
    let episode = |t: &mut Task, seed: u64| {
        let mut out = t.reset(seed).unwrap();
        for k in 0..4 {
            let s = t.step(&[0.1 * k as f64, -0.05, 0.0, 0.02]).unwrap();
            out.extend(s.observation);
            out.push(s.reward);
        }
        out.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
    };
    let mut used = Task::new(text(name), name, TaskSpec::recover(), None).unwrap();
    episode(&mut used, 3);
    episode(&mut used, 4);
    let mut fresh = Task::new(text(name), name, TaskSpec::recover(), None).unwrap();
    assert_eq!(episode(&mut used, 5), episode(&mut fresh, 5));
}
