//! Property tests (issue 7): reading a damaged, foreign or forged MCAP log never panics.
//!
//! `flightlog::replay::read_summary`, `replay::export_csv` and `check::check_log` are given
//! truncated logs (every prefix length on a grid, and random lengths), logs with random bits
//! flipped, random bytes (with and without the MCAP magic), valid MCAP files written with the
//! `mcap` crate without flapwing metadata (random channels, messages, metadata, attachments,
//! chunking and compression), and real logs whose `flapwing` metadata was rewritten (random
//! command, settings, model text and log rate). Each call must return `Ok` (a truncated or
//! damaged log: partial, with `damage` saying what was lost) or an error whose message names
//! the file, and never panic. A truncated log yields more messages the longer the prefix,
//! and `check_log` finds its samples equal to a re-run.
//!
//! Generated inputs per property (the file runs in a few seconds in release):
//!
//! | property / test                                   | inputs |
//! |---------------------------------------------------|--------|
//! | `truncation_grid` (deterministic: 97 grid points, chunk ends +-1, edges) | ~110 (check_log on ~10) |
//! | `truncated_at_random_lengths`                     |     60 |
//! | `flipped_bits`                                    |     80 |
//! | `random_bytes`                                    |    200 |
//! | `foreign_mcap_files`                              |    100 |
//! | `forged_flapwing_metadata`                        |     60 |
//!
//! `FLAPWING_PROP_SCALE=N` multiplies every proptest case count (for long local soak runs).

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::io::{BufWriter, Cursor};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use std::time::Duration;

use flapsim::{Mode, Simulation, Vehicle};
use flightlog::check::{CheckOutcome, check_log};
use flightlog::replay::{ReplaySummary, export_csv, read_summary};
use flightlog::{Error, LogOptions, Recorder, RunInfo, SimSettings};
use proptest::prelude::*;
use proptest::sample::Index;

#[path = "../../wingforce/tests/support/prop_config.rs"]
mod prop_config;

// ---------------------------------------------------------------------------------------------
// The fixture: a short drosophila run recorded exactly as `flapwing simulate --mcap` does.
// ---------------------------------------------------------------------------------------------

struct Fixture {
    _dir: tempfile::TempDir,
    bytes: Vec<u8>,
    summary: ReplaySummary,
}

/// Records `wingbeats` drosophila wingbeats at `rate` (None: every step) into `path`.
fn record(path: &Path, wingbeats: f64, rate: Option<f64>) {
    let toml = flapsim::DROSOPHILA_TOML;
    let vehicle = Vehicle::from_toml(toml, "drosophila.toml").unwrap();
    let duration = wingbeats / vehicle.freq_hz();
    let settings = SimSettings::new(Mode::Free, duration, rate, [0.0; 3]);
    let info = RunInfo::new(
        "simulate",
        format!("flapwing simulate --duration-s {duration}"),
        toml,
        "drosophila.toml",
        settings.to_json(),
    );
    let opts = LogOptions {
        mcap: Some(path.to_owned()),
        log_rate_hz: rate,
        ..LogOptions::default()
    };
    let mut rec = Recorder::create(&opts, &info, &vehicle).unwrap();
    let mut sim = Simulation::new(vehicle, Mode::Free);
    let n = (duration / sim.dt_s()).round() as u64;
    for _ in 0..n {
        let out = sim.step().unwrap();
        rec.record(&out).unwrap();
    }
    rec.finish().unwrap();
}

/// Six wingbeats logged at every step: several chunks, about 600 samples.
fn fixture() -> &'static Fixture {
    static F: OnceLock<Fixture> = OnceLock::new();
    F.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("full.mcap");
        record(&path, 6.0, None);
        let bytes = std::fs::read(&path).unwrap();
        let summary = read_summary(&path).unwrap();
        assert!(summary.complete && summary.damage.is_none());
        assert!(summary.samples > 500, "{}", summary.samples);
        Fixture {
            _dir: dir,
            bytes,
            summary,
        }
    })
}

