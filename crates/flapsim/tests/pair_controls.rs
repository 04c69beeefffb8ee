//! Controls per wing pair (`[[pairs]] control_gain`): each further pair's kinematic offsets
//! are the control channels' times its gain, so a tandem vehicle can hold a pair still
//! (gain 0) or move it against the first (gain -1: a mean-stroke command shifts the fore and
//! hind strokes apart, the pitch couple a dragonfly makes).

use flapsim::Vehicle;
use flapsim::averaged::{FrozenState, mean_loads};
use flapsim::model::Controls;
use nalgebra::Vector3;

fn dragonfly(gain: Option<&str>) -> Vehicle {
    let text = flapsim::builtin_model("dragonfly").unwrap();
    let text = match gain {
        Some(g) => text.replacen(
            "phase_offset_deg = ",
            &format!("control_gain = {g}\nphase_offset_deg = "),
            1,
        ),
        None => text.to_owned(),
    };
    Vehicle::from_toml(&text, "dragonfly.toml").unwrap()
}

fn command() -> Controls {
    Controls {
        mean_stroke_rad: 0.1,
        amplitude_rad: 0.05,
        diff_amplitude_rad: 0.02,
        ..Controls::default()
    }
}

#[test]
fn each_pair_moves_by_its_gain() {
    let c = command();
    for (gain, g) in [
        (Some("0.0"), 0.0),
        (Some("-1.0"), -1.0),
        (Some("0.5"), 0.5),
        (None, 1.0),
    ] {
        let mut v = dragonfly(gain);
        v.apply_controls(&c).unwrap();
        for i in 0..4 {
            let k = v.wings[i].kinematics();
            let base = &v.base_kinematics[i];
            let half = if i % 2 == 0 { 0.5 } else { -0.5 };
            let scale = if i < 2 { 1.0 } else { g };
            let d_mean = k.mean_stroke_rad - base.mean_stroke_rad;
            let d_amp = k.amplitude_rad - base.amplitude_rad;
            assert!(
                (d_mean - scale * 0.1).abs() < 1e-15,
                "gain {g}, wing {i}: {d_mean}"
            );
            assert!(
                (d_amp - scale * (0.05 + half * 0.02)).abs() < 1e-15,
                "gain {g}, wing {i}: {d_amp}"
            );
            assert_eq!(k.freq_hz, base.freq_hz);
        }
    }
}

#[test]
fn gain_one_is_the_default_bit_for_bit() {
    let state = FrozenState {
        world_from_body: nalgebra::UnitQuaternion::identity(),
        velocity_body_m_s: Vector3::new(1.5, 0.0, 0.0),
        angular_velocity_body_rad_s: Vector3::zeros(),
    };
    let mut a = dragonfly(None);
    let mut b = dragonfly(Some("1.0"));
    a.apply_controls(&command()).unwrap();
    b.apply_controls(&command()).unwrap();
    assert_eq!(
        mean_loads(&a, &state, 200).unwrap(),
        mean_loads(&b, &state, 200).unwrap()
    );
    // Held still, the hind pair's loads do not follow the command.
    let mut held = dragonfly(Some("0.0"));
    let base = mean_loads(&held, &state, 200).unwrap();
    held.apply_controls(&command()).unwrap();
    let moved = mean_loads(&held, &state, 200).unwrap();
    assert_ne!(base, moved);
}

#[test]
fn a_bad_gain_is_refused_naming_it() {
    for g in ["nan", "5.0", "-3.0"] {
        let text = flapsim::builtin_model("dragonfly").unwrap().replacen(
            "phase_offset_deg = ",
            &format!("control_gain = {g}\nphase_offset_deg = "),
            1,
        );
        let e = Vehicle::from_toml(&text, "dragonfly.toml")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("dragonfly.toml")
                && e.contains("pairs[0].control_gain")
                && e.contains("[-2, 2]"),
            "{e}"
        );
    }
}
