//! A closed-loop hover step on the true state in still air beside the same step flown on the
//! estimator (the model's IMU and motion capture sampled, the error-state Kalman filter
//! updated, the controller's prediction across the latencies) in Dryden turbulence (issue
//! #27's bound: the two together add at most 20 %).
//!
//! Besides the criterion groups (whole 0.05 s hovers), `ratio_rounds` interleaves the kinds
//! of run (this VM's speed changes by up to 2x from minute to minute, so only ratios measured
//! side by side mean anything) and prints the median ratios to the true-state still-air run.
use std::hint::black_box;
use std::time::Instant;

use criterion::{Criterion, criterion_group, criterion_main};
use flapsim::Vehicle;
use flapsim::control::{Disturbance, HoverController, LqrWeights, run_hover, run_hover_estimated};
use flapsim::estimator::{EstimatedFeedback, Prior};
use flapsim::trim::{Trim, trim, trimmed_vehicle};

/// The fruit fly trimmed, in still air and in turbulence (intensity 0.1 m/s, length scale
/// 0.5 m: the example of crates/flapsim/README.md's `[wind]`).
fn flies() -> (Vehicle, Vehicle, Trim) {
    let still = Vehicle::from_toml(flapsim::DROSOPHILA_TOML, "drosophila").expect("built-in");
    let turbulent_toml = format!(
        "{}\n[wind.turbulence]\nintensity_m_s = [0.1, 0.1, 0.1]\nlength_scale_m = [0.5, 0.5, 0.5]\nseed = 7\n",
        flapsim::DROSOPHILA_TOML
    );
    let turbulent = Vehicle::from_toml(&turbulent_toml, "drosophila_turbulent").expect("valid");
    let t = trim(&still).expect("the fly trims");
    (
        trimmed_vehicle(&still, &t).expect("trimmed"),
        trimmed_vehicle(&turbulent, &t).expect("trimmed"),
        t,
    )
}

/// One hover of `duration_s`, on the truth or on the estimate, with controller `c` (designed
/// outside the timed part); returns the steps taken.
fn hover(v: &Vehicle, t: &Trim, c: &HoverController, estimated: bool, duration_s: f64) -> u64 {
    let c = c.clone();
    let d = Disturbance {
        pitch_deg: 5.0,
        ..Default::default()
    };
    let mut steps = 0u64;
    let o = if estimated {
        let mut fb = EstimatedFeedback::new(v, 0, &Prior::hover(v, t.attitude())).expect("sensors");
        run_hover_estimated(v, t, Some(c), &d, duration_s, &mut fb, |o, _| {
            black_box(o.t_s);
            steps += 1;
            true
        })
    } else {
        run_hover(v, t, Some(c), &d, duration_s, |o| {
            black_box(o.t_s);
            steps += 1;
            true
        })
    };
    assert!(o.expect("runs").diverged.is_none());
    steps
}

fn bench(c: &mut Criterion) {
    let (still, turbulent, t) = flies();
    let c0 = HoverController::design(&still, &t, &LqrWeights::default(), 0).expect("designs");
    let mut g = c.benchmark_group("hover_0.05s");
    g.sample_size(20);
    g.bench_function("truth_still_air", |b| {
        b.iter(|| hover(&still, &t, &c0, false, 0.05))
    });
    g.bench_function("estimate_turbulence", |b| {
        b.iter(|| hover(&turbulent, &t, &c0, true, 0.05))
    });
    g.finish();
    ratio_rounds(&still, &turbulent, &t, &c0);
}

/// Interleaved rounds of 0.1 s hovers (2180 steps, each from the hover's set-up: the
/// actuated-wing settling and the simulation's construction, but not the controller's
/// design) of four kinds, rotating their order; prints each kind's median cost ratio to the
/// true-state still-air hover.
fn ratio_rounds(still: &Vehicle, turbulent: &Vehicle, t: &Trim, c: &HoverController) {
    let kinds: [(&str, &Vehicle, bool); 4] = [
        ("truth, still air", still, false),
        ("truth, turbulence", turbulent, false),
        ("estimate, still air", still, true),
        ("estimate, turbulence", turbulent, true),
    ];
    let rounds = 21;
    let mut ratios = vec![Vec::new(); kinds.len()];
    for r in 0..rounds {
        let mut secs = [0.0; 4];
        for k in 0..kinds.len() {
            let i = (k + r) % kinds.len();
            let (_, v, est) = kinds[i];
            let t0 = Instant::now();
            black_box(hover(v, t, c, est, 0.1));
            secs[i] = t0.elapsed().as_secs_f64();
        }
        for i in 0..kinds.len() {
            ratios[i].push(secs[i] / secs[0]);
        }
    }
    for (i, (name, _, _)) in kinds.iter().enumerate() {
        let v = &mut ratios[i];
        v.sort_by(f64::total_cmp);
        println!(
            "closed-loop hover step, {name} / truth, still air ({rounds} interleaved rounds of 0.1 s): median {:.3}x [quartiles {:.3} {:.3}]",
            v[v.len() / 2],
            v[v.len() / 4],
            v[3 * v.len() / 4]
        );
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
