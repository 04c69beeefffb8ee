//! `flapwing identify`: fit model parameters to a logged flight (an MCAP log written by
//! `flapwing hover`/`simulate` with sensors, a motion-capture CSV with the commands, or a
//! ROS 2 bag whose topics are given roles) by
//! nonlinear least squares, report each parameter with its standard error, 95 % interval
//! and identifiability, and write the fitted model (`--out`). The method is
//! flapwing-identify's (crates/identify/README.md); this command parses, calls and prints.
//!
//! Exit codes: 0 converged; 1 the fit did not converge or was interrupted (the report is
//! printed, no model written); 2 bad input (missing file, channels or columns, unknown
//! parameter, an existing `--out` without `--force`).

use std::io::Write;
use std::path::PathBuf;

use anyhow::Result;
use flapwing_identify::{FitOptions, Param, StartStates, fitted_model_toml, identify};

use crate::error::input_error;
use crate::flight_input::classify;

/// Arguments of `flapwing identify`.
#[derive(Debug, clap::Args)]
pub struct IdentifyArgs {
    /// The flight: an MCAP log (`flapwing hover --mcap FILE` on a model with [sensors.mocap]),
    /// a motion-capture CSV (`.csv`, needs --model; columns in crates/identify/README.md) or a
    /// ROS 2 bag (needs --model and its pose topic: --pose-topic or --roles).
    #[arg(value_name = "LOG.mcap|FLIGHT.csv|BAG.mcap")]
    pub file: PathBuf,
    /// Parameters to fit, comma-separated: inertia_xx_kg_m2, inertia_yy_kg_m2,
    /// inertia_zz_kg_m2, mass_kg, com_offset_x_m, com_offset_z_m, air_density_kg_m3,
    /// rotational_coefficient, stroke_plane_tilt_rad, mocap_bias_{x,y,z}_m,
    /// gyro_bias_{x,y,z}_rad_s, accel_bias_{x,y,z}_m_s2.
    #[arg(long, default_value = "inertia_yy_kg_m2,com_offset_x_m,com_offset_z_m")]
    pub params: String,
    /// The vehicle model the fit starts from: needed for a CSV; for a log, replaces the
    /// model embedded in it. A TOML file or a built-in name.
    #[arg(long, value_name = "FILE|NAME")]
    pub model: Option<String>,
    /// Wingbeats per segment (each restarted from the state at its first wingbeat).
    #[arg(long = "segment-wingbeats", default_value_t = 4)]
    pub segment_wingbeats: u32,
    /// Use the IMU's samples as measurements too (needed for gyro_bias_*/accel_bias_*). Fit
    /// the biases of every axis with it: an unfitted 1 deg/s turn-on bias is many times a
    /// MEMS gyroscope's noise per sample.
    #[arg(long)]
    pub imu: bool,
    /// The solver stops after this many times (n + 1) residual evaluations.
    #[arg(long, default_value_t = 30)]
    pub patience: usize,
    /// Central-difference step of the Jacobian, fraction of each parameter's scale
    /// [default: 1e-3; 1e-2 for wings with hinge stops, whose strikes make the motion
    /// jagged on a finer scale]
    #[arg(long = "fd-step")]
    pub fd_step: Option<f64>,
    /// Whether each segment's start state is fitted too (12 unknowns per segment: full
    /// multiple shooting). auto: fitted when the starts are estimated from the motion
    /// capture (a CSV flight), held when a log holds the state.
    #[arg(long = "start-states", value_enum, default_value = "auto")]
    pub start_states: StartStatesArg,
    /// Fit only the first this many seconds of the flight.
    #[arg(long = "duration-s")]
    pub duration_s: Option<f64>,
    /// Write the fitted model (TOML, loads with --model) here when the fit converges.
    #[arg(long, value_name = "FITTED.toml")]
    pub out: Option<PathBuf>,
    /// Replace an existing --out file.
    #[arg(long)]
    pub force: bool,
    /// Print the report as one JSON document on stdout.
    #[arg(long)]
    pub json: bool,
    /// The roles of a ROS 2 bag's topics and its frame conventions.
    #[command(flatten)]
    pub roles: crate::flight_input::BagRoleArgs,
}

