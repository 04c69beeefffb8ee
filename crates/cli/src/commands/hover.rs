//! `flapwing hover`: the main job. Trim the vehicle, design the per-wingbeat LQR hover
//! controller on the averaged model, and fly it from a disturbed start or through a gust;
//! report how far it strayed and how fast it recovered. `--open-loop` holds the trim
//! kinematics and shows the uncontrolled divergence. With `--speed-m-s` / `--climb-m-s` the
//! vehicle is trimmed and the regulator designed at that flight condition, and it holds a
//! point moving at the condition's velocity.

use std::fmt::Write;

use anyhow::Result;
use flapsim::control::{
    Disturbance, HoverController, HoverOutcome, HoverStep, LqrWeights, run_hover_with,
};
use flapsim::estimator::{EstimatedFeedback, EstimatorStats, Prior};
use serde::Serialize;

use crate::error::input_error;
use crate::vehicle::{build_vehicle, check_duration, read_vehicle, sim_error};

/// Arguments of `flapwing hover`.
#[derive(Debug, clap::Args)]
pub struct HoverArgs {
    /// Vehicle model: a TOML file or a built-in name (drosophila, bumblebee, robobee_kinematic, dragonfly; actuated: robobee, hummingbird).
    #[arg(long, value_name = "FILE|NAME")]
    pub model: Option<String>,
    /// Simulated time, s.
    #[arg(long = "duration-s", default_value_t = 1.0)]
    pub duration_s: f64,
    /// Disturbance as comma-separated key=value pairs: pitch_deg, roll_deg, vx_m_s, vy_m_s,
    /// vz_m_s, gust_x_m_s, gust_y_m_s, gust_z_m_s, gust_start_s, gust_duration_s.
    #[arg(long, default_value = "pitch_deg=5")]
    pub disturbance: String,
    /// The flight condition to trim at, design the regulator about and fly (hover by
    /// default); the velocities of --disturbance add to it.
    #[command(flatten)]
    pub condition: crate::condition::ConditionArgs,
    /// Hold the trim kinematics (no controller).
    #[arg(long = "open-loop")]
    pub open_loop: bool,
    /// Sensor delay of the controller, whole wingbeats.
    #[arg(long = "delay-wingbeats", default_value_t = 0, value_parser = clap::value_parser!(u16).range(0..=1000))]
    pub delay_wingbeats: u16,
    /// The state the controller flies on: `true` (the simulation's state) or `estimated`
    /// (the error-state Kalman filter of flapsim::estimator on the model's IMU and motion
    /// capture, with their noise, biases and latencies).
    #[arg(long, value_enum, default_value_t = Feedback::True)]
    pub feedback: Feedback,
    /// Print one JSON document on stdout instead of the text report.
    #[arg(long)]
    pub json: bool,
    /// Log outputs (hover writes an MCAP log and a Rerun recording under logs/ by default).
    #[command(flatten)]
    pub log: crate::logging::LogArgs,
    /// Pacing and the live view's start.
    #[command(flatten)]
    pub pace: crate::pacing::PaceArgs,
    /// Sensors.
    #[command(flatten)]
    pub sensors: crate::sensing::SensorArgs,
    /// Wind (the model's `[wind]` unless changed here), on top of the disturbance's gust.
    #[command(flatten)]
    pub wind: crate::wind::WindArgs,
}

/// What the controller flies on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Feedback {
    /// The simulation's true state.
    True,
    /// The state estimated from the model's sensors.
    Estimated,
}

