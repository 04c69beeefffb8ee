//! Bad input on the file and pacing surfaces of issue #40, through the real binary: outputs
//! that are an input (the log a `replay` reads, a model file) or each other, a plot format
//! the plotter does not write, outputs checked before any work, a pace factor that would
//! run for ever, and a truncated log given to `identify`. Each case: the exit code, a
//! message naming the flag, file and value, and the protected files unchanged by hash.

use crate::common;

use std::hash::{DefaultHasher, Hasher};
use std::path::Path;

use common::{Run, argv, flapwing_in};

/// The file's length and a hash of its bytes (`None` when it does not exist).
fn fingerprint(path: &Path) -> Option<(usize, u64)> {
    let bytes = std::fs::read(path).ok()?;
    let mut h = DefaultHasher::new();
    h.write(&bytes);
    Some((bytes.len(), h.finish()))
}

/// Asserts bad input (exit 2, no panic) whose message names every needle.
fn assert_refused(run: &Run, needles: &[&str]) {
    run.assert_bad_input();
    for n in needles {
        assert!(run.stderr.contains(n), "`{n}` missing from: {}", run.stderr);
    }
}

/// Runs the command line `line` (split at white space) in `d`: bad input whose message
/// names every needle, and the file `kept` in `d` unchanged by hash.
fn assert_refused_keeping(d: &Path, line: &str, needles: &[&str], kept: &str) {
    let before = fingerprint(&d.join(kept));
    let run = flapwing_in(d, &argv(line));
    assert_refused(&run, needles);
    assert_eq!(fingerprint(&d.join(kept)), before, "{line}");
}

/// A short simulate log `run.mcap` in `dir` (20 ms of the fruit fly: 44 samples).
fn small_log(dir: &Path) {
    let run = flapwing_in(dir, &argv("simulate --duration-s 0.02 --mcap run.mcap"));
    assert_eq!(run.code, 0, "{run:?}");
}

#[test]
fn replay_never_writes_over_the_log_it_reads() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    small_log(d);
    std::fs::create_dir(d.join("sub")).unwrap();
    std::fs::hard_link(d.join("run.mcap"), d.join("linked.mcap")).unwrap();
    let before = fingerprint(&d.join("run.mcap"));
    let cases = [
        "replay run.mcap --rrd run.mcap --force",
        "replay run.mcap --csv /vehicle/state run.mcap --force",
        "replay run.mcap --rrd sub/../run.mcap --force",
        "replay run.mcap --rrd linked.mcap --force",
        "replay run.mcap --csv /vehicle/state ./run.mcap --check",
    ];
    for line in cases {
        let flag = if line.contains("--rrd") {
            "--rrd"
        } else {
            "--csv"
        };
        assert_refused_keeping(
            d,
            line,
            &[flag, "run.mcap", "is the input FILE"],
            "run.mcap",
        );
        assert_eq!(fingerprint(&d.join("run.mcap")), before, "{line}");
    }
    // --csv and --rrd at one path: refused before either is written.
    let run = flapwing_in(
        d,
        &argv("replay run.mcap --csv /vehicle/state out --rrd out"),
    );
    assert_refused(&run, &["--csv and --rrd", "same file", "out"]);
    assert!(!d.join("out").exists());
    // The log still replays whole.
    let run = flapwing_in(d, &["replay", "run.mcap", "--check"]);
    assert_eq!(run.code, 0, "{run:?}");
}

#[test]
fn simulate_refuses_one_path_for_two_logs_and_the_model_as_a_log() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let run = flapwing_in(d, &argv("simulate --duration-s 0.01 --mcap x --rrd ./x"));
    assert_refused(&run, &["--mcap and --rrd", "same file", "x"]);
    assert!(!d.join("x").exists(), "nothing written");
    // With --force over an existing file: refused, and the file is as it was.
    std::fs::write(d.join("x"), b"keep me").unwrap();
    assert_refused_keeping(
        d,
        "simulate --duration-s 0.01 --mcap x --rrd x --force",
        &["--mcap and --rrd", "x"],
        "x",
    );
    // The model file as the log.
    std::fs::write(d.join("m.toml"), flapsim_model()).unwrap();
    assert_refused_keeping(
        d,
        "simulate --model m.toml --duration-s 0.01 --mcap m.toml --force",
        &["--mcap", "m.toml", "is the input --model"],
        "m.toml",
    );
}

/// The fruit fly's model file as shipped.
fn flapsim_model() -> &'static str {
    include_str!("../../../models/drosophila.toml")
}

