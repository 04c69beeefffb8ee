//! Wind on the CLI, end to end through the real binary: `simulate` and `hover` fly the wind
//! flags (steady wind, Dryden turbulence, 1 - cosine gusts; flapsim::wind), the same seed
//! gives the same run, and bad wind input exits 2 naming what is wrong.

use crate::common;

use common::flapwing;

fn simulate(extra: &[&str]) -> common::Run {
    let mut args = vec![
        "simulate",
        "--tethered",
        "--duration-s",
        "0.01",
        "--no-log",
        "--json",
    ];
    args.extend_from_slice(extra);
    flapwing(&args)
}

#[test]
fn turbulence_is_reproducible_per_seed_and_changes_the_loads() {
    let still = simulate(&[]);
    assert_eq!(still.code, 0, "{still:?}");
    assert!(
        still.json().get("wind").is_none(),
        "still air has no wind field"
    );
    let run = |seed: &str| {
        let r = simulate(&[
            "--turbulence-intensity-m-s",
            "0.3",
            "--turbulence-length-scale-m",
            "0.05",
            "--wind-seed",
            seed,
        ]);
        assert_eq!(r.code, 0, "{r:?}");
        r.json()
    };
    let (a, b, c) = (run("3"), run("3"), run("4"));
    assert_eq!(a["summary"], b["summary"]);
    assert_ne!(a["summary"], c["summary"]);
    assert_ne!(a["summary"], still.json()["summary"]);
    assert_eq!(a["wind"]["turbulence"]["seed"], 3);
    assert_eq!(a["wind"]["turbulence"]["intensity_m_s"][2], 0.3);
}

#[test]
fn steady_wind_and_gusts_fly_in_simulate_and_hover() {
    let r = simulate(&["--wind-world-m-s", "-0.5,0,0"]);
    assert_eq!(r.code, 0, "{r:?}");
    assert_eq!(r.json()["wind"]["steady_world_m_s"][0], -0.5);
    let h = flapwing(&[
        "hover",
        "--duration-s",
        "0.03",
        "--no-log",
        "--json",
        "--gust",
        "amplitude_m_s=0.3,direction=0:0:1,start_s=0.005,duration_s=0.02",
    ]);
    assert_eq!(h.code, 0, "{h:?}");
    let j = h.json();
    assert_eq!(j["wind"]["gusts"][0]["amplitude_m_s"], 0.3);
    let text = flapwing(&[
        "hover",
        "--duration-s",
        "0.01",
        "--no-log",
        "--turbulence-intensity-m-s",
        "0.1",
    ]);
    assert_eq!(text.code, 0, "{text:?}");
    assert!(text.stdout.contains("wind: steady"), "{}", text.stdout);
}

#[test]
fn bad_wind_input_exits_2() {
    let bad = |extra: &[&str], needle: &str| {
        let r = simulate(extra);
        r.assert_bad_input();
        assert!(r.stderr.contains(needle), "{needle}: {}", r.stderr);
    };
    bad(
        &["--turbulence-intensity-m-s", "-0.1"],
        "--turbulence-intensity-m-s",
    );
    bad(
        &["--turbulence-intensity-m-s", "0.1,0.2"],
        "one value or three",
    );
    bad(
        &[
            "--turbulence-intensity-m-s",
            "0.1",
            "--turbulence-length-scale-m",
            "0",
        ],
        "--turbulence-length-scale-m",
    );
    bad(&["--wind-seed", "3"], "need turbulence");
    bad(&["--gust", "amplitude_m_s=1"], "direction");
    bad(&["--gust", "amplitude_m_s=1,direction=0:0"], "X:Y:Z");
    bad(
        &["--gust", "amplitude_m_s=1,direction=0:0:0,duration_s=0.001"],
        "direction_world",
    );
    bad(
        &[
            "--gust",
            "amplitude_m_s=1,direction=0:0:1,start_s=0.005,duration_s=0.01",
        ],
        "gusts[0]",
    );
    bad(
        &["--gust", "amplitude_m_s=1,direction=0:0:1,speed=2"],
        "unknown key",
    );
}

/// `replay --check` re-runs the wind the run met: the field the flags made (in the log's
/// settings), and still air where `--no-wind` switched a model's `[wind]` off. Fails if the
/// check re-runs the model's wind instead (a false mismatch, exit 1).
#[test]
fn replay_check_reruns_the_wind_of_the_flags() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let model = format!(
        "{}\n[wind]\nsteady_world_m_s = [0.2, 0.0, 0.0]\n",
        include_str!("../../../models/drosophila.toml")
    );
    std::fs::write(d.join("windy.toml"), model).unwrap();
    let cases: [&[&str]; 3] = [
        &["--turbulence-intensity-m-s", "0.1"],
        &["--model", "windy.toml", "--no-wind"],
        &["--model", "windy.toml", "--wind-world-m-s", "0,0.1,0"],
    ];
    for (k, extra) in cases.iter().enumerate() {
        let log = format!("w{k}.mcap");
        let mut args = vec!["simulate", "--duration-s", "0.01", "--mcap", &log];
        args.extend_from_slice(extra);
        let run = common::flapwing_in(d, &args);
        assert_eq!(run.code, 0, "{run:?}");
        let check = common::flapwing_in(d, &["replay", &log, "--check"]);
        assert_eq!(check.code, 0, "{extra:?}: {check:?}");
        assert!(check.stdout.starts_with("match: "), "{check:?}");
    }
}
