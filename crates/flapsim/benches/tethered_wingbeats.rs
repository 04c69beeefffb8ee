//! Throughput of tethered wingbeats: the built-in drosophila, 20 strips per wing, one
//! wingbeat = 100 phase samples of `averaged::mean_loads`' inner loop for both wings (all
//! four force terms). Criterion reports the time per wingbeat; the throughput line gives
//! wingbeats per second. A second benchmark times one study case (`hover_responses`: the
//! mean loads plus the wings' cycle means and aerodynamic power, two passes).
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use flapsim::Vehicle;
use flapsim::averaged::{FrozenState, mean_loads};
use flapsim::study::hover_responses;
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
    group.bench_function("study_case_hover_responses", |b| {
        b.iter(|| hover_responses(black_box(&vehicle), STEPS_PER_WINGBEAT).expect("built-in"))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