/// Parses `--disturbance`.
pub fn parse_disturbance(s: &str) -> Result<Disturbance> {
    let mut d = Disturbance::default();
    for part in s.split(',').map(str::trim).filter(|p| !p.is_empty()) {
        let (k, v) = part
            .split_once('=')
            .ok_or_else(|| input_error(format!("--disturbance: `{part}` is not key=value")))?;
        let x: f64 = v
            .trim()
            .parse()
            .ok()
            .filter(|x: &f64| x.is_finite())
            .ok_or_else(|| {
                input_error(format!(
                    "--disturbance: `{k}` = `{v}` is not a finite number"
                ))
            })?;
        let check = |lim: f64| -> Result<f64> {
            if x.abs() <= lim {
                Ok(x)
            } else {
                Err(input_error(format!(
                    "--disturbance: {k} = {x} is not allowed: |{k}| <= {lim}"
                )))
            }
        };
        match k.trim() {
            "pitch_deg" => d.pitch_deg = check(89.0)?,
            "roll_deg" => d.roll_deg = check(89.0)?,
            "vx_m_s" => d.velocity_m_s[0] = check(10.0)?,
            "vy_m_s" => d.velocity_m_s[1] = check(10.0)?,
            "vz_m_s" => d.velocity_m_s[2] = check(10.0)?,
            "gust_x_m_s" => d.gust_m_s[0] = check(20.0)?,
            "gust_y_m_s" => d.gust_m_s[1] = check(20.0)?,
            "gust_z_m_s" => d.gust_m_s[2] = check(20.0)?,
            "gust_start_s" => d.gust_start_s = check(3600.0)?,
            "gust_duration_s" => d.gust_duration_s = check(3600.0)?,
            other => {
                return Err(input_error(format!(
                    "--disturbance: unknown key `{other}`; allowed: pitch_deg, roll_deg, vx_m_s, vy_m_s, vz_m_s, gust_x_m_s, gust_y_m_s, gust_z_m_s, gust_start_s, gust_duration_s"
                )));
            }
        }
    }
    Ok(d)
}

#[derive(Serialize)]
struct Report<'a> {
    model: &'a str,
    /// The flight condition flown (hover: both zero).
    condition: flapsim::flight::FlightCondition,
    disturbance: Disturbance,
    trim_pitch_deg: f64,
    /// The trimmed controls (stroke amplitude and mean stroke angle in deg, or an actuated
    /// vehicle's drive amplitude and bias in V).
    trim_controls: [crate::vehicle::TrimRow; 2],
    delay_wingbeats: usize,
    /// The state the controller flew on.
    feedback: Feedback,
    outcome: &'a HoverOutcome,
    /// What the estimator did (`--feedback estimated` only).
    estimator: Option<EstimatorStats>,
    /// What the model's sensors sampled (`None` without sensors).
    sensors: Option<&'a flapsim::sensor_run::SensorSummary>,
    /// The run's `[wind]` (absent: still air).
    #[serde(skip_serializing_if = "Option::is_none")]
    wind: Option<&'a flapsim::WindSpec>,
}

