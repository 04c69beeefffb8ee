//! `flapwing simulate`: fly (or tether) a vehicle for a while and summarise the run.

use std::fmt::Write;

use anyhow::Result;
use flapsim::sensor_run::SensorSummary;
use flapsim::{Mode, RunSummary, Simulation, SummaryBuilder};
use serde::Serialize;
use wingforce::Term;

use crate::vehicle::{build_vehicle, check_duration, read_vehicle, sim_error};

/// Arguments of `flapwing simulate`.
#[derive(Debug, clap::Args)]
pub struct SimulateArgs {
    /// Vehicle model: a TOML file or a built-in name (drosophila, bumblebee, robobee_kinematic, dragonfly; actuated: robobee, hummingbird).
    #[arg(long, value_name = "FILE|NAME")]
    pub model: Option<String>,
    /// Simulated time, s.
    #[arg(long = "duration-s", default_value_t = 0.1)]
    pub duration_s: f64,
    /// Hold the body still and report the loads like a force sensor.
    #[arg(long, conflicts_with = "longitudinal")]
    pub tethered: bool,
    /// Free flight with only surge, heave and pitch.
    #[arg(long)]
    pub longitudinal: bool,
    /// Print one JSON document on stdout instead of the text report.
    #[arg(long)]
    pub json: bool,
    /// Log outputs.
    #[command(flatten)]
    pub log: crate::logging::LogArgs,
    /// Pacing and the live view's start.
    #[command(flatten)]
    pub pace: crate::pacing::PaceArgs,
    /// Sensors.
    #[command(flatten)]
    pub sensors: crate::sensing::SensorArgs,
    /// Wind (the model's `[wind]` unless changed here).
    #[command(flatten)]
    pub wind: crate::wind::WindArgs,
}

#[derive(Serialize)]
struct Report<'a> {
    model: &'a str,
    mode: &'a str,
    dt_s: f64,
    steps_per_wingbeat: usize,
    weight_n: f64,
    /// The added-mass term's form (`impulse`, `paper` for eq 7-8, or `off`).
    added_mass_form: &'static str,
    /// The induced flow the wings meet (`off`, `frozen` or `dynamic`; `[aero] inflow`).
    inflow_model: &'static str,
    summary: &'a RunSummary,
    /// What the model's sensors sampled (`None` without sensors).
    sensors: Option<&'a SensorSummary>,
    /// The run's `[wind]` (absent: still air).
    #[serde(skip_serializing_if = "Option::is_none")]
    wind: Option<&'a flapsim::WindSpec>,
    error: Option<String>,
}

/// Runs the command.
pub fn run(args: SimulateArgs) -> Result<()> {
    let src = read_vehicle(args.model.as_deref())?;
    let vehicle = build_vehicle(&src)?;
    let duration_s = check_duration(args.duration_s)?;
    let mut pacer = crate::pacing::check(&args.pace, duration_s)?;
    let mode = if args.tethered {
        Mode::Tethered
    } else if args.longitudinal {
        Mode::LONGITUDINAL
    } else {
        Mode::Free
    };
    let mode_name = if args.tethered {
        "tethered"
    } else if args.longitudinal {
        "longitudinal"
    } else {
        "free"
    };
    let weight = vehicle.weight_n();
    let added_mass = vehicle.wings[0].options().added_mass;
    let inflow_model = vehicle.inflow_model();
    let steps_per_wingbeat = vehicle.sim.steps_per_wingbeat;
    let name = vehicle.name.clone();
    let rate = if args.log.full_rate {
        None
    } else {
        Some(args.log.log_rate_hz)
    };
    let wind_spec = crate::wind::spec(&args.wind, &vehicle)?;
    let wind = crate::wind::start(&args.wind, &vehicle, &src.origin, duration_s)?;
    let wind_text = wind.as_ref().map(crate::wind::describe);
    let settings = flightlog::SimSettings::new(mode, duration_s, rate, [0.0; 3]).to_json();
    // A wind field the flags made (not the embedded model's) goes into the settings, as
    // `hover` does, so that `identify` replays the wind the run met.
    // `null` when `--no-wind` switched the model's off (`replay --check` re-runs still air).
    let settings = if wind_spec.as_ref() != vehicle.wind.as_ref() {
        let mut v: serde_json::Value = serde_json::from_str(&settings)?;
        v["wind"] = serde_json::to_value(&wind_spec)?;
        v.to_string()
    } else {
        settings
    };
    let mut sensors = crate::sensing::start(&args.sensors, &vehicle)?;
    // `/wind` in runs with a wind field (the model's `[wind]` or the wind flags).
    let log_wind = wind.is_some();
    let mut rec = crate::logging::open(
        &args.log,
        "simulate",
        &src,
        &vehicle,
        settings,
        false,
        crate::logging::Channels {
            sensors: sensors.is_some(),
            wind: log_wind,
            estimate: false,
        },
    )?;
    crate::pacing::wait_for_client(&args.pace, args.log.foxglove.as_deref(), rec.as_ref())?;
    let mut log_error = None;
    let mut flushed_reported = 0;
    let mut sim = Simulation::new(vehicle, mode);
    sim.set_wind_model(wind);
    let dt = sim.dt_s();
    let n = (duration_s / dt).round() as u64;
    let bar = crate::progress::progress_bar(n, "simulating", "steps");
    let mut summary = SummaryBuilder::new(weight);
    // Simulation::run_while's loop, with the simulation's wing winds after each step.
    let mut result = Ok(true);
    for _ in 0..n {
        // A copy, so that the wing set's output of the step can be read beside it.
        let out = match sim.step() {
            Ok(out) => *out,
            Err(e) => {
                result = Err(e);
                break;
            }
        };
        let (t_s, step) = (out.t_s, out.step);
        crate::pacing::pace(&mut pacer, t_s);
        summary.observe(&out, dt);
        let logged = crate::logging::record_all(&mut rec, &out, &sim)
            .and_then(|()| crate::sensing::observe(&mut sensors, &mut rec, &out))
            .and_then(|()| match log_wind {
                true => crate::logging::record_wind(&mut rec, t_s, &sim),
                false => Ok(()),
            });
        if let Err(e) = logged {
            log_error = Some(e);
            result = Ok(false);
            break;
        }
        if args.log.report_flushed {
            crate::logging::report_flushed(&rec, &mut flushed_reported);
        }
        if step % 1024 == 0 {
            bar.set_position(step);
        }
        if crate::interrupt::requested() {
            result = Ok(false);
            break;
        }
    }
    bar.finish_and_clear();
    let s = summary.finish(sim.state());
    let failure = result.as_ref().err().map(|e| e.to_string());
    let interrupted = matches!(result, Ok(false));
    crate::logging::finish(rec, sim.time_s(), failure, interrupted, log_error)?;
    let error = match &result {
        Err(e) => Some(e.to_string()),
        Ok(false) => Some("interrupted (Ctrl-C)".to_owned()),
        Ok(true) => None,
    };
    let report = Report {
        model: &src.origin,
        mode: mode_name,
        dt_s: dt,
        steps_per_wingbeat,
        weight_n: weight,
        added_mass_form: added_mass.name(),
        inflow_model: inflow_model.name(),
        summary: &s,
        sensors: sensors.as_ref().map(|r| r.summary()),
        wind: wind_spec.as_ref(),
        error: error.clone(),
    };
    if args.json {
        crate::output::print_json(&report)?;
    } else {
        print_text(&name, &report, wind_text.as_deref())?;
    }
    match result.map_err(sim_error)? {
        true => Ok(()),
        false => Err(anyhow::anyhow!(
            "interrupted by Ctrl-C after {:.4} s",
            s.duration_s
        )),
    }
}

