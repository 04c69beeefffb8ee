//! Throughput of tethered wingbeats: the built-in drosophila, 20 strips per wing, one
//! wingbeat = 100 phase samples of `averaged::mean_loads`' inner loop for both wings (all
//! four force terms). Criterion reports the time per wingbeat; the throughput line gives
//! wingbeats per second. (One study case, `hover_responses`, is timed in flapstudy's
//! `study_case` benchmark.)
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use flapsim::Vehicle;
use flapsim::averaged::{FrozenState, mean_loads};
use nalgebra::Vector3;
use std::hint::black_box;

const STEPS_PER_WINGBEAT: usize = 100;

fn bench(c: &mut Criterion) {
    let vehicle =
        Vehicle::from_toml(flapsim::DROSOPHILA_TOML, "drosophila").expect("built-in model");
    for wing in &vehicle.wings {
        assert_eq!(wing.geometry().strips.len(), 20, "20 strips per wing");
    }
    let state = FrozenState {
        world_from_body: vehicle.initial_attitude,
        velocity_body_m_s: Vector3::zeros(),
        angular_velocity_body_rad_s: Vector3::zeros(),
    };
    let mut group = c.benchmark_group("tethered_drosophila");
    group.throughput(Throughput::Elements(1));
    group.bench_function("wingbeat_100_steps_20_strips", |b| {
        b.iter(|| mean_loads(black_box(&vehicle), black_box(&state), STEPS_PER_WINGBEAT))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
