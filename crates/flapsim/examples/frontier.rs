//! The error-cost frontier of the two load samplings (issue 37, `wingset::sampling`): for
//! each built-in vehicle, open-loop free flight from its model's initial state for
//! `DURATION` wingbeats at several steps per wingbeat, under `step_start` and `midpoint`;
//! the error of the final attitude (deg) and velocity (relative) against a `midpoint` run at
//! 3200 steps per wingbeat, and the wall time of each run (one run each: the times are for
//! reading the frontier's shape, not ratios; docs/speed.md's ratios come from interleaved
//! rounds). Prints a markdown table, one line per run.
//!
//! `cargo run --release --example frontier -- [--plot FILE.svg] [MODEL ...]` (all built-in
//! vehicles when none is given); `--plot` also draws the attitude error against the steps
//! per wingbeat, log-log, one colour per vehicle, the midpoint sampling solid and the
//! step-start sampling thin.

use std::time::Instant;

use plotters::prelude::*;

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

/// One run's attitude error, deg (`None`: it diverged).
type Row = (String, LoadSampling, usize, Option<f64>);

/// The frontier as an SVG (or a PNG, by the file's extension): attitude error against
/// steps per wingbeat, log-log.
fn plot(path: &str, rows: &[Row]) -> Result<(), Box<dyn std::error::Error>> {
    if path.ends_with(".png") {
        draw(
            BitMapBackend::new(path, (900, 600)).into_drawing_area(),
            rows,
        )
    } else {
        draw(SVGBackend::new(path, (900, 600)).into_drawing_area(), rows)
    }
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    rows: &[Row],
) -> Result<(), Box<dyn std::error::Error>>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "error-cost frontier: open loop, 30 wingbeats, against 3200 steps per wingbeat",
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d((15.0f64..900.0).log_scale(), (1e-6f64..100.0).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("steps per wingbeat (midpoint: 1.10x the cost per step)")
        .x_label_formatter(&|x| format!("{x:.0}"))
        .y_desc("final attitude error [deg]")
        .draw()?;
    let colors = [RED, BLUE, GREEN, MAGENTA, CYAN, BLACK];
    let mut names: Vec<&str> = Vec::new();
    for r in rows {
        if !names.contains(&r.0.as_str()) {
            names.push(&r.0);
        }
    }
    for (i, name) in names.iter().enumerate() {
        let color = colors[i % colors.len()];
        for sampling in LoadSampling::ALL {
            let points: Vec<(f64, f64)> = rows
                .iter()
                .filter(|r| r.0 == *name && r.1 == sampling)
                .filter_map(|r| r.3.map(|e| (r.2 as f64, e.max(1e-6))))
                .collect();
            let width = if sampling == LoadSampling::Midpoint {
                3
            } else {
                1
            };
            let series = chart.draw_series(LineSeries::new(
                points.iter().copied(),
                color.stroke_width(width),
            ))?;
            series
                .label(format!("{name}, {}", sampling.name()))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(width))
                });
            chart.draw_series(points.iter().map(|&p| Circle::new(p, 3, color.filled())))?;
        }
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerLeft)
        .border_style(BLACK)
        .background_style(WHITE.mix(0.8))
        .draw()?;
    root.present()?;
    Ok(())
}

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let plot_path = match args.iter().position(|a| a == "--plot") {
        Some(i) if i + 1 < args.len() => {
            let p = args.remove(i + 1);
            args.remove(i);
            Some(p)
        }
        _ => None,
    };
    let mut rows: Vec<Row> = Vec::new();
    let names: Vec<&str> = if args.is_empty() {
        flapsim::BUILTIN_MODELS.to_vec()
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
                        rows.push((name.to_owned(), sampling, steps, Some(da)));
                    }
                    Err(e) => {
                        println!(
                            "| {name} | {} | {steps} | failed: {e} | | |",
                            sampling.name()
                        );
                        rows.push((name.to_owned(), sampling, steps, None));
                    }
                }
            }
        }
    }
    if let Some(path) = plot_path {
        if let Err(e) = plot(&path, &rows) {
            eprintln!("error: could not draw {path}: {e}");
            std::process::exit(1);
        }
        eprintln!("wrote {path}");
    }
}
