//! Re-running a `simulate` or `hover` log and comparing its trajectory bit for bit.
//!
//! A `hover` log re-runs the command's controlled hover from its logged settings
//! (`hover.rs`: the trim, the disturbance, the controller, the wind); the rest of this doc
//! is the `simulate` re-run, and the comparison (`compare.rs`) is the same for both.
//!
//! [`check_log`] rebuilds the vehicle from the embedded model text
//! (`flapsim::Vehicle::from_toml(model_toml, model_origin)`), runs
//! `flapsim::Simulation::new(vehicle, mode)` with `set_wind(wind_world_m_s)` and the run's
//! wind field (`set_wind_model`): the settings' `wind` when the run's wind flags made one
//! (`flapwing simulate` writes it there; `null` when `--no-wind` switched the model's off),
//! else the model's `[wind]` field, if any, for
//! `round(duration_s / dt)` steps with no controller (exactly what `flapwing simulate`
//! does), picks samples with the same [`crate::Decimator`], and compares every logged
//! `/vehicle/state` sample: position, velocity, attitude quaternion and body rates, as f64
//! bits (the log's `load_sampling` metadata, or, for a log written before issue 37, the
//! step-start sampling of that time, sets where the re-run takes the loads, and its
//! `body_rotation` metadata, or its absence, how it advances the body's rates; protobuf
//! doubles are the bits themselves, but for the sign of a zero, which proto3
//! does not keep; the JSON numbers of logs written before
//! issue #16 are read back with a correctly rounded parser, so they survive the round trip
//! exactly, and there a logged 0 matches a non-finite value, which JSON could not hold). A
//! log that ends early (a stopped or truncated run) is compared as far as it goes.
//!
//! A log with `/wind` (a run with a wind field) has each logged wing wind compared too, bit
//! for bit, with the re-run's [`flapsim::Simulation::wing_winds_m_s`] after the same step
//! (the uniform wind at each wing without a field). The other optional channels
//! (`/sensors/imu`, `/sensors/mocap`, `/estimate`) are not re-run.

use std::path::Path;

use nalgebra::Vector3;

mod compare;
mod hover;
mod outcome;

use crate::error::{Error, Result};
use crate::json::Json;
use crate::options::SimSettings;
use crate::read::read_log;
use crate::schema::{
    ACTUATED_STAGE_LOADS_INTERPOLATED, ACTUATED_STAGE_LOADS_KEY, ACTUATED_STAGE_LOADS_SPLIT,
    ACTUATED_STEP_MEAN_KEY, ACTUATED_STEP_MEAN_SPLIT, BODY_ROTATION_KEY, BODY_ROTATION_MIDPOINT,
    STRIKE_IMPULSE_KEY, STRIKE_IMPULSE_SHARED, STRIKE_IMPULSE_SHARED_TRAPEZOIDAL, TOPIC_STATE,
    TOPIC_WIND,
};
use compare::{Comparer, logged_values};
pub use outcome::CheckOutcome;

/// The wing winds of a `/wind` message (world, m/s), `None` if it does not read.
fn logged_winds(v: &Json) -> Option<Vec<[f64; 3]>> {
    match v.get("wing_winds_world_m_s") {
        Some(Json::Arr(items)) => items
            .iter()
            .map(|w| Some([w.f64_at("x")?, w.f64_at("y")?, w.f64_at("z")?]))
            .collect(),
        // proto3 leaves an empty list off the wire.
        None => Some(Vec::new()),
        Some(_) => None,
    }
}

