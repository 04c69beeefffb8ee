//! An actuated free-flight step (wing dynamics sub-stepped, the full aerodynamic kernel every
//! step) beside a prescribed-kinematics step of the same RoboBee-class vehicle, and the
//! actuated RoboBee's real-time factor; likewise the hummingbird, whose wings strike
//! inelastic hinge stops every half stroke (against the same prescribed step: it has no
//! prescribed twin).
//!
//! Besides the criterion groups, `ratio_rounds` interleaves the two kinds of step (this VM's
//! speed changes by up to 2x from minute to minute, so only ratios measured side by side
//! mean anything) and prints the median ratio and the real-time factor.
use std::hint::black_box;
use std::time::Instant;

use criterion::{Criterion, criterion_group, criterion_main};
use flapsim::{Mode, Simulation, Vehicle};

fn vehicles() -> (Vehicle, Vehicle, Vehicle) {
    let prescribed =
        Vehicle::from_toml(flapsim::ROBOBEE_KINEMATIC_TOML, "robobee").expect("built-in");
    let actuated = Vehicle::from_toml(flapsim::ROBOBEE_TOML, "robobee").expect("built-in");
    let stops = Vehicle::from_toml(flapsim::HUMMINGBIRD_TOML, "hummingbird").expect("built-in");
    (prescribed, actuated, stops)
}

fn stepper(v: &Vehicle) -> impl FnMut() {
    let v = v.clone();
    let mut sim = Simulation::new(v.clone(), Mode::Free);
    move || {
        if sim.step().map(|o| black_box(o.t_s)).is_err() || sim.time_s() > 0.05 {
            sim = Simulation::new(v.clone(), Mode::Free);
        }
    }
}

fn bench(c: &mut Criterion) {
    let (prescribed, actuated, stops) = vehicles();
    let mut p = stepper(&prescribed);
    c.bench_function("robobee_kinematic_free_step", |b| b.iter(&mut p));
    let mut a = stepper(&actuated);
    c.bench_function("robobee_free_step", |b| b.iter(&mut a));
    let mut h = stepper(&stops);
    c.bench_function("hummingbird_free_step", |b| b.iter(&mut h));
    ratio_rounds("robobee", &prescribed, &actuated);
    ratio_rounds("hummingbird", &prescribed, &stops);
}

/// Interleaved rounds of 2000 steps each; prints the median cost ratio and the actuated
/// vehicle's real-time factor (simulated seconds per wall-clock second).
fn ratio_rounds(name: &str, prescribed: &Vehicle, actuated: &Vehicle) {
    let n = 2000;
    let time = |v: &Vehicle| {
        let mut sim = Simulation::new(v.clone(), Mode::Free);
        let t0 = Instant::now();
        for _ in 0..n {
            black_box(sim.step().expect("a short free flight runs").t_s);
        }
        (t0.elapsed().as_secs_f64(), sim.time_s())
    };
    let mut ratios = Vec::new();
    let mut rtf = Vec::new();
    for _ in 0..15 {
        let (tp, _) = time(prescribed);
        let (ta, sim_s) = time(actuated);
        ratios.push(ta / tp);
        rtf.push(sim_s / ta);
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        (v[v.len() / 4], v[v.len() / 2], v[3 * v.len() / 4])
    };
    let (r1, r2, r3) = median(&mut ratios);
    let (f1, f2, f3) = median(&mut rtf);
    println!(
        "actuated / prescribed free-flight step ({name} against robobee_kinematic, interleaved, 15 rounds of {n} steps): median {r2:.2}x [quartiles {r1:.2} {r3:.2}]"
    );
    println!(
        "actuated {name} free flight: {f2:.1}x real time [quartiles {f1:.1} {f3:.1}] at {} steps per wingbeat",
        actuated.sim.steps_per_wingbeat
    );
}

criterion_group!(benches, bench);
criterion_main!(benches);
