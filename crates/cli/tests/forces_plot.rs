//! `forces --plot` draws the paper's Fig 23-24 curves and refuses to overwrite.

use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_flapwing");

#[test]
fn plot_is_written_and_not_overwritten() {
    let dir = tempfile::tempdir().unwrap();
    let run = |extra: &[&str]| {
        Command::new(BIN)
            .current_dir(dir.path())
            .args([
                "forces",
                "--cycles",
                "1",
                "--steps-per-cycle",
                "50",
                "--plot",
                "fig.svg",
            ])
            .args(extra)
            .output()
            .unwrap()
    };
    let out = run(&[]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let svg = std::fs::read_to_string(dir.path().join("fig.svg")).unwrap();
    assert!(
        svg.starts_with("<svg")
            && svg.contains("C_L with wake capture")
            && svg.contains("C_D without")
    );
    let again = run(&[]);
    assert_eq!(again.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&again.stderr).contains("--force"));
    assert_eq!(run(&["--force"]).status.code(), Some(0));
}