// ---------------------------------------------------------------------------------------------
// Checks.
// ---------------------------------------------------------------------------------------------

fn panic_message(p: Box<dyn std::any::Any + Send>) -> String {
    p.downcast_ref::<String>()
        .cloned()
        .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_default()
}

/// Runs `f`, turning a panic into a test failure naming `what`.
fn guarded<T>(what: &str, f: impl FnOnce() -> T) -> Result<T, TestCaseError> {
    catch_unwind(AssertUnwindSafe(f))
        .map_err(|p| TestCaseError::fail(format!("{what} panicked: {}", panic_message(p))))
}

/// An error from reading `path`: a message that names the file (all but JSON/Rerun errors).
fn check_read_error(e: &Error, path: &Path) -> Result<(), TestCaseError> {
    let s = e.to_string();
    let name = path.file_name().unwrap().to_string_lossy();
    prop_assert!(!s.trim().is_empty(), "empty error message");
    prop_assert!(
        s.contains(name.as_ref()),
        "the error does not name the file `{}`: {} ({:?})",
        name,
        s,
        e
    );
    prop_assert!(
        e.is_bad_input(),
        "a bad file is not classed as bad input: {s} ({e:?})"
    );
    Ok(())
}

/// `read_summary` of a damaged log: Ok with a damage note unless whole, or a clear error.
/// Returns the summary.
fn summary_of(path: &Path) -> Result<Option<ReplaySummary>, TestCaseError> {
    match guarded("read_summary", || read_summary(path))? {
        Ok(s) => {
            prop_assert!(
                s.complete || s.damage.is_some(),
                "an incomplete log without a damage note"
            );
            // The text and JSON forms of the summary (what `flapwing replay` prints).
            guarded("Display of the summary", || s.to_string())?;
            guarded("JSON of the summary", || serde_json::to_string(&s))?
                .map_err(|e| TestCaseError::fail(format!("summary is not JSON: {e}")))?;
            Ok(Some(s))
        }
        Err(e) => {
            check_read_error(&e, path)?;
            Ok(None)
        }
    }
}

/// `export_csv` of one topic: Ok, or a clear error (an unknown topic lists the others).
fn csv_of(path: &Path, topic: &str, out: &Path) -> Result<(), TestCaseError> {
    match guarded("export_csv", || export_csv(path, topic, out))? {
        Ok(stats) => prop_assert!(stats.columns >= 1),
        Err(Error::UnknownTopic { .. }) => {}
        Err(e) => check_read_error(&e, path)?,
    }
    Ok(())
}

/// `check_log` in a thread with a time limit (a re-run must not hang on any input).
fn check_with_limit(
    path: &Path,
    limit: Duration,
) -> Result<Option<flightlog::Result<CheckOutcome>>, TestCaseError> {
    let p = path.to_owned();
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let r = catch_unwind(AssertUnwindSafe(|| check_log(&p)));
        let _ = tx.send(r);
    });
    match rx.recv_timeout(limit) {
        Ok(Ok(r)) => Ok(Some(r)),
        Ok(Err(p)) => Err(TestCaseError::fail(format!(
            "check_log panicked: {}",
            panic_message(p)
        ))),
        Err(_) => Ok(None),
    }
}

fn config(cases: u32) -> ProptestConfig {
    prop_config::scaled_config(cases, 500)
}

/// Maps a `Result<(), TestCaseError>` of a plain test to a panic.
fn ok(r: Result<(), TestCaseError>) {
    if let Err(e) = r {
        panic!("{e}");
    }
}

// ---------------------------------------------------------------------------------------------
// Truncation.
// ---------------------------------------------------------------------------------------------

/// End offsets of the chunk records of a whole log.
fn chunk_ends(bytes: &[u8]) -> Vec<usize> {
    let summary = mcap::Summary::read(bytes).unwrap().unwrap();
    let mut v: Vec<usize> = summary
        .chunk_indexes
        .iter()
        .map(|c| (c.chunk_start_offset + c.chunk_length) as usize)
        .collect();
    v.sort();
    v
}