/// Re-runs a `simulate` or `hover` log and compares it (see the module docs). Errors: the
/// file cannot be read or is not a flapwing log, the embedded settings are not valid, the
/// embedded model does not load.
pub fn check_log(path: impl AsRef<Path>) -> Result<CheckOutcome> {
    let path = path.as_ref();
    let log = read_log(path)?;
    let md = log.run_metadata();
    let command = md.get("command").map(String::as_str).unwrap_or("");
    let settings_text = md.get("settings").map(String::as_str).unwrap_or("");
    let run = match command {
        "simulate" => {
            let settings = SimSettings::from_json(settings_text)?;
            if settings.mode == "locked" {
                return Ok(CheckOutcome::NotCheckable {
                    reason: "the run used a custom locked mode, which the settings do not describe"
                        .into(),
                });
            }
            let mode = settings.mode_value()?;
            if !(settings.duration_s.is_finite() && settings.duration_s >= 0.0) {
                return Err(Error::Embedded(format!(
                    "the settings' duration {} s is not a finite time >= 0",
                    settings.duration_s
                )));
            }
            Rerun::Simulate(settings, mode)
        }
        "hover" => match hover::HoverSettings::from_json(settings_text)? {
            Ok(s) => Rerun::Hover(s),
            Err(reason) => return Ok(CheckOutcome::NotCheckable { reason }),
        },
        _ => {
            return Ok(CheckOutcome::NotCheckable {
                reason: format!(
                    "the log was written by `flapwing {command}`; only `simulate` and `hover` logs can be re-run"
                ),
            });
        }
    };
    let origin = md
        .get("model_origin")
        .map(String::as_str)
        .unwrap_or("model");
    let toml = md.get("model_toml").map(String::as_str).unwrap_or("");
    let embedded = |e: flapsim::Error| {
        Error::Embedded(format!(
            "the model embedded in `{}` does not load: {e}",
            path.display()
        ))
    };
    let mut spec = flapsim::VehicleSpec::from_toml(toml, origin).map_err(embedded)?;
    spec.aero.added_mass = logged_added_mass_form(md, spec.aero.added_mass)?;
    spec.sim.load_sampling = Some(logged_load_sampling(md, spec.actuation.is_some())?);
    // A run logged before the midpoint rotation advanced the body's rates as rapier does.
    spec.sim.rotation_at_step_start =
        md.get(BODY_ROTATION_KEY).map(String::as_str) != Some(BODY_ROTATION_MIDPOINT);
    // A run logged before the strikes were shared between steps reported each in its step.
    spec.sim.strike_share = Some(logged_strike_share(md)?);
    // A run logged before the stops' stage loads were interpolated took them at every stage.
    spec.sim.actuated_stage_loads = logged_stage_loads(md)?;
    let vehicle = spec.build(origin).map_err(embedded)?;
    // The rate the recorder actually used (it writes it itself), else the settings'.
    let settings_rate = match &run {
        Rerun::Simulate(settings, _) => settings.log_rate_hz,
        Rerun::Hover(_) => None,
    };
    let rate = match md.get("log_rate_hz").map(String::as_str) {
        Some("every step") => None,
        Some(r) => match r.parse::<f64>() {
            Ok(r) if r.is_finite() && r > 0.0 => Some(r),
            Ok(r) => {
                return Ok(CheckOutcome::NotCheckable {
                    reason: format!("the log's `log_rate_hz` metadata {r} is not a rate > 0"),
                });
            }
            Err(_) => settings_rate,
        },
        None => settings_rate,
    };

    let json = log.message_encoding(TOPIC_STATE) == Some("json");
    let mut logged = Vec::new();
    for (i, m) in log.on(TOPIC_STATE).enumerate() {
        match log.parse(m).as_ref().and_then(logged_values) {
            Some(v) => logged.push(v),
            None => {
                return Ok(CheckOutcome::Mismatch {
                    samples_matched: i as u64,
                    detail: format!(
                        "/vehicle/state message {i} (log time {} ns) is not a readable state",
                        m.log_time
                    ),
                });
            }
        }
    }
    if logged.is_empty() {
        return Ok(CheckOutcome::NotCheckable {
            reason: "the log holds no /vehicle/state sample".into(),
        });
    }
    // The logged winds by log time.
    let mut winds = std::collections::HashMap::new();
    for (i, m) in log.on(TOPIC_WIND).enumerate() {
        match log.parse(m).as_ref().and_then(logged_winds) {
            Some(w) => {
                winds.insert(m.log_time, w);
            }
            None => {
                return Ok(CheckOutcome::Mismatch {
                    samples_matched: 0,
                    detail: format!(
                        "/wind message {i} (log time {} ns) is not a readable wind",
                        m.log_time
                    ),
                });
            }
        }
    }
    let comparer = Comparer::new(logged, winds, json, rate);
    let complete = log.complete;
    match run {
        Rerun::Simulate(settings, mode) => {
            let wind = simulate_wind(path, origin, settings_text, &vehicle)?;
            rerun_simulate(&settings, mode, vehicle, wind, comparer, complete)
        }
        Rerun::Hover(settings) => hover::rerun(&settings, vehicle, comparer, complete),
    }
}

