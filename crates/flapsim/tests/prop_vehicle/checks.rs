//! Loading a vehicle and the contract every load follows: never a panic; an error whose
//! Display starts with `<origin>: `, a value error naming its field and saying "not
//! allowed", or a parse error; a vehicle that loads starts simulating without a panic or a
//! non-finite load or state (a divergence is a legitimate outcome of a run).

use std::panic::{AssertUnwindSafe, catch_unwind};

use flapsim::{Error, Mode, Simulation, Vehicle};
use proptest::prelude::*;

use crate::toml_mutation::{guarded, panic_message};

const ORIGIN: &str = "mut/vehicle variant é.toml";

pub(crate) fn load(text: &str) -> Result<Vehicle, Error> {
    Vehicle::from_toml(text, ORIGIN)
}

/// Loads with a `catch_unwind` guard.
pub(crate) fn load_guarded(text: &str) -> Result<Result<Vehicle, Error>, TestCaseError> {
    guarded(text, load)
}

pub(crate) fn check_error(e: &Error, text: &str) -> Result<(), TestCaseError> {
    let s = e.to_string();
    if KNOWN_BUG_CONTROLS && is_known_bug_controls(e) {
        return Ok(());
    }
    prop_assert!(
        s.starts_with(&format!("{ORIGIN}: ")),
        "error does not start with the origin: {s}\ninput:\n{text}"
    );
    match e {
        Error::Model(wingforce::Error::Invalid {
            origin,
            field,
            value,
            allowed,
        }) => {
            prop_assert_eq!(origin, ORIGIN);
            prop_assert!(!field.is_empty() && !value.is_empty() && !allowed.is_empty());
            prop_assert!(
                s.contains(&format!("field `{field}`")) && s.contains("not allowed"),
                "{}",
                s
            );
        }
        Error::Model(wingforce::Error::Parse { origin, message }) => {
            prop_assert_eq!(origin, ORIGIN);
            prop_assert!(!message.trim().is_empty());
        }
        other => prop_assert!(false, "loading returned a non-model error: {other}"),
    }
    Ok(())
}

/// Builds a simulation of a vehicle that loaded and runs up to `steps` steps: must not
/// panic; a step either succeeds or reports a divergence. Returns the first step's error.
pub(crate) fn simulate_briefly(v: Vehicle, steps: usize) -> Result<Option<String>, String> {
    catch_unwind(AssertUnwindSafe(|| {
        let mut sim = Simulation::new(v, Mode::Free);
        for _ in 0..steps {
            match sim.step() {
                Ok(_) => {}
                Err(e @ Error::Diverged { .. }) => return Some(e.to_string()),
                Err(e) => return Some(format!("non-divergence error: {e}")),
            }
        }
        None
    }))
    .map_err(panic_message)
}

/// What is wrong with a vehicle that loaded: a non-finite Re, a panic in the first steps,
/// or a first few steps that stop because a load or the state is not finite. (Stopping
/// because the speed exceeds `sim.max_speed_m_s` is a legitimate outcome of a run: a hinge
/// 1 m from a 1 mg body flips it at once; `flapwing simulate` exits 1 "diverged".)
pub(crate) fn unusable(v: Vehicle) -> Option<String> {
    for w in &v.wings {
        if !(w.reynolds().is_finite() && w.reynolds() > 0.0) {
            return Some(format!("Re = {}", w.reynolds()));
        }
    }
    match simulate_briefly(v, 3) {
        Err(panic) => Some(format!("simulation PANICKED: {panic}")),
        Ok(Some(e)) if e.contains("not finite") || e.contains("non-divergence") => Some(e),
        Ok(_) => None,
    }
}

/// KNOWN BUG (issue 7, reported to the lead): `VehicleSpec::build` calls
/// `Vehicle::apply_controls` before its own checks of the resulting amplitude and frequency
/// (the `controls (resulting left amplitude, deg)` errors), so a `[controls]` section whose
/// offsets are each within range but push the kinematics out of range (e.g. drosophila with
/// `[controls] amplitude_deg = 50.0`: 140 + 50 > 180) fails with `Error::Analysis("controls
/// give wing 0 an amplitude of 190.00 deg ...")`: no origin, no field, and the CLI exits 1
/// instead of 2. While this is `true`, such inputs are only checked to be rejected without a
/// panic; set it to `false` once fixed (the full contract below then applies).
pub(crate) const KNOWN_BUG_CONTROLS: bool = false;

/// The error of `KNOWN_BUG_CONTROLS` (`check_error` lets exactly it through while the flag is
/// set: random values of `controls.*` reach it in the structural and exhaustive tests too).
fn is_known_bug_controls(e: &Error) -> bool {
    matches!(e, Error::Analysis(m) if m.starts_with("controls give wing"))
}
