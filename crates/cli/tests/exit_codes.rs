//! The documented exit codes (crate README): 0 ok, 1 the run failed, 2 bad input, driven
//! through the real `flapwing` binary. Never 101 (a Rust panic), whatever stdout and stderr
//! are connected to (a full disk, a closed pipe).
//!
//! Not property tests: fixed inputs, about 80 runs of the binary in all (a few seconds in
//! release). `validate` runs its paper's cases only (`--section cases`, a fraction of a
//! second): its output path is the same for every section, and the whole command's exit code
//! is `tests/validate.rs`'s.

use crate::common;

use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::{ROBOFLY, Run, argv};

const DROSOPHILA: &str = include_str!("../../../models/drosophila.toml");

/// Where the child's stdout or stderr goes.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Sink {
    /// Captured.
    Pipe,
    /// A pipe whose read end is closed at once (`flapwing ... | head -0`).
    ClosedPipe,
    /// `/dev/full`: every write fails with ENOSPC (Linux). Only used after
    /// [`full_device`] has found a real one.
    Full,
}

/// The node the full-disk tests write to; `FLAPWING_TEST_FULL_DEVICE` names another (the
/// tests of the check below point it at a missing node).
const FULL_DEVICE: &str = "/dev/full";

/// `path`, if it is what the full-disk tests rely on: a character device whose writes fail
/// with ENOSPC (Linux's `/dev/full`). Otherwise why not. Nothing is created or written where
/// the node is missing or is something else (a regular file there would be filled, and a
/// binary told to write to a missing `/dev/full` creates it: as root, in /dev).
fn full_device_at(path: &Path) -> Result<std::path::PathBuf, String> {
    use std::io::Write;
    use std::os::unix::fs::FileTypeExt;
    let meta = std::fs::metadata(path).map_err(|e| format!("{}: {e}", path.display()))?;
    if !meta.file_type().is_char_device() {
        return Err(format!("{} is not a character device", path.display()));
    }
    // A character device is opened without create or truncate; one write must fail ENOSPC.
    let mut f = std::fs::OpenOptions::new()
        .write(true)
        .open(path)
        .map_err(|e| format!("{}: cannot open for writing: {e}", path.display()))?;
    match f.write_all(b"x").and_then(|()| f.flush()) {
        Err(e) if e.raw_os_error() == Some(28) => Ok(path.to_path_buf()),
        Err(e) => Err(format!(
            "{}: a write failed with {e}, not ENOSPC",
            path.display()
        )),
        Ok(()) => Err(format!(
            "{}: a write succeeded (expected ENOSPC)",
            path.display()
        )),
    }
}

/// The full device for this run, or `None` after printing why the test is skipped.
fn full_device(test: &str) -> Option<std::path::PathBuf> {
    let path = std::env::var_os("FLAPWING_TEST_FULL_DEVICE")
        .map_or_else(|| std::path::PathBuf::from(FULL_DEVICE), Into::into);
    match full_device_at(&path) {
        Ok(p) => Some(p),
        Err(why) => {
            eprintln!("SKIPPED {test}: needs a full device (writes fail with ENOSPC): {why}");
            None
        }
    }
}

fn run_with(dir: &Path, args: &[&str], out: Sink, err: Sink) -> Run {
    let stdio = |s: Sink| match s {
        Sink::Pipe | Sink::ClosedPipe => Stdio::piped(),
        Sink::Full => Stdio::from(
            std::fs::OpenOptions::new()
                .write(true)
                .open(full_device("run_with").expect("callers check full_device first"))
                .expect("the full device"),
        ),
    };
    let mut child = Command::new(env!("CARGO_BIN_EXE_flapwing"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(stdio(out))
        .stderr(stdio(err))
        .spawn()
        .expect("spawn flapwing");
    let reader = |p: Option<Box<dyn Read + Send>>, sink: Sink| {
        std::thread::spawn(move || {
            let mut b = Vec::new();
            // ClosedPipe: the read end is dropped here without reading.
            if let Some(mut p) = p
                && sink == Sink::Pipe
            {
                let _ = p.read_to_end(&mut b);
            }
            b
        })
    };
    let t_out = reader(boxed(child.stdout.take()), out);
    let t_err = reader(boxed(child.stderr.take()), err);
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().expect("wait") {
            break s;
        }
        if start.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            panic!("flapwing {args:?} did not finish within 60 s");
        }
        std::thread::sleep(Duration::from_millis(2));
    };
    Run {
        code: status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&t_out.join().unwrap()).into_owned(),
        stderr: String::from_utf8_lossy(&t_err.join().unwrap()).into_owned(),
    }
}