/// What a log's command re-runs.
enum Rerun {
    /// `flapwing simulate`: its settings and mode.
    Simulate(SimSettings, flapsim::Mode),
    /// `flapwing hover`.
    Hover(hover::HoverSettings),
}

/// The wind field of a `simulate` log's run: the settings' `wind` (the wind flags' field;
/// `null`: still air, `--no-wind`), else the model's own `[wind]`, as `flapwing simulate`
/// flies it.
fn simulate_wind(
    path: &Path,
    origin: &str,
    settings_text: &str,
    vehicle: &flapsim::Vehicle,
) -> Result<Option<flapsim::Wind>> {
    let raw: serde_json::Value =
        serde_json::from_str(settings_text).unwrap_or(serde_json::Value::Null);
    let spec = match raw.get("wind") {
        Some(serde_json::Value::Null) => None,
        Some(w) => Some(
            serde_json::from_value::<flapsim::WindSpec>(w.clone()).map_err(|e| {
                Error::Embedded(format!(
                    "the settings' `wind` in `{}` does not load: {e}",
                    path.display()
                ))
            })?,
        ),
        None => vehicle.wind.clone(),
    };
    spec.as_ref()
        .map(|w| flapsim::Wind::from_spec(w, origin, vehicle.initial_position_m))
        .transpose()
        .map_err(|e| {
            Error::Embedded(format!(
                "the model embedded in `{}` does not load: {e}",
                path.display()
            ))
        })
}

/// Re-runs a `simulate` log: `vehicle` in its mode, no controller, in `wind`, for
/// round(duration / dt) steps, exactly as `flapwing simulate` does.
fn rerun_simulate(
    settings: &SimSettings,
    mode: flapsim::Mode,
    vehicle: flapsim::Vehicle,
    wind: Option<flapsim::Wind>,
    mut comparer: Comparer,
    complete: bool,
) -> Result<CheckOutcome> {
    let mut sim = flapsim::Simulation::new(vehicle, mode);
    sim.set_wind(Vector3::from(settings.wind_world_m_s));
    sim.set_wind_model(wind);
    let n = (settings.duration_s / sim.dt_s()).round() as u64;
    for _ in 0..n {
        if comparer.done() {
            break;
        }
        let out = match sim.step() {
            Ok(out) => *out,
            Err(e) => return Ok(comparer.stopped(&e.to_string())),
        };
        if let Some(m) = comparer.step(&out, &sim) {
            return Ok(m);
        }
    }
    Ok(comparer.finish(settings.duration_s, complete))
}

