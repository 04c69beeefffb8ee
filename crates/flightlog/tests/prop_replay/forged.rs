//! Real logs with forged `flapwing` metadata (what `replay --check` re-runs): random
//! command, settings, model text and log rate, and missing keys. `read_summary`,
//! `export_csv` and `check_log` return `Ok` or a clear error, never panic, and `check_log`
//! finishes within 30 s.

use std::collections::BTreeMap;
use std::io::{BufWriter, Cursor};
use std::time::Duration;

use proptest::prelude::*;
use proptest::sample::Index;

use crate::checks::{check_with_limit, config, csv_of, summary_of};
use crate::fixture::small_log;

/// Copies an MCAP file, replacing its `flapwing` metadata with `md`.
fn with_metadata(bytes: &[u8], md: &BTreeMap<String, String>) -> Vec<u8> {
    let summary = mcap::Summary::read(bytes).unwrap().unwrap();
    let mut w = mcap::WriteOptions::new()
        .compression_threads(0)
        .create(BufWriter::new(Cursor::new(Vec::new())))
        .unwrap();
    for i in &summary.metadata_indexes {
        let mut m = mcap::read::metadata(bytes, i).unwrap();
        if m.name == "flapwing" {
            m.metadata = md.clone();
        }
        w.write_metadata(&m).unwrap();
    }
    for m in mcap::MessageStream::new(bytes).unwrap() {
        w.write(&m.unwrap()).unwrap();
    }
    w.finish().unwrap();
    w.into_inner().into_inner().unwrap().into_inner()
}

fn original_metadata(bytes: &[u8]) -> BTreeMap<String, String> {
    let summary = mcap::Summary::read(bytes).unwrap().unwrap();
    summary
        .metadata_indexes
        .iter()
        .map(|i| mcap::read::metadata(bytes, i).unwrap())
        .find(|m| m.name == "flapwing")
        .unwrap()
        .metadata
}

/// A settings JSON text: the real shape with odd values, or garbage.
fn settings_json() -> impl Strategy<Value = String> {
    let number = prop_oneof![
        (0.0f64..0.02).prop_map(|x| format!("{x}")),
        prop::sample::select(vec![
            "0", "-1", "1e300", "1e-300", "null", "\"x\"", "NaN", "1e400", "[]",
        ])
        .prop_map(str::to_owned),
    ];
    let mode = prop::sample::select(vec!["free", "tethered", "longitudinal", "locked", "", "x"]);
    prop_oneof![
        4 => (mode, number.clone(), number.clone(), number.clone()).prop_map(|(m, d, r, w)| {
            format!(
                r#"{{"mode":"{m}","duration_s":{d},"log_rate_hz":{r},"wind_world_m_s":[{w},0,0]}}"#
            )
        }),
        1 => "[\\[\\]{}\":,0-9a-z_.e+-]{0,60}",
    ]
}

fn model_text() -> impl Strategy<Value = String> {
    let d = flapsim::DROSOPHILA_TOML;
    prop_oneof![
        3 => Just(d.to_owned()),
        1 => Just(flapsim::ROBOBEE_KINEMATIC_TOML.to_owned()),
        1 => any::<Index>().prop_map(move |i| d[..i.index(d.len())].to_owned()),
        1 => Just(d.replace("freq_hz = 218.0", "freq_hz = 0.0")),
        1 => Just(d.replace("mass_kg = 1.0e-6", "mass_kg = 1.0e300")),
        1 => ".{0,40}",
    ]
}

/// KNOWN BUG (issue 7, reported to the lead): `check_log` re-runs `round(duration_s / dt)`
/// steps and stops early only once every logged sample has been met. A forged log whose
/// settings say a huge `duration_s` (1e300 s; 1e6 s is already hours) and whose
/// `log_rate_hz` metadata puts every re-run step in the same decimator bucket ("0", "NaN",
/// "inf", "1e-9") never meets its second sample, so `check_log` (and `flapwing replay
/// --check`) runs for ever (verified: no result after 10 s for each of these four rates).
/// Exactly these inputs are left out below; remove the filter once the re-run is bounded.
fn known_bug_check_hang(settings: &str, rate: &str) -> bool {
    let huge = settings.contains("\"duration_s\":1e300");
    let stuck = rate
        .parse::<f64>()
        .is_ok_and(|r| !(r.is_finite() && r.abs() >= 1e-3));
    // Fixed: the re-run now stops as soon as it passes a logged step it does not log.
    let _ = (huge, stuck);
    false
}

proptest! {
    #![proptest_config(config(60))]

    /// A real log whose `flapwing` metadata is forged (command, settings, model text, log
    /// rate, missing keys): read_summary, export_csv and check_log return Ok or a clear error,
    /// never panic, and check_log finishes within 30 s.
    #[test]
    fn forged_flapwing_metadata(
        command in prop::sample::select(vec!["simulate", "simulate", "hover", "", "x"]),
        settings in settings_json(),
        model in model_text(),
        rate in prop::sample::select(vec![
            "2000", "every step", "0", "-5", "NaN", "inf", "1e-9", "abc", "1e300",
        ]),
        drop in prop::collection::vec(
            prop::sample::select(vec!["command", "settings", "model_toml", "model_origin", "log_rate_hz"]),
            0..2,
        ),
    ) {
        prop_assume!(!known_bug_check_hang(&settings, rate));
        let base = small_log();
        let mut md = original_metadata(base);
        md.insert("command".into(), command.into());
        md.insert("settings".into(), settings.clone());
        md.insert("model_toml".into(), model.clone());
        md.insert("log_rate_hz".into(), rate.into());
        for k in &drop {
            md.remove(*k);
        }
        let bytes = with_metadata(base, &md);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("forged.mcap");
        std::fs::write(&path, &bytes).unwrap();
        summary_of(&path)?;
        csv_of(&path, "/vehicle/state", &dir.path().join("s.csv"))?;
        match check_with_limit(&path, Duration::from_secs(30))? {
            None => prop_assert!(false, "check_log hangs (settings {settings}, rate {rate})"),
            Some(Ok(_)) => {}
            Some(Err(e)) => {
                let s = e.to_string();
                prop_assert!(!s.trim().is_empty());
                prop_assert!(!s.contains("panicked"), "{s}");
            }
        }
    }
}
