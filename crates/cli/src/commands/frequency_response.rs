//! `flapwing frequency-response`: sweep the drive frequency (and optionally the voltage) of
//! a tethered actuated vehicle and report stroke and pitch amplitude, the pitch-to-stroke
//! phase, mean lift and lift per volt, with the stroke system's natural frequency from the
//! model. The analysis is `flapsim::actuated::frequency_response`.

use std::fmt::Write;
use std::sync::atomic::{AtomicU64, Ordering};

use anyhow::Result;
use flapsim::actuated::{ResponseOptions, frequency_response};
use serde::Serialize;

use crate::error::input_error;
use crate::vehicle::{build_vehicle, read_vehicle, sim_error};

/// Arguments of `flapwing frequency-response`.
#[derive(Debug, clap::Args)]
pub struct FrequencyResponseArgs {
    /// Actuated vehicle model: a TOML file with an [actuation] section or a built-in name
    /// (robobee, hummingbird).
    #[arg(long, value_name = "FILE|NAME", default_value = "robobee")]
    pub model: String,
    /// Lowest drive frequency, Hz (default: half the stroke's natural frequency).
    #[arg(long)]
    pub from_hz: Option<f64>,
    /// Highest drive frequency, Hz (default: 1.5 times the stroke's natural frequency).
    #[arg(long)]
    pub to_hz: Option<f64>,
    /// Number of frequencies, evenly spaced.
    #[arg(long, default_value_t = 21)]
    pub points: usize,
    /// Drive amplitudes to sweep, V, comma separated (default: the model's).
    #[arg(long, value_delimiter = ',', value_name = "V,V,...")]
    pub voltages: Vec<f64>,
    /// Drive periods run from rest before measuring.
    #[arg(long, default_value_t = 30)]
    pub settle_cycles: usize,
    /// Drive periods measured.
    #[arg(long, default_value_t = 4)]
    pub measure_cycles: usize,
    /// Steps per drive period.
    #[arg(long, default_value_t = 100)]
    pub steps_per_cycle: usize,
    /// Draw a Bode-style figure (amplitudes, phases, lift against frequency) to this SVG
    /// file (PNG when it ends in .png; other extensions are refused).
    #[arg(long, value_name = "FILE")]
    pub plot: Option<std::path::PathBuf>,
    /// Replace the --plot file if it already exists.
    #[arg(long)]
    pub force: bool,
    /// Print one JSON document on stdout instead of the table.
    #[arg(long)]
    pub json: bool,
}

#[derive(Serialize)]
struct Report<'a> {
    model: &'a str,
    weight_n: f64,
    #[serde(flatten)]
    response: &'a flapsim::actuated::FrequencyResponse,
}

