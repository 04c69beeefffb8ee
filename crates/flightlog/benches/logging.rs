//! Cost of logging: one drosophila wingbeat (100 free-flight steps) without a log, with the
//! MCAP log at the CLI's default rate (2000 Hz) and at full rate (every step).
use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use flapsim::{Mode, Simulation, Vehicle};
use flightlog::{LogOptions, Recorder, RunInfo, SimSettings};

fn bench(c: &mut Criterion) {
    let vehicle =
        Vehicle::from_toml(flapsim::DROSOPHILA_TOML, "drosophila").expect("built-in model");
    let steps = vehicle.sim.steps_per_wingbeat;
    let dir = std::env::temp_dir().join(format!("flapwing-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let mut group = c.benchmark_group("wingbeat_100_steps");
    for (name, rate) in [
        ("no_log", None),
        ("mcap_2000hz", Some(Some(2000.0))),
        ("mcap_full_rate", Some(None)),
    ] {
        group.bench_function(name, |b| {
            let mut sim = Simulation::new(vehicle.clone(), Mode::Tethered);
            let mut rec = rate.map(|r| {
                let opts = LogOptions {
                    mcap: Some(dir.join(format!("{name}.mcap"))),
                    log_rate_hz: r,
                    ..LogOptions::default()
                };
                let info = RunInfo::new(
                    "bench",
                    "bench",
                    flapsim::DROSOPHILA_TOML,
                    "drosophila",
                    SimSettings::new(Mode::Tethered, 1.0, r, [0.0; 3]).to_json(),
                );
                Recorder::create(&opts, &info, &vehicle).expect("recorder")
            });
            b.iter(|| {
                for _ in 0..steps {
                    let out = sim.step().expect("tethered step");
                    if let Some(r) = rec.as_mut() {
                        r.record(&out).expect("record");
                    }
                    black_box(&out);
                }
            });
            if let Some(r) = rec {
                r.finish().expect("finish");
            }
        });
    }
    group.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, bench);
criterion_main!(benches);