fn boxed(p: Option<impl Read + Send + 'static>) -> Option<Box<dyn Read + Send>> {
    p.map(|p| Box::new(p) as Box<dyn Read + Send>)
}

fn run_in(dir: &Path, args: &[&str]) -> Run {
    run_with(dir, args, Sink::Pipe, Sink::Pipe)
}

fn run(args: &[&str]) -> Run {
    let dir = tempfile::tempdir().unwrap();
    run_in(dir.path(), args)
}

#[track_caller]
fn assert_code(r: &Run, code: i32, what: &str) {
    assert_eq!(r.code, code, "{what}: {r:?}");
    assert!(!r.stderr.contains("panicked"), "{what}: {r:?}");
    if code != 0 {
        assert!(
            r.stderr.contains("error"),
            "{what}: no error message: {r:?}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// 0: success.
// ---------------------------------------------------------------------------------------------

#[test]
fn success_exits_0() {
    for line in [
        "--help",
        "--version",
        "wake-capture --help",
        "validate --section cases",
        "wake-capture --re 408 --dtau-a 0.12 --dtau-d 0.03",
        "forces --cycles 1 --steps-per-cycle 50 --json",
        "simulate --duration-s 0.001 --no-log",
        "simulate --model robobee --duration-s 0.001 --tethered",
    ] {
        let args = argv(line);
        assert_code(&run(&args), 0, &format!("{args:?}"));
    }
    let r = run(&["validate", "--section", "cases", "--json"]);
    assert_code(&r, 0, "validate --section cases --json");
    let v: serde_json::Value = serde_json::from_str(&r.stdout).unwrap();
    assert_eq!(v["all_passed"], true, "{}", r.stdout);
}

// ---------------------------------------------------------------------------------------------
// 2: bad input.
// ---------------------------------------------------------------------------------------------

#[test]
fn bad_flags_exit_2() {
    // No subcommand: clap prints the usage (no `error:` line) and exits 2.
    let r = run(&[]);
    assert_eq!(r.code, 2, "{r:?}");
    assert!(r.stderr.contains("Usage"), "{r:?}");
    for line in [
        "no-such-command",
        "validate --no-such-flag",
        "wake-capture --re -1 --dtau-a 0.1 --dtau-d 0.1",
        "wake-capture --re=-1 --dtau-a 0.1 --dtau-d 0.1",
        "wake-capture --re 0 --dtau-a 0.1 --dtau-d 0.1",
        "wake-capture --re nan --dtau-a 0.1 --dtau-d 0.1",
        "wake-capture --re inf --dtau-a 0.1 --dtau-d 0.1",
        "wake-capture --re 1e309 --dtau-a 0.1 --dtau-d 0.1",
        "wake-capture --re 100 --dtau-a 0.5 --dtau-d 0.1",
        "wake-capture --re 100 --dtau-a 0.1",
        "forces --cycles 0",
        "forces --steps-per-cycle 1",
        "forces --re abc",
        "simulate --duration-s nan",
        "simulate --duration-s -1",
        "simulate --duration-s=-1",
        "simulate --duration-s 0",
        "simulate --duration-s 3601",
        "simulate --duration-s 1e300",
        "simulate --tethered --longitudinal",
        "simulate --duration-s 0.001 --log-rate-hz nan",
        "simulate --duration-s 0.001 --log-rate-hz 0",
        "simulate --model nonesuch",
        "hover --duration-s 0.001 --disturbance pitch_deg=90",
        "hover --duration-s 0.001 --disturbance pitch_deg=nan",
        "hover --duration-s 0.001 --disturbance yaw_deg=1",
        "hover --duration-s 0.001 --disturbance pitch_deg",
        "hover --delay-wingbeats -1",
    ] {
        let args = argv(line);
        let r = run(&args);
        assert_code(&r, 2, &format!("{args:?}"));
        assert!(r.stdout.is_empty(), "{args:?}: {r:?}");
    }
}

#[test]
fn missing_model_file_exits_2_naming_it() {
    for cmd in [
        &["forces"][..],
        &["simulate", "--duration-s", "0.001"],
        &["trim"],
        &["stability", "--no-floquet"],
        &["hover", "--duration-s", "0.001"],
    ] {
        let mut args = cmd.to_vec();
        args.extend(["--model", "no such model.toml"]);
        let r = run(&args);
        assert_code(&r, 2, &format!("{args:?}"));
        assert!(r.stderr.contains("no such model.toml"), "{args:?}: {r:?}");
    }
    let r = run(&["replay", "no such log.mcap"]);
    assert_code(&r, 2, "replay of a missing file");
    assert!(r.stderr.contains("no such log.mcap"), "{r:?}");
}

#[test]
fn invalid_model_files_exit_2_naming_file_and_field() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, text: &str| {
        std::fs::write(dir.path().join(name), text).unwrap();
        name.to_owned()
    };
    // (command, file, base model, field, its value there, the bad value written instead).
    let cases = [
        (
            "forces",
            "amp.toml",
            ROBOFLY,
            "kinematics.amplitude_deg",
            "155.0",
            "200.0",
        ),
        (
            "forces",
            "nan.toml",
            ROBOFLY,
            "fluid.density_kg_m3",
            "1229.0",
            "nan",
        ),
        (
            "simulate",
            "mass.toml",
            DROSOPHILA,
            "body.mass_kg",
            "1.0e-6",
            "-1.0e-6",
        ),
        (
            "trim",
            "freq.toml",
            DROSOPHILA,
            "kinematics.freq_hz",
            "218.0",
            "0.0",
        ),
        (
            "hover",
            "tilt.toml",
            DROSOPHILA,
            "hinge.stroke_plane_tilt_deg",
            "45.0",
            "91.0",
        ),
    ];
    for (cmd, name, base, field, good, bad) in cases {
        let key = field.rsplit('.').next().unwrap();
        let text = base.replace(&format!("{key} = {good}"), &format!("{key} = {bad}"));
        assert_ne!(text, base, "{key} = {good} not in the base model");
        let file = write(name, &text);
        let mut args = vec![cmd, "--model", file.as_str()];
        if cmd == "simulate" || cmd == "hover" {
            args.extend(["--duration-s", "0.001"]);
        }
        let r = run_in(dir.path(), &args);
        assert_code(&r, 2, &format!("{cmd} {file}"));
        assert!(
            r.stderr.contains(file.as_str())
                && r.stderr.contains(field)
                && r.stderr.contains("not allowed"),
            "{cmd} {file}: {r:?}"
        );
    }
    // Malformed TOML, an unknown field, a directory, a file that is not UTF-8.
    let malformed = write("malformed.toml", "[wing\nplanform = 3");
    let unknown = write(
        "unknown.toml",
        &DROSOPHILA.replace("[body]", "[body]\nmass_g = 1.0"),
    );
    let binary = "binary.toml";
    std::fs::write(dir.path().join(binary), [0xff, 0xfe, 0x00, 0x80]).unwrap();
    std::fs::create_dir(dir.path().join("dir.toml")).unwrap();
    for (args, needle) in [
        (vec!["forces", "--model", &malformed], malformed.as_str()),
        (vec!["simulate", "--model", &unknown], "mass_g"),
        (vec!["simulate", "--model", binary], binary),
        (vec!["forces", "--model", binary], binary),
        (vec!["forces", "--model", "dir.toml"], "dir.toml"),
        (vec!["trim", "--model", "dir.toml"], "dir.toml"),
    ] {
        let r = run_in(dir.path(), &args);
        assert_code(&r, 2, &format!("{args:?}"));
        assert!(r.stderr.contains(needle), "{args:?}: {r:?}");
    }
}

#[test]
fn refusing_to_overwrite_exits_2() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("out.csv"), "keep me").unwrap();
    let r = run_in(
        dir.path(),
        &argv("forces --cycles 1 --steps-per-cycle 10 --csv out.csv"),
    );
    assert_code(&r, 2, "existing --csv");
    assert!(r.stderr.contains("--force"), "{r:?}");
    assert_eq!(
        std::fs::read_to_string(dir.path().join("out.csv")).unwrap(),
        "keep me"
    );
    std::fs::write(dir.path().join("run.mcap"), "keep me").unwrap();
    let r = run_in(
        dir.path(),
        &["simulate", "--duration-s", "0.001", "--mcap", "run.mcap"],
    );
    assert_code(&r, 2, "existing --mcap");
}

