//! The state estimator (`flapsim::estimator`, an error-state Kalman filter on the IMU and
//! motion capture) alone and in the hover loop.
//!
//! - `nees_within_chi_square_bounds`: consistency. A filter is consistent when its
//!   covariance P describes its actual errors; the normalised estimation error squared
//!   e' P^-1 e of a consistent filter is chi-square with as many degrees of freedom as e has
//!   (Bar-Shalom, Li & Kirubarajan 2001, "Estimation with Applications to Tracking and
//!   Navigation", section 5.4.2). Here e = (position error, attitude error): 6 degrees of
//!   freedom, taken at the end of a run for each of N = 30 seeds (independent sensor noise,
//!   turn-on biases and prior draws), so N times the mean NEES is chi-square with 6 N = 180
//!   degrees of freedom; its two-sided 95% interval (Wilson-Hilferty 1931, accurate to 0.1%
//!   at 180 degrees of freedom) divided by N bounds the mean: [4.82, 7.30]. The IMU samples
//!   every simulation step there (its datasheet noise densities kept): at the model's 1 kHz
//!   the filter's propagation of point samples of the wingbeat's motion errs by 100 (velocity)
//!   and 1300 (attitude) times the IMU noise its Q carries, and the filter is not consistent
//!   (velocity NEES 40 against 3; measured per block and rate in `tests/estimator_rates.rs`,
//!   explained in the module documentation of `flapsim::estimator`, "What the filter does not
//!   model").
//! - `hover_on_estimate_recovers_from_pitch`: the fruit fly with its model's sensor noise
//!   (IMU sampling every step, latencies zero) flies the LQR on the estimate from a 5 degree
//!   pitch disturbance and recovers by the criterion of `run_hover` (within 1 body length
//!   and 2 degrees of the hover for good) within the 1 s run, as it does on the true state.
//! - `hover_on_estimate_with_model_latencies`: the same with the model's latencies (IMU
//!   5 ms, motion capture 6.5 ms), which the controller compensates by predicting the
//!   filter's state of whole wingbeats ago forward on its design model: with an 8 kHz IMU it
//!   recovers (0.88 s measured) and, under a stated 0.2 m/s gust, holds within 2 body lengths
//!   and settles again; with the model's 1 kHz IMU it holds (no divergence, within 2 body
//!   lengths and 45 degrees; measured 0.78 body lengths and 16 degrees) without settling
//!   inside the 2 degree criterion. Without the prediction the loop diverged within 32 ms.
//! - `prediction_compensates_a_delay_on_the_design_model`: on the discrete averaged model
//!   itself the predicted loop fed 1, 2 or 3 wingbeats late retraces the undelayed loop to
//!   rounding (an exact identity of the Smith predictor; 1e-12 bound, 6e-14 measured).
//! - `noiseless_sensors_reproduce_true_state_loop`: with noiseless, unbiased sensors sampled
//!   every step without latency, the filter's semi-implicit prediction is the rigid-body
//!   integrator's own step, so the estimate should equal the true state up to rounding and
//!   the closed loop on the estimate retrace the closed loop on the truth; measured within
//!   1.5e-6 of each scale (an observed bound of 1e-5 in the test, not yet derived).
//! - `controller_input_interpolates_between_imu_samples`: on the model's 1 kHz IMU with its
//!   latencies, the state the controller flies on (the filter's state at its instant whole
//!   wingbeats ago, interpolated between IMU samples) is within 1.5 degrees rms of the truth
//!   (1.14 measured; 1.95 carried forward from the older sample).
//! - `estimated_feedback_needs_sensors`: a model without `[sensors]`, or without motion
//!   capture, is refused with an error naming what is missing.

#[path = "support/estimation.rs"]
mod estimation;

use estimation::fly;
use flapsim::control::{Disturbance, HoverController, LqrWeights, run_hover, run_hover_estimated};
use flapsim::estimator::{EstimatedFeedback, Estimator, IP, ITH, Prior};
use flapsim::sensor_run::SensorRun;
use flapsim::sensors::SensorParams;
use flapsim::{Mode, Simulation, State, Vehicle};
use nalgebra::{Matrix6, UnitQuaternion, Vector3, Vector6};

