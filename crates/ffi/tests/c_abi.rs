//! The C ABI from C and C++: tests/c/abi_check.c and tests/c/abi_check.cpp, built with the
//! system compilers against include/flapwing.h (C11 and C++17, -Wall -Wextra -Werror) and
//! linked against the crate's staticlib, reproduce the Rust `WingSet`'s numbers bit for bit:
//! the fruit fly tethered at rest for one wingbeat, the fly with a moving, rotated body, wind
//! and controls at a host step, and the actuated RoboBee. Bad input through the C program
//! gives each its code and a message.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use flapsim::{Controls, FromVehicle, State, Vehicle, WingSet};
use nalgebra::{Quaternion, UnitQuaternion, Vector3};

/// One printed line: "<what> <k>" and its values.
type Line = (String, Vec<f64>);

fn crate_dir() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The staticlib cargo built with this test (deps/libflapwing.a, next to the test binary); if
/// it is not there, `cargo build --release -p flapwing-ffi` builds it.
fn staticlib() -> PathBuf {
    let exe = std::env::current_exe().expect("the test binary's path");
    let deps = exe.parent().expect("the deps directory");
    let lib = deps.join("libflapwing.a");
    if lib.exists() {
        return lib;
    }
    let status = Command::new(env!("CARGO"))
        .args(["build", "--release", "-p", "flapwing-ffi"])
        .current_dir(crate_dir())
        .status()
        .expect("run cargo build");
    assert!(
        status.success(),
        "cargo build --release -p flapwing-ffi failed"
    );
    let lib = deps.parent().expect("target/release").join("libflapwing.a");
    assert!(lib.exists(), "no staticlib at {}", lib.display());
    lib
}

/// Compiles one of tests/c/ with `compiler` (CC/CXX or cc/c++) into CARGO_TARGET_TMPDIR.
fn build(source: &str, compiler_env: &str, default: &str, std_flag: &str) -> PathBuf {
    let compiler = std::env::var(compiler_env).unwrap_or_else(|_| default.to_string());
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join(source.replace('.', "_"));
    let output = Command::new(&compiler)
        .arg(std_flag)
        .args([
            "-Wall",
            "-Wextra",
            "-Werror",
            "-O2",
            "-ffp-contract=off",
            "-I",
        ])
        .arg(crate_dir().join("include"))
        .arg(crate_dir().join("tests/c").join(source))
        .arg(staticlib())
        .args(["-lm", "-lpthread", "-ldl", "-o"])
        .arg(&out)
        .output()
        .unwrap_or_else(|e| panic!("run {compiler}: {e}"));
    assert!(
        output.status.success(),
        "{compiler} {source} failed:\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    out
}

fn c_program() -> &'static Path {
    static P: OnceLock<PathBuf> = OnceLock::new();
    P.get_or_init(|| build("abi_check.c", "CC", "cc", "-std=c11"))
}

fn cpp_program() -> &'static Path {
    static P: OnceLock<PathBuf> = OnceLock::new();
    P.get_or_init(|| build("abi_check.cpp", "CXX", "c++", "-std=c++17"))
}

