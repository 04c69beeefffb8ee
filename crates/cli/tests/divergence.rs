//! A run that diverges stops, says when and why, exits 1 and leaves a finished, readable
//! log whose events record the divergence.

use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_flapwing");

#[test]
fn diverging_run_leaves_a_finished_log() {
    let dir = tempfile::tempdir().unwrap();
    // The built-in fly, untrimmed and spun up: the yaw rate passes the runaway limit soon.
    let model = flapsim::DROSOPHILA_TOML
        .replace("[sim]\n", "[sim]\nmax_angular_speed_rad_s = 50.0\n")
        + "angular_velocity_deg_s = [0.0, 0.0, 2000.0]\n";
    assert!(model.contains("max_angular_speed_rad_s = 50.0"));
    std::fs::write(dir.path().join("spin.toml"), model).unwrap();
    let out = Command::new(BIN)
        .current_dir(dir.path())
        .args([
            "simulate",
            "--model",
            "spin.toml",
            "--duration-s",
            "1",
            "--mcap",
            "spin.mcap",
        ])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("diverged at t = ") && stderr.contains("angular speed"),
        "{stderr}"
    );
    let replay = Command::new(BIN)
        .current_dir(dir.path())
        .args(["replay", "spin.mcap"])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&replay.stdout);
    assert_eq!(replay.status.code(), Some(0), "{text}");
    assert!(
        text.contains("complete") && text.contains("ERROR") && text.contains("diverged"),
        "{text}"
    );
}