fn pitch5() -> Disturbance {
    Disturbance {
        pitch_deg: 5.0,
        ..Default::default()
    }
}

fn dt_s(v: &Vehicle) -> f64 {
    Simulation::new(v.clone(), Mode::Free).dt_s()
}

/// The two-sided 95% interval of a chi-square variable with `k` degrees of freedom
/// (Wilson & Hilferty 1931: (X/k)^(1/3) is nearly normal, mean 1 - 2/(9k), variance 2/(9k)).
fn chi2_95(k: f64) -> (f64, f64) {
    let s = (2.0 / (9.0 * k)).sqrt();
    let m = 1.0 - 2.0 / (9.0 * k);
    let q = |z: f64| k * (m + z * s).powi(3);
    (q(-1.959_964), q(1.959_964))
}

#[test]
fn nees_within_chi_square_bounds() {
    let (mut v, t) = fly();
    let dt = dt_s(&v);
    let mut sp: SensorParams = v.sensors.unwrap();
    sp.imu.rate_hz = 1.0 / dt;
    let mocap = sp.mocap.as_mut().unwrap();
    // 109 IMU samples per frame: 21.8 kHz / 109 = 200 Hz, the model's frame rate, with the
    // frames on IMU sample times.
    mocap.rate_hz = sp.imu.rate_hz / 109.0;
    assert!((mocap.rate_hz - 200.0).abs() < 1e-6);
    v.sensors = Some(sp);
    // The truth: the fruit fly hovering on the true state from a 5 degree pitch.
    let d = pitch5();
    let c = HoverController::design(&v, &t, &LqrWeights::default(), 0).unwrap();
    let mut truth: Vec<(f64, State)> = Vec::new();
    let o = run_hover(&v, &t, Some(c), &d, 0.15, |out| {
        truth.push((out.t_s, out.state));
        true
    })
    .unwrap();
    assert!(o.diverged.is_none(), "{o:?}");
    let s0 = truth[0].1;
    let n_seeds = 30u64;
    let mut nees = Vec::new();
    for seed in 0..n_seeds {
        let prior = estimation::drawn_prior(&v, &s0, 1000 + seed);
        let mut filter = Estimator::for_vehicle(&v, &prior).unwrap();
        let mut sensors = SensorRun::new(&v, seed).unwrap();
        for (ts, s) in &truth {
            sensors.observe(*ts, s, |r| filter.reading(&r));
        }
        assert_eq!(filter.stats().mocap_dropped, 0);
        assert!(filter.stats().mocap_frames >= 25, "{:?}", filter.stats());
        let (tf, x, p) = filter.latest();
        let tf = tf.unwrap();
        let k = (tf / dt).round() as usize;
        assert!((truth[k].0 - tf).abs() < 1e-9, "{} vs {tf}", truth[k].0);
        let s = truth[k].1;
        let ep = s.position_m - x.position_world_m;
        let eth = (x.world_from_body.inverse() * s.world_from_body).scaled_axis();
        let e = Vector6::new(ep.x, ep.y, ep.z, eth.x, eth.y, eth.z);
        let mut p6 = Matrix6::zeros();
        let idx = [IP, IP + 1, IP + 2, ITH, ITH + 1, ITH + 2];
        for (a, &i) in idx.iter().enumerate() {
            for (b, &j) in idx.iter().enumerate() {
                p6[(a, b)] = p[(i, j)];
            }
        }
        let inv = p6.cholesky().expect("P positive definite").inverse();
        nees.push((e.transpose() * inv * e)[(0, 0)]);
    }
    let n = n_seeds as f64;
    let mean = nees.iter().sum::<f64>() / n;
    let (lo, hi) = chi2_95(6.0 * n);
    let (lo, hi) = (lo / n, hi / n);
    eprintln!("NEES over {n_seeds} seeds: mean {mean:.3}, 95% bounds [{lo:.3}, {hi:.3}]");
    assert!((4.8..4.85).contains(&lo) && (7.28..7.32).contains(&hi));
    assert!(
        mean > lo && mean < hi,
        "mean NEES {mean} outside [{lo}, {hi}]: {nees:?}"
    );
}

