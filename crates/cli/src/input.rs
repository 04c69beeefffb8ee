//! Reading model files: a user's file, or the built-in robofly model compiled into the binary
//! so that the commands work from any directory.

use std::path::Path;

use wingforce::WingModelSpec;

use crate::error::InputContext;

/// `models/robofly.toml`: the paper's robotic fruit-fly wing in its run V3 (Table 5).
pub const BUILTIN_ROBOFLY: &str = include_str!("../../../models/robofly.toml");

/// How errors and reports name the built-in model.
pub const BUILTIN_ROBOFLY_ORIGIN: &str = "<built-in robofly>";

/// A parsed (not yet validated) wing model and where it came from.
#[derive(Debug, Clone)]
pub struct LoadedSpec {
    /// The model as written.
    pub spec: WingModelSpec,
    /// The file path, or [`BUILTIN_ROBOFLY_ORIGIN`].
    pub origin: String,
}

/// Reads and parses the wing model at `path`, or the built-in robofly model when `None`.
/// Unreadable files and parse errors are bad input; the message names the file.
pub fn load_wing_spec(path: Option<&Path>) -> anyhow::Result<LoadedSpec> {
    let (text, origin) = match path {
        Some(p) => {
            let origin = p.display().to_string();
            let text = flapsim::model::read_model_file(p)
                .input_context(format!("cannot read model file `{origin}`"))?;
            (text, origin)
        }
        None => (
            BUILTIN_ROBOFLY.to_owned(),
            BUILTIN_ROBOFLY_ORIGIN.to_owned(),
        ),
    };
    let spec = WingModelSpec::from_toml(&text, &origin)?;
    Ok(LoadedSpec { spec, origin })
}
