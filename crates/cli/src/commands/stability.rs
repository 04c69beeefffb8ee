//! `flapwing stability`: averaged-model modes (Sun and Xiong 2005's method) beside the
//! Floquet exponents of the full time-periodic system, and a plot of the eigenvalues.

use std::fmt::Write;
use std::path::{Path, PathBuf};

use anyhow::Result;
use flapsim::stability::{ModeInfo, StabilityReport};
use plotters::prelude::*;

use crate::vehicle::{build_vehicle, read_vehicle, sim_error};

/// Arguments of `flapwing stability`.
#[derive(Debug, clap::Args)]
pub struct StabilityArgs {
    /// Vehicle model: a TOML file or a built-in name (drosophila, bumblebee, robobee_kinematic, dragonfly; actuated: robobee, hummingbird).
    #[arg(long, value_name = "FILE|NAME")]
    pub model: Option<String>,
    /// The induced flow the wings meet, in place of the model's `[aero] inflow`: `frozen`
    /// (the hover downwash held at the condition), `dynamic` (each pair's wake answers its
    /// loads and the body; issue #38) or `off` (still air).
    #[arg(long, value_name = "MODEL", value_parser = crate::vehicle::parse_inflow)]
    pub inflow: Option<wingforce::InflowModel>,
    /// Skip the Floquet analysis (full simulations over one wingbeat).
    #[arg(long = "no-floquet")]
    pub no_floquet: bool,
    /// Steps per wingbeat for the analysis, in place of the model's `[sim]
    /// steps_per_wingbeat` (10 to 100000): the full simulations of the Floquet analysis and
    /// an actuated vehicle's periodic wing motion. Run it at twice the step to see whether
    /// the Floquet exponents have converged (docs/commands.md, "Averaged against Floquet").
    #[arg(long, value_name = "N")]
    pub steps_per_wingbeat: Option<usize>,
    /// The flight condition to trim at and analyse about (hover by default).
    #[command(flatten)]
    pub condition: crate::condition::ConditionArgs,
    /// Write a plot of the eigenvalues in the complex plane (FILE.svg: SVG, FILE.png: PNG;
    /// other extensions are refused).
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
    /// Replace the --plot file if it exists.
    #[arg(long)]
    pub force: bool,
    /// Print one JSON document on stdout instead of the text report.
    #[arg(long)]
    pub json: bool,
}

/// Runs the command.
pub fn run(args: StabilityArgs) -> Result<()> {
    let src = read_vehicle(args.model.as_deref())?;
    let mut vehicle = crate::vehicle::with_inflow(build_vehicle(&src)?, args.inflow)?;
    if let Some(n) = args.steps_per_wingbeat {
        if !(10..=100_000).contains(&n) {
            return Err(crate::error::input_error(format!(
                "--steps-per-wingbeat {n}: allowed 10 to 100000 steps per wingbeat"
            )));
        }
        vehicle.sim.steps_per_wingbeat = n;
        crate::vehicle::warn_coarse_step(&vehicle);
    }
    let condition = args.condition.check(&vehicle)?;
    // Fail before the analysis if the plot cannot be written.
    drop(crate::outputs::create_plot(
        &src.origin,
        args.plot.as_deref(),
        args.force,
    )?);
    let report = flapsim::stability::analyze_at(&vehicle, &condition, !args.no_floquet)
        .map_err(sim_error)?;
    for w in &report.floquet_warnings {
        eprintln!("warning: Floquet analysis: {w}");
    }
    if let Some(p) = &args.plot {
        plot(&report, p, &vehicle.name)?;
    }
    if args.json {
        return crate::output::print_json(&report);
    }
    let mut o = String::new();
    let t = &report.trim;
    writeln!(
        o,
        "{} stability of {} about its trim (pitch {:.2} deg, {})",
        if condition.is_hover() {
            "hover".to_owned()
        } else {
            condition.describe()
        },
        src.origin,
        t.pitch_rad.to_degrees(),
        crate::vehicle::trim_summary(&vehicle, t)
    )?;
    writeln!(o, "induced flow: {}", vehicle.inflow_model().describe())?;
    writeln!(
        o,
        "averaged model, longitudinal (states {}):",
        report.longitudinal_states.join(", ")
    )?;
    for m in &report.longitudinal_modes {
        writeln!(o, "  {}", describe(m))?;
    }
    if !report.floquet_longitudinal.is_empty() {
        writeln!(
            o,
            "Floquet exponents of the full periodic system, longitudinal ({} steps per wingbeat):",
            vehicle.sim.steps_per_wingbeat
        )?;
        for f in &report.floquet_longitudinal {
            writeln!(
                o,
                "  {:+.4} {:+.4}i 1/s   (multiplier {:.6} {:+.6}i)",
                f.exponent.0, f.exponent.1, f.multiplier.0, f.multiplier.1
            )?;
        }
    }
    writeln!(
        o,
        "averaged model, lateral (states {}):",
        report.lateral_states.join(", ")
    )?;
    for m in &report.lateral_modes {
        writeln!(o, "  {}", describe(m))?;
    }
    let r = &report.nondimensional_reference;
    writeln!(
        o,
        "longitudinal derivatives (x forward, z up, q > 0 nose down), non-dimensional as Sun & Xiong 2005: U = 2 Phi n r_2 = {:.4} m/s (Phi {:.2} deg, n {:.2} Hz, r_2 {:.4e} m), time 1/n, force 0.5 rho U^2 S_t = {:.4e} N, moments with c = {:.4e} m:",
        r.speed_m_s,
        r.stroke_amplitude_rad.to_degrees(),
        r.freq_hz,
        r.r2_m,
        r.force_n,
        r.chord_m
    )?;
    for d in &report.nondimensional {
        writeln!(
            o,
            "  {:<4} {:>12.4e} {:<10} {:>+10.4}",
            d.name, d.value, d.unit, d.nondimensional
        )?;
    }
    writeln!(o, "longitudinal system matrix:")?;
    for row in &report.a_longitudinal {
        writeln!(
            o,
            "  {}",
            row.iter()
                .map(|x| format!("{x:>12.4e}"))
                .collect::<Vec<_>>()
                .join(" ")
        )?;
    }
    crate::output::print_stdout(&o)
}