// ---------------------------------------------------------------------------------------------
// 1: the run failed.
// ---------------------------------------------------------------------------------------------

/// drosophila.toml with a tiny angular-speed limit and an initial yaw rate above it: the run
/// stops at once.
fn diverging_drosophila() -> String {
    let text = DROSOPHILA
        .replace("[sim]\n", "[sim]\nmax_angular_speed_rad_s = 1.0\n")
        .replace(
            "[initial]\n",
            "[initial]\nangular_velocity_deg_s = [0.0, 0.0, 100.0]\n",
        );
    assert!(text.contains("max_angular_speed_rad_s = 1.0"));
    assert!(text.contains("angular_velocity_deg_s = [0.0, 0.0, 100.0]"));
    text
}

#[test]
fn diverging_simulation_exits_1() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("spin.toml"), diverging_drosophila()).unwrap();
    let r = run_in(
        dir.path(),
        &["simulate", "--model", "spin.toml", "--duration-s", "0.01"],
    );
    assert_code(&r, 1, "diverging simulate");
    assert!(r.stderr.contains("diverged"), "{r:?}");
    // With --json the report (with the error) is still the one document on stdout.
    let r = run_in(
        dir.path(),
        &argv("simulate --model spin.toml --duration-s 0.01 --json --no-log"),
    );
    assert_code(&r, 1, "diverging simulate --json");
    let v: serde_json::Value = serde_json::from_str(&r.stdout).expect("JSON report");
    assert!(
        v["error"].as_str().is_some_and(|e| e.contains("diverged")),
        "{}",
        r.stdout
    );
}

