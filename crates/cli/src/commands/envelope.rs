//! `flapwing envelope`: trim, power, limit margin and modes over a grid of forward speeds
//! and climb rates (`flapstudy::envelope`), in parallel with a progress bar; a table on
//! stdout, `--json`, `--csv` and `--plot` (power required and mode loci against speed).

use std::fmt::Write;
use std::path::PathBuf;

use anyhow::Result;
use flapstudy::envelope::{EnvelopeGrid, EnvelopeRow, INTERRUPTED, envelope, to_csv};

use crate::error::InputContext;
use crate::vehicle::{build_vehicle, read_vehicle};

/// Arguments of `flapwing envelope`.
#[derive(Debug, clap::Args)]
pub struct EnvelopeArgs {
    /// Vehicle model: a TOML file or a built-in name (drosophila, bumblebee, robobee_kinematic, dragonfly; actuated: robobee, hummingbird).
    #[arg(long, value_name = "FILE|NAME")]
    pub model: Option<String>,
    /// The induced flow the wings meet, in place of the model's `[aero] inflow`: `frozen`
    /// (the hover downwash held at each condition), `dynamic` (each pair's wake answers its
    /// loads and the body; issue #38) or `off` (still air).
    #[arg(long, value_name = "MODEL", value_parser = crate::vehicle::parse_inflow)]
    pub inflow: Option<wingforce::InflowModel>,
    /// What carries the weight at every point, as `trim --vary` (default: the model's
    /// `[trim] lift_variable`, else the amplitude); `angle-of-attack` holds the stroke
    /// amplitude and frequency, as Dudley & Ellington's bumblebees flew.
    #[arg(long, value_enum)]
    pub vary: Option<crate::commands::trim::Vary>,
    /// Forward speeds, m/s, comma separated (default: 10 speeds from 0 to 4.5 m/s, the
    /// range Dudley & Ellington 1990 filmed bumblebees over).
    #[arg(
        long = "speeds-m-s",
        value_name = "U,...",
        value_delimiter = ',',
        allow_negative_numbers = true
    )]
    pub speeds_m_s: Vec<f64>,
    /// Climb rates, m/s, comma separated (default: 0).
    #[arg(
        long = "climbs-m-s",
        value_name = "W,...",
        value_delimiter = ',',
        allow_negative_numbers = true
    )]
    pub climbs_m_s: Vec<f64>,
    /// Write the table as CSV to this file.
    #[arg(long, value_name = "FILE.csv")]
    pub csv: Option<PathBuf>,
    /// Plot the power required, the trim angles and the modes' real parts against speed
    /// (FILE.svg: SVG, FILE.png: PNG; other extensions are refused).
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
    /// Replace the --csv and --plot files if they exist.
    #[arg(long)]
    pub force: bool,
    /// Print one JSON document on stdout instead of the text table.
    #[arg(long)]
    pub json: bool,
}

/// Runs the command.
pub fn run(args: EnvelopeArgs) -> Result<()> {
    let src = read_vehicle(args.model.as_deref())?;
    let mut vehicle = crate::vehicle::with_inflow(build_vehicle(&src)?, args.inflow)?;
    vehicle.trim_lift = crate::commands::trim::Vary::or_model(args.vary, &vehicle);
    let speeds = if args.speeds_m_s.is_empty() {
        (0..10).map(|i| 0.5 * i as f64).collect()
    } else {
        args.speeds_m_s.clone()
    };
    let climbs = if args.climbs_m_s.is_empty() {
        vec![0.0]
    } else {
        args.climbs_m_s.clone()
    };
    let grid = EnvelopeGrid::new(speeds, climbs, "--speeds-m-s / --climbs-m-s")
        .input_context("envelope grid")?;
    // Fail before the work if an output cannot be written: the plot's format, then both
    // outputs together (distinct, not the model file, existing ones only with --force).
    crate::outputs::check_csv_and_plot(
        &crate::outputs::model_input(&src.origin),
        args.csv.as_deref(),
        args.plot.as_deref(),
        args.force,
    )?;
    let csv_file = match &args.csv {
        Some(p) => Some(crate::output::create_output_file(p, args.force, "CSV")?),
        None => None,
    };
    if let Some(p) = &args.plot {
        drop(crate::output::create_output_file(p, args.force, "plot")?);
    }
    let n = grid.conditions().len();
    let bar =
        crate::progress::progress_bar(n as u64, format!("envelope of {}", vehicle.name), "points");
    let rows = envelope(
        &vehicle,
        &grid,
        &|_| bar.inc(1),
        &crate::interrupt::requested,
    );
    bar.finish_and_clear();
    if let (Some(mut f), Some(path)) = (csv_file, &args.csv) {
        std::io::Write::write_all(&mut f, to_csv(&rows).as_bytes())?;
        crate::output::note(&format!("wrote {}", path.display()));
    }
    if let Some(p) = &args.plot {
        crate::commands::envelope_plot::plot(&rows, p, &vehicle.name)?;
        crate::output::note(&format!("wrote {}", p.display()));
    }
    if rows.iter().any(|r| r.no_trim_reason == INTERRUPTED) {
        print_table(&src.origin, &rows, &vehicle)?;
        anyhow::bail!("interrupted: the points marked `interrupted` did not run");
    }
    if args.json {
        crate::output::print_json(&rows)?;
    } else {
        print_table(&src.origin, &rows, &vehicle)?;
    }
    if rows.iter().all(|r| r.point.is_none()) {
        anyhow::bail!(
            "no point of the envelope trims (each row says why): {}",
            rows[0].no_trim_reason
        );
    }
    Ok(())
}

