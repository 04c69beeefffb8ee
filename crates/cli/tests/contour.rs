//! `sweep contour` maps a response over two factors of a sweep CSV.

use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_flapwing");

#[test]
fn contour_of_a_small_grid() {
    let dir = tempfile::tempdir().unwrap();
    let csv = "case,a,b,lift_over_weight,wake_capture_clamped\n0,1.0,10.0,0.5,0\n1,2.0,10.0,0.7,0\n2,1.0,20.0,0.9,0\n3,2.0,20.0,1.1,0\n";
    std::fs::write(dir.path().join("s.csv"), csv).unwrap();
    let run = |resp: &str| {
        Command::new(BIN)
            .current_dir(dir.path())
            .args([
                "sweep",
                "contour",
                "s.csv",
                "--x",
                "a",
                "--y",
                "b",
                "--response",
                resp,
                "--plot",
                "c.svg",
                "--force",
            ])
            .output()
            .unwrap()
    };
    let out = run("lift_over_weight");
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let svg = std::fs::read_to_string(dir.path().join("c.svg")).unwrap();
    // Each cell's mean is written in it.
    for v in ["0.5000", "0.7000", "0.9000", "1.1000"] {
        assert!(svg.contains(v), "{v} missing");
    }
    let bad = run("no_such_column");
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("no_such_column"));
}
