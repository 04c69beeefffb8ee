//! A study file as written: its tables (the base model, the factors, the design, the
//! responses) and their parsing from TOML.

use serde::Deserialize;

use super::super::error::{StudyError, StudyResult};

/// The most cases one study may have.
pub const MAX_CASES: usize = 1_000_000;

/// A study file as written.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StudySpec {
    /// Name used in output file names (default: the file stem, chosen by the caller).
    #[serde(default)]
    pub name: Option<String>,
    /// Built-in vehicle name (`drosophila`, `robobee`, `bumblebee`) or a vehicle TOML path.
    pub base_model: String,
    /// The design.
    pub design: DesignKind,
    /// Latin hypercube: number of samples.
    #[serde(default)]
    pub samples: Option<usize>,
    /// Latin hypercube: random seed.
    #[serde(default)]
    pub seed: Option<u64>,
    /// Phase samples per wingbeat for the cycle means (default: the model's
    /// `sim.steps_per_wingbeat`).
    #[serde(default)]
    pub steps_per_wingbeat: Option<usize>,
    /// Names of the responses to evaluate, in output order.
    pub responses: Vec<String>,
    /// The factors.
    #[serde(rename = "factor")]
    pub factors: Vec<FactorSpec>,
}

/// How the cases are chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DesignKind {
    /// Every combination of levels; the first factor varies slowest.
    FullFactorial,
    /// Latin hypercube sampling of the factor ranges.
    LatinHypercube,
    /// Taguchi L9(3^4).
    TaguchiL9,
    /// Taguchi L18(6^1 x 3^6) (first three columns: the seed paper's Table 2).
    TaguchiL18,
    /// Taguchi L27(3^13).
    TaguchiL27,
}

impl DesignKind {
    /// The snake-case name.
    pub fn name(self) -> &'static str {
        match self {
            Self::FullFactorial => "full_factorial",
            Self::LatinHypercube => "latin_hypercube",
            Self::TaguchiL9 => "taguchi_l9",
            Self::TaguchiL18 => "taguchi_l18",
            Self::TaguchiL27 => "taguchi_l27",
        }
    }
}

/// One factor as written.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FactorSpec {
    /// Dotted path of a numeric field of the vehicle TOML, e.g. `kinematics.amplitude_deg`.
    pub path: String,
    /// Explicit levels.
    #[serde(default)]
    pub levels: Option<Vec<f64>>,
    /// `[lo, hi]`: with `count`, evenly spaced levels; for a Latin hypercube, the range.
    #[serde(default)]
    pub range: Option<[f64; 2]>,
    /// Number of evenly spaced levels over `range`.
    #[serde(default)]
    pub count: Option<usize>,
}

impl StudySpec {
    /// Parses a study file (`origin` names it in errors).
    pub fn from_toml(text: &str, origin: &str) -> StudyResult<Self> {
        toml::from_str(text).map_err(|e| StudyError::Invalid {
            origin: origin.to_owned(),
            message: e.to_string().trim_end().to_owned(),
        })
    }
}
