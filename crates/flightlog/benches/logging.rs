//! Cost of logging in wall time, as a user sees it: a whole tethered drosophila run of 20
//! wingbeats (2000 steps), from `Recorder::create` to `Recorder::finish` (so the writer
//! thread's backlog and the MCAP summary are included), without a log, with the MCAP log at
//! the CLI's default rate (2000 Hz, about 9 samples per wingbeat) and at full rate (every
//! step). The targets: 2000 Hz at most 1.1x and full rate at most 2x the run without a log.
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
//!
//! And `writer_ratio` compares MCAP writers the same way (interleaved rounds): flightlog's
//! recorder at full rate on 2000 precomputed free-flight steps (building, encoding,
//! compressing and writing), against the foxglove SDK's `McapWriter` (zstd, its default
//! chunking) given the very same encoded messages through raw channels (so it does less:
//! no building or encoding). Both write a whole file, summary included.
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

/// The messages of a log: (topic, schema name, schema data, [(log time, bytes)]) per channel,
/// and the file order as (channel index, message index).
type Messages = (
    Vec<(String, String, Vec<u8>, Vec<(u64, Vec<u8>)>)>,
    Vec<(usize, usize)>,
);

fn read_messages(path: &std::path::Path) -> Messages {
    let bytes = std::fs::read(path).expect("log");
    let mut channels: Vec<(String, String, Vec<u8>, Vec<(u64, Vec<u8>)>)> = Vec::new();
    let mut order = Vec::new();
    for m in mcap::MessageStream::new(&bytes).expect("mcap") {
        let m = m.expect("message");
        let c = match channels.iter().position(|c| c.0 == m.channel.topic) {
            Some(c) => c,
            None => {
                let s = m.channel.schema.as_ref().expect("schema");
                channels.push((
                    m.channel.topic.clone(),
                    s.name.clone(),
                    s.data.to_vec(),
                    vec![],
                ));
                channels.len() - 1
            }
        };
        order.push((c, channels[c].3.len()));
        channels[c].3.push((m.log_time, m.data.to_vec()));
    }
    (channels, order)
}

/// The foxglove SDK's MCAP writer given `msgs` (see the module docs): wall time.
fn sdk_write(msgs: &Messages, path: &std::path::Path) -> Duration {
    use foxglove::{Context, McapCompression, McapWriteOptions, PartialMetadata, Schema};
    let _ = std::fs::remove_file(path);
    let start = Instant::now();
    let ctx = Context::new();
    let channels: Vec<_> = msgs
        .0
        .iter()
        .map(|(topic, name, data, _)| {
            ctx.channel_builder(topic.as_str())
                .message_encoding("protobuf")
                .schema(Schema::new(name.as_str(), "protobuf", data.clone()))
                .build_raw()
                .expect("channel")
        })
        .collect();
    let options = McapWriteOptions::new().compression(Some(McapCompression::Zstd));
    let file = std::io::BufWriter::new(std::fs::File::create(path).expect("file"));
    let writer = ctx
        .mcap_writer_with_options(options)
        .create(file)
        .expect("SDK writer");
    for &(c, i) in &msgs.1 {
        let (t, data) = &msgs.0[c].3[i];
        channels[c].log_with_meta(data, PartialMetadata { log_time: Some(*t) });
    }
    black_box(writer.close().expect("close"));
    start.elapsed()
}

/// flightlog's recorder at full rate on precomputed steps: wall time.
fn own_write(vehicle: &Vehicle, outs: &[StepOutput], path: &std::path::Path) -> Duration {
    let _ = std::fs::remove_file(path);
    let start = Instant::now();
    let mut rec = recorder(vehicle, path.to_owned(), None);
    for out in outs {
        rec.record(out).expect("record");
    }
    black_box(rec.finish().expect("finish"));
    start.elapsed()
}

/// See the module docs: per-round ratios of the SDK's writer to flightlog's.
fn writer_ratio() {
    let rounds: usize = std::env::var("FLAPWING_BENCH_ROUNDS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(100);
    let vehicle =
        Vehicle::from_toml(flapsim::DROSOPHILA_TOML, "drosophila").expect("built-in model");
    let steps = WINGBEATS * vehicle.sim.steps_per_wingbeat;
    let mut sim = Simulation::new(vehicle.clone(), Mode::Free);
    let outs: Vec<StepOutput> = (0..steps).map(|_| *sim.step().expect("step")).collect();
    let dir = std::env::temp_dir().join(format!("flapwing-writers-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let (own, sdk) = (dir.join("own.mcap"), dir.join("sdk.mcap"));
    own_write(&vehicle, &outs, &own);
    let msgs = read_messages(&own);
    let (mut t_own, mut t_sdk, mut ratio) = (vec![], vec![], vec![]);
    for round in 0..rounds {
        let (a, b) = if round % 2 == 0 {
            let a = own_write(&vehicle, &outs, &own);
            (a, sdk_write(&msgs, &sdk))
        } else {
            let b = sdk_write(&msgs, &sdk);
            (own_write(&vehicle, &outs, &own), b)
        };
        t_own.push(a.as_secs_f64() * 1e3);
        t_sdk.push(b.as_secs_f64() * 1e3);
        ratio.push(b.as_secs_f64() / a.as_secs_f64());
    }
    let size = |p: &std::path::Path| std::fs::metadata(p).map(|m| m.len()).unwrap_or(0);
    let [o, s, r] = [&mut t_own, &mut t_sdk, &mut ratio].map(|x| quartiles(x));
    println!(
        "writer_ratio: {rounds} rounds, {steps} free-flight samples at full rate: flightlog {:.2} ms ({} bytes), foxglove SDK McapWriter {:.2} ms ({} bytes): SDK / flightlog {:.2}x [{:.2} {:.2}]",
        o[1],
        size(&own),
        s[1],
        size(&sdk),
        r[1],
        r[0],
        r[2]
    );
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
    if !listing && filter.is_none_or(|f| "writer_ratio".contains(f.as_str())) {
        writer_ratio();
    }
}
