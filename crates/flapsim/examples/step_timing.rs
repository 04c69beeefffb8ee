//! Times `steps` free-flight steps of a built-in vehicle from its trim, in-process, and
//! prints the seconds: the Rust side of the Python-overhead benchmark
//! (`crates/python/bench/bench.py` runs it interleaved with the same steps through
//! `flapwing.Simulation.run`).
//!
//! `cargo run --release -p flapsim --example step_timing -- [MODEL] [STEPS] [ROUNDS]`

use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let model = args.get(1).map_or("drosophila", String::as_str);
    let steps: u64 = args.get(2).map_or(Ok(21_800), |s| s.parse())?;
    let rounds: usize = args.get(3).map_or(Ok(1), |s| s.parse())?;
    let text = flapsim::builtin_model(model).ok_or_else(|| format!("no built-in {model}"))?;
    let v = flapsim::Vehicle::from_toml(text, model)?;
    let t = flapsim::trim::trim(&v)?;
    let v = flapsim::trim::trimmed_vehicle(&v, &t)?;
    for _ in 0..rounds {
        let mut sim = flapsim::Simulation::new(v.clone(), flapsim::Mode::Free);
        let mut summary = flapsim::SummaryBuilder::new(v.weight_n());
        let dt = sim.dt_s();
        let start = Instant::now();
        for _ in 0..steps {
            let out = sim.step()?;
            summary.observe(out, dt);
        }
        let s = start.elapsed().as_secs_f64();
        std::hint::black_box(summary.finish(sim.state()));
        println!("{s:.9}");
    }
    Ok(())
}