#[test]
fn hover_on_estimate_recovers_from_pitch() {
    let (mut v, t) = fly();
    // The model's noise densities, biases and motion capture; the IMU sampling every step
    // and both latencies zero (the model's latencies: `hover_on_estimate_with_model_latencies`).
    let mut sp: SensorParams = v.sensors.unwrap();
    sp.imu.rate_hz = 1.0 / dt_s(&v);
    sp.imu.latency_s = 0.0;
    sp.mocap.as_mut().unwrap().latency_s = 0.0;
    v.sensors = Some(sp);
    let d = pitch5();
    let c = HoverController::design(&v, &t, &LqrWeights::default(), 0).unwrap();
    let on_truth = run_hover(&v, &t, Some(c.clone()), &d, 1.0, |_| true).unwrap();
    let mut fb = EstimatedFeedback::new(&v, 0, &Prior::hover(&v, t.attitude())).unwrap();
    let mut worst_p: f64 = 0.0;
    let on_estimate = run_hover_estimated(&v, &t, Some(c), &d, 1.0, &mut fb, |out, f| {
        if out.t_s > 0.1 {
            let e = f.estimate(out.t_s);
            worst_p = worst_p.max((e.position_m - out.state.position_m).norm());
        }
        true
    })
    .unwrap();
    eprintln!("on the truth: {on_truth:?}");
    eprintln!("on the estimate: {on_estimate:?}");
    eprintln!(
        "filter: {:?}; largest position estimate error after 0.1 s {worst_p:.3e} m",
        fb.filter().stats()
    );
    assert!(on_truth.recovery_time_s.is_some(), "{on_truth:?}");
    assert!(on_estimate.diverged.is_none(), "{on_estimate:?}");
    assert!(
        on_estimate.recovery_time_s.is_some(),
        "not recovered on the estimate: {on_estimate:?}"
    );
}

