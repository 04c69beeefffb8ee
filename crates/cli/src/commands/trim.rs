//! `flapwing trim`: the kinematics and body pitch at which the cycle-averaged forces and
//! moments balance, in hover or at a flight condition (`--speed-m-s`, `--climb-m-s`).

use std::fmt::Write;

use anyhow::Result;
use serde::Serialize;

use crate::vehicle::{TrimRow, build_vehicle, read_vehicle, sim_error, trim_rows};

/// Arguments of `flapwing trim`.
#[derive(Debug, clap::Args)]
pub struct TrimArgs {
    /// Vehicle model: a TOML file or a built-in name (drosophila, bumblebee, robobee_kinematic, dragonfly; actuated: robobee, hummingbird).
    #[arg(long, value_name = "FILE|NAME")]
    pub model: Option<String>,
    /// The induced flow the wings meet, in place of the model's `[aero] inflow`: `frozen`
    /// (the hover downwash held at the condition), `dynamic` (each pair's wake answers its
    /// loads and the body; issue #38) or `off` (still air).
    #[arg(long, value_name = "MODEL", value_parser = crate::vehicle::parse_inflow)]
    pub inflow: Option<wingforce::InflowModel>,
    /// What carries the weight: the stroke amplitude, the mid-stroke angle of attack (both
    /// half strokes moved alike, as Sun & Xiong 2005 trimmed) or the wingbeat frequency
    /// (default: the model's `[trim] lift_variable`, else the amplitude).
    #[arg(long, value_enum)]
    pub vary: Option<Vary>,
    /// The flight condition (hover by default).
    #[command(flatten)]
    pub condition: crate::condition::ConditionArgs,
    /// Write the trimmed model (controls and initial attitude set) to this TOML file.
    #[arg(long, value_name = "OUT.toml")]
    pub write: Option<std::path::PathBuf>,
    /// Replace the --write file if it exists.
    #[arg(long)]
    pub force: bool,
    /// Print one JSON document on stdout instead of the text report.
    #[arg(long)]
    pub json: bool,
}

/// `--vary`.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum Vary {
    /// The stroke amplitude (an actuated vehicle's drive amplitude).
    Amplitude,
    /// The mid-stroke angle of attack of both half strokes.
    AngleOfAttack,
    /// The wingbeat frequency.
    Frequency,
}

impl Vary {
    /// The trim's lift variable: `vary`'s, else the model's `[trim] lift_variable`.
    pub fn or_model(vary: Option<Vary>, vehicle: &flapsim::Vehicle) -> flapsim::trim::LiftVariable {
        match vary {
            None => vehicle.trim_lift,
            Some(Vary::Amplitude) => flapsim::trim::LiftVariable::Amplitude,
            Some(Vary::AngleOfAttack) => flapsim::trim::LiftVariable::AngleOfAttack,
            Some(Vary::Frequency) => flapsim::trim::LiftVariable::Frequency,
        }
    }
}

#[derive(Serialize)]
struct Report<'a> {
    model: &'a str,
    forward_speed_m_s: f64,
    climb_rate_m_s: f64,
    /// The trimmed controls (for prescribed kinematics, stroke amplitude and mean stroke
    /// angle in deg; for an actuated vehicle, drive amplitude and bias in V).
    controls: [TrimRow; 2],
    pitch_deg: f64,
    /// The stroke plane's angle to the horizontal, deg, positive tilted forward (Dudley &
    /// Ellington 1990's beta); 0 in hover for a model whose stroke plane is horizontal there.
    stroke_plane_angle_deg: f64,
    aero_power_w: f64,
    residual_fx_over_weight: f64,
    residual_fz_over_weight: f64,
    residual_my_over_weight_length: f64,
    iterations: usize,
}