/// A write that fails part-way (a full disk) is a failed run, not bad input.
#[cfg(target_os = "linux")]
#[test]
fn full_disk_exits_1() {
    let Some(full) = full_device("full_disk_exits_1") else {
        return;
    };
    let full = full.to_str().expect("a UTF-8 path");
    let r = run(&argv(&format!(
        "forces --cycles 1 --steps-per-cycle 10000 --csv {full} --force"
    )));
    assert_code(&r, 1, &format!("--csv {full}"));
    assert!(r.stderr.contains(full), "{r:?}");
}

/// On a machine without the node (a VM whose /dev has no `full`) or with something else at
/// its path, the check says so and leaves the path as it was: nothing is created or written.
#[cfg(target_os = "linux")]
#[test]
fn a_missing_or_ordinary_full_node_is_skipped_and_never_written() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("full");
    let why = full_device_at(&missing).unwrap_err();
    assert!(why.contains("No such file"), "{why}");
    assert!(!missing.exists(), "the check created {}", missing.display());

    let regular = dir.path().join("regular");
    std::fs::write(&regular, b"kept").unwrap();
    let why = full_device_at(&regular).unwrap_err();
    assert!(why.contains("not a character device"), "{why}");
    assert_eq!(std::fs::read(&regular).unwrap(), b"kept");

    // /dev/null is a character device whose writes succeed: not a full device either.
    let null = Path::new("/dev/null");
    if null.exists() {
        let why = full_device_at(null).unwrap_err();
        assert!(why.contains("succeeded"), "{why}");
    }
}

