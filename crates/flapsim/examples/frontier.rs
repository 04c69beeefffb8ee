//! The error-cost frontier of the two load samplings (issue 37, `wingset::sampling`): for
//! each built-in vehicle, open-loop free flight from its model's initial state for
//! `DURATION` wingbeats at several steps per wingbeat, under `step_start` and `midpoint`;
//! the error of the final attitude (deg) and velocity (relative) against a `midpoint` run at
//! 3200 steps per wingbeat, and the wall time of each run (one run each: the times are for
//! reading the frontier's shape, not ratios; docs/speed.md's ratios come from interleaved
//! rounds). Prints a markdown table, one line per run.
//!
//! `cargo run --release --example frontier -- [MODEL ...]` (all built-in vehicles when none
//! is given).

use std::time::Instant;

use flapsim::{LoadSampling, Mode, Simulation, State, Vehicle, VehicleSpec};

/// Wingbeats flown per run.
const DURATION: usize = 30;
/// Steps per wingbeat of the runs compared.
const STEPS: [usize; 9] = [20, 24, 30, 40, 50, 100, 200, 400, 800];
/// Steps per wingbeat of the reference.
const REFERENCE: usize = 3200;

fn vehicle(name: &str, steps: usize, sampling: LoadSampling) -> Result<Vehicle, String> {
    let text = flapsim::builtin_model(name).ok_or_else(|| format!("no built-in {name}"))?;
    let mut spec = VehicleSpec::from_toml(text, name).map_err(|e| e.to_string())?;
    spec.sim.steps_per_wingbeat = steps;
    spec.sim.load_sampling = Some(sampling);
    spec.build(name).map_err(|e| e.to_string())
}

/// The final state and the wall time, or the error that stopped the run.
fn fly(name: &str, steps: usize, sampling: LoadSampling) -> Result<(State, f64), String> {
    let mut sim = Simulation::try_new(vehicle(name, steps, sampling)?, Mode::Free)
        .map_err(|e| e.to_string())?;
    let start = Instant::now();
    for _ in 0..steps * DURATION {
        sim.step().map_err(|e| e.to_string())?;
    }
    Ok((sim.state(), start.elapsed().as_secs_f64()))
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let names: Vec<&str> = if args.is_empty() {
        vec![
            "drosophila",
            "bumblebee",
            "robobee_kinematic",
            "dragonfly",
            "robobee",
            "hummingbird",
        ]
    } else {
        args.iter().map(String::as_str).collect()
    };
    println!(
        "| vehicle | sampling | steps/wingbeat | attitude error (deg) | velocity error (rel.) | wall time (s) |"
    );
    println!("|---|---|---|---|---|---|");
    for name in names {
        let reference = match fly(name, REFERENCE, LoadSampling::Midpoint) {
            Ok((s, _)) => s,
            Err(e) => {
                println!("| {name} | | {REFERENCE} | reference failed: {e} | | |");
                continue;
            }
        };
        for sampling in LoadSampling::ALL {
            for steps in STEPS {
                match fly(name, steps, sampling) {
                    Ok((s, t)) => {
                        let da = s
                            .world_from_body
                            .angle_to(&reference.world_from_body)
                            .to_degrees();
                        let dv = (s.velocity_m_s - reference.velocity_m_s).norm()
                            / reference.velocity_m_s.norm();
                        println!(
                            "| {name} | {} | {steps} | {da:.3e} | {dv:.3e} | {t:.4} |",
                            sampling.name()
                        );
                    }
                    Err(e) => println!(
                        "| {name} | {} | {steps} | failed: {e} | | |",
                        sampling.name()
                    ),
                }
            }
        }
    }
}
