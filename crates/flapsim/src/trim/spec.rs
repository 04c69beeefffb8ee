//! The `[trim]` table of a model file: what the hover trim varies to carry the weight. Plain
//! data below the vehicle model, which holds it, and the trim of [`crate::trim`], which
//! reads it.

use serde::{Deserialize, Serialize};

/// What the trim varies to carry the weight (with the mean stroke angle for the pitch moment
/// and the body pitch for the horizontal force). Sun & Xiong (2005) trimmed their bumblebee's
/// angle of attack at fixed amplitude and frequency; other studies trim the amplitude or the
/// frequency. An actuated vehicle always trims its drive amplitude.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LiftVariable {
    /// The stroke amplitude (or an actuated vehicle's drive amplitude).
    #[default]
    Amplitude,
    /// The mid-stroke angle of attack of both half strokes, moved alike (Sun & Xiong 2005;
    /// their group's control study found an equal change mainly moves the vertical force).
    AngleOfAttack,
    /// The wingbeat frequency.
    Frequency,
}

impl LiftVariable {
    /// Every lift variable, in the order their names are listed.
    pub const ALL: [LiftVariable; 3] = [
        LiftVariable::Amplitude,
        LiftVariable::AngleOfAttack,
        LiftVariable::Frequency,
    ];

    /// The lift variable of a model-file name ([`Self::name`]).
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|v| v.name() == name)
    }

    /// The name used in model files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            LiftVariable::Amplitude => "amplitude",
            LiftVariable::AngleOfAttack => "angle_of_attack",
            LiftVariable::Frequency => "frequency",
        }
    }
}

/// `[trim]` of a vehicle model file.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TrimSpec {
    /// What carries the weight: `amplitude` (default), `angle_of_attack` or `frequency`.
    pub lift_variable: LiftVariable,
}