fn print_table(origin: &str, rows: &[EnvelopeRow], vehicle: &flapsim::Vehicle) -> Result<()> {
    let mass_kg = vehicle.mass_kg;
    let mut o = String::new();
    writeln!(
        o,
        "flight envelope of {origin} (averaged model; modes about each trim)"
    )?;
    writeln!(o, "induced flow: {}", vehicle.inflow_model().describe())?;
    writeln!(
        o,
        "{:>7} {:>7} {:>8} {:>8} {:>8} {:>10} {:>7} {:>9} {:>9}  modes / reason",
        "U m/s", "W m/s", "pitch", "plane", "ampl", "power W", "W/kg", "margin", "sigma 1/s"
    )?;
    for r in rows {
        let c = &r.condition;
        match &r.point {
            Some(p) => {
                let sigma = p
                    .longitudinal_modes
                    .iter()
                    .chain(&p.lateral_modes)
                    .map(|m| m.re_per_s)
                    .fold(f64::NEG_INFINITY, f64::max);
                let unstable = |what: &str, modes: &[flapsim::stability::ModeInfo]| {
                    let u: Vec<&str> = modes
                        .iter()
                        .filter(|m| !m.stable && m.time_to_half_or_double_s.is_some())
                        .map(|m| m.description.as_str())
                        .collect();
                    (!u.is_empty()).then(|| format!("{what}: {}", u.join(", ")))
                };
                let unstable: Vec<String> = [
                    unstable("lon", &p.longitudinal_modes),
                    unstable("lat", &p.lateral_modes),
                ]
                .into_iter()
                .flatten()
                .collect();
                writeln!(
                    o,
                    "{:>7.2} {:>7.2} {:>8.2} {:>8.2} {:>8.2} {:>10.3e} {:>7.1} {:>8.1}% {:>+9.3}  {}",
                    c.forward_speed_m_s,
                    c.climb_rate_m_s,
                    p.trim.pitch_rad.to_degrees(),
                    p.point.stroke_plane_angle_rad.to_degrees(),
                    p.point.stroke_amplitude_rad.to_degrees(),
                    p.point.power.aero_w,
                    p.point.power.aero_w / mass_kg,
                    100.0 * p.margin.fraction,
                    sigma,
                    if unstable.is_empty() {
                        "all stable".to_owned()
                    } else {
                        unstable.join("; ")
                    }
                )?;
            }
            None => writeln!(
                o,
                "{:>7.2} {:>7.2}  no trim: {}",
                c.forward_speed_m_s, c.climb_rate_m_s, r.no_trim_reason
            )?,
        }
    }
    writeln!(
        o,
        "pitch: body pitch, deg; plane: stroke plane to the horizontal, deg (tilted forward > 0); ampl: stroke amplitude, deg; power: aerodynamic, W (W/kg of body mass); margin: to the amplitude or voltage limit; sigma: the largest real part of the modes' eigenvalues, 1/s (> 0: a mode grows); modes: the unstable ones, longitudinal (lon) and lateral (lat)"
    )?;
    crate::output::print_stdout(&o)
}