fn describe(m: &ModeInfo) -> String {
    let timing = match (m.time_to_half_or_double_s, m.stable) {
        (None, _) => "no growth or decay".to_owned(),
        (Some(t), true) => format!("half time {t:.4} s"),
        (Some(t), false) => format!("doubling time {t:.4} s"),
    };
    let period = m
        .period_s
        .map(|p| format!(", period {p:.4} s"))
        .unwrap_or_default();
    let big: Vec<String> = m
        .eigenvector
        .iter()
        .filter(|(_, x)| *x > 0.3)
        .map(|(n, x)| format!("{n} {x:.2}"))
        .collect();
    format!(
        "{:<22} lambda = {:+.4} {:+.4}i 1/s, {timing}{period}  [{}]",
        m.description,
        m.re_per_s,
        m.im_rad_s,
        big.join(", ")
    )
}

fn plot(r: &StabilityReport, path: &Path, name: &str) -> Result<()> {
    let mut pts: Vec<(f64, f64, u8)> = Vec::new();
    for m in &r.longitudinal_modes {
        pts.push((m.re_per_s, m.im_rad_s, 0));
        pts.push((m.re_per_s, -m.im_rad_s, 0));
    }
    for m in &r.lateral_modes {
        pts.push((m.re_per_s, m.im_rad_s, 1));
        pts.push((m.re_per_s, -m.im_rad_s, 1));
    }
    for f in &r.floquet_longitudinal {
        pts.push((f.exponent.0, f.exponent.1, 2));
    }
    let xmax = pts.iter().map(|p| p.0.abs()).fold(1.0, f64::max) * 1.1;
    let ymax = pts.iter().map(|p| p.1.abs()).fold(1.0, f64::max) * 1.2;
    crate::plot::render!(path, (800, 600), draw(&pts, xmax, ymax, name))
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    pts: &[(f64, f64, u8)],
    xmax: f64,
    ymax: f64,
    name: &str,
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    let e = crate::plot::draw_error::<DB::ErrorType>;
    root.fill(&WHITE).map_err(e)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(format!("{name}: hover eigenvalues"), ("sans-serif", 20))
        .margin(15)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(-xmax..xmax, -ymax..ymax)
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc("Re [1/s]")
        .y_desc("Im [rad/s]")
        .draw()
        .map_err(e)?;
    let styles = [
        ("averaged, longitudinal", BLUE),
        ("averaged, lateral", GREEN),
        ("Floquet, longitudinal", RED),
    ];
    for (k, (label, color)) in styles.iter().enumerate() {
        let c = *color;
        let series: Vec<(f64, f64)> = pts
            .iter()
            .filter(|p| p.2 as usize == k)
            .map(|p| (p.0, p.1))
            .collect();
        if k == 2 {
            chart
                .draw_series(
                    series
                        .iter()
                        .map(|&(x, y)| Cross::new((x, y), 7, c.stroke_width(2))),
                )
                .map_err(e)?
                .label(*label)
                .legend(move |(x, y)| Cross::new((x, y), 5, c.stroke_width(2)));
        } else {
            chart
                .draw_series(
                    series
                        .iter()
                        .map(|&(x, y)| Circle::new((x, y), 4, c.filled())),
                )
                .map_err(e)?
                .label(*label)
                .legend(move |(x, y)| Circle::new((x, y), 4, c.filled()));
        }
    }
    chart
        .draw_series(std::iter::once(PathElement::new(
            vec![(0.0, -ymax), (0.0, ymax)],
            BLACK.mix(0.4),
        )))
        .map_err(e)?;
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(e)?;
    root.present().map_err(e)?;
    Ok(())
}