/// Where in a step the logged run took the wings' loads: the log's `load_sampling`
/// metadata, else (a log written before issue 37, when there was one sampling) the step's
/// start. Actuated wings (`actuated`) logged under the step mean before it split their steps
/// at stroke reversals (no [`ACTUATED_STEP_MEAN_KEY`]) took their loads as the midpoint
/// sampling still does, and re-run with it.
fn logged_load_sampling(
    md: &std::collections::BTreeMap<String, String>,
    actuated: bool,
) -> Result<flapsim::LoadSampling> {
    use flapsim::LoadSampling;
    match md.get("load_sampling") {
        Some(name) => match LoadSampling::from_name(name) {
            Some(LoadSampling::StepMean)
                if actuated
                    && md.get(ACTUATED_STEP_MEAN_KEY).map(String::as_str)
                        != Some(ACTUATED_STEP_MEAN_SPLIT) =>
            {
                Ok(LoadSampling::Midpoint)
            }
            Some(s) => Ok(s),
            None => Err(Error::Embedded(format!(
                "the log's `load_sampling` metadata `{name}` is not a sampling: allowed {}",
                LoadSampling::allowed()
            ))),
        },
        None => Ok(LoadSampling::StepStart),
    }
}

/// How the logged run's actuated wings shared a strike between steps
/// ([`STRIKE_IMPULSE_KEY`]).
fn logged_strike_share(
    md: &std::collections::BTreeMap<String, String>,
) -> Result<flapsim::actuated::dynamics::StrikeShare> {
    use flapsim::actuated::dynamics::StrikeShare;
    match md.get(STRIKE_IMPULSE_KEY).map(String::as_str) {
        None => Ok(StrikeShare::WholeInStep),
        Some(STRIKE_IMPULSE_SHARED) => Ok(StrikeShare::SemiImplicitPose),
        Some(STRIKE_IMPULSE_SHARED_TRAPEZOIDAL) => Ok(StrikeShare::TrapezoidalPose),
        Some(other) => Err(Error::Embedded(format!(
            "the log's `{STRIKE_IMPULSE_KEY}` metadata `{other}` is not a way of sharing a strike: allowed \"{STRIKE_IMPULSE_SHARED}\", \"{STRIKE_IMPULSE_SHARED_TRAPEZOIDAL}\" (none: whole in its step)"
        ))),
    }
}

/// How the logged run's wings on inelastic stops took their loads within a step
/// ([`ACTUATED_STAGE_LOADS_KEY`]).
fn logged_stage_loads(
    md: &std::collections::BTreeMap<String, String>,
) -> Result<flapsim::actuated::dynamics::StageLoads> {
    use flapsim::actuated::dynamics::StageLoads;
    match md.get(ACTUATED_STAGE_LOADS_KEY).map(String::as_str) {
        None => Ok(StageLoads::EveryStage),
        Some(ACTUATED_STAGE_LOADS_INTERPOLATED) => Ok(StageLoads::Interpolated),
        Some(ACTUATED_STAGE_LOADS_SPLIT) => Ok(StageLoads::Split),
        Some(other) => Err(Error::Embedded(format!(
            "the log's `{ACTUATED_STAGE_LOADS_KEY}` metadata `{other}` is not a way of taking the loads: allowed \"{ACTUATED_STAGE_LOADS_INTERPOLATED}\", \"{ACTUATED_STAGE_LOADS_SPLIT}\" (none: at every stage)"
        ))),
    }
}

/// The added-mass form the logged run used: the log's `added_mass_form` metadata, else (a log
/// written before the forms existed, when eq 7-8 was the only form) the paper's form, unless
/// the embedded model switched the term off. `from_model` is what the embedded model file
/// resolves to today.
fn logged_added_mass_form(
    md: &std::collections::BTreeMap<String, String>,
    from_model: wingforce::AddedMassForm,
) -> Result<wingforce::AddedMassForm> {
    use wingforce::AddedMassForm;
    match md.get("added_mass_form") {
        Some(name) => AddedMassForm::from_name(name).ok_or_else(|| {
            Error::Embedded(format!(
                "the log's `added_mass_form` metadata `{name}` is not a form: allowed \"impulse\", \"paper\", \"off\""
            ))
        }),
        None if from_model == AddedMassForm::Off => Ok(AddedMassForm::Off),
        None => Ok(AddedMassForm::Paper),
    }
}
