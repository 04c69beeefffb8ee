//! `flapwing sweep`: the shipped example studies, shards and their merge, bad input.
//!
//! The L18 check compares with the seed paper's Table 2 (shared/seeds/000_94b36197bfdef766.txt).

use crate::common;

use common::{argv, flapwing_in};

const AMPLITUDE_AOA: &str = include_str!("../../../examples/studies/drosophila_amplitude_aoa.toml");
const WAKE_L18: &str = include_str!("../../../examples/studies/wake_l18.toml");

fn dir_with(files: &[(&str, &str)]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in files {
        std::fs::write(dir.path().join(name), text).unwrap();
    }
    dir
}

fn read(dir: &tempfile::TempDir, path: &str) -> String {
    std::fs::read_to_string(dir.path().join(path)).unwrap()
}

#[test]
fn merged_shards_equal_the_unsharded_run() {
    let dir = dir_with(&[("study.toml", AMPLITUDE_AOA)]);
    let run = flapwing_in(dir.path(), &["sweep", "study.toml", "--out", "whole"]);
    assert_eq!(run.code, 0, "{run:?}");
    assert!(run.stdout.contains("20 of 20 cases"), "{run:?}");
    let whole = read(&dir, "whole/drosophila_amplitude_aoa.csv");
    assert_eq!(whole.lines().count(), 21);
    assert!(whole.starts_with(
        "case,kinematics.amplitude_deg,kinematics.mid_stroke_aoa_deg,lift_over_weight,"
    ));
    for k in 1..=3 {
        let shard = format!("{k}/3");
        let run = flapwing_in(
            dir.path(),
            &[
                "sweep",
                "study.toml",
                "--out",
                "parts",
                "--shard",
                &shard,
                "--jobs",
                "1",
            ],
        );
        assert_eq!(run.code, 0, "{run:?}");
    }
    let shard1 = read(&dir, "parts/drosophila_amplitude_aoa-shard-1-of-3.csv");
    // The study line, the header and 6 cases; the merge drops the study line.
    assert_eq!(shard1.lines().count(), 2 + 6);
    assert!(
        shard1.starts_with("# flapwing study ") && shard1.lines().nth(1) == whole.lines().next(),
        "{shard1}"
    );
    let run = flapwing_in(dir.path(), &["sweep", "merge", "parts"]);
    assert_eq!(run.code, 0, "{run:?}");
    assert_eq!(read(&dir, "parts/drosophila_amplitude_aoa.csv"), whole);
    // The flag form merges too (into a fresh directory copy).
    std::fs::create_dir(dir.path().join("again")).unwrap();
    for k in 1..=3 {
        let name = format!("drosophila_amplitude_aoa-shard-{k}-of-3.csv");
        std::fs::copy(
            dir.path().join("parts").join(&name),
            dir.path().join("again").join(&name),
        )
        .unwrap();
    }
    let run = flapwing_in(dir.path(), &["sweep", "--merge", "again"]);
    assert_eq!(run.code, 0, "{run:?}");
    assert_eq!(read(&dir, "again/drosophila_amplitude_aoa.csv"), whole);
    // Merging again refuses to overwrite without --force, and works with it.
    flapwing_in(dir.path(), &["sweep", "merge", "parts"]).assert_bad_input();
    let run = flapwing_in(dir.path(), &["sweep", "merge", "parts", "--force"]);
    assert_eq!(run.code, 0, "{run:?}");
}

#[test]
fn wake_l18_runs_table_2() {
    // Table 2's (Re, dtau_D, dtau_A) level numbers, tests 1-18.
    let table2 = flapstudy::taguchi::SEED_PAPER_TABLE2;
    let dir = dir_with(&[("wake_l18.toml", WAKE_L18)]);
    let run = flapwing_in(dir.path(), &["sweep", "wake_l18.toml"]);
    assert_eq!(run.code, 0, "{run:?}");
    let csv = read(&dir, "wake_l18.csv");
    let rows: Vec<Vec<f64>> = csv
        .lines()
        .skip(1)
        .map(|l| {
            // Every case finished: `status` ok, `error` empty; the rest are numbers.
            let cells: Vec<&str> = l.split(',').collect();
            assert_eq!(cells[cells.len() - 2..], ["ok", ""], "{l}");
            cells[..cells.len() - 2]
                .iter()
                .map(|f| f.parse().unwrap())
                .collect()
        })
        .collect();
    assert_eq!(rows.len(), 18);
    let mut nu: Vec<f64> = rows.iter().map(|r| r[1]).collect();
    nu.sort_by(|a, b| b.total_cmp(a));
    nu.dedup();
    let dtau = [0.06, 0.12, 0.18];
    for (row, want) in rows.iter().zip(table2) {
        let level = |levels: &[f64], x: f64| levels.iter().position(|&l| l == x).unwrap() as u8 + 1;
        // Re level 1 is the largest viscosity.
        assert_eq!(
            [
                level(&nu, row[1]),
                level(&dtau, row[2]),
                level(&dtau, row[3])
            ],
            want
        );
    }
    // At dtau_A + dtau_D = 0.24 the Reynolds numbers are the paper's Table 1 levels.
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let re_col = header.iter().position(|&h| h == "reynolds").unwrap();
    for (row, level) in [
        (1, 136.0),
        (4, 272.0),
        (8, 680.0),
        (9, 1360.0),
        (14, 2720.0),
        (15, 6800.0),
    ] {
        let re = rows[row][re_col];
        assert!(
            (re - level).abs() / level < 2e-5,
            "test {}: Re {re}",
            row + 1
        );
    }
}

