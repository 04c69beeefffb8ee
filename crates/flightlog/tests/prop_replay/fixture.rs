//! The fixtures: a short drosophila run recorded exactly as `flapwing simulate --mcap` does
//! (six wingbeats logged at every step: several chunks, about 600 samples), and a second,
//! smaller one for re-running (two wingbeats at 2000 Hz); and the test that both are
//! flapwing logs (the small one passes `check_log`).

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use flapsim::{Mode, Simulation, Vehicle};
use flightlog::check::{CheckOutcome, check_log};
use flightlog::replay::{ReplaySummary, read_summary};
use flightlog::{LogOptions, Recorder, RunInfo, SimSettings};

pub(crate) struct Fixture {
    _dir: tempfile::TempDir,
    pub(crate) bytes: Vec<u8>,
    pub(crate) summary: ReplaySummary,
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

/// Thirty wingbeats logged at every step (the fly's 20 steps per wingbeat): several chunks,
/// about 600 samples.
pub(crate) fn fixture() -> &'static Fixture {
    static F: OnceLock<Fixture> = OnceLock::new();
    F.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("full.mcap");
        record(&path, 30.0, None);
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

/// A second fixture: two wingbeats at 2000 Hz (a few samples), for re-running.
pub(crate) fn small_log() -> &'static Vec<u8> {
    static B: OnceLock<Vec<u8>> = OnceLock::new();
    B.get_or_init(|| {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("small.mcap");
        record(&path, 2.0, Some(2000.0));
        std::fs::read(&path).unwrap()
    })
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