#[test]
fn noiseless_sensors_reproduce_true_state_loop() {
    let (mut v, t) = fly();
    let dt = dt_s(&v);
    let mut sp: SensorParams = v.sensors.unwrap();
    let imu = &mut sp.imu;
    imu.rate_hz = 1.0 / dt;
    imu.latency_s = 0.0;
    imu.gyro_noise_density = 0.0;
    imu.gyro_bias_rad_s = 0.0;
    imu.gyro_bias_walk = 0.0;
    imu.accel_noise_density = 0.0;
    imu.accel_bias_m_s2 = 0.0;
    imu.accel_bias_walk = 0.0;
    let m = sp.mocap.as_mut().unwrap();
    m.rate_hz = 1.0 / dt;
    m.latency_s = 0.0;
    m.position_noise_m = 0.0;
    m.attitude_noise_rad = 0.0;
    v.sensors = Some(sp);
    let d = pitch5();
    let c = HoverController::design(&v, &t, &LqrWeights::default(), 0).unwrap();
    let duration = 0.2;
    let mut truth_run = Vec::new();
    run_hover(&v, &t, Some(c.clone()), &d, duration, |o| {
        truth_run.push(o.state);
        true
    })
    .unwrap();
    // The filter starts from the trim pose at rest (1 body length, 10 deg off at most in its
    // prior), not from the disturbed truth: the first exact frame puts it there.
    let mut fb = EstimatedFeedback::new(&v, 0, &Prior::hover(&v, t.attitude())).unwrap();
    let mut est_run = Vec::new();
    let mut worst_estimate: (f64, f64, f64, f64) = (0.0, 0.0, 0.0, 0.0);
    run_hover_estimated(&v, &t, Some(c), &d, duration, &mut fb, |o, f| {
        let e = f.estimate(o.t_s);
        let s = &o.state;
        worst_estimate.0 = worst_estimate.0.max((e.position_m - s.position_m).norm());
        worst_estimate.1 = worst_estimate
            .1
            .max((e.velocity_m_s - s.velocity_m_s).norm());
        worst_estimate.2 = worst_estimate
            .2
            .max((e.world_from_body.inverse() * s.world_from_body).angle());
        worst_estimate.3 = worst_estimate
            .3
            .max((e.angular_velocity_body_rad_s - s.angular_velocity_body_rad_s).norm());
        est_run.push(o.state);
        true
    })
    .unwrap();
    assert_eq!(truth_run.len(), est_run.len());
    let (mut dp, mut dv, mut dth, mut dw) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let (mut vmax, mut wmax) = (0.0f64, 0.0f64);
    for (a, b) in truth_run.iter().zip(&est_run) {
        dp = dp.max((a.position_m - b.position_m).norm());
        dv = dv.max((a.velocity_m_s - b.velocity_m_s).norm());
        dth = dth.max((a.world_from_body.inverse() * b.world_from_body).angle());
        dw = dw.max((a.angular_velocity_body_rad_s - b.angular_velocity_body_rad_s).norm());
        vmax = vmax.max(a.velocity_m_s.norm());
        wmax = wmax.max(a.angular_velocity_body_rad_s.norm());
    }
    eprintln!(
        "estimate vs truth in the loop: position {:.3e} m, velocity {:.3e} m/s, attitude {:.3e} rad, rate {:.3e} rad/s",
        worst_estimate.0, worst_estimate.1, worst_estimate.2, worst_estimate.3
    );
    eprintln!(
        "trajectories: position {dp:.3e} m (of {:.3e} m), velocity {dv:.3e} m/s (of {vmax:.3e}), attitude {dth:.3e} rad, rate {dw:.3e} rad/s (of {wmax:.3e})",
        v.length_m
    );
    // Measured: 1.5e-6 body lengths, 1.3e-6 of the largest speed, 4.4e-8 rad, 4e-8 of the
    // largest rate. Rounding alone and rapier's third-order rotation difference ((|w| dt)^3
    // / 12 per step, about 1e-11 rad over the run) would give far less; the remaining
    // difference is not yet explained, so this bound (1e-5 of each scale) is an observed
    // one, not derived: it still separates the noiseless loop from a loop on noisy sensors
    // (body lengths of 1e-1, degrees).
    let l = v.length_m;
    assert!(dp <= 1e-5 * l, "position differs by {dp} m");
    assert!(dv <= 1e-5 * vmax, "velocity differs by {dv} m/s");
    assert!(dth <= 1e-5, "attitude differs by {dth} rad");
    assert!(dw <= 1e-5 * wmax, "rate differs by {dw} rad/s");
}

#[test]
fn estimated_feedback_needs_sensors() {
    let (mut v, t) = fly();
    let prior = Prior::hover(&v, t.attitude());
    let sp = v.sensors.unwrap();
    v.sensors = None;
    let e = EstimatedFeedback::new(&v, 0, &prior)
        .unwrap_err()
        .to_string();
    assert!(e.contains("drosophila") && e.contains("[sensors]"), "{e}");
    v.sensors = Some(SensorParams { mocap: None, ..sp });
    let e = EstimatedFeedback::new(&v, 0, &prior)
        .unwrap_err()
        .to_string();
    assert!(e.contains("[sensors.mocap]"), "{e}");
    let bad = Prior {
        attitude_std_rad: -1.0,
        ..prior
    };
    v.sensors = Some(sp);
    let e = EstimatedFeedback::new(&v, 0, &bad).unwrap_err().to_string();
    assert!(e.contains("attitude_std_rad = -1"), "{e}");
}