/// Runs the command.
pub fn run(args: HoverArgs) -> Result<()> {
    let src = read_vehicle(args.model.as_deref())?;
    let vehicle = build_vehicle(&src)?;
    let duration_s = check_duration(args.duration_s)?;
    let mut pacer = crate::pacing::check(&args.pace, duration_s)?;
    let disturbance = parse_disturbance(&args.disturbance)?;
    let condition = args.condition.check(&vehicle)?;
    if !condition.is_hover() && args.feedback == Feedback::Estimated {
        return Err(input_error(
            "--feedback estimated: the filter starts at rest, so it flies hover only; allowed: --feedback true with --speed-m-s / --climb-m-s",
        ));
    }
    let trim =
        flapsim::trim::trim_at(&vehicle, vehicle.trim_lift, &condition).map_err(sim_error)?;
    let mut trimmed = flapsim::trim::trimmed_vehicle(&vehicle, &trim).map_err(sim_error)?;
    // The wind (checked against the run) goes to run_hover in the vehicle's `[wind]`.
    let wind_text = crate::wind::start(&args.wind, &trimmed, &src.origin, duration_s)?
        .as_ref()
        .map(crate::wind::describe);
    trimmed.wind = crate::wind::spec(&args.wind, &trimmed)?;
    let controller = if args.open_loop {
        None
    } else {
        Some(
            HoverController::design(
                &trimmed,
                &trim,
                &LqrWeights::default(),
                usize::from(args.delay_wingbeats),
            )
            .map_err(sim_error)?,
        )
    };
    let mut feedback = match args.feedback {
        Feedback::True => None,
        Feedback::Estimated => Some(estimated_feedback(&args, &trimmed, &trim)?),
    };
    let mut settings = serde_json::json!({
        "duration_s": duration_s,
        "disturbance": disturbance,
        "open_loop": args.open_loop,
        "delay_wingbeats": args.delay_wingbeats,
        "feedback": args.feedback,
        "trim": trim,
    });
    if let Some(w) = &trimmed.wind {
        settings["wind"] = serde_json::to_value(w)?;
    }
    if feedback.is_some() {
        // The sensors' noise the controller flew on: `replay --check` re-runs it from this.
        settings["sensor_seed"] = args.sensors.sensor_seed.unwrap_or(0).into();
    }
    let settings = settings.to_string();
    // On the estimate the feedback's own sensors are the ones sampled and logged.
    let mut sensors = match feedback {
        Some(_) => None,
        None => crate::sensing::start(&args.sensors, &trimmed)?,
    };
    let log_sensors = sensors.is_some() || feedback.is_some();
    // `/wind` when the air moves: a `[wind]` field (the model's or the flags') or the
    // disturbance's gust.
    let gust = disturbance.gust_duration_s > 0.0 && disturbance.gust_m_s.iter().any(|g| *g != 0.0);
    let log_wind = trimmed.wind.is_some() || gust;
    let mut rec = crate::logging::open(
        &args.log,
        "hover",
        &src,
        &trimmed,
        settings,
        true,
        crate::logging::Channels {
            sensors: log_sensors,
            wind: log_wind,
            estimate: feedback.is_some(),
        },
    )?;
    crate::pacing::wait_for_client(&args.pace, args.log.foxglove.as_deref(), rec.as_ref())?;
    let mut log_error = None;
    let mut flushed_reported = 0;
    let steps =
        (duration_s * vehicle.freq_hz() * vehicle.sim.steps_per_wingbeat as f64).round() as u64;
    let bar = crate::progress::progress_bar(steps, "hovering", "steps");
    let each_step = |step: &HoverStep<'_>| {
        let (out, fb) = (step.out, step.feedback);
        crate::pacing::pace(&mut pacer, out.t_s);
        if out.step % 1024 == 0 {
            bar.set_position(out.step);
        }
        // With every wing's output (the pairs' inflow states on `/inflow` where the wake
        // answers).
        let logged = crate::logging::record_all(&mut rec, out, step.sim)
            .and_then(|()| match fb {
                Some(fb) => log_estimate(&mut rec, out.t_s, fb),
                None => crate::sensing::observe(&mut sensors, &mut rec, out),
            })
            .and_then(|()| match log_wind {
                true => crate::logging::record_wind(&mut rec, out.t_s, step.sim),
                false => Ok(()),
            });
        if let Err(e) = logged {
            log_error = Some(e);
            return false;
        }
        if args.log.report_flushed {
            crate::logging::report_flushed(&rec, &mut flushed_reported);
        }
        !crate::interrupt::requested()
    };
    let outcome = run_hover_with(
        &trimmed,
        &trim,
        controller,
        &disturbance,
        duration_s,
        feedback.as_mut(),
        each_step,
    )
    .map_err(sim_error)?;
    bar.finish_and_clear();
    crate::logging::finish(
        rec,
        outcome.duration_s,
        outcome.diverged.clone(),
        outcome.interrupted,
        log_error,
    )?;
    let report = Report {
        model: &src.origin,
        condition,
        disturbance,
        trim_pitch_deg: trim.pitch_rad.to_degrees(),
        trim_controls: crate::vehicle::trim_rows(&vehicle, &trim),
        delay_wingbeats: usize::from(args.delay_wingbeats),
        feedback: args.feedback,
        outcome: &outcome,
        estimator: feedback.as_ref().map(|f| *f.filter().stats()),
        sensors: match &feedback {
            Some(f) => Some(f.summary()),
            None => sensors.as_ref().map(|r| r.summary()),
        },
        wind: trimmed.wind.as_ref(),
    };
    let interrupted = outcome.interrupted;
    if args.json {
        crate::output::print_json(&report)?;
    } else {
        print_text(&src.origin, &args.disturbance, &report)?;
        if let Some(w) = &wind_text {
            crate::output::print_stdout(&format!("{w}\n"))?;
        }
    }
    if interrupted {
        return Err(anyhow::anyhow!(
            "interrupted by Ctrl-C after {:.4} s",
            outcome.duration_s
        ));
    }
    Ok(())
}