/// Runs the command.
pub fn run(args: TrimArgs) -> Result<()> {
    let src = read_vehicle(args.model.as_deref())?;
    let vehicle = crate::vehicle::with_inflow(build_vehicle(&src)?, args.inflow)?;
    let condition = args.condition.check(&vehicle)?;
    if args.write.is_some() && !condition.is_hover() {
        return Err(crate::error::input_error(format!(
            "--write {}: a model file holds a hover trim only (its induced inflow is the hover downwash); allowed: --write without --speed-m-s / --climb-m-s",
            args.write
                .as_ref()
                .map(|p| p.display().to_string())
                .unwrap_or_default()
        )));
    }
    let out_file = match &args.write {
        Some(p) => {
            // The trimmed model never replaces the model file it was read from.
            crate::outputs::check(
                &crate::outputs::model_input(&src.origin),
                &[crate::outputs::Named::new("--write", p)],
                args.force,
            )?;
            Some(crate::output::create_output_file(
                p,
                args.force,
                "trimmed model",
            )?)
        }
        None => None,
    };
    let lift = Vary::or_model(args.vary, &vehicle);
    let t = flapsim::trim::trim_at(&vehicle, lift, &condition).map_err(sim_error)?;
    let point = flapsim::flight::trim_point(&vehicle, &t).map_err(sim_error)?;
    let report = Report {
        model: &src.origin,
        forward_speed_m_s: condition.forward_speed_m_s,
        climb_rate_m_s: condition.climb_rate_m_s,
        controls: trim_rows(&vehicle, &t),
        pitch_deg: t.pitch_rad.to_degrees(),
        stroke_plane_angle_deg: point.stroke_plane_angle_rad.to_degrees(),
        aero_power_w: point.power.aero_w,
        residual_fx_over_weight: t.residual_fx_over_weight,
        residual_fz_over_weight: t.residual_fz_over_weight,
        residual_my_over_weight_length: t.residual_my_over_weight_length,
        iterations: t.iterations,
    };
    if let (Some(mut f), Some(path)) = (out_file, &args.write) {
        let mut doc: toml::Value = toml::from_str(&src.text)?;
        let table = doc
            .as_table_mut()
            .ok_or_else(|| anyhow::anyhow!("model is not a TOML table"))?;
        let controls = table
            .entry("controls")
            .or_insert_with(|| toml::Value::Table(Default::default()));
        if let Some(c) = controls.as_table_mut() {
            for row in &report.controls {
                c.insert(row.controls_field.into(), toml::Value::Float(row.offset));
            }
        }
        let initial = table
            .entry("initial")
            .or_insert_with(|| toml::Value::Table(Default::default()));
        if let Some(i) = initial.as_table_mut() {
            i.insert(
                "attitude_deg".into(),
                toml::Value::Array(vec![0.0.into(), report.pitch_deg.into(), 0.0.into()]),
            );
        }
        let text = format!(
            "# Trimmed by `flapwing trim` from {}.\n{}",
            src.origin,
            toml::to_string_pretty(&doc)?
        );
        std::io::Write::write_all(&mut f, text.as_bytes())?;
        crate::output::note(&format!("wrote {}", path.display()));
    }
    if args.json {
        return crate::output::print_json(&report);
    }
    let mut o = String::new();
    let what = if condition.is_hover() {
        "hover trim".to_owned()
    } else {
        format!("trim at {}", condition.describe())
    };
    writeln!(
        o,
        "{what} of {} ({} Newton iterations)",
        src.origin, t.iterations
    )?;
    writeln!(
        o,
        "  {:<18} {}",
        "induced flow",
        vehicle.inflow_model().describe()
    )?;
    for row in &report.controls {
        writeln!(
            o,
            "  {:<18} {:.4} {} (offset {:+.4} {})",
            row.name, row.value, row.unit, row.offset, row.unit
        )?;
    }
    writeln!(o, "  {:<18} {:.4} deg", "body pitch", report.pitch_deg)?;
    writeln!(
        o,
        "  {:<18} {:.4} deg (to the horizontal, tilted forward)",
        "stroke plane", report.stroke_plane_angle_deg
    )?;
    writeln!(
        o,
        "  {:<18} {:.4e} W ({:.1} W/kg of body mass)",
        "aerodynamic power",
        report.aero_power_w,
        report.aero_power_w / vehicle.mass_kg
    )?;
    writeln!(
        o,
        "residuals: Fx/W {:.2e}, Fz/W - 1 {:.2e}, My/(W R) {:.2e}",
        report.residual_fx_over_weight,
        report.residual_fz_over_weight,
        report.residual_my_over_weight_length
    )?;
    crate::output::print_stdout(&o)
}