/// Every prefix length on a grid (97 points) plus each chunk end +-1: read_summary is Ok
/// (partial, with damage) or a clear error; the message count never decreases as the prefix
/// grows; only the whole file is complete; export_csv never panics; check_log (on every
/// twelfth cut) finds a match, nothing to check, or a clear error, never a mismatch.
#[test]
fn truncation_grid() {
    ok((|| {
        let f = fixture();
        let len = f.bytes.len();
        let ends = chunk_ends(&f.bytes);
        prop_assert!(ends.len() >= 3, "only {} chunks", ends.len());
        let mut cuts: Vec<usize> = (0..=96).map(|i| i * len / 96).collect();
        for e in &ends {
            cuts.extend([e - 1, *e, e + 1]);
        }
        cuts.extend([1, 7, 8, 9, len - 1]);
        cuts.sort();
        cuts.dedup();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cut.mcap");
        let csv = dir.path().join("state.csv");
        let mut last_count = 0;
        let mut checked = 0;
        for (k, &cut) in cuts.iter().enumerate() {
            std::fs::write(&path, &f.bytes[..cut]).unwrap();
            let s = summary_of(&path)
                .map_err(|e| TestCaseError::fail(format!("cut at {cut} of {len}: {e}")))?;
            if let Some(s) = &s {
                prop_assert!(
                    s.message_count >= last_count,
                    "cut at {cut}: {} messages, fewer than {last_count} at a shorter cut",
                    s.message_count
                );
                prop_assert!(s.message_count <= f.summary.message_count);
                prop_assert_eq!(s.complete, cut == len, "cut at {} of {}", cut, len);
                last_count = s.message_count;
            }
            csv_of(&path, "/vehicle/state", &csv)?;
            if k % 12 == 0 || cut == len {
                checked += 1;
                match check_with_limit(&path, Duration::from_secs(60))? {
                    None => prop_assert!(false, "check_log of a cut at {cut} hangs"),
                    Some(Ok(CheckOutcome::Mismatch { detail, .. })) => {
                        prop_assert!(false, "cut at {cut}: the re-run differs: {detail}")
                    }
                    Some(Ok(_)) => {}
                    Some(Err(e)) => check_read_error(&e, &path)?,
                }
            }
        }
        prop_assert_eq!(last_count, f.summary.message_count);
        eprintln!(
            "truncation_grid: {} cuts, check_log on {checked}",
            cuts.len()
        );
        Ok(())
    })());
}

proptest! {
    #![proptest_config(config(60))]

    /// Random prefix lengths: Ok (partial, with damage) or a clear error; never more
    /// messages than the whole log.
    #[test]
    fn truncated_at_random_lengths(at in any::<Index>()) {
        let f = fixture();
        let cut = at.index(f.bytes.len() + 1);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cut.mcap");
        std::fs::write(&path, &f.bytes[..cut]).unwrap();
        if let Some(s) = summary_of(&path)? {
            prop_assert!(s.message_count <= f.summary.message_count);
        }
        csv_of(&path, "/wing/left/forces", &dir.path().join("f.csv"))?;
    }
}

// ---------------------------------------------------------------------------------------------
// Bit flips.
// ---------------------------------------------------------------------------------------------