/// The sensors and filter of `--feedback estimated`: the model's `[sensors]` (seed
/// `--sensor-seed`, default 0), the filter starting at the trim pose at rest.
fn estimated_feedback(
    args: &HoverArgs,
    vehicle: &flapsim::Vehicle,
    trim: &flapsim::trim::Trim,
) -> Result<EstimatedFeedback> {
    if args.open_loop {
        return Err(input_error(
            "--feedback estimated is for the closed loop: drop --open-loop (or use --feedback true)",
        ));
    }
    if args.sensors.no_sensors {
        return Err(input_error(
            "--feedback estimated flies on the model's sensors: drop --no-sensors (or use --feedback true)",
        ));
    }
    let seed = args.sensors.sensor_seed.unwrap_or(0);
    EstimatedFeedback::new(vehicle, seed, &Prior::hover(vehicle, trim.attitude()))
        .map_err(|e| input_error(format!("--feedback estimated: {e}")))
}

/// Logs the readings the feedback's sensors delivered at `t_s` and (at the log's sample
/// times) the filter's estimate.
fn log_estimate(
    rec: &mut Option<flightlog::Recorder>,
    t_s: f64,
    fb: &EstimatedFeedback,
) -> Result<()> {
    if let Some(rec) = rec.as_mut() {
        for r in fb.readings() {
            rec.sensor(t_s, r)?;
        }
        rec.estimate(t_s, fb.filter())?;
    }
    Ok(())
}

fn print_text(origin: &str, disturbance: &str, report: &Report<'_>) -> Result<()> {
    let o = report.outcome;
    let mut w = String::new();
    writeln!(
        w,
        "{} {} of {} for {:.3} s from {}",
        if o.closed_loop {
            "closed-loop"
        } else {
            "open-loop"
        },
        if report.condition.is_hover() {
            "hover".to_owned()
        } else {
            format!("flight at {}", report.condition.describe())
        },
        origin,
        o.duration_s,
        disturbance
    )?;
    writeln!(
        w,
        "trim: body pitch {:.2} deg, {}",
        report.trim_pitch_deg,
        crate::vehicle::rows_summary(&report.trim_controls)
    )?;
    writeln!(
        w,
        "largest excursion: {:.3e} m ({:.2} body lengths), attitude error {:.2} deg",
        o.max_position_error_m, o.max_position_error_body_lengths, o.max_attitude_error_deg
    )?;
    writeln!(
        w,
        "at the end: position error {:.3e} m, attitude error {:.3} deg",
        o.final_position_error_m, o.final_attitude_error_deg
    )?;
    if o.interrupted {
        writeln!(w, "interrupted by Ctrl-C")?;
    }
    match (&o.diverged, o.recovery_time_s) {
        (Some(why), _) => writeln!(w, "diverged: {why}")?,
        (None, Some(t)) => writeln!(
            w,
            "recovered (within 1 body length and 2 deg for good) after {t:.4} s"
        )?,
        (None, None) => writeln!(w, "not recovered within the run")?,
    }
    if let Some(x) = report.sensors {
        writeln!(w, "{}", crate::sensing::describe(x))?;
    }
    if let Some(e) = &report.estimator {
        writeln!(
            w,
            "flew on the estimate: {} IMU samples and {} motion-capture frames fused ({} dropped), mean normalised innovation squared {:.2} (6 expected)",
            e.imu_samples,
            e.mocap_frames,
            e.mocap_dropped,
            if e.mocap_frames > 0 {
                e.nis_sum / e.mocap_frames as f64
            } else {
                f64::NAN
            }
        )?;
    }
    crate::output::print_stdout(&w)
}