#[test]
fn plots_are_svg_or_png_and_every_output_is_checked_first() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let envelope = |extra: &str| format!("envelope --model bumblebee --speeds-m-s 0 {extra}");
    for bad in ["out.bmp", "out.pdf", "out"] {
        let run = flapwing_in(d, &argv(&envelope(&format!("--plot {bad}"))));
        assert_refused(&run, &["--plot", bad, ".svg", ".png"]);
        assert!(!d.join(bad).exists(), "{bad} written");
    }
    // The same file for --csv and --plot, existing, with --force: refused, unchanged.
    std::fs::write(d.join("p.svg"), b"<svg/>").unwrap();
    let before = fingerprint(&d.join("p.svg"));
    assert_refused_keeping(
        d,
        &envelope("--csv p.svg --plot p.svg --force"),
        &["--csv and --plot", "same file", "p.svg"],
        "p.svg",
    );
    // An existing --plot without --force: refused before the CSV is created.
    assert_refused_keeping(
        d,
        &envelope("--csv new.csv --plot p.svg"),
        &["--plot", "p.svg", "--force"],
        "p.svg",
    );
    assert!(!d.join("new.csv").exists(), "CSV created before the check");
    assert_eq!(fingerprint(&d.join("p.svg")), before);
    // Upper-case extensions are the same formats; the plot is written.
    let run = flapwing_in(d, &argv(&envelope("--plot ok.SVG")));
    assert_eq!(run.code, 0, "{run:?}");
    let svg = std::fs::read_to_string(d.join("ok.SVG")).unwrap();
    assert!(svg.starts_with("<svg"), "{}", &svg[..40.min(svg.len())]);
    // Other commands with a plot: stability and forces (forces' --csv and --plot too).
    let run = flapwing_in(d, &["stability", "--plot", "modes.bmp"]);
    assert_refused(&run, &["--plot", "modes.bmp", ".svg", ".png"]);
    let run = flapwing_in(d, &["forces", "--csv", "f.svg", "--plot", "f.svg"]);
    assert_refused(&run, &["--csv and --plot", "f.svg"]);
    assert!(!d.join("f.svg").exists());
}

#[test]
fn a_model_is_never_written_over_its_input() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("m.toml"), flapsim_model()).unwrap();
    assert_refused_keeping(
        d,
        "trim --model m.toml --write ./m.toml --force",
        &["--write", "m.toml", "is the input --model"],
        "m.toml",
    );
}

#[test]
fn realtime_factors_that_would_run_for_ever_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    for (factor, needles) in [
        ("1e-300", &["--realtime 1e-300", "24 h", "1.157e-6"][..]),
        // 0.1 s of simulated time over 86400 s: factor 1.157e-6 is the smallest allowed.
        ("1e-6", &["--realtime 1e-6", "24 h", "1.157e-6"][..]),
    ] {
        let run = flapwing_in(dir.path(), &["simulate", "--no-log", "--realtime", factor]);
        assert_refused(&run, needles);
    }
    // A slow pace within the bound runs (1 ms of flight over 50 ms).
    let run = flapwing_in(
        dir.path(),
        &argv("simulate --no-log --duration-s 0.001 --realtime 0.02"),
    );
    assert_eq!(run.code, 0, "{run:?}");
    assert!(!dir.path().join("logs").exists());
}

#[test]
fn identify_says_what_a_truncated_log_held_and_keeps_it() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let run = flapwing_in(
        d,
        &argv("hover --duration-s 0.15 --mcap h.mcap --rrd h.rrd"),
    );
    assert_eq!(run.code, 0, "{run:?}");
    let whole = std::fs::read(d.join("h.mcap")).unwrap();
    std::fs::write(d.join("cut.mcap"), &whole[..whole.len() * 2 / 3]).unwrap();
    let before = fingerprint(&d.join("cut.mcap"));
    let fit = argv("identify cut.mcap --params inertia_yy_kg_m2 --patience 1 --duration-s 0.05");
    let run = flapwing_in(d, &fit);
    // The short fit stops at its patience (exit 1); the warning comes before it.
    assert!(run.code == 0 || run.code == 1, "{run:?}");
    assert!(!run.stderr.contains("panicked"), "{run:?}");
    for n in [
        "warning: `cut.mcap` is incomplete",
        "truncated",
        "recovered",
        "motion-capture frames",
    ] {
        assert!(run.stderr.contains(n), "`{n}` missing from: {}", run.stderr);
    }
    // The whole log gives no such warning.
    let mut whole_fit = fit.clone();
    whole_fit[1] = "h.mcap";
    let run = flapwing_in(d, &whole_fit);
    assert!(!run.stderr.contains("incomplete"), "{run:?}");
    // --out may not be the log.
    let mut out_is_log = fit.to_vec();
    out_is_log.extend(["--out", "cut.mcap", "--force"]);
    let run = flapwing_in(d, &out_is_log);
    assert_refused(&run, &["--out", "cut.mcap", "is the input FILE"]);
    assert_eq!(fingerprint(&d.join("cut.mcap")), before);
}

/// `--model` reads a regular file of at most 1 MiB (flapsim::model::read_model_file): a
/// device (`/dev/zero` read until memory ran out), a FIFO without a writer (blocked for
/// ever) and an oversized file are refused at once, naming the file and what is allowed.
#[test]
fn model_files_are_regular_and_bounded() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    if Path::new("/dev/zero").exists() {
        let run = flapwing_in(d, &["trim", "--model", "/dev/zero"]);
        assert_refused(&run, &["/dev/zero", "not a regular file"]);
    } else {
        eprintln!("SKIPPED the /dev/zero case: this machine has no /dev/zero");
    }
    let fifo = d.join("model.fifo");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .is_ok_and(|s| s.success());
    if made {
        let run = flapwing_in(d, &["trim", "--model", "model.fifo"]);
        assert_refused(&run, &["model.fifo", "not a regular file"]);
    } else {
        eprintln!("SKIPPED the FIFO case: mkfifo is not available");
    }
    let big = d.join("big.toml");
    std::fs::write(&big, vec![b'#'; (1 << 20) + 1]).unwrap();
    let run = flapwing_in(d, &["trim", "--model", "big.toml"]);
    assert_refused(&run, &["big.toml", "1048577 bytes", "1048576"]);
    let study = d.join("study.toml");
    std::fs::write(&study, vec![b'#'; (1 << 20) + 1]).unwrap();
    let run = flapwing_in(d, &["sweep", "study.toml"]);
    assert_refused(&run, &["study.toml", "1048577 bytes"]);
}
