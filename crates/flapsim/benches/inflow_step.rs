//! A free-flight step of the fruit fly with its wake dynamic (`[aero] inflow = "dynamic"`:
//! the pair's three inflow states stepped with the loads, issue #38) beside the same step
//! with the wake frozen (the built-in model); and the RoboBee's actuated step and the
//! four-winged dragonfly's step with the dynamic wake beside their own still air (the
//! actuated pair's disc measured from its stroke; the dragonfly's two pairs crossing each
//! other's discs).
//!
//! Besides the criterion functions, `ratio_rounds` interleaves the two (this VM's speed
//! changes by up to 2x from minute to minute, so only ratios measured side by side mean
//! anything) and prints the median ratio with its quartiles.
use std::hint::black_box;
use std::time::Instant;

use criterion::{Criterion, criterion_group, criterion_main};
use flapsim::{Mode, Simulation, Vehicle};
use wingforce::InflowModel;

fn vehicles() -> (Vehicle, Vehicle) {
    let frozen =
        Vehicle::from_toml(flapsim::DROSOPHILA_TOML, "drosophila").expect("built-in model");
    let dynamic = frozen
        .with_inflow_model(InflowModel::Dynamic)
        .expect("the fly's one pair takes the dynamic wake");
    (frozen, dynamic)
}

/// A simulation past its first step (a dynamic wake's start runs its inflow into its
/// periodic motion there).
fn started(v: &Vehicle) -> Simulation {
    let mut sim = Simulation::new(v.clone(), Mode::Free);
    sim.step().expect("a first step");
    sim
}

fn stepper(v: &Vehicle) -> impl FnMut() {
    let v = v.clone();
    let mut sim = started(&v);
    move || {
        if sim.step().map(|o| black_box(o.t_s)).is_err() || sim.time_s() > 0.5 {
            sim = started(&v);
        }
    }
}

fn bench(c: &mut Criterion) {
    let (frozen, dynamic) = vehicles();
    let mut f = stepper(&frozen);
    c.bench_function("fly_free_step_frozen_wake", |b| b.iter(&mut f));
    let mut d = stepper(&dynamic);
    c.bench_function("fly_free_step_dynamic_wake", |b| b.iter(&mut d));
    ratio_rounds("fly free step, dynamic / frozen wake", &frozen, &dynamic);
    for (name, text) in [
        ("robobee", flapsim::ROBOBEE_TOML),
        ("dragonfly", flapsim::DRAGONFLY_TOML),
    ] {
        let still = Vehicle::from_toml(text, name).expect("built-in model");
        let dynamic = still
            .with_inflow_model(InflowModel::Dynamic)
            .expect("every vehicle takes the dynamic wake");
        ratio_rounds(
            &format!("{name} free step, dynamic wake / still air"),
            &still,
            &dynamic,
        );
    }
}

/// Interleaved rounds of 500 steps each from a started flight (the start, where a dynamic
/// wake runs into its periodic motion, is not timed; 500 steps keep the open-loop dragonfly
/// short of its tumble, 0.45 s); prints the median cost ratio `dynamic` / `frozen` and its
/// quartiles.
fn ratio_rounds(label: &str, frozen: &Vehicle, dynamic: &Vehicle) {
    let n = 500;
    let time = |v: &Vehicle| {
        let mut sim = started(v);
        let t0 = Instant::now();
        for _ in 0..n {
            black_box(sim.step().expect("a short free flight runs").t_s);
        }
        t0.elapsed().as_secs_f64()
    };
    let mut ratios: Vec<f64> = (0..31)
        .map(|round| {
            // Alternate which goes first.
            if round % 2 == 0 {
                let f = time(frozen);
                time(dynamic) / f
            } else {
                let d = time(dynamic);
                d / time(frozen)
            }
        })
        .collect();
    ratios.sort_by(f64::total_cmp);
    let q = |p: f64| ratios[((ratios.len() - 1) as f64 * p).round() as usize];
    println!(
        "{label} ({} interleaved rounds of {n} steps): median {:.3}x [quartiles {:.3} {:.3}]",
        ratios.len(),
        q(0.5),
        q(0.25),
        q(0.75)
    );
}

criterion_group!(benches, bench);
criterion_main!(benches);
