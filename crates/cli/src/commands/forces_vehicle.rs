//! `flapwing forces --model VEHICLE`: what `forces` evaluates. A wing model file (the
//! paper's robotic wing, the default) is one wing; a vehicle (a built-in name or a vehicle
//! model file, told apart by its `[body]` table) is the left wing of one of its pairs
//! (`--pair`), with the vehicle's own aerodynamic options and induced flow, held on a fixed
//! mount. An actuated vehicle's wing has no prescribed motion: it is evaluated on the
//! periodic motion its drive gives it with the body held still
//! ([`flapsim::actuated::periodic::settle`]), over one drive period at the model's step.

use std::path::Path;

use wingforce::{Wing, WingForces};

use crate::cli::ForcesArgs;
use crate::error::input_error;
use crate::input::{BUILTIN_ROBOFLY_ORIGIN, LoadedSpec, load_wing_spec};
use crate::vehicle::{VehicleSource, build_vehicle, sim_error};

/// Wingbeats evaluated by default (the means are the last one's).
pub const DEFAULT_CYCLES: u32 = 3;
/// Samples per wingbeat by default.
pub const DEFAULT_STEPS_PER_CYCLE: u32 = 1000;

/// The wing `forces` evaluates, and how.
pub struct Subject {
    /// The model's name.
    pub name: String,
    /// The model file, or `<built-in NAME>`.
    pub origin: String,
    /// Which wing of the model, in words.
    pub wing_label: String,
    /// The wing (an actuated one with the stroke reference measured on its periodic motion).
    pub wing: Wing,
    /// An actuated wing's periodic motion; `None`: prescribed kinematics.
    pub periodic: Option<Periodic>,
}

/// An actuated wing's forces over one drive period of its periodic motion.
pub struct Periodic {
    /// The wing's forces at each step of the period (phase k / steps).
    pub samples: Vec<WingForces>,
    /// Drive periods run to reach it, the one averaged included.
    pub cycles: usize,
    /// The drive frequency, Hz.
    pub freq_hz: f64,
}

/// Whether `--model` names a vehicle: a built-in vehicle, or a file with a `[body]` table.
fn vehicle_text(model: &Path) -> anyhow::Result<Option<VehicleSource>> {
    if let Some(name) = model.to_str()
        && flapsim::builtin_model(name).is_some()
    {
        return crate::vehicle::read_vehicle(Some(name)).map(Some);
    }
    if model.as_os_str() == "robofly" && !model.exists() {
        return Ok(None);
    }
    let origin = model.display().to_string();
    let text = flapsim::model::read_model_file(model).map_err(|e| {
        input_error(format!(
            "cannot read model file `{origin}` (give a wing model file, the built-in robofly, or a vehicle: a built-in name among drosophila, bumblebee, robobee_kinematic, dragonfly, robobee and hummingbird, or a vehicle model file): {e}"
        ))
    })?;
    let is_vehicle = text
        .parse::<toml::Table>()
        .is_ok_and(|t| t.contains_key("body"));
    Ok(is_vehicle.then_some(VehicleSource { text, origin }))
}

/// Loads `--model` as a wing model file, or as a vehicle (see the module doc).
pub fn load(args: &ForcesArgs) -> anyhow::Result<Result<LoadedSpec, Subject>> {
    let Some(model) = args.model.as_deref() else {
        if args.pair.is_some() {
            return Err(input_error(
                "--pair chooses a vehicle's wing pair: give the vehicle with --model (the default, the built-in robofly, is one wing)",
            ));
        }
        return load_wing_spec(None).map(Ok);
    };
    let vehicle = match vehicle_text(model)? {
        Some(src) => src,
        None => {
            if args.pair.is_some() {
                return Err(input_error(format!(
                    "--pair chooses a vehicle's wing pair; `{}` is a wing model file (one wing)",
                    model.display()
                )));
            }
            return if model.as_os_str() == "robofly" && !model.exists() {
                let mut loaded = load_wing_spec(None)?;
                loaded.origin = BUILTIN_ROBOFLY_ORIGIN.to_owned();
                Ok(Ok(loaded))
            } else {
                load_wing_spec(Some(model)).map(Ok)
            };
        }
    };
    vehicle_subject(args, &vehicle).map(Err)
}

/// The vehicle's wing `--pair` chooses, with the command's options applied.
fn vehicle_subject(args: &ForcesArgs, src: &VehicleSource) -> anyhow::Result<Subject> {
    let origin = &src.origin;
    let mut vehicle = build_vehicle(src)?;
    if args.dtau_a.is_some() || args.dtau_d.is_some() {
        return Err(input_error(format!(
            "--dtau-a and --dtau-d set a wing model file's trapezoidal kinematics; `{origin}` is a vehicle (edit its [kinematics] instead)"
        )));
    }
    let pairs = vehicle.pair_count();
    let pair = args.pair.unwrap_or(1);
    if !(1..=pairs).contains(&pair) {
        return Err(input_error(format!(
            "--pair {pair}: `{origin}` has {pairs} wing pair(s); allowed: 1 to {pairs}"
        )));
    }
    if args.no_wake_capture {
        for w in &mut vehicle.wings {
            let mut o = w.options().clone();
            o.wake_capture = None;
            w.set_options(o);
        }
    }
    let wing_label = format!("left wing of pair {pair} of {pairs}, on a fixed mount");
    if vehicle.actuation.is_none() {
        let mut wing = vehicle.wings[2 * (pair - 1)].clone();
        if let Some(re) = args.re {
            wing.set_reynolds(re)?;
        }
        return Ok(Subject {
            name: vehicle.name.clone(),
            origin: origin.clone(),
            wing_label,
            wing,
            periodic: None,
        });
    }
    let refused = [
        (args.re.is_some(), "--re"),
        (args.cycles.is_some(), "--cycles"),
        (args.steps_per_cycle.is_some(), "--steps-per-cycle"),
    ];
    if let Some((_, flag)) = refused.iter().find(|(given, _)| *given) {
        return Err(input_error(format!(
            "{flag}: `{origin}` has actuated wings, evaluated on the periodic motion their drive gives them at the model's own fluid, [sim] steps_per_wingbeat and [actuation] settle_cycles; {flag} applies to prescribed kinematics (edit the model file instead)"
        )));
    }
    let p = flapsim::actuated::periodic::settle(&vehicle, &wingforce::BodyMotion::default())
        .map_err(sim_error)?;
    Ok(Subject {
        name: vehicle.name.clone(),
        origin: origin.clone(),
        wing_label: format!("{wing_label}, on the periodic motion its drive gives it"),
        wing: p.wings[0].clone(),
        periodic: Some(Periodic {
            samples: p.samples.iter().map(|s| s[0]).collect(),
            cycles: p.cycles,
            freq_hz: vehicle.freq_hz(),
        }),
    })
}

/// The acceleration fractions that set `wing`'s wake-capture inputs: its measured stroke's
/// when it has one, else its kinematics'.
pub fn acceleration_fractions(wing: &Wing) -> (f64, f64) {
    match wing.stroke_reference() {
        Some(r) => (r.dtau_a, r.dtau_d),
        None => wing.kinematics().acceleration_fractions(),
    }
}