fn run(program: &Path, args: &[&str]) -> String {
    let out = Command::new(program)
        .args(args)
        .output()
        .expect("run the program");
    assert!(
        out.status.success(),
        "{} {args:?} failed ({}):\n{}",
        program.display(),
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("UTF-8 output")
}

/// The numeric lines of a program's output (not "version" or "error").
fn parse(output: &str) -> Vec<Line> {
    output
        .lines()
        .filter(|l| !l.starts_with("version ") && !l.starts_with("error "))
        .map(|l| {
            let mut parts = l.split_whitespace();
            let what = parts.next().expect("a name");
            let k = parts.next().expect("a step");
            let values = parts
                .map(|v| {
                    v.parse::<f64>()
                        .unwrap_or_else(|e| panic!("{v:?} in {l:?}: {e}"))
                })
                .collect();
            (format!("{what} {k}"), values)
        })
        .collect()
}

/// The moving, rotated body of step k (as in abi_check.c and abi_check.cpp).
fn moving(k: u64) -> State {
    let x = k as f64;
    State {
        position_m: Vector3::new(0.001 * x, -0.002 * x, 0.1 + 0.0005 * x),
        world_from_body: UnitQuaternion::from_quaternion(Quaternion::new(
            0.953150604096219,
            0.10033164253644411,
            0.28092859910204354,
            -0.050165821268222055,
        )),
        velocity_m_s: Vector3::new(0.3 - 0.01 * x, 0.05, -0.1 + 0.02 * x),
        angular_velocity_body_rad_s: Vector3::new(1.5, -2.0 + 0.1 * x, 0.5),
    }
}

fn vehicle(name: &str) -> Vehicle {
    let text = flapsim::builtin_model(name).expect("a built-in model");
    Vehicle::from_toml(text, &format!("<built-in {name}>")).expect("the built-in model loads")
}

fn load_values(l: &flapsim::BodyLoad) -> Vec<f64> {
    l.force_n
        .iter()
        .chain(l.moment_nm.iter())
        .copied()
        .collect()
}

/// What the programs print, computed with the Rust `WingSet` directly.
fn rust_lines(scenario: &str, n: u64) -> Vec<Line> {
    let (mut set, moves) = match scenario {
        "fly_rest" => (
            WingSet::from_vehicle_sized(&vehicle("drosophila")).unwrap(),
            false,
        ),
        "fly_moving" => {
            let mut set = WingSet::from_vehicle(&vehicle("drosophila"), 2.0e-5).unwrap();
            set.set_controls(Controls {
                amplitude_rad: 0.05,
                diff_pitch_bias_rad: 0.02,
                ..Controls::default()
            })
            .unwrap();
            set.set_wind(Vector3::new(0.1, -0.2, 0.05));
            (set, true)
        }
        "robobee" => {
            let mut set = WingSet::from_vehicle_sized(&vehicle("robobee")).unwrap();
            set.set_controls(Controls {
                amplitude_v: 5.0,
                diff_bias_v: 2.0,
                ..Controls::default()
            })
            .unwrap();
            (set, false)
        }
        other => panic!("no scenario {other}"),
    };
    let v = set.vehicle().unwrap().clone();
    let mut lines = vec![
        ("count 0".to_string(), vec![set.len() as f64]),
        ("dt 0".to_string(), vec![set.dt_s()]),
    ];
    let mut body = vec![v.mass_kg];
    for r in 0..3 {
        for c in 0..3 {
            body.push(v.inertia_kg_m2[(r, c)]);
        }
    }
    body.push(v.gravity_m_s2);
    body.extend(v.initial_position_m.iter());
    let q = v.initial_attitude;
    body.extend([q.w, q.i, q.j, q.k]);
    lines.push(("body 0".to_string(), body));
    for k in 0..n {
        let state = if moves { moving(k) } else { State::at_rest() };
        let o = set.step(&state).unwrap();
        lines.push((format!("total {k}"), load_values(&o.total)));
        for (t, load) in o.terms.iter().enumerate() {
            lines.push((format!("term{t} {k}"), load_values(load)));
        }
        lines.push((format!("inertia {k}"), load_values(&o.wing_inertia)));
        for (i, w) in o.wings.iter().enumerate() {
            let a = &w.angles;
            let mut values = vec![a.phi, a.theta, a.eta, a.phi_dot, a.theta_dot, a.eta_dot];
            values.extend(w.total.force_n.iter());
            values.push(o.actuated.get(i).map_or(0.0, |s| s.hinge_moment_nm));
            lines.push((format!("wing{i} {k}"), values));
        }
    }
    lines.push((format!("time {n}"), vec![set.time_s()]));
    lines
}

/// Every line and every value equal bit for bit (NaN never appears).
fn assert_bit_identical(program: &str, got: &[Line], want: &[Line]) {
    for (g, w) in got.iter().zip(want) {
        assert_eq!(g.0, w.0, "{program}: line order");
        assert_eq!(
            g.1.len(),
            w.1.len(),
            "{program}: {} has {} values",
            g.0,
            g.1.len()
        );
        for (i, (a, b)) in g.1.iter().zip(&w.1).enumerate() {
            assert!(
                a.to_bits() == b.to_bits(),
                "{program}: {}[{i}] = {a:e} through the C ABI, {b:e} from the Rust WingSet",
                g.0
            );
        }
    }
    assert_eq!(got.len(), want.len(), "{program}: number of lines");
}

fn steps_per_wingbeat(name: &str) -> u64 {
    vehicle(name).sim.steps_per_wingbeat as u64
}

fn check_scenario(scenario: &str, n: u64) {
    let want = rust_lines(scenario, n);
    // The scenario moves something: not all zeros.
    assert!(
        want.iter()
            .any(|(k, v)| k.starts_with("total") && v.iter().any(|x| *x != 0.0)),
        "{scenario}: the wings apply no load"
    );
    let n_arg = n.to_string();
    for (name, program) in [("C", c_program()), ("C++", cpp_program())] {
        let got = parse(&run(program, &[scenario, &n_arg]));
        assert_bit_identical(&format!("{name} {scenario}"), &got, &want);
    }
}

#[test]
fn fly_tethered_at_rest_one_wingbeat_is_bit_identical() {
    check_scenario("fly_rest", steps_per_wingbeat("drosophila"));
}

#[test]
fn fly_moving_rotated_body_with_wind_and_controls_is_bit_identical() {
    check_scenario("fly_moving", 30);
}

#[test]
fn actuated_robobee_is_bit_identical() {
    let want = rust_lines("robobee", 40);
    assert!(
        want.iter()
            .any(|(k, v)| k.starts_with("wing") && v[9] != 0.0),
        "the RoboBee's hinge moments are all zero"
    );
    check_scenario("robobee", 40);
}

#[test]
fn bad_input_from_c_gives_codes_and_messages() {
    let out = run(c_program(), &["errors"]);
    let errors: Vec<(&str, i32, &str)> = out
        .lines()
        .filter_map(|l| l.strip_prefix("error "))
        .map(|l| {
            let mut p = l.splitn(3, ' ');
            let case = p.next().unwrap();
            let code = p.next().unwrap().parse().unwrap();
            (case, code, p.next().unwrap_or(""))
        })
        .collect();
    let expect: [(&str, i32, &[&str]); 14] = [
        (
            "unknown_builtin",
            3,
            &["no_such_fly", "drosophila, bumblebee"],
        ),
        ("missing_file", 4, &["/nonexistent/flapwing/fly.toml"]),
        ("null_name", 1, &["`name` is NULL"]),
        ("null_out", 1, &["`out` is NULL"]),
        ("negative_dt", 2, &["dt_s = -0.00001", "allowed"]),
        ("nan_dt", 2, &["dt_s = NaN", "allowed"]),
        (
            "null_handle_step",
            1,
            &["flapwing_wings_step", "`wings` is NULL"],
        ),
        (
            "null_handle_count",
            1,
            &["flapwing_wings_count", "`wings` is NULL"],
        ),
        ("nan_state", 2, &["velocity_world_m_s[1] = NaN", "finite"]),
        ("null_state", 1, &["`body` is NULL"]),
        ("null_total", 1, &["`total_out` is NULL"]),
        ("wing_out_of_range", 2, &["wing index 2", "0..2"]),
        ("term_out_of_range", 2, &["term = 4", "0..4"]),
        ("ok_after_errors", 0, &[]),
    ];
    assert_eq!(
        errors.iter().map(|e| e.0).collect::<Vec<_>>(),
        expect.iter().map(|e| e.0).collect::<Vec<_>>(),
        "{out}"
    );
    for ((case, code, message), (_, want_code, parts)) in errors.iter().zip(expect) {
        assert_eq!(*code, want_code, "{case}: {message}");
        for p in parts {
            assert!(message.contains(p), "{case}: {message:?} lacks {p:?}");
        }
    }
    assert!(out.starts_with(&format!("version 0 {}\n", env!("CARGO_PKG_VERSION"))));
}

#[test]
fn cpp_wrapper_reports_an_error_as_an_exception() {
    let out = run(cpp_program(), &["fly_rest", "1"]);
    let line = out
        .lines()
        .find(|l| l.starts_with("error unknown_builtin"))
        .expect("the C++ program reports the unknown model");
    assert!(line.starts_with("error unknown_builtin 3 "), "{line}");
    assert!(line.contains("no_such_fly"), "{line}");
}

#[test]
fn the_hover_loads_example_builds_and_reports_the_wingbeat_mean() {
    let exe = Path::new(env!("CARGO_TARGET_TMPDIR")).join("hover_loads");
    let output = Command::new(std::env::var("CC").unwrap_or_else(|_| "cc".into()))
        .args(["-std=c11", "-Wall", "-Wextra", "-Werror", "-O2", "-I"])
        .arg(crate_dir().join("include"))
        .arg(crate_dir().join("examples/c/hover_loads.c"))
        .arg(staticlib())
        .args(["-lm", "-lpthread", "-ldl", "-o"])
        .arg(&exe)
        .output()
        .expect("run cc");
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let out = run(&exe, &[]);
    // The wingbeat mean from Rust: the fly's tethered mean force.
    let mut set = WingSet::from_vehicle_sized(&vehicle("drosophila")).unwrap();
    let v = set.vehicle().unwrap().clone();
    let state = State {
        position_m: v.initial_position_m,
        world_from_body: v.initial_attitude,
        ..State::at_rest()
    };
    let n = v.sim.steps_per_wingbeat;
    let mut fz = 0.0;
    for _ in 0..n {
        fz += set.step(&state).unwrap().total.force_n[2];
    }
    fz /= n as f64;
    assert!(out.contains(&format!("{n} steps")), "{out}");
    let line = out
        .lines()
        .find(|l| l.starts_with("mean force"))
        .expect("a mean force line");
    let inside = line.split(['[', ']']).nth(1).expect("[x, y, z]");
    let z: f64 = inside.split(',').nth(2).unwrap().trim().parse().unwrap();
    assert!(
        (z - fz).abs() <= 1e-3 * fz.abs(),
        "{line}: Rust mean {fz:e}"
    );
}