/// Runs the command.
pub fn run(args: FrequencyResponseArgs) -> Result<()> {
    let src = read_vehicle(Some(args.model.as_str()))?;
    let vehicle = build_vehicle(&src)?;
    let Some(act) = &vehicle.actuation else {
        return Err(input_error(format!(
            "{}: no [actuation] section: frequency-response needs an actuated vehicle (built-ins: robobee, hummingbird)",
            src.origin
        )));
    };
    let f_n = act.dynamics.stroke_natural_freq_hz();
    let from = args.from_hz.unwrap_or(0.5 * f_n);
    let to = args.to_hz.unwrap_or(1.5 * f_n);
    if !(from.is_finite() && to.is_finite() && from > 0.0 && to >= from && to <= 1e5) {
        return Err(input_error(format!(
            "--from-hz {from} --to-hz {to} is not allowed: 0 < from <= to <= 100000 Hz"
        )));
    }
    if !(1..=1000).contains(&args.points) {
        return Err(input_error(format!(
            "--points {} is not allowed: an integer in [1, 1000]",
            args.points
        )));
    }
    if !(20..=10_000).contains(&args.steps_per_cycle)
        || !(1..=1000).contains(&args.measure_cycles)
        || args.settle_cycles > 10_000
    {
        return Err(input_error(format!(
            "--steps-per-cycle {} --measure-cycles {} --settle-cycles {} is not allowed: steps in [20, 10000], measured cycles in [1, 1000], settling cycles at most 10000",
            args.steps_per_cycle, args.measure_cycles, args.settle_cycles
        )));
    }
    let limit = act.dynamics.stroke.voltage_limit_v();
    for &v in &args.voltages {
        if !(v.is_finite() && v > 0.0) {
            return Err(input_error(format!(
                "--voltages {v} is not allowed: amplitudes > 0 V (up to the actuator's {limit} V limit)"
            )));
        }
    }
    let plot_file = crate::outputs::create_plot(&src.origin, args.plot.as_deref(), args.force)?;
    let freqs: Vec<f64> = (0..args.points)
        .map(|i| {
            if args.points == 1 {
                from
            } else {
                from + (to - from) * i as f64 / (args.points - 1) as f64
            }
        })
        .collect();
    let opts = ResponseOptions {
        freqs_hz: freqs,
        amplitudes_v: args.voltages.clone(),
        settle_cycles: args.settle_cycles,
        measure_cycles: args.measure_cycles,
        steps_per_cycle: args.steps_per_cycle,
    };
    let n = (args.points * args.voltages.len().max(1)) as u64;
    let bar = crate::progress::progress_bar(n, "frequency response", "points");
    let done = AtomicU64::new(0);
    let resp = frequency_response(&vehicle, &opts, &|| {
        bar.set_position(done.fetch_add(1, Ordering::Relaxed) + 1);
    })
    .map_err(|e| match e {
        flapsim::Error::Analysis(m) => input_error(m),
        e => sim_error(e),
    })?;
    bar.finish_and_clear();
    if let (Some(file), Some(path)) = (plot_file, &args.plot) {
        drop(file);
        super::frequency_response_plot::plot(
            &resp,
            path,
            &format!("frequency response of {}", src.origin),
        )?;
        crate::output::note(&format!("wrote {}", path.display()));
    }
    let stopped = resp.points.iter().filter(|p| p.failed.is_some()).count();
    if stopped > 0 {
        crate::output::note(&format!(
            "warning: {stopped} of {} points have no steady response (the run stopped; the table says why)",
            resp.points.len()
        ));
    }
    if resp.points.iter().any(|p| p.wake_capture_out_of_range) {
        crate::output::note(
            "warning: some points' measured wake-capture inputs are outside the fitted range (Re 136-6800, dtau 0.06-0.18): clamped",
        );
    }
    if args.json {
        return crate::output::print_json(&Report {
            model: &src.origin,
            weight_n: vehicle.weight_n(),
            response: &resp,
        });
    }
    let mut o = String::new();
    writeln!(
        o,
        "frequency response of {} (tethered, both wings, {} settling + {} measured periods at {} steps)",
        src.origin, args.settle_cycles, args.measure_cycles, args.steps_per_cycle
    )?;
    writeln!(
        o,
        "stroke natural frequency {:.2} Hz (undamped, from the model); pitch mode {:.2} Hz (stroke held)",
        resp.stroke_natural_freq_hz, resp.pitch_natural_freq_hz
    )?;
    writeln!(
        o,
        "{:>9} {:>7} {:>10} {:>10} {:>10} {:>10} {:>11} {:>12} {:>6} {:>8}",
        "freq_Hz",
        "volt_V",
        "stroke_deg",
        "pitch_deg",
        "phase_deg",
        "lag_deg",
        "lift_N",
        "lift_per_V",
        "L/W",
        "Re"
    )?;
    for p in &resp.points {
        if let Some(why) = &p.failed {
            writeln!(
                o,
                "{:>9.2} {:>7.2}  no steady response: {why}",
                p.freq_hz, p.amplitude_v
            )?;
            continue;
        }
        writeln!(
            o,
            "{:>9.2} {:>7.2} {:>10.2} {:>10.2} {:>+10.2} {:>10.2} {:>11.4e} {:>12.4e} {:>6.3} {:>8.1}",
            p.freq_hz,
            p.amplitude_v,
            p.stroke_amplitude_deg,
            p.pitch_amplitude_deg,
            p.pitch_phase_deg,
            p.stroke_lag_deg,
            p.mean_lift_n,
            p.lift_per_volt_n_v,
            p.lift_to_weight,
            p.reynolds,
        )?;
    }
    writeln!(
        o,
        "stroke/pitch: half peak-to-peak; phase: pitch vs stroke (0 symmetric rotation, + advanced); lag: stroke behind the drive voltage"
    )?;
    crate::output::print_stdout(&o)?;
    if stopped == resp.points.len() {
        return Err(anyhow::anyhow!(
            "no point of the sweep has a steady response (every run stopped; see the table)"
        ));
    }
    Ok(())
}