fn print_text(name: &str, r: &Report<'_>, wind: Option<&str>) -> Result<()> {
    let s = r.summary;
    let mut o = String::new();
    writeln!(
        o,
        "{name} ({}), {} flight, {:.4} s = {} steps (dt {:.3e} s, {} steps per wingbeat)",
        r.model, r.mode, s.duration_s, s.steps, r.dt_s, r.steps_per_wingbeat
    )?;
    if let Some(w) = wind {
        writeln!(o, "{w}")?;
    }
    writeln!(
        o,
        "cycle means over {} complete wingbeats, body frame (x fwd, y left, z up), about the CoM:",
        s.wingbeats_averaged
    )?;
    writeln!(
        o,
        "  {:<14} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12}",
        "term", "Fx [N]", "Fy [N]", "Fz [N]", "Mx [N m]", "My [N m]", "Mz [N m]"
    )?;
    for (t, l) in Term::ALL
        .iter()
        .zip(&s.mean_terms)
        .map(|(t, l)| (t.name(), l))
        .chain(std::iter::once(("total", &s.mean_total)))
    {
        writeln!(
            o,
            "  {:<14} {:>12.4e} {:>12.4e} {:>12.4e} {:>12.4e} {:>12.4e} {:>12.4e}",
            t, l.force_n.x, l.force_n.y, l.force_n.z, l.moment_nm.x, l.moment_nm.y, l.moment_nm.z
        )?;
    }
    if let Some(form) = wingforce::AddedMassForm::from_name(r.added_mass_form) {
        writeln!(o, "  (added mass: {})", form.describe())?;
    }
    if let Some(m) = wingforce::InflowModel::from_name(r.inflow_model) {
        writeln!(o, "  (induced flow: {})", m.describe())?;
    }
    if let Some(m) = &s.wing_motion {
        writeln!(
            o,
            "wing motion over the last complete drive period (amplitudes half peak-to-peak; phase + advanced, - delayed rotation):"
        )?;
        for (side, w) in ["left", "right"].iter().zip(&m.wings) {
            writeln!(o, "  {side:<5} {}", w.describe())?;
        }
        if m.amplitude_change_deg.is_finite() {
            writeln!(
                o,
                "  amplitudes changed by up to {:.3} deg from the period before{}",
                m.amplitude_change_deg,
                if !m.is_settled() {
                    " (still settling: run longer for the periodic motion)"
                } else {
                    ""
                }
            )?;
        }
    }
    writeln!(
        o,
        "mean lift / weight: {:.4} (weight {:.4e} N)",
        s.mean_lift_over_weight, r.weight_n
    )?;
    let p = s.final_state.position_m;
    writeln!(
        o,
        "final position [m]: ({:.4e}, {:.4e}, {:.4e}); roll/pitch/yaw [deg]: ({:.2}, {:.2}, {:.2})",
        p.x, p.y, p.z, s.final_euler_deg[0], s.final_euler_deg[1], s.final_euler_deg[2]
    )?;
    writeln!(
        o,
        "drift: {:.4e} m; largest excursion: {:.4e} m",
        s.drift_m, s.max_excursion_m
    )?;
    if let Some(x) = r.sensors {
        writeln!(o, "{}", crate::sensing::describe(x))?;
    }
    if let Some(e) = &r.error {
        writeln!(o, "stopped: {e}")?;
    }
    crate::output::print_stdout(&o)
}