proptest! {
    #![proptest_config(config(80))]

    /// One to four flipped bits anywhere: read_summary and export_csv never panic; a
    /// summary never has more messages than the whole log. With a single flip, check_log is
    /// run too (its re-run is bounded by the log's samples).
    #[test]
    fn flipped_bits(
        flips in prop::collection::vec((any::<Index>(), 0u8..8), 1..5),
        run_check in prop::bool::weighted(0.15),
    ) {
        let f = fixture();
        let mut b = f.bytes.clone();
        let n = b.len();
        for (i, bit) in &flips {
            b[i.index(n)] ^= 1 << bit;
        }
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("flipped.mcap");
        std::fs::write(&path, &b).unwrap();
        if let Some(s) = summary_of(&path)? {
            prop_assert!(s.message_count <= f.summary.message_count);
        }
        csv_of(&path, "/vehicle/state", &dir.path().join("s.csv"))?;
        if run_check && flips.len() == 1 {
            match check_with_limit(&path, Duration::from_secs(60))? {
                None => prop_assert!(false, "check_log hangs"),
                Some(Ok(_)) => {}
                Some(Err(e)) => prop_assert!(!e.to_string().trim().is_empty()),
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Random bytes.
// ---------------------------------------------------------------------------------------------

const MAGIC: &[u8] = b"\x89MCAP0\r\n";

proptest! {
    #![proptest_config(config(200))]

    /// Random bytes, sometimes behind the MCAP magic, sometimes a random splice into the real
    /// log's header: a clear error (or Ok), never a panic.
    #[test]
    fn random_bytes(
        body in prop::collection::vec(any::<u8>(), 0..2000),
        how in 0u8..4,
        at in any::<Index>(),
    ) {
        let f = fixture();
        let bytes = match how {
            0 => body.clone(),
            1 => [MAGIC, &body].concat(),
            2 => [MAGIC, &body, MAGIC].concat(),
            _ => {
                // The real log's first part, then garbage.
                let cut = at.index(f.bytes.len().min(4096) + 1);
                [&f.bytes[..cut], &body].concat()
            }
        };
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("random.mcap");
        std::fs::write(&path, &bytes).unwrap();
        summary_of(&path)?;
        csv_of(&path, "/vehicle/state", &dir.path().join("s.csv"))?;
        match guarded("check_log", || check_log(&path))? {
            Ok(_) => {}
            Err(e) => check_read_error(&e, &path)?,
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Foreign MCAP files (valid MCAP, not written by flapwing).
// ---------------------------------------------------------------------------------------------

#[derive(Debug, Clone)]
struct Foreign {
    channels: Vec<(String, String, String)>,
    messages: Vec<(Index, u64, Vec<u8>)>,
    metadata: Vec<(String, BTreeMap<String, String>)>,
    attachments: Vec<(String, Vec<u8>)>,
    chunked: bool,
    compression: u8,
    chunk_size: u64,
}

fn foreign() -> impl Strategy<Value = Foreign> {
    let topic = prop_oneof![
        Just("/vehicle/state".to_owned()),
        Just("/events".to_owned()),
        Just("/wing/left/forces".to_owned()),
        "/[a-z/]{0,12}",
        ".{0,8}",
    ];
    let payload = prop_oneof![
        prop::collection::vec(any::<u8>(), 0..64),
        Just(br#"{"phase":0.5,"position_m":{"x":1,"y":2,"z":3},"total":{"force_n":{"x":1,"y":0,"z":2},"moment_nm":{"x":0,"y":0,"z":0}}}"#.to_vec()),
        Just(br#"{"level":4,"message":"boom"}"#.to_vec()),
        "[\\[\\]{}\":,0-9a-z.e+-]{0,40}".prop_map(String::into_bytes),
    ];
    let meta_name = prop_oneof![
        4 => "[a-z.]{0,10}".prop_filter("not flapwing", |s| s != "flapwing"),
        1 => Just("flapwing.end".to_owned()),
    ];
    (
        prop::collection::vec(
            (
                topic,
                "[a-z.]{0,10}",
                prop_oneof![Just("json".to_owned()), "[a-z]{0,5}"],
            ),
            0..5,
        ),
        prop::collection::vec((any::<Index>(), any::<u64>(), payload), 0..40),
        prop::collection::vec(
            (
                meta_name,
                prop::collection::btree_map(".{0,6}", ".{0,12}", 0..4),
            ),
            0..3,
        ),
        prop::collection::vec((".{0,10}", prop::collection::vec(any::<u8>(), 0..32)), 0..3),
        any::<bool>(),
        0u8..3,
        prop_oneof![Just(64u64), Just(1024), Just(1 << 20)],
    )
        .prop_map(
            |(channels, messages, metadata, attachments, chunked, compression, chunk_size)| {
                Foreign {
                    channels,
                    messages,
                    metadata,
                    attachments,
                    chunked,
                    compression,
                    chunk_size,
                }
            },
        )
}

fn write_foreign(f: &Foreign) -> Vec<u8> {
    let compression = match f.compression {
        0 => None,
        1 => Some(mcap::Compression::Zstd),
        _ => Some(mcap::Compression::Lz4),
    };
    let mut w = mcap::WriteOptions::new()
        .compression(compression)
        .compression_threads(0)
        .use_chunks(f.chunked)
        .chunk_size(Some(f.chunk_size))
        .library("someone-else")
        .create(Cursor::new(Vec::new()))
        .unwrap();
    let mut ids = Vec::new();
    for (topic, schema, encoding) in &f.channels {
        let s = w
            .add_schema(schema, "jsonschema", br#"{"type":"object"}"#)
            .unwrap();
        ids.push(w.add_channel(s, topic, encoding, &BTreeMap::new()).unwrap());
    }
    for (k, (ch, t, data)) in f.messages.iter().enumerate() {
        if ids.is_empty() {
            break;
        }
        w.write_to_known_channel(
            &mcap::records::MessageHeader {
                channel_id: *ch.get(&ids),
                sequence: k as u32,
                log_time: *t,
                publish_time: *t,
            },
            data,
        )
        .unwrap();
    }
    for (name, md) in &f.metadata {
        w.write_metadata(&mcap::records::Metadata {
            name: name.clone(),
            metadata: md.clone(),
        })
        .unwrap();
    }
    for (name, data) in &f.attachments {
        w.attach(&mcap::Attachment {
            log_time: 0,
            create_time: 0,
            name: name.clone(),
            media_type: "application/octet-stream".into(),
            data: Cow::Borrowed(data),
        })
        .unwrap();
    }
    w.finish().unwrap();
    w.into_inner().into_inner()
}

proptest! {
    #![proptest_config(config(100))]

    /// Valid MCAP files without a `flapwing` metadata record: read_summary and check_log
    /// say "not a flapwing log" naming the file; export_csv never panics. Cut in half, the
    /// same (or an MCAP/"not MCAP" error naming the file).
    #[test]
    fn foreign_mcap_files(f in foreign(), cut in any::<Index>()) {
        let bytes = write_foreign(&f);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("other.mcap");
        std::fs::write(&path, &bytes).unwrap();
        let e = guarded("read_summary", || read_summary(&path))?
            .expect_err("a foreign MCAP file read as a flapwing log");
        check_read_error(&e, &path)?;
        prop_assert!(matches!(e, Error::NotFlapwing { .. }), "{e:?}");
        prop_assert!(e.to_string().contains("not a flapwing log"), "{e}");
        let e = guarded("check_log", || check_log(&path))?
            .expect_err("a foreign MCAP file checked");
        check_read_error(&e, &path)?;
        csv_of(&path, "/vehicle/state", &dir.path().join("s.csv"))?;
        // Truncated too.
        let short = dir.path().join("short.mcap");
        std::fs::write(&short, &bytes[..cut.index(bytes.len() + 1)]).unwrap();
        if let Err(e) = guarded("read_summary", || read_summary(&short))? {
            check_read_error(&e, &short)?;
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Real logs with forged `flapwing` metadata (what `replay --check` re-runs).
// ---------------------------------------------------------------------------------------------

/// A second fixture: two wingbeats at 2000 Hz (a few samples), for re-running.
fn small_log() -> &'static Vec<u8> {
    static B: OnceLock<Vec<u8>> = OnceLock::new();
    B.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("small.mcap");
        record(&path, 2.0, Some(2000.0));
        std::fs::read(&path).unwrap()
    })
}

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

#[test]
fn fixtures_are_flapwing_logs() {
    let f = fixture();
    assert!(f.summary.channels.len() >= 5);
    let dir = tempfile::tempdir().unwrap();
    let path: PathBuf = dir.path().join("small.mcap");
    std::fs::write(&path, small_log()).unwrap();
    match check_log(&path).unwrap() {
        CheckOutcome::Match { samples, .. } => assert!(samples > 5),
        other => panic!("{other:?}"),
    }
}
