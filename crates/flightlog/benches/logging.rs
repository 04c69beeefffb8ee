//! Cost of logging in wall time, as a user sees it: a whole tethered drosophila run of 20
//! wingbeats (2000 steps), from `Recorder::create` to `Recorder::finish` (so the writer
//! thread's backlog and the MCAP summary are included), without a log, with the MCAP log at
//! the CLI's default rate (2000 Hz, about 9 samples per wingbeat) and at full rate (every
//! step). The targets: 2000 Hz at most 1.25x and full rate at most 3x the run without a log.
//!
//! A second group feeds 2000 precomputed steps to the recorder at full rate with no
//! simulation: the logging pipeline's own throughput (its cost per sample).
//!
//! Last, `overhead_ratio` measures the ratios themselves, tethered and in free flight: it
//! runs the three variants of the same 20-wingbeat run back to back (each from a fresh
//! simulation at rest), many times in rotating order, and prints the median and quartiles
//! of the per-round ratios. The speed of this virtual machine drifts by up to 2x over
//! seconds, and criterion measures one variant after the other, so ratios of criterion's
//! figures scatter; rounds of a few tens of milliseconds see the same machine.
//! `FLAPWING_BENCH_ROUNDS` sets the number of rounds (default 100).
use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, SamplingMode, criterion_group};
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

/// A 20-wingbeat run of `sim`, logged at `rate` (`None`: no log; `Some(None)`: every step)
/// to a new file at `path`: wall time from `Recorder::create` to `finish`.
fn timed_run(
    vehicle: &Vehicle,
    sim: &mut Simulation,
    path: &std::path::Path,
    rate: Option<Option<f64>>,
) -> Duration {
    let steps = WINGBEATS * vehicle.sim.steps_per_wingbeat;
    // A new file each time, as a real run writes (replacing a file makes ext4 write it back
    // on close, which a run does not pay).
    let _ = std::fs::remove_file(path);
    let start = Instant::now();
    let mut rec = rate.map(|r| recorder(vehicle, path.to_owned(), r));
    for _ in 0..steps {
        let out = sim.step().expect("step");
        if let Some(r) = rec.as_mut() {
            r.record(out).expect("record");
        }
        black_box(out);
    }
    if let Some(r) = rec {
        black_box(r.finish().expect("finish"));
    }
    start.elapsed()
}

/// The median and quartiles of `x` (sorted here).
fn quartiles(x: &mut [f64]) -> [f64; 3] {
    x.sort_by(f64::total_cmp);
    [x.len() / 4, x.len() / 2, 3 * x.len() / 4].map(|i| x[i])
}

/// See the module docs: per-round ratios of logged to unlogged runs.
fn overhead_ratio() {
    let rounds: usize = std::env::var("FLAPWING_BENCH_ROUNDS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(100);
    let vehicle =
        Vehicle::from_toml(flapsim::DROSOPHILA_TOML, "drosophila").expect("built-in model");
    let dir = std::env::temp_dir().join(format!("flapwing-ratio-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("run.mcap");
    let variants: [Option<Option<f64>>; 3] = [None, Some(Some(2000.0)), Some(None)];
    println!("overhead_ratio: {rounds} rounds of 3 runs of {WINGBEATS} wingbeats (median [q1 q3])");
    for (name, mode) in [("tethered", Mode::Tethered), ("free flight", Mode::Free)] {
        let mut ms = [vec![], vec![], vec![]];
        let mut ratios = [vec![], vec![]];
        for round in 0..rounds {
            let mut t = [0.0; 3];
            for k in 0..3 {
                let v = (round + k) % 3;
                let mut sim = Simulation::new(vehicle.clone(), mode);
                t[v] = timed_run(&vehicle, &mut sim, &path, variants[v]).as_secs_f64() * 1e3;
            }
            for v in 0..3 {
                ms[v].push(t[v]);
            }
            ratios[0].push(t[1] / t[0]);
            ratios[1].push(t[2] / t[0]);
        }
        let [a, b] = ratios.each_mut().map(|r| quartiles(r));
        let [n, d, f] = ms.each_mut().map(|m| quartiles(m));
        println!(
            "  {name:11}: no log {:.2} ms; MCAP 2000 Hz {:.2}x [{:.2} {:.2}] ({:.2} ms); full rate {:.2}x [{:.2} {:.2}] ({:.2} ms)",
            n[1], a[1], a[0], a[2], d[1], b[1], b[0], b[2], f[1]
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
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
                (0..iters)
                    .map(|_| timed_run(&vehicle, &mut sim, &path, rate))
                    .sum()
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

fn main() {
    benches();
    Criterion::default().configure_from_args().final_summary();
    // The ratio rounds run with every `cargo bench` of this file, and with a filter that
    // names them.
    let args: Vec<String> = std::env::args().skip(1).collect();
    let filter = args.iter().find(|a| !a.starts_with('-'));
    let listing = args.iter().any(|a| a == "--list");
    if !listing && filter.is_none_or(|f| "overhead_ratio".contains(f.as_str())) {
        overhead_ratio();
    }
}
