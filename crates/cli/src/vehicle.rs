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
    let text = std::fs::read_to_string(name).input_context(format!(
        "cannot read model file `{name}` (give a TOML path or a built-in model: drosophila, bumblebee, robobee_kinematic, and the actuated robobee and hummingbird)"
    ))?;
    Ok(VehicleSource {
        text,
        origin: name.to_owned(),
    })
}

/// Parses and validates a vehicle; model errors are bad input (exit 2).
pub fn build_vehicle(src: &VehicleSource) -> anyhow::Result<flapsim::Vehicle> {
    flapsim::Vehicle::from_toml(&src.text, &src.origin).map_err(sim_error)
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
