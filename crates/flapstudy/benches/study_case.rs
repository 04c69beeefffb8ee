//! One study case (`hover_responses` of the built-in drosophila at 100 phase samples per
//! wingbeat: the mean loads plus the wings' cycle means and aerodynamic power, two passes),
//! beside flapsim's `tethered_wingbeats` (one pass of the mean loads).
use criterion::{Criterion, criterion_group, criterion_main};
use flapsim::Vehicle;
use flapstudy::hover_responses;
use std::hint::black_box;

const STEPS_PER_WINGBEAT: usize = 100;

fn bench(c: &mut Criterion) {
    let vehicle =
        Vehicle::from_toml(flapsim::DROSOPHILA_TOML, "drosophila").expect("built-in model");
    let mut group = c.benchmark_group("tethered_drosophila");
    group.bench_function("study_case_hover_responses", |b| {
        b.iter(|| hover_responses(black_box(&vehicle), STEPS_PER_WINGBEAT).expect("built-in"))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