/// The fruit fly on its model's sensors with their latencies (IMU 5 ms, motion capture
/// 6.5 ms: 1.1 and 1.4 wingbeats) and the IMU at `imu_rate_hz`, from a 5 degree pitch and
/// with an optional uniform gust, 1 s.
fn hover_with_latencies(imu_rate_hz: f64, gust_x_m_s: f64) -> flapsim::control::HoverOutcome {
    let (mut v, t) = fly();
    let mut sp: SensorParams = v.sensors.unwrap();
    assert_eq!(
        (sp.imu.latency_s, sp.mocap.unwrap().latency_s),
        (5.0e-3, 6.5e-3)
    );
    sp.imu.rate_hz = imu_rate_hz;
    v.sensors = Some(sp);
    let c = HoverController::design(&v, &t, &LqrWeights::default(), 0).unwrap();
    let mut fb = EstimatedFeedback::new(&v, 0, &Prior::hover(&v, t.attitude())).unwrap();
    let d = Disturbance {
        gust_m_s: [gust_x_m_s, 0.0, 0.0],
        gust_start_s: 0.3,
        gust_duration_s: 0.2,
        ..pitch5()
    };
    let o = run_hover_estimated(&v, &t, Some(c), &d, 1.0, &mut fb, |_, _| true).unwrap();
    eprintln!(
        "IMU {imu_rate_hz} Hz, gust {gust_x_m_s} m/s: {o:?}; {:?}",
        fb.filter().stats()
    );
    o
}

#[test]
fn hover_on_estimate_with_model_latencies() {
    // An 8 kHz IMU (the ICM-20602's highest gyroscope output rate, datasheet DS-000176
    // rev 1.0, the part models/drosophila.toml cites): the loop recovers by run_hover's
    // criterion (1 body length, 2 degrees) within the second, the latencies compensated by
    // the controller's prediction (on the truth without latency: 0.08 s; with the IMU
    // every step and no latency: 0.75 s, `hover_on_estimate_recovers_from_pitch`).
    let fast = hover_with_latencies(8000.0, 0.0);
    assert!(fast.diverged.is_none(), "{fast:?}");
    assert!(fast.recovery_time_s.is_some(), "{fast:?}");
    // The model's own 1 kHz IMU (4.6 point samples a wingbeat, the body rate's 3rd and 5th
    // and the specific force's 4th and 6th wingbeat harmonics above its Nyquist frequency:
    // module documentation of flapsim::estimator): what the controller flies on errs by
    // 1.1-1.3 degrees rms (seeds 0-2), most of the recovery criterion's 2 degrees, so the
    // loop holds (no divergence; measured 0.78 body lengths and 16 degrees at most) without
    // settling inside 2 degrees.
    let datasheet = hover_with_latencies(1000.0, 0.0);
    assert!(datasheet.diverged.is_none(), "{datasheet:?}");
    assert!(
        datasheet.max_position_error_body_lengths < 2.0 && datasheet.max_attitude_error_deg < 45.0,
        "{datasheet:?}"
    );
    // A 0.2 m/s gust along x for 0.2 s from t = 0.3 s (80 body lengths per second, about a
    // third of the fly's forward speeds): measured, it pushes the fly 1.2 body lengths
    // off; the loop holds and settles again within the second.
    let gust = hover_with_latencies(8000.0, 0.2);
    assert!(gust.diverged.is_none(), "{gust:?}");
    assert!(gust.max_position_error_body_lengths < 2.0, "{gust:?}");
    assert!(gust.recovery_time_s.is_some(), "{gust:?}");
}

