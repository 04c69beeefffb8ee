//! Bad model files and bad flags exit with 2 and a message naming the file and the field;
//! the binary never panics on them.

use crate::common;

use common::{ROBOFLY, Run, flapwing, flapwing_in};

/// Writes `text` as `bad.toml` and runs `flapwing forces --model bad.toml`.
fn forces_with_model(text: &str) -> Run {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bad.toml"), text).unwrap();
    flapwing_in(dir.path(), &["forces", "--model", "bad.toml"])
}

fn assert_names(run: &Run, needles: &[&str]) {
    run.assert_bad_input();
    for n in needles {
        assert!(run.stderr.contains(n), "`{n}` missing from: {}", run.stderr);
    }
}

#[test]
fn shipped_model_loads_from_a_file() {
    let run = forces_with_model(ROBOFLY);
    assert_eq!(run.code, 0, "{run:?}");
}

#[test]
fn unknown_field() {
    let text = ROBOFLY.replace(
        "amplitude_deg = 155.0",
        "amplitude_deg = 155.0\nampltude = 3.0",
    );
    assert_names(&forces_with_model(&text), &["bad.toml", "ampltude"]);
}

#[test]
fn negative_chord() {
    let (head, _) = ROBOFLY.split_once("[wing.planform]").unwrap();
    let text = format!(
        "{head}[wing.planform]\nshape = \"rectangular\"\nspan_m = 0.25\nchord_m = -0.1\n\n\
         [kinematics]\nfamily = \"harmonic\"\nfreq_hz = 1.0\namplitude_deg = 120.0\n\
         mid_stroke_aoa_deg = 40.0\n"
    );
    assert_names(
        &forces_with_model(&text),
        &["bad.toml", "wing.planform.chord_m", "-0.1", "> 0"],
    );
}

#[test]
fn nan_angle() {
    let text = ROBOFLY.replace("mid_stroke_aoa_deg = 40.0", "mid_stroke_aoa_deg = nan");
    assert_names(
        &forces_with_model(&text),
        &["bad.toml", "kinematics.mid_stroke_aoa_deg", "NaN"],
    );
}

#[test]
fn amplitude_of_200_degrees() {
    let text = ROBOFLY.replace("amplitude_deg = 155.0", "amplitude_deg = 200.0");
    assert_names(
        &forces_with_model(&text),
        &["bad.toml", "kinematics.amplitude_deg", "200", "180"],
    );
}

#[test]
fn malformed_toml() {
    assert_names(&forces_with_model("[wing\nplanform = 3"), &["bad.toml"]);
}

#[test]
fn nonexistent_file() {
    let run = flapwing(&["forces", "--model", "no_such_model.toml"]);
    assert_names(&run, &["no_such_model.toml", "cannot read model file"]);
}

#[test]
fn directory_as_model() {
    let run = flapwing(&["forces", "--model", "."]);
    assert_names(&run, &["cannot read model file"]);
}

#[test]
fn bad_flags() {
    for args in [
        &["forces", "--bogus"][..],
        &["forces", "--cycles", "0"],
        &["forces", "--steps-per-cycle", "-3"],
        &["forces", "--re", "nan"],
        &["forces", "--dtau-d", "0.7"],
        &["no-such-command"],
        &[],
    ] {
        let run = flapwing(args);
        assert_eq!(run.code, 2, "{args:?}: {run:?}");
        assert!(!run.stderr.contains("panicked"), "{args:?}: {run:?}");
    }
}

#[test]
fn overrides_that_break_the_kinematics_name_the_flags() {
    // Each ramp is allowed alone, but both must fit in one half stroke.
    let run = flapwing(&["forces", "--dtau-a", "0.3", "--dtau-d", "0.3"]);
    assert_names(&run, &["--dtau-a/--dtau-d", "dtau_a + dtau_d", "0.5"]);
}

#[test]
fn stability_step_override_out_of_range() {
    let run = flapwing(&[
        "stability",
        "--model",
        "bumblebee",
        "--no-floquet",
        "--steps-per-wingbeat",
        "5",
    ]);
    assert_names(&run, &["--steps-per-wingbeat", "5", "10 to 100000"]);
}

/// A vehicle stepped more coarsely than its model file's stated accuracy bound
/// (`sim.accurate_steps_per_wingbeat`, from the error-cost frontier) warns and still runs;
/// at the bound it is silent; an impossible bound is refused naming the field.
#[test]
fn a_step_coarser_than_the_stated_bound_warns() {
    let dir = tempfile::tempdir().unwrap();
    let fly = flapsim::DROSOPHILA_TOML;
    assert!(fly.contains("\naccurate_steps_per_wingbeat = 20 "));
    let with_steps = |n: usize| {
        fly.replace(
            "\nsteps_per_wingbeat = 20 ",
            &format!("\nsteps_per_wingbeat = {n} "),
        )
    };
    std::fs::write(dir.path().join("coarse.toml"), with_steps(16)).unwrap();
    std::fs::write(dir.path().join("bound.toml"), with_steps(20)).unwrap();
    let args = |m: &'static str| {
        [
            "simulate",
            "--model",
            m,
            "--duration-s",
            "0.005",
            "--no-log",
        ]
    };
    let run = flapwing_in(dir.path(), &args("coarse.toml"));
    assert_eq!(run.code, 0, "{run:?}");
    assert!(
        run.stderr.contains(
            "warning: `drosophila` is stepped at 16 steps per wingbeat, coarser than the 20"
        ),
        "{}",
        run.stderr
    );
    let run = flapwing_in(dir.path(), &args("bound.toml"));
    assert_eq!(run.code, 0, "{run:?}");
    assert!(!run.stderr.contains("coarser than"), "{}", run.stderr);
    let bad = fly.replace(
        "\naccurate_steps_per_wingbeat = 20 ",
        "\naccurate_steps_per_wingbeat = 5 ",
    );
    std::fs::write(dir.path().join("bad.toml"), bad).unwrap();
    let run = flapwing_in(dir.path(), &args("bad.toml"));
    assert_names(
        &run,
        &[
            "bad.toml",
            "sim.accurate_steps_per_wingbeat",
            "5",
            "[10, 100000]",
        ],
    );
    let _ = flapwing;
}