/// `--start-states`.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum StartStatesArg {
    Auto,
    Fixed,
    Fitted,
}

impl From<StartStatesArg> for StartStates {
    fn from(a: StartStatesArg) -> Self {
        match a {
            StartStatesArg::Auto => StartStates::Auto,
            StartStatesArg::Fixed => StartStates::Fixed,
            StartStatesArg::Fitted => StartStates::Fitted,
        }
    }
}

/// Runs the command.
pub fn run(args: IdentifyArgs) -> Result<()> {
    if !args.file.is_file() {
        return Err(input_error(format!(
            "cannot read `{}`: no such file",
            args.file.display()
        )));
    }
    let opts = FitOptions {
        params: Param::parse_list(&args.params)
            .map_err(|e| input_error(format!("--params: {e}")))?,
        segment_wingbeats: args.segment_wingbeats,
        use_imu: args.imu,
        fd_step: args.fd_step,
        patience: args.patience,
        max_duration_s: args.duration_s,
        start_states: args.start_states.into(),
    };
    opts.check().map_err(classify)?;
    if let Some(out) = &args.out {
        // The fitted model never replaces the flight or the model it was read from.
        let mut inputs = vec![crate::outputs::Named::new("FILE", &args.file)];
        let model = args.model.as_deref().map(std::path::Path::new);
        if let Some(m) = model.filter(|m| m.is_file()) {
            inputs.push(crate::outputs::Named::new("--model", m));
        }
        crate::outputs::check(
            &inputs,
            &[crate::outputs::Named::new("--out", out)],
            args.force,
        )?;
    }
    let (mut data, from_log) =
        crate::flight_input::read_flight(&args.file, args.model.as_deref(), &args.roles, false)?;
    if let Some(damage) = &data.damage {
        // A killed run's log: fit what its complete chunks hold, and say so.
        crate::output::note(&format!(
            "warning: `{}` is incomplete ({damage}); fitting the {} motion-capture frames ({:.3} s) and {} IMU samples recovered from it",
            args.file.display(),
            data.mocap.len(),
            data.duration_s(),
            data.imu.len()
        ));
    }
    if let (true, Some(model)) = (from_log, args.model.as_deref()) {
        let src = crate::vehicle::read_vehicle(Some(model))?;
        crate::vehicle::build_vehicle(&src)?;
        data.model_toml = src.text;
        data.model_origin = src.origin;
    }
    let bar = crate::progress::progress_bar(1, "identifying", "simulations");
    let report = identify(&data, &opts, &mut |p| {
        bar.set_length(p.max_simulations);
        bar.set_position(p.simulations);
        !crate::interrupt::requested()
    })
    .map_err(classify)?;
    bar.finish_and_clear();
    let mut written = None;
    if let Some(out) = &args.out
        && report.converged
    {
        let command = format!("flapwing identify --params {}", args.params);
        let text = fitted_model_toml(&data.model_toml, &report, &command).map_err(classify)?;
        let mut f = crate::output::create_output_file(out, args.force, "fitted model")?;
        f.write_all(text.as_bytes())
            .map_err(|e| anyhow::anyhow!("cannot write `{}`: {e}", out.display()))?;
        written = Some(out.clone());
    }
    if args.json {
        let mut v = serde_json::to_value(&report)?;
        v["fitted_model"] = serde_json::json!(written);
        crate::output::print_json(&v)?;
    } else {
        let mut text = report.to_string();
        match (&written, &args.out) {
            (Some(p), _) => text.push_str(&format!("wrote the fitted model to {}\n", p.display())),
            (None, Some(p)) => text.push_str(&format!(
                "no model written to {}: the fit did not converge\n",
                p.display()
            )),
            _ => {}
        }
        crate::output::print_stdout(&text)?;
    }
    if report.interrupted {
        return Err(anyhow::anyhow!("interrupted by Ctrl-C"));
    }
    if !report.converged {
        return Err(anyhow::anyhow!(
            "the fit of `{}` did not converge: {}",
            args.file.display(),
            report.termination
        ));
    }
    Ok(())
}