/// The controller's prediction is exact on its own design model: on the discrete averaged
/// model x+ = A_d x + B_d u, a loop fed the state d wingbeats late through
/// `update_from_past` retraces the loop fed the current state (a discrete Smith predictor,
/// Astrom & Wittenmark 1997 section 5.8), to rounding.
#[test]
fn prediction_compensates_a_delay_on_the_design_model() {
    use flapsim::control::discretize;
    use flapsim::linear::{AveragedModel, N_STATES};
    use nalgebra::DVector;
    let (v, t) = fly();
    let model = AveragedModel::new(&v, t.attitude(), t.controls, 100);
    let (a, b) = model.linearize(&DVector::zeros(N_STATES)).unwrap();
    let (ad, bd) = discretize(&a, &b, 1.0 / v.freq_hz());
    let c0 = HoverController::design(&v, &t, &LqrWeights::default(), 0).unwrap();
    let drive = v.drive_controlled();
    let trim_u = t.controls.channels(drive);
    // The error state of a State (HoverController::error_state's inverse).
    let state_of = |x: &DVector<f64>| State {
        position_m: v.initial_position_m + Vector3::new(x[0], x[1], x[2]),
        velocity_m_s: Vector3::new(x[3], x[4], x[5]),
        world_from_body: t.attitude()
            * UnitQuaternion::from_scaled_axis(Vector3::new(x[6], x[7], x[8])),
        angular_velocity_body_rad_s: Vector3::new(x[9], x[10], x[11]),
    };
    let mut x0 = DVector::zeros(N_STATES);
    x0[6] = 0.0;
    x0[7] = -5f64.to_radians();
    x0[3] = 0.01;
    for d in [1usize, 2, 3] {
        let (mut now, mut late) = (c0.clone(), c0.clone());
        let (mut xa, mut xb) = (x0.clone(), x0.clone());
        let mut past: Vec<DVector<f64>> = vec![x0.clone()];
        let mut worst: f64 = 0.0;
        for n in 0..40usize {
            let ua = now.update(&state_of(&xa)).channels(drive);
            // Before the run the state was the start (the loop begins at rest at x0).
            let xp = &past[n.saturating_sub(d).min(past.len() - 1)];
            let (s, ago) = if n >= d {
                (state_of(xp), d)
            } else {
                (state_of(&x0), n)
            };
            let ub = late.update_from_past(&s, ago).unwrap().channels(drive);
            let du = |u: [f64; 4]| DVector::from_iterator(4, (0..4).map(|i| u[i] - trim_u[i]));
            xa = &ad * &xa + &bd * du(ua);
            xb = &ad * &xb + &bd * du(ub);
            past.push(xb.clone());
            worst = worst.max((&xa - &xb).amax());
        }
        eprintln!("delay {d} wingbeats: largest state difference {worst:.3e}");
        assert!(worst < 1e-12, "delay {d}: {worst}");
        assert!(xa.amax() < 0.2 * x0.amax(), "the loop settles: {xa}");
    }
}

/// What the controller flies on across the model's latencies on its 1 kHz IMU: the filter's
/// state at the controller's instant d wingbeats ago, read between the two IMU samples around
/// it (`Estimator::state_in_history`). Measured over the 1 s hover from a 5 degree pitch
/// (seed 0), against the truth at the instant the input stands for: 1.14 degrees rms
/// interpolated, 1.95 degrees when the older sample was carried forward at constant rates
/// (1.84-2.04 over seeds 0-2), the in-wingbeat oscillation (26.8 rad/s of pitch rate at
/// 218 Hz) moving the body by up to 1.1 degrees within an IMU period. The bound, 1.5 degrees,
/// separates the two with room on both sides.
#[test]
fn controller_input_interpolates_between_imu_samples() {
    let (v, t) = fly();
    let period = 1.0 / v.freq_hz();
    let dt = dt_s(&v);
    let c = HoverController::design(&v, &t, &LqrWeights::default(), 0).unwrap();
    let mut fb = EstimatedFeedback::new(&v, 0, &Prior::hover(&v, t.attitude())).unwrap();
    let mut truth: Vec<State> = Vec::new();
    let (mut sum2, mut n) = (0.0, 0usize);
    run_hover_estimated(&v, &t, Some(c), &pitch5(), 1.0, &mut fb, |out, f| {
        truth.push(out.state);
        let k = truth.len() - 1;
        // The controller acts at each wingbeat's first step (100 steps a wingbeat).
        if out.t_s > 0.1 && k.is_multiple_of(100) {
            let (s, ago) = f.controller_input(out.t_s, period);
            assert!(ago >= 1, "the IMU's 5 ms latency is more than a wingbeat");
            let i = ((out.t_s - ago as f64 * period) / dt).round() as usize;
            let e = (s.world_from_body.inverse() * truth[i].world_from_body).angle();
            sum2 += e * e;
            n += 1;
        }
        true
    })
    .unwrap();
    let rms_deg = (sum2 / n as f64).sqrt().to_degrees();
    eprintln!("controller input attitude error {rms_deg:.3} deg rms over {n} wingbeats");
    assert!(n > 150, "{n}");
    assert!(rms_deg < 1.5, "{rms_deg} deg");
}
