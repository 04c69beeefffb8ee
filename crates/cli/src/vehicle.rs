//! Loading vehicle models: a built-in name (`drosophila`, the default; `robobee`;
//! `bumblebee`) or a TOML file path.

use crate::error::{InputContext, input_error};

/// A vehicle model's text and where it came from.
#[derive(Debug, Clone)]
pub struct VehicleSource {
    /// The TOML text.
    pub text: String,
    /// A file path or `<built-in NAME>`.
    pub origin: String,
}

/// Reads the model named by `--model` (default: the built-in drosophila).
pub fn read_vehicle(model: Option<&str>) -> anyhow::Result<VehicleSource> {
    let name = model.unwrap_or("drosophila");
    if let Some(text) = flapsim::builtin_model(name) {
        return Ok(VehicleSource {
            text: text.to_owned(),
            origin: format!("<built-in {name}>"),
        });
    }
    let text = flapsim::model::read_model_file(std::path::Path::new(name)).input_context(format!(
        "cannot read model file `{name}` (give a TOML path or a built-in model: drosophila, bumblebee, robobee_kinematic, the four-winged dragonfly, and the actuated robobee and hummingbird)"
    ))?;
    Ok(VehicleSource {
        text,
        origin: name.to_owned(),
    })
}

/// Parses and validates a vehicle; model errors are bad input (exit 2).
pub fn build_vehicle(src: &VehicleSource) -> anyhow::Result<flapsim::Vehicle> {
    let v = flapsim::Vehicle::from_toml(&src.text, &src.origin).map_err(sim_error)?;
    warn_coarse_step(&v);
    Ok(v)
}

/// Says on stderr when `v` is stepped more coarsely than its model's stated accuracy bound.
pub fn warn_coarse_step(v: &flapsim::Vehicle) {
    if let Some(w) = v.coarse_step_warning() {
        crate::output::note(&format!("warning: {w}"));
    }
}

/// `--inflow`: an induced-flow model by name.
pub fn parse_inflow(name: &str) -> Result<wingforce::InflowModel, String> {
    wingforce::InflowModel::from_name(name).ok_or_else(|| {
        format!("`{name}` is not an induced-flow model; allowed: off, frozen, dynamic")
    })
}

/// The vehicle with `--inflow`'s induced flow in place of its model file's, if given.
pub fn with_inflow(
    vehicle: flapsim::Vehicle,
    inflow: Option<wingforce::InflowModel>,
) -> anyhow::Result<flapsim::Vehicle> {
    match inflow {
        Some(m) => {
            use crate::error::InputContext;
            vehicle
                .with_inflow_model(m)
                .input_context(format!("--inflow {m}"))
        }
        None => Ok(vehicle),
    }
}

/// A flapsim error as an anyhow error, keeping model errors recognisable as bad input.
pub fn sim_error(e: flapsim::Error) -> anyhow::Error {
    match e {
        flapsim::Error::Model(m) => anyhow::Error::new(m),
        other => anyhow::Error::new(other),
    }
}

/// Checks a duration flag.
pub fn check_duration(duration_s: f64) -> anyhow::Result<f64> {
    if duration_s.is_finite() && duration_s > 0.0 && duration_s <= 3600.0 {
        Ok(duration_s)
    } else {
        Err(input_error(format!(
            "--duration-s {duration_s} is not allowed: a number of seconds in (0, 3600]"
        )))
    }
}

/// One trimmed control as the reports show it (degrees or volts: the CLI is the edge).
#[derive(Debug, Clone, serde::Serialize)]
pub struct TrimRow {
    /// What it is (`stroke amplitude`, `drive bias`, ...).
    pub name: &'static str,
    /// Its key in a model's `[controls]` table (what `trim --write` sets).
    pub controls_field: &'static str,
    /// The value at trim (the model's base plus the offset), in `unit`.
    pub value: f64,
    /// The offset on the model's base value that the trim found, in `unit`.
    pub offset: f64,
    /// `deg`, `Hz` or `V`.
    pub unit: &'static str,
}

/// The two controls a hover trim solves for: stroke amplitude and mean stroke angle for
/// prescribed kinematics, drive amplitude and bias for an actuated vehicle.
pub fn trim_rows(vehicle: &flapsim::Vehicle, t: &flapsim::trim::Trim) -> [TrimRow; 2] {
    let c = &t.controls;
    match &vehicle.actuation {
        Some(a) => [
            TrimRow {
                name: "drive amplitude",
                controls_field: "amplitude_v",
                value: a.base_drives[0].amplitude_v + c.amplitude_v,
                offset: c.amplitude_v,
                unit: "V",
            },
            TrimRow {
                name: "drive bias",
                controls_field: "bias_v",
                value: a.base_drives[0].bias_v + c.bias_v,
                offset: c.bias_v,
                unit: "V",
            },
        ],
        None => [
            {
                let k = &vehicle.base_kinematics[0];
                match t.lift_variable {
                    flapsim::trim::LiftVariable::Amplitude => TrimRow {
                        name: "stroke amplitude",
                        controls_field: "amplitude_deg",
                        value: (k.amplitude_rad + c.amplitude_rad).to_degrees(),
                        offset: c.amplitude_rad.to_degrees(),
                        unit: "deg",
                    },
                    flapsim::trim::LiftVariable::AngleOfAttack => TrimRow {
                        name: "downstroke angle of attack",
                        controls_field: "aoa_deg",
                        // Both half strokes move alike; the row shows the downstroke's.
                        value: k
                            .mid_stroke_aoa_rad()
                            .map_or(f64::NAN, |(down, _)| (down + c.aoa_rad).to_degrees()),
                        offset: c.aoa_rad.to_degrees(),
                        unit: "deg",
                    },
                    flapsim::trim::LiftVariable::Frequency => TrimRow {
                        name: "wingbeat frequency",
                        controls_field: "freq_hz",
                        value: k.freq_hz + c.freq_hz,
                        offset: c.freq_hz,
                        unit: "Hz",
                    },
                }
            },
            TrimRow {
                name: "mean stroke angle",
                controls_field: "mean_stroke_deg",
                value: (vehicle.base_kinematics[0].mean_stroke_rad + c.mean_stroke_rad)
                    .to_degrees(),
                offset: c.mean_stroke_rad.to_degrees(),
                unit: "deg",
            },
        ],
    }
}

/// The trimmed controls in one line: `stroke amplitude 90.0 deg (+0.0), mean stroke ...`.
pub fn trim_summary(vehicle: &flapsim::Vehicle, t: &flapsim::trim::Trim) -> String {
    rows_summary(&trim_rows(vehicle, t))
}

/// See [`trim_summary`].
pub fn rows_summary(rows: &[TrimRow]) -> String {
    rows.iter()
        .map(|r| format!("{} {:.3} {} ({:+.3})", r.name, r.value, r.unit, r.offset))
        .collect::<Vec<_>>()
        .join(", ")
}