/// KNOWN BUG (issue 7, reported to the lead): the stdout write errors of `simulate`, `hover`,
/// `trim` and `stability` have no context: `error: No space left on device (os error 28)`,
/// where `validate`, `wake-capture` and `forces` say `error: cannot write to stdout: ...`.
/// These four commands are left out of the message check (not of the exit-code check) while
/// this is `true`.
const KNOWN_BUG_STDOUT_CONTEXT: bool = false;

/// stdout on a full disk: exit 1 with a message, never a panic (`println!` would panic).
#[cfg(target_os = "linux")]
#[test]
fn full_stdout_exits_1() {
    if full_device("full_stdout_exits_1").is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    for (line, has_context) in [
        ("validate --section cases", true),
        ("validate --section cases --json", true),
        ("wake-capture --re 408 --dtau-a 0.12 --dtau-d 0.03", true),
        ("forces --cycles 1 --steps-per-cycle 20", true),
        ("simulate --duration-s 0.001 --no-log", false),
        ("hover --duration-s 0.001 --no-log", false),
        ("trim", false),
        ("stability --no-floquet", false),
    ] {
        let args = argv(line);
        let r = run_with(dir.path(), &args, Sink::Full, Sink::Pipe);
        assert_code(&r, 1, &format!("{args:?} >/dev/full"));
        if has_context || !KNOWN_BUG_STDOUT_CONTEXT {
            assert!(r.stderr.contains("stdout"), "{args:?}: {r:?}");
        }
    }
    // Help and version are clap's: printed as best it can, exit 0.
    for args in [&["--help"][..], &["--version"]] {
        let r = run_with(dir.path(), args, Sink::Full, Sink::Pipe);
        assert!(matches!(r.code, 0 | 1), "{args:?}: {r:?}");
    }
}

/// A closed stdout (`flapwing validate | head -0`) is not an error.
#[test]
fn closed_stdout_is_not_an_error() {
    let dir = tempfile::tempdir().unwrap();
    for args in [
        &["validate", "--section", "cases"][..],
        &["validate", "--section", "cases", "--json"],
        &["forces", "--cycles", "1", "--steps-per-cycle", "20"],
    ] {
        let r = run_with(dir.path(), args, Sink::ClosedPipe, Sink::Pipe);
        assert_code(&r, 0, &format!("{args:?} | head -0"));
    }
}

/// KNOWN BUG (issue 7, reported to the lead): `eprintln!` panics when stderr cannot be
/// written, and `crates/cli/src/logging.rs:116` (`warning: ...`), `:167` (`logging to ...`)
/// and `crates/cli/src/commands/trim.rs:99` (`wrote ...`) use it: e.g.
/// `flapwing simulate --duration-s 0.001 2>/dev/full` and
/// `flapwing trim --write out.toml 2>/dev/full` exit 101. Those runs are left out below
/// while this is `true`.
const KNOWN_BUG_EPRINTLN: bool = false;

/// stderr on a full disk: the exit codes do not change (the message is lost), no panic.
#[cfg(target_os = "linux")]
#[test]
fn full_stderr_keeps_the_exit_code() {
    if full_device("full_stderr_keeps_the_exit_code").is_none() {
        return;
    }
    let mut cases = vec![
        ("wake-capture --re nan --dtau-a 0.1 --dtau-d 0.1", 2),
        ("forces --model missing.toml", 2),
        ("simulate --duration-s nan", 2),
        ("validate --section cases", 0),
        ("forces --cycles 1 --steps-per-cycle 20", 0),
        ("simulate --duration-s 0.001 --no-log --model robobee", 0),
    ];
    if !KNOWN_BUG_EPRINTLN {
        cases.extend([
            ("simulate --duration-s 0.001", 0),
            ("hover --duration-s 0.001", 0),
            ("trim --write trimmed.toml", 0),
        ]);
    }
    for (line, code) in cases {
        let args = argv(line);
        let dir = tempfile::tempdir().unwrap();
        let r = run_with(dir.path(), &args, Sink::Pipe, Sink::Full);
        assert_eq!(r.code, code, "{args:?} 2>/dev/full: {r:?}");
    }
}

// ---------------------------------------------------------------------------------------------
// Known bugs whose exit code is wrong (reported to the lead; each test checks only that the
// run fails without a panic while its flag is `true`, the documented code once fixed).
// ---------------------------------------------------------------------------------------------

