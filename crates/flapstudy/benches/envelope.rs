//! One envelope point of the built-in bumblebee at 2.5 m/s (trim, power and the averaged
//! model's modes: `flapstudy::envelope::envelope_point`), and the whole 10-point envelope
//! from hover to 4.5 m/s on one rayon thread and on all of them (the speed-up the issue asks
//! for; criterion reports both, run in the same process).
use criterion::{Criterion, criterion_group, criterion_main};
use flapsim::Vehicle;
use flapsim::flight::FlightCondition;
use flapstudy::envelope::{EnvelopeGrid, envelope, envelope_point};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let bee = Vehicle::from_toml(flapsim::BUMBLEBEE_TOML, "bumblebee").expect("built-in model");
    let condition = FlightCondition::new(2.5, 0.0).expect("valid");
    let grid = EnvelopeGrid::speeds(0.0, 4.5, 10, "bench").expect("valid");
    let mut group = c.benchmark_group("bumblebee_envelope");
    group.sample_size(10);
    group.bench_function("point_2_5_m_s", |b| {
        b.iter(|| envelope_point(black_box(&bee), &condition))
    });
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a pool");
    let all = rayon::ThreadPoolBuilder::new().build().expect("a pool");
    group.bench_function("ten_points_1_thread", |b| {
        b.iter(|| one.install(|| envelope(black_box(&bee), &grid, &|_| {}, &|| false)))
    });
    group.bench_function("ten_points_all_threads", |b| {
        b.iter(|| all.install(|| envelope(black_box(&bee), &grid, &|_| {}, &|| false)))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
