//! Damaged logs given to `flapwing replay`: a short log written by the binary itself
//! (`simulate --mcap`), truncated, bit-flipped or replaced by garbage, replayed plain or with
//! `--json`, `--csv`, `--rrd` or `--check`: exit 0, 1 or 2, never a panic, and a bad-input
//! exit names the file (24 cases).

use proptest::prelude::*;
use proptest::sample::Index;

use crate::harness::{check_json, check_run, config, flapwing};

/// A short log written by the binary itself (`simulate --mcap`), once per test run.
fn log_bytes() -> &'static Vec<u8> {
    static B: std::sync::OnceLock<Vec<u8>> = std::sync::OnceLock::new();
    B.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        let args: Vec<String> = ["simulate", "--duration-s", "0.01", "--mcap", "run.mcap"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        let r = flapwing(dir.path(), &args);
        assert_eq!(r.code, 0, "{r:?}");
        std::fs::read(dir.path().join("run.mcap")).unwrap()
    })
}

#[derive(Debug, Clone)]
enum LogDamage {
    Truncate(Index),
    Flip(Vec<(Index, u8)>),
    Garbage(Vec<u8>),
}

proptest! {
    #![proptest_config(config(24))]

    /// `flapwing replay` of a truncated, bit-flipped or garbage log, with --json, --csv,
    /// --rrd or --check: exit 0, 1 or 2, never a panic; a bad-input exit names the file.
    #[test]
    fn replay_of_damaged_logs(
        damage in prop_oneof![
            2 => any::<Index>().prop_map(LogDamage::Truncate),
            2 => prop::collection::vec((any::<Index>(), 0u8..8), 1..4).prop_map(LogDamage::Flip),
            1 => prop::collection::vec(any::<u8>(), 0..256).prop_map(LogDamage::Garbage),
        ],
        mode in prop::sample::select(vec!["", "--json", "--csv", "--rrd", "--check"]),
    ) {
        let good = log_bytes();
        let bytes = match &damage {
            LogDamage::Truncate(i) => good[..i.index(good.len() + 1)].to_vec(),
            LogDamage::Flip(flips) => {
                let mut b = good.clone();
                for (i, bit) in flips {
                    b[i.index(good.len())] ^= 1 << bit;
                }
                b
            }
            LogDamage::Garbage(g) => g.clone(),
        };
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("damaged log.mcap"), &bytes).unwrap();
        let mut args = vec!["replay".to_owned(), "damaged log.mcap".to_owned()];
        match mode {
            "" => {}
            "--csv" => args.extend(["--csv", "/vehicle/state", "out.csv"].map(String::from)),
            "--rrd" => args.extend(["--rrd", "out.rrd"].map(String::from)),
            m => args.push(m.to_owned()),
        }
        let r = flapwing(dir.path(), &args);
        check_run(&r)?;
        check_json(&r, mode == "--json")?;
        // KNOWN BUG (issue 7, reported to the lead): when the embedded model of a damaged
        // log does not load, the message names the model's origin, not the log file:
        // `--rrd`: "error: the log's embedded model does not load: <built-in drosophila>:
        // TOML parse error ..."; `--check`: "error: <built-in drosophila>: TOML parse error
        // ..." (which reads as if the built-in model were broken). Exactly these messages
        // (naming the embedded origin `<built-in drosophila>`) are exempt from the file-name
        // check below; remove once they name the log.
        if r.code == 2 {
            prop_assert!(
                r.stderr.contains("damaged log.mcap"),
                "{:?}: stderr does not name the file: {}", damage, r.stderr
            );
        }
    }
}
