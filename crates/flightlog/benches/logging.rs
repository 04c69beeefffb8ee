//! Cost of logging in wall time, as a user sees it: a whole tethered drosophila run of 20
//! wingbeats (2000 steps), from `Recorder::create` to `Recorder::finish` (so the writer
//! thread's backlog and the MCAP summary are included), without a log, with the MCAP log at
//! the CLI's default rate (2000 Hz, about 9 samples per wingbeat) and at full rate (every
//! step). The targets: 2000 Hz at most 1.25x and full rate at most 3x the run without a log.
//!
//! A second group feeds 2000 precomputed steps to the recorder at full rate with no
//! simulation: the logging pipeline's own throughput (its cost per sample).
use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, SamplingMode, criterion_group, criterion_main};
use flapsim::{Mode, Simulation, StepOutput, Vehicle};
use flightlog::{LogOptions, Recorder, RunInfo, SimSettings};

const WINGBEATS: usize = 20;

fn recorder(vehicle: &Vehicle, path: std::path::PathBuf, rate: Option<f64>) -> Recorder {
    let opts = LogOptions {
        mcap: Some(path),
        log_rate_hz: rate,
        ..LogOptions::default()
    };
    let settings = SimSettings::new(Mode::Tethered, 1.0, rate, [0.0; 3]);
    let info = RunInfo::new(
        "bench",
        "bench",
        flapsim::DROSOPHILA_TOML,
        "drosophila",
        settings.to_json(),
    );
    Recorder::create(&opts, &info, vehicle).expect("recorder")
}

fn bench(c: &mut Criterion) {
    let vehicle =
        Vehicle::from_toml(flapsim::DROSOPHILA_TOML, "drosophila").expect("built-in model");
    let steps = WINGBEATS * vehicle.sim.steps_per_wingbeat;
    let dir = std::env::temp_dir().join(format!("flapwing-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");

    let mut group = c.benchmark_group("run_20_wingbeats");
    group.sampling_mode(SamplingMode::Flat).sample_size(20);
    for (name, rate) in [
        ("no_log", None),
        ("mcap_2000hz", Some(Some(2000.0))),
        ("mcap_full_rate", Some(None)),
    ] {
        group.bench_function(name, |b| {
            // One simulation for every iteration: a tethered body stays put, and the
            // simulation's setup is not part of the logging cost.
            let mut sim = Simulation::new(vehicle.clone(), Mode::Tethered);
            let path = dir.join(format!("{name}.mcap"));
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                for _ in 0..iters {
                    // A new file each time, as a real run writes (replacing a file makes
                    // ext4 write it back on close, which a run does not pay).
                    let _ = std::fs::remove_file(&path);
                    let start = Instant::now();
                    let mut rec = rate.map(|r| recorder(&vehicle, path.clone(), r));
                    for _ in 0..steps {
                        let out = sim.step().expect("tethered step");
                        if let Some(r) = rec.as_mut() {
                            r.record(&out).expect("record");
                        }
                        black_box(&out);
                    }
                    if let Some(r) = rec {
                        black_box(r.finish().expect("finish"));
                    }
                    total += start.elapsed();
                }
                total
            });
        });
    }
    group.finish();

    let mut sim = Simulation::new(vehicle.clone(), Mode::Tethered);
    let outs: Vec<StepOutput> = (0..steps)
        .map(|_| *sim.step().expect("tethered step"))
        .collect();
    let mut group = c.benchmark_group("log_2000_steps_no_sim");
    group.sampling_mode(SamplingMode::Flat).sample_size(20);
    group.bench_function("mcap_full_rate", |b| {
        let path = dir.join("no_sim.mcap");
        b.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            for _ in 0..iters {
                let _ = std::fs::remove_file(&path);
                let start = Instant::now();
                let mut rec = recorder(&vehicle, path.clone(), None);
                for out in &outs {
                    rec.record(out).expect("record");
                }
                black_box(rec.finish().expect("finish"));
                total += start.elapsed();
            }
            total
        });
    });
    group.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, bench);
criterion_main!(benches);
