//! # flapsim
//!
//! An insect-scale flapping-wing vehicle as a rapier3d-f64 rigid body, fed the forces of
//! [`wingforce`] every step through its wing set (the force element, crate [`wingset`]:
//! wingforce and nalgebra only, no rapier, no I/O; re-exported in [`wings`]): tethered (a
//! force sensor), free flight, or free with chosen degrees of freedom locked. flapsim holds
//! the vehicle model (TOML, controls mapped onto the wings: [`wings::FromVehicle`]) and the
//! set's rapier hosts ([`Simulation`], [`host::RapierWings`]). Deterministic: the same model
//! and inputs give bit-identical trajectories. Drive it step by step through [`Simulation`],
//! the plugin face of flapwing.
//!
//! Frames: world z up; body x forward, y left, z up, origin at the centre of mass
//! (MODEL.md section 1). rapier's glam types meet wingforce's nalgebra types only in
//! [`frames`].

pub mod actuated;
pub mod averaged;
pub mod cancel;
pub mod control;
pub mod controls;
pub mod derivatives;
mod error;
pub mod estimator;
pub mod flight;
pub mod frames;
pub mod host;
pub mod linear;
pub mod model;
pub mod operating_points;
pub mod randomize;
pub mod sensor_run;
pub mod sensors;
pub mod sim;
pub mod stability;
pub mod summary;
pub mod sun_xiong;
pub mod task;
pub mod trim;
pub mod vehicle_validation;
pub mod wind;
pub mod wings;

pub use error::{Error, Result};
pub use model::{Controls, Vehicle, VehicleSpec};
pub use sim::{BodyLoad, Mode, Simulation, State, StepOutput};
pub use summary::{RunSummary, SummaryBuilder};
pub use wind::{Wind, WindSpec};
pub use wings::{FromVehicle, WingSet, WingSetBuilder, WingSetOutput};
pub use wingset::{LoadSampling, StepMemory};

/// The built-in default vehicle (a hovering fruit fly).
pub const DROSOPHILA_TOML: &str = include_str!("../../../models/drosophila.toml");
/// The built-in RoboBee-class vehicle with prescribed wing kinematics.
pub const ROBOBEE_KINEMATIC_TOML: &str = include_str!("../../../models/robobee_kinematic.toml");
/// The built-in RoboBee-class vehicle: actuated wings (piezo stroke, passive pitch).
pub const ROBOBEE_TOML: &str = include_str!("../../../models/robobee.toml");
/// The built-in Purdue hummingbird robot (DC motors, passive pitch).
pub const HUMMINGBIRD_TOML: &str = include_str!("../../../models/hummingbird.toml");
/// The built-in bumblebee of Sun and Xiong (2005).
pub const BUMBLEBEE_TOML: &str = include_str!("../../../models/bumblebee.toml");

/// The built-in four-winged dragonfly of Azuma and Watanabe (1988) in forward flight (fore
/// and hind pairs: `[[pairs]]`).
pub const DRAGONFLY_TOML: &str = include_str!("../../../models/dragonfly.toml");

/// The built-in vehicles' names, the lightest first (each loads with [`builtin_model`]).
pub const BUILTIN_MODELS: [&str; 6] = [
    "drosophila",
    "bumblebee",
    "robobee_kinematic",
    "robobee",
    "hummingbird",
    "dragonfly",
];

/// A built-in model's text by name (`drosophila`, `bumblebee`, `robobee_kinematic`, the
/// four-winged `dragonfly`, and the actuated `robobee` and `hummingbird`).
pub fn builtin_model(name: &str) -> Option<&'static str> {
    match name {
        "drosophila" => Some(DROSOPHILA_TOML),
        "robobee" => Some(ROBOBEE_TOML),
        "robobee_kinematic" => Some(ROBOBEE_KINEMATIC_TOML),
        "bumblebee" => Some(BUMBLEBEE_TOML),
        "hummingbird" => Some(HUMMINGBIRD_TOML),
        "dragonfly" => Some(DRAGONFLY_TOML),
        _ => None,
    }
}
