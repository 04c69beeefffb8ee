//! Where the hover trim's Newton search starts (`flapsim::trim::trim_at`).
//!
//! A model file holds its body at the attitude it is flown from, which for the built-in
//! dragonfly (Azuma & Watanabe 1988, experiment 2) is level, in forward flight at 1.5 m/s,
//! with its stroke planes tilted 55 deg (fore pair) and 48 deg (hind pair) to the body. In
//! hover the wings' mean force lies close to the normal of their stroke plane, which an
//! insect holds nearly horizontal (Weis-Fogh 1973, J Exp Biol 59:169, "normal hovering"), so
//! the hover balance lies some 50 deg of body pitch from the file's attitude, too far for
//! Newton's method from there (it left the allowed range before 2026-12-06, and `trim`,
//! `stability` and `hover` refused the dragonfly). The trim then searches again from the body
//! pitch that levels the mean stroke plane. Checked here: that pitch is the mean of the
//! file's tilts (analytic), the trim balances, and it does not depend on where it starts.

use flapsim::flight::FlightCondition;
use flapsim::trim::{LiftVariable, level_stroke_plane_pitch_rad, trim, trim_from};
use flapsim::{Vehicle, builtin_model};
use nalgebra::Vector3;

fn dragonfly() -> Vehicle {
    Vehicle::from_toml(builtin_model("dragonfly").unwrap(), "dragonfly").unwrap()
}

#[test]
fn the_level_stroke_plane_pitch_is_the_mean_of_the_pairs_tilts() {
    // Two wings at 55 deg and two at 48 deg to the body (models/dragonfly.toml).
    let p = level_stroke_plane_pitch_rad(&dragonfly()).to_degrees();
    assert!((p - 51.5).abs() < 1e-9, "{p}");
}

#[test]
fn the_dragonfly_trims_in_hover_from_its_level_body_and_from_any_start_nearby() {
    let v = dragonfly();
    let t = trim(&v).unwrap();
    assert!(t.max_residual() < 1e-10, "{t:?}");
    assert!(t.condition.is_hover());
    // Newton's root from starts 16 deg below to 28 deg above the levelled stroke plane
    // (51.5 deg): one trim (from 30 deg and below the search leaves the range).
    for start_deg in [35.0f64, 45.0, 65.0, 80.0] {
        let s = trim_from(
            &v,
            LiftVariable::Amplitude,
            &FlightCondition::HOVER,
            Vector3::new(0.0, 0.0, start_deg.to_radians()),
        )
        .unwrap();
        assert!(
            (s.pitch_rad - t.pitch_rad).abs() < 1e-8,
            "{start_deg}: {s:?}"
        );
        assert!(
            (s.controls.amplitude_rad - t.controls.amplitude_rad).abs() < 1e-8,
            "{start_deg}: {s:?}"
        );
    }
    // The hover trim is the limit of the forward-flight trims as the speed falls (each a
    // continuation from it): 0.02 m/s moves the body pitch by less than 2 deg (1.1 deg
    // measured; the fore-aft drag derivative X_u = -7.3e-3 N s/m over the 7.7e-3 N weight
    // tilts the force by 1.1 deg at that speed).
    let slow = flapsim::trim::trim_at(
        &v,
        LiftVariable::Amplitude,
        &FlightCondition {
            forward_speed_m_s: 0.02,
            climb_rate_m_s: 0.0,
        },
    )
    .unwrap();
    assert!(
        (slow.pitch_rad - t.pitch_rad).abs().to_degrees() < 2.0,
        "{slow:?} against {t:?}"
    );
}
