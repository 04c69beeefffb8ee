//! `flapwing identify` driven as a user would: a hover logged by the real binary, fitted,
//! the fitted model written and loaded by `flapwing trim`; bad inputs and a fit that does
//! not converge give clear messages and exit codes.

use crate::common;

use std::path::Path;

use common::{Run as Out, flapwing_in};

/// Runs the binary in the test's working directory (the paths below are absolute).
fn flapwing(args: &[&str]) -> Out {
    flapwing_in(Path::new("."), args)
}

/// A 0.5 s closed-loop hover of the built-in fruit fly with its sensors, logged by `hover`.
fn hover_log(dir: &Path) -> String {
    let log = dir.join("hover.mcap");
    let log_s = log.to_str().unwrap().to_owned();
    let rrd = dir.join("hover.rrd");
    let o = flapwing(&[
        "hover",
        "--model",
        "drosophila",
        "--duration-s",
        "0.5",
        "--mcap",
        &log_s,
        "--rrd",
        rrd.to_str().unwrap(),
    ]);
    assert_eq!(o.code, 0, "{}{}", o.stdout, o.stderr);
    log_s
}

/// The whole path: the real `hover` log of the built-in model (its 200 Hz, 0.15 mm, 3.4 deg
/// motion capture), fitted from the model it was flown with: converges, the rms residual is
/// the noise's (about 1: the model is the truth), the JSON has every documented field, the
/// roll inertia is flagged not identifiable, and the written model loads in `trim`. Fails
/// if the replay does not reproduce `hover`'s flight or the model writer breaks the file.
#[test]
fn a_hover_log_is_identified_and_the_fitted_model_loads() {
    let dir = tempfile::tempdir().unwrap();
    let log = hover_log(dir.path());
    let out = dir.path().join("fitted.toml");
    let out_s = out.to_str().unwrap();
    let o = flapwing(&[
        "identify",
        &log,
        "--params",
        "inertia_yy_kg_m2,com_offset_x_m,inertia_xx_kg_m2",
        "--out",
        out_s,
        "--json",
    ]);
    assert_eq!(o.code, 0, "{}{}", o.stdout, o.stderr);
    let v: serde_json::Value = serde_json::from_str(&o.stdout).unwrap();
    for k in [
        "source",
        "segments",
        "residuals",
        "dof",
        "iterations",
        "simulations",
        "cost_before",
        "cost_after",
        "rms_after",
        "converged",
        "termination",
        "condition_number",
        "params",
        "fitted_model",
    ] {
        assert!(v.get(k).is_some(), "no `{k}` in {v}");
    }
    assert_eq!(v["converged"], true);
    let rms = v["rms_after"].as_f64().unwrap();
    assert!(rms > 0.8 && rms < 1.2, "rms {rms}");
    let p = &v["params"];
    for k in [
        "name",
        "start",
        "fitted",
        "std_error",
        "ci95",
        "identifiable",
        "reason",
    ] {
        assert!(p[0].get(k).is_some(), "no `{k}` in {}", p[0]);
    }
    assert_eq!(p[0]["identifiable"], true, "{}", p[0]);
    assert_eq!(p[2]["identifiable"], false, "{}", p[2]);
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("FITTED body.inertia_diag_kg_m2[1]"), "{text}");
    assert!(text.contains("hover.mcap"), "the comment names the log");
    let t = flapwing(&["trim", "--model", out_s]);
    assert_eq!(t.code, 0, "{}{}", t.stdout, t.stderr);
    // The text report and --force.
    let o = flapwing(&["identify", &log, "--out", out_s]);
    assert_eq!(o.code, 2, "an existing --out needs --force");
    assert!(o.stderr.contains("--force"), "{}", o.stderr);
    let o = flapwing(&["identify", &log, "--out", out_s, "--force"]);
    assert_eq!(o.code, 0, "{}{}", o.stdout, o.stderr);
    assert!(
        o.stdout.contains("95% interval") && o.stdout.contains("wrote the fitted model"),
        "{}",
        o.stdout
    );
}

/// A fit with too little patience: the report says it did not converge, no model is
/// written, exit 1.
#[test]
fn a_fit_that_does_not_converge_is_reported_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let log = hover_log(dir.path());
    let out = dir.path().join("fitted.toml");
    let o = flapwing(&[
        "identify",
        &log,
        "--patience",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.code, 1, "{}{}", o.stdout, o.stderr);
    assert!(o.stdout.contains("did not converge"), "{}", o.stdout);
    assert!(o.stderr.contains("did not converge"), "{}", o.stderr);
    assert!(!out.exists());
}

/// Bad inputs exit 2 with the file, the field or column and what is allowed.
#[test]
fn bad_inputs_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let o = flapwing(&["identify", "no/such.mcap"]);
    assert_eq!(o.code, 2);
    assert!(o.stderr.contains("no/such.mcap"), "{}", o.stderr);
    // A log without sensors.
    let plain = dir.path().join("plain.mcap");
    let plain_s = plain.to_str().unwrap();
    let s = flapwing(&[
        "simulate",
        "--duration-s",
        "0.01",
        "--mcap",
        plain_s,
        "--no-sensors",
    ]);
    assert_eq!(s.code, 0, "{}", s.stderr);
    let o = flapwing(&["identify", plain_s]);
    assert_eq!(o.code, 2, "{}", o.stderr);
    assert!(
        o.stderr.contains("/sensors/mocap") && o.stderr.contains("plain.mcap"),
        "{}",
        o.stderr
    );
    // A CSV with unsorted times, missing columns, or without --model.
    let csv = dir.path().join("f.csv");
    let csv_s = csv.to_str().unwrap();
    let h = "t_s,x_m,y_m,z_m,qw,qx,qy,qz,mean_stroke_rad,amplitude_rad,diff_amplitude_rad,diff_pitch_bias_rad";
    std::fs::write(
        &csv,
        format!("{h}\n0.002,0,0,0,1,0,0,0,0,0,0,0\n0.001,0,0,0,1,0,0,0,0,0,0,0\n"),
    )
    .unwrap();
    let o = flapwing(&["identify", csv_s]);
    assert_eq!(o.code, 2);
    assert!(o.stderr.contains("--model"), "{}", o.stderr);
    let o = flapwing(&["identify", csv_s, "--model", "drosophila"]);
    assert_eq!(o.code, 2);
    assert!(
        o.stderr.contains("line 3") && o.stderr.contains("increasing"),
        "{}",
        o.stderr
    );
    std::fs::write(&csv, "t_s,x_m\n0,0\n").unwrap();
    let o = flapwing(&["identify", csv_s, "--model", "drosophila"]);
    assert_eq!(o.code, 2);
    assert!(
        o.stderr.contains("missing column") && o.stderr.contains("qw"),
        "{}",
        o.stderr
    );
    // An unknown parameter.
    let o = flapwing(&["identify", plain_s, "--params", "wing_colour"]);
    assert_eq!(o.code, 2);
    assert!(
        o.stderr.contains("wing_colour") && o.stderr.contains("allowed"),
        "{}",
        o.stderr
    );
}
