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
use flapwing_identify::bag::{ControlsRole, ImuRole, PoseRole};
use flapwing_identify::{
    BagRoles, BodyConvention, FitOptions, FlightData, Param, QuaternionOrder, StartStates,
    WorldConvention, fitted_model_toml, identify,
};

use crate::error::input_error;

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
    /// Central-difference step of the Jacobian, fraction of each parameter's scale.
    #[arg(long = "fd-step", default_value_t = 1e-3)]
    pub fd_step: f64,
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
    /// A ROS 2 bag's roles and frame conventions, a TOML file ([pose], [imu], [controls],
    /// [frames]; format in crates/identify/README.md). The flags below override it.
    #[arg(long, value_name = "ROLES.toml", help_heading = "ROS 2 bags")]
    pub roles: Option<PathBuf>,
    /// The bag's topic with the body's pose (PoseStamped, PoseWithCovarianceStamped,
    /// Odometry, TransformStamped or TFMessage).
    #[arg(long = "pose-topic", value_name = "TOPIC", help_heading = "ROS 2 bags")]
    pub pose_topic: Option<String>,
    /// For a TFMessage pose topic: the body's frame (child_frame_id).
    #[arg(
        long = "child-frame",
        value_name = "FRAME",
        help_heading = "ROS 2 bags"
    )]
    pub child_frame: Option<String>,
    /// The bag's IMU topic (sensor_msgs/msg/Imu), used with --imu.
    #[arg(long = "imu-topic", value_name = "TOPIC", help_heading = "ROS 2 bags")]
    pub imu_topic: Option<String>,
    /// The bag's controls topic (a Float64MultiArray holds the vehicle's four control
    /// channels in data.0..3; other types name their fields in the roles file).
    #[arg(
        long = "controls-topic",
        value_name = "TOPIC",
        help_heading = "ROS 2 bags"
    )]
    pub controls_topic: Option<String>,
    /// The bag's world frame: enu (x east, y north, z up; ROS) or ned.
    #[arg(
        long = "world-frame",
        value_name = "enu|ned",
        help_heading = "ROS 2 bags"
    )]
    pub world_frame: Option<String>,
    /// The bag's body frame: flu (x forward, y left, z up; ROS) or frd.
    #[arg(
        long = "body-frame",
        value_name = "flu|frd",
        help_heading = "ROS 2 bags"
    )]
    pub body_frame: Option<String>,
    /// How the bag's quaternions fill their x, y, z, w fields: xyzw (ROS) or wxyz (a
    /// scalar-first quaternion written in order).
    #[arg(
        long = "quaternion-order",
        value_name = "xyzw|wxyz",
        help_heading = "ROS 2 bags"
    )]
    pub quaternion_order: Option<String>,
}

impl IdentifyArgs {
    /// True when any ROS 2 role or convention is given.
    fn names_bag_roles(&self) -> bool {
        self.roles.is_some()
            || self.pose_topic.is_some()
            || self.child_frame.is_some()
            || self.imu_topic.is_some()
            || self.controls_topic.is_some()
            || self.world_frame.is_some()
            || self.body_frame.is_some()
            || self.quaternion_order.is_some()
    }

