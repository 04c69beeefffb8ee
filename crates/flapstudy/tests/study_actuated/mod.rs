//! A study of an actuated vehicle varies what moves its wings.
//!
//! An actuated wing's motion is an output of its dynamics (`[actuation]`: the drive, the
//! transmission, the hinge); the model's `[kinematics]` is only the nominal motion its first
//! wingbeat starts from (the Re and wake-capture inputs until the motion has been measured).
//! A study's responses are taken on the wings' periodic motion, so a factor under
//! `kinematics` moves none of them: before this was refused, a RoboBee sweep of
//! `kinematics.amplitude_deg` wrote identical rows marked `ok`, and its `reynolds` column,
//! taken from the nominal motion, moved as though something had changed.

use flapstudy::hover_responses;
use flapstudy::spec::StudySpec;

/// The built-in `name` with the nominal `[kinematics]` line `from` replaced by `to`.
fn edited(name: &str, from: &str, to: &str) -> flapsim::Vehicle {
    let text = flapsim::builtin_model(name).unwrap();
    let edited = text.replacen(from, to, 1);
    assert_ne!(edited, text, "`{from}` not found in {name}");
    flapsim::Vehicle::from_toml(&edited, name).unwrap()
}

#[test]
fn the_nominal_kinematics_move_no_response_of_an_actuated_vehicle() {
    let base =
        flapsim::Vehicle::from_toml(flapsim::builtin_model("robobee").unwrap(), "robobee").unwrap();
    let other = edited(
        "robobee",
        "amplitude_deg = 90.0                # robobee3d",
        "amplitude_deg = 60.0                # robobee3d",
    );
    assert_ne!(
        base.wings[0].reynolds(),
        other.wings[0].reynolds(),
        "the nominal motion sets the unmeasured wing's Re"
    );
    let a = hover_responses(&base, base.sim.steps_per_wingbeat).unwrap();
    let b = hover_responses(&other, other.sim.steps_per_wingbeat).unwrap();
    // The same periodic motion: every response the same, bit for bit, Re included (the
    // measured motion's, not the nominal one's).
    assert_eq!(a, b);
    assert!(
        a.reynolds < 0.8 * base.wings[0].reynolds(),
        "{}",
        a.reynolds
    );
}

#[test]
fn a_study_refuses_a_kinematics_factor_on_an_actuated_vehicle() {
    for (name, path) in [
        ("robobee", "kinematics.amplitude_deg"),
        ("hummingbird", "kinematics.freq_hz"),
    ] {
        let study = format!(
            "base_model = \"{name}\"\ndesign = \"full_factorial\"\nresponses = [\"lift_over_weight\"]\n\
             [[factor]]\npath = \"{path}\"\nlevels = [30.0, 40.0]\n"
        );
        let spec = StudySpec::from_toml(&study, "study.toml").unwrap();
        let text = flapsim::builtin_model(name).unwrap();
        let e = spec
            .resolve("study.toml", "s", text, name)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with(&format!(
                "study.toml: factor 1 (`{path}`): base_model `{name}` has actuated wings"
            )),
            "{e}"
        );
        assert!(e.contains("`actuation.drive.freq_hz`"), "{e}");
    }
    // The same path on a prescribed vehicle is a factor like any other.
    let study = "base_model = \"drosophila\"\ndesign = \"full_factorial\"\nresponses = [\"lift_over_weight\"]\n\
                 [[factor]]\npath = \"kinematics.amplitude_deg\"\nlevels = [130.0, 140.0]\n";
    let spec = StudySpec::from_toml(study, "study.toml").unwrap();
    let text = flapsim::builtin_model("drosophila").unwrap();
    assert!(spec.resolve("study.toml", "s", text, "drosophila").is_ok());
}