#[test]
fn bad_studies_and_shards_exit_2() {
    let bad = AMPLITUDE_AOA.replace("\"aero_power_w\"", "\"power\"");
    let dir = dir_with(&[("bad.toml", &bad), ("ok.toml", AMPLITUDE_AOA)]);
    let run = flapwing_in(dir.path(), &["sweep", "bad.toml"]);
    run.assert_bad_input();
    assert!(
        run.stderr.contains("bad.toml") && run.stderr.contains("unknown response `power`"),
        "{run:?}"
    );

    let run = flapwing_in(dir.path(), &["sweep", "ok.toml", "--shard", "4/3"]);
    assert_eq!(run.code, 2, "{run:?}");
    let run = flapwing_in(dir.path(), &["sweep", "missing.toml"]);
    run.assert_bad_input();

    // An incomplete set of shards is refused.
    let run = flapwing_in(
        dir.path(),
        &["sweep", "ok.toml", "--out", "p", "--shard", "1/2"],
    );
    assert_eq!(run.code, 0, "{run:?}");
    let run = flapwing_in(dir.path(), &["sweep", "merge", "p"]);
    run.assert_bad_input();
    assert!(run.stderr.contains("missing shard(s) 2"), "{run:?}");

    // A level the model rejects names the factor.
    let out_of_range = AMPLITUDE_AOA.replace("160.0]", "190.0]");
    std::fs::write(dir.path().join("range.toml"), out_of_range).unwrap();
    let run = flapwing_in(dir.path(), &["sweep", "range.toml"]);
    run.assert_bad_input();
    assert!(run.stderr.contains("`kinematics.amplitude_deg`"), "{run:?}");

    // The output is never silently replaced.
    let run = flapwing_in(dir.path(), &["sweep", "ok.toml"]);
    assert_eq!(run.code, 0, "{run:?}");
    flapwing_in(dir.path(), &["sweep", "ok.toml"]).assert_bad_input();
}

#[test]
fn analyze_gives_snr_main_effects_regression_and_a_plot() {
    let dir = dir_with(&[("wake_l18.toml", WAKE_L18)]);
    let run = flapwing_in(dir.path(), &["sweep", "wake_l18.toml"]);
    assert_eq!(run.code, 0, "{run:?}");
    let run = flapwing_in(
        dir.path(),
        &[
            "sweep",
            "analyze",
            "wake_l18.csv",
            "--response",
            "cl_mean_wake_capture",
            "--ln",
            "fluid.kinematic_viscosity_m2_s",
            "--plot",
            "effects.svg",
            "--json",
        ],
    );
    assert_eq!(run.code, 0, "{run:?}");
    let j = run.json();
    assert_eq!(j["runs"], 18);
    let effects = j["snr_main_effects"].as_array().unwrap();
    let levels: Vec<usize> = effects
        .iter()
        .map(|e| e["levels"].as_array().unwrap().len())
        .collect();
    assert_eq!(levels, [6, 3, 3]);
    // Eq 17: the dtau_D terms change dCL_bar by 0.39 between the 0.06 and 0.18 levels, more
    // than the whole Re term can (|c1| = 0.195), so dtau_D has the largest effect.
    assert_eq!(effects[1]["factor"], "kinematics.dtau_d");
    assert_eq!(effects[1]["rank"], 1);
    // The SNR main effect of dtau_D = 0.06 is the mean of eq 15 (n = 1: 20 log10 y) over
    // the six runs at that level, recomputed here from the CSV.
    let csv = read(&dir, "wake_l18.csv");
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let col = header
        .iter()
        .position(|&h| h == "cl_mean_wake_capture")
        .unwrap();
    let snr_006: Vec<f64> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|f| f[2] == "0.06")
        .map(|f| 20.0 * f[col].parse::<f64>().unwrap().log10())
        .collect();
    assert_eq!(snr_006.len(), 6);
    let by_hand = snr_006.iter().sum::<f64>() / 6.0;
    let got = effects[1]["means"][0].as_f64().unwrap();
    assert!((got - by_hand).abs() < 1e-12, "{got} vs {by_hand}");
    // Eq 16's ten terms on 18 runs: 8 residual degrees of freedom.
    let reg = &j["regression"];
    assert_eq!(reg["names"].as_array().unwrap().len(), 10);
    assert_eq!(reg["names"][1], "ln(fluid.kinematic_viscosity_m2_s)");
    assert_eq!(reg["dof"], 8);
    let svg = read(&dir, "effects.svg");
    assert!(
        svg.contains("<svg") && svg.contains("kinematics.dtau_d"),
        "not an SVG plot"
    );

    let run = flapwing_in(
        dir.path(),
        &["sweep", "analyze", "wake_l18.csv", "--response", "lift"],
    );
    run.assert_bad_input();
    assert!(
        run.stderr.contains("`lift`") && run.stderr.contains("lift_over_weight"),
        "{run:?}"
    );
    let run = flapwing_in(
        dir.path(),
        &argv("sweep analyze wake_l18.csv --response aero_power_w --ln nu"),
    );
    run.assert_bad_input();
    let run = flapwing_in(
        dir.path(),
        &argv("sweep analyze wake_l18.csv --response aero_power_w --snr nominal"),
    );
    run.assert_bad_input();
    assert!(run.stderr.contains("replicate"), "{run:?}");
}