    /// The roles file, overridden by the flags.
    fn bag_roles(&self) -> Result<BagRoles> {
        let mut roles = match &self.roles {
            Some(p) => {
                let text = flapsim::model::read_model_file(p).map_err(|e| {
                    input_error(format!("--roles: cannot read `{}`: {e}", p.display()))
                })?;
                BagRoles::from_toml(&text, &p.display().to_string()).map_err(classify)?
            }
            None => BagRoles::default(),
        };
        if let Some(t) = &self.pose_topic {
            let child_frame = roles.pose.take().and_then(|p| p.child_frame);
            roles.pose = Some(PoseRole {
                topic: t.clone(),
                child_frame,
            });
        }
        if let Some(c) = &self.child_frame {
            let Some(p) = roles.pose.as_mut() else {
                return Err(input_error(
                    "--child-frame names the body's frame of a TF pose topic: give --pose-topic too",
                ));
            };
            p.child_frame = Some(c.clone());
        }
        if let Some(t) = &self.imu_topic {
            let body = roles.imu.take().and_then(|i| i.body);
            roles.imu = Some(ImuRole {
                topic: t.clone(),
                body,
            });
        }
        if let Some(t) = &self.controls_topic {
            let fields = roles.controls.take().map(|c| c.fields).unwrap_or_default();
            roles.controls = Some(ControlsRole {
                topic: t.clone(),
                fields,
            });
        }
        fn pick<T: Copy>(flag: &str, value: &str, options: &[(&str, T)]) -> Result<T> {
            let lower = value.to_ascii_lowercase();
            options
                .iter()
                .find(|(n, _)| *n == lower)
                .map(|(_, v)| *v)
                .ok_or_else(|| {
                    let names: Vec<&str> = options.iter().map(|(n, _)| *n).collect();
                    input_error(format!(
                        "{flag} `{value}` is not a convention; allowed: {}",
                        names.join(", ")
                    ))
                })
        }
        if let Some(v) = &self.world_frame {
            roles.frames.world = pick(
                "--world-frame",
                v,
                &[("enu", WorldConvention::Enu), ("ned", WorldConvention::Ned)],
            )?;
        }
        if let Some(v) = &self.body_frame {
            roles.frames.body = pick(
                "--body-frame",
                v,
                &[("flu", BodyConvention::Flu), ("frd", BodyConvention::Frd)],
            )?;
        }
        if let Some(v) = &self.quaternion_order {
            roles.frames.quaternion = pick(
                "--quaternion-order",
                v,
                &[
                    ("xyzw", QuaternionOrder::Xyzw),
                    ("wxyz", QuaternionOrder::Wxyz),
                ],
            )?;
        }
        Ok(roles)
    }
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

fn classify(e: flapwing_identify::Error) -> anyhow::Error {
    if e.is_bad_input() {
        input_error(e.to_string())
    } else {
        anyhow::Error::new(e)
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
    let is_csv = args
        .file
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"));
    let bag = !is_csv && args.names_bag_roles();
    let mut data = if is_csv || bag {
        let Some(model) = args.model.as_deref() else {
            let what = if bag { "a ROS 2 bag" } else { "a CSV flight" };
            return Err(input_error(format!(
                "`{}` is {what}: give the vehicle it flew with --model FILE|NAME",
                args.file.display()
            )));
        };
        let src = crate::vehicle::read_vehicle(Some(model))?;
        if bag {
            let roles = args.bag_roles()?;
            let data = FlightData::from_bag(&args.file, &src.text, &src.origin, &roles)
                .map_err(classify)?;
            crate::output::note(&format!(
                "ROS 2 bag `{}`: {}; {} poses over {:.3} s, {} IMU samples, {} wingbeats",
                args.file.display(),
                roles.describe(),
                data.mocap.len(),
                data.duration_s(),
                data.imu.len(),
                data.wingbeat_controls.len()
            ));
            data
        } else {
            FlightData::from_csv(&args.file, &src.text, &src.origin).map_err(classify)?
        }
    } else {
        FlightData::from_mcap(&args.file).map_err(|e| {
            // A ROS 2 bag given without its roles: say what is missing.
            match flightlog::ros2::bag::read_bag(&args.file) {
                Ok(b) if b.has_ros2() => input_error(format!(
                    "`{}` is a ROS 2 bag, not a flapwing log: name the topic with the body's pose (--pose-topic TOPIC or --roles FILE) and the vehicle (--model); its topics: {}",
                    args.file.display(),
                    b.topics()
                )),
                _ => classify(e),
            }
        })?
    };
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
    if let (false, false, Some(model)) = (is_csv, bag, args.model.as_deref()) {
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