/// While `known_bug`, only that the run failed (1 or 2) without a panic; once fixed, exit 2
/// with an error naming the file and the field (`[file, field]`).
#[track_caller]
fn assert_bad_input_unless_known_bug(r: &Run, known_bug: bool, what: &str, names: [&str; 2]) {
    if known_bug {
        assert!(matches!(r.code, 1 | 2), "{r:?}");
        assert!(!r.stderr.contains("panicked"), "{r:?}");
    } else {
        assert_code(r, 2, what);
        assert!(names.iter().all(|n| r.stderr.contains(n)), "{r:?}");
    }
}

/// KNOWN BUG: drosophila with `[controls] amplitude_deg = 50.0` (140 + 50 > 180 deg) fails
/// in `Vehicle::apply_controls` with `Error::Analysis` ("controls give wing 0 an amplitude of
/// 190.00 deg ..."): no file, no field, exit 1 instead of 2.
const KNOWN_BUG_CONTROLS: bool = false;

#[test]
fn controls_beyond_the_kinematics_are_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let text = format!("{DROSOPHILA}\n[controls]\namplitude_deg = 50.0\n");
    std::fs::write(dir.path().join("ctl.toml"), text).unwrap();
    let r = run_in(
        dir.path(),
        &["simulate", "--model", "ctl.toml", "--duration-s", "0.001"],
    );
    assert_bad_input_unless_known_bug(
        &r,
        KNOWN_BUG_CONTROLS,
        "controls beyond the kinematics",
        ["ctl.toml", "controls"],
    );
}

/// KNOWN BUG: a refitted `aero.wake_capture_model` with `dcd.c2 = 1.0` loads (coefficients
/// finite, mu* > 0) but `c1 exp(c2 Re)` overflows over its fitted Re range, every force is
/// NaN and `forces` exits 1 "non-finite forces" instead of 2 naming the field.
const KNOWN_BUG_WAKE_OVERFLOW: bool = false;

#[test]
fn overflowing_wake_model_is_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let model = r#"
[aero.wake_capture_model.dcl]
c0 = 0.94839
c1 = -1.17098
c2 = -0.00234646
c3 = -8.3413
c4 = 37.6766
[aero.wake_capture_model.dcd]
c0 = 1.0
c1 = -1.0
c2 = 1.0
c3 = -1.0
c4 = 1.0
[aero.wake_capture_model.mu_star]
m0 = 0.04195
m1 = 0.01034
m2 = 0.12917
[aero.wake_capture_model.re_range]
min = 136.0
max = 6800.0
[aero.wake_capture_model.dtau_a_range]
min = 0.06
max = 0.18
[aero.wake_capture_model.dtau_d_range]
min = 0.06
max = 0.18
"#;
    std::fs::write(dir.path().join("wake.toml"), format!("{ROBOFLY}\n{model}")).unwrap();
    let r = run_in(
        dir.path(),
        &argv("forces --model wake.toml --cycles 1 --steps-per-cycle 20"),
    );
    assert_bad_input_unless_known_bug(
        &r,
        KNOWN_BUG_WAKE_OVERFLOW,
        "overflowing wake model",
        ["wake.toml", "wake_capture_model"],
    );
}

/// KNOWN BUG: `hover --delay-wingbeats 18446744073709551615` panics ("Out of bounds access",
/// crates/flapsim/src/control.rs:196, now control/controller.rs: `delay_wingbeats + 1` wraps
/// to 0), exit 101. Once fixed it must exit 0 (the delay is legal) or 2 (rejected as out of
/// range).
const KNOWN_BUG_DELAY: bool = false;

#[test]
fn huge_controller_delay_does_not_panic() {
    if KNOWN_BUG_DELAY {
        return;
    }
    let r = run(&argv(
        "hover --duration-s 0.005 --no-log --delay-wingbeats 18446744073709551615",
    ));
    assert!(matches!(r.code, 0 | 2), "{r:?}");
    assert!(!r.stderr.contains("panicked"), "{r:?}");
}
