//! Bad model files give an error naming the file, the field, the value and what is allowed.

use wingforce::{Error, WingModelSpec};

const GOOD: &str = include_str!("../../../models/robofly.toml");

fn load(text: &str) -> Result<wingforce::Wing, Error> {
    WingModelSpec::from_toml(text, "bad.toml").and_then(|s| s.build("bad.toml"))
}

/// `text` is refused with a value error naming bad.toml, `want_field` and `want_value`, and
/// saying `allowed_has` in what is allowed.
fn assert_invalid(text: &str, want_field: &str, want_value: &str, allowed_has: &str) {
    match load(text).unwrap_err() {
        Error::Invalid {
            origin,
            field,
            value,
            allowed,
        } => {
            assert_eq!(origin, "bad.toml");
            assert_eq!(field, want_field);
            assert_eq!(value, want_value);
            assert!(allowed.contains(allowed_has), "{allowed}");
        }
        e => panic!("wrong error {e}"),
    }
}

#[test]
fn good_model_loads() {
    load(GOOD).unwrap();
}

#[test]
fn unknown_field_is_named() {
    let text = GOOD.replace(
        "amplitude_deg = 155.0",
        "amplitude_deg = 155.0\nampltude = 3.0",
    );
    let e = load(&text).unwrap_err().to_string();
    assert!(e.contains("bad.toml") && e.contains("ampltude"), "{e}");
}

#[test]
fn negative_chord_is_rejected() {
    let rect = GOOD.split("[wing.planform]").next().unwrap().to_owned()
        + "[wing.planform]\nshape = \"rectangular\"\nspan_m = 0.25\nchord_m = -0.1\n\n[kinematics]\nfamily = \"harmonic\"\nfreq_hz = 1.0\namplitude_deg = 120.0\nmid_stroke_aoa_deg = 40.0\n";
    assert_invalid(&rect, "wing.planform.chord_m", "-0.1", "> 0");
}

#[test]
fn nan_is_rejected() {
    let text = GOOD.replace("mid_stroke_aoa_deg = 40.0", "mid_stroke_aoa_deg = nan");
    let e = load(&text).unwrap_err();
    let s = e.to_string();
    assert!(
        s.contains("kinematics.mid_stroke_aoa_deg") && s.contains("NaN") && s.contains("[0, 90]"),
        "{s}"
    );
}

#[test]
fn amplitude_beyond_180_is_rejected() {
    let text = GOOD.replace("amplitude_deg = 155.0", "amplitude_deg = 200.0");
    let s = load(&text).unwrap_err().to_string();
    assert!(
        s.contains("bad.toml")
            && s.contains("kinematics.amplitude_deg")
            && s.contains("200")
            && s.contains("180"),
        "{s}"
    );
}

#[test]
fn malformed_toml_names_the_file() {
    let s = load("[wing\nplanform = 3").unwrap_err().to_string();
    assert!(s.starts_with("bad.toml"), "{s}");
}

#[test]
fn non_periodic_table_is_rejected() {
    let text = GOOD.split("[kinematics]").next().unwrap().to_owned()
        + "[kinematics]\nfamily = \"tabulated\"\nt_s = [0.0, 0.1, 0.2, 0.3, 0.4]\nstroke_deg = [-60.0, 0.0, 60.0, 0.0, -50.0]\npitch_deg = [90.0, 45.0, 90.0, 135.0, 90.0]\n";
    let s = load(&text).unwrap_err().to_string();
    assert!(
        s.contains("kinematics.stroke_deg[4]") && s.contains("periodic"),
        "{s}"
    );
}

#[test]
fn non_monotonic_times_are_rejected() {
    let text = GOOD.split("[kinematics]").next().unwrap().to_owned()
        + "[kinematics]\nfamily = \"tabulated\"\nt_s = [0.0, 0.2, 0.1, 0.3, 0.4]\nstroke_deg = [-60.0, 0.0, 60.0, 0.0, -60.0]\npitch_deg = [90.0, 45.0, 90.0, 135.0, 90.0]\n";
    let s = load(&text).unwrap_err().to_string();
    assert!(
        s.contains("kinematics.t_s[2]") && s.contains("increase"),
        "{s}"
    );
}

#[test]
fn refitted_wake_model_must_be_finite_with_positive_mu_star() {
    let model = toml::to_string(&wingforce::WakeCaptureModel::paper()).unwrap();
    let table = |m: &str| format!("{GOOD}\n[aero.wake_capture_model]\n{m}");
    // The paper's own model, written out and read back, is accepted.
    let ok = table(
        &model
            .replace("[dcl]", "[aero.wake_capture_model.dcl]")
            .replace("[dcd]", "[aero.wake_capture_model.dcd]")
            .replace("[mu_star]", "[aero.wake_capture_model.mu_star]")
            .replace("[re_range]", "[aero.wake_capture_model.re_range]")
            .replace("[dtau_a_range]", "[aero.wake_capture_model.dtau_a_range]")
            .replace("[dtau_d_range]", "[aero.wake_capture_model.dtau_d_range]"),
    );
    load(&ok).unwrap();
    let nan = ok.replacen("c0 = 0.94839", "c0 = nan", 1);
    let s = load(&nan).unwrap_err().to_string();
    assert!(
        s.contains("aero.wake_capture_model.dcl.c0") && s.contains("NaN"),
        "{s}"
    );
    let neg = ok.replacen("m0 = 0.04195", "m0 = -1.0", 1);
    let s = load(&neg).unwrap_err().to_string();
    assert!(
        s.contains("aero.wake_capture_model.mu_star") && s.contains("mu* > 0"),
        "{s}"
    );
}

#[test]
fn pitch_flip_longer_than_a_half_stroke_is_rejected() {
    let text = GOOD.split("[kinematics]").next().unwrap().to_owned()
        + "[kinematics]\nfamily = \"harmonic_flip\"\nfreq_hz = 1.0\namplitude_deg = 120.0\ndownstroke_aoa_deg = 40.0\nupstroke_aoa_deg = 35.0\nflip_duration = 0.6\n";
    assert_invalid(&text, "kinematics.flip_duration", "0.6", "0.5");
}
