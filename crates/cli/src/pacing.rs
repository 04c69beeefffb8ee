//! Watching a run live (`simulate`, `hover`): `--realtime FACTOR` paces the simulation to
//! the wall clock, and `--wait-for-client` holds the run until a Foxglove client watches.
//!
//! The pacer sleeps against a schedule fixed at the first step (simulated time since then,
//! divided by the factor, against the wall time elapsed since then), so oversleeping and
//! slow steps never add up: a step that is late runs at once and the next ones catch up.
//! It only ever slows a run, and without `--realtime` there is no pacer at all.

use std::time::{Duration, Instant};

use flightlog::{LiveWait, Recorder};

use crate::error::input_error;

/// Pacing flags shared by the commands that fly a vehicle.
#[derive(Debug, Clone, clap::Args)]
pub struct PaceArgs {
    /// Pace the run to FACTOR simulated seconds per wall-clock second (1 is real time, 0.01
    /// is 100 times slower, to watch the wings flap in a live view); default: unpaced.
    /// Allowed: a finite FACTOR > 0 whose paced run lasts at most 24 h of wall-clock time
    /// (FACTOR >= duration / 86400 s: 1.16e-5 for a 1 s run).
    #[arg(long, value_name = "FACTOR")]
    pub realtime: Option<f64>,
    /// With --foxglove: before the run, wait until a Foxglove client has connected and
    /// subscribed to a channel (Ctrl-C stops waiting and the run).
    #[arg(long = "wait-for-client", requires = "foxglove")]
    pub wait_for_client: bool,
    /// With --wait-for-client: start the run anyway after this many wall-clock seconds.
    #[arg(
        long = "wait-timeout-s",
        value_name = "SECONDS",
        requires = "wait_for_client"
    )]
    pub wait_timeout_s: Option<f64>,
}

/// The longest wall-clock time a paced run may take, s (24 h): `--realtime` is for
/// watching a run, and a factor that would stretch it past a day is a typo (`1e-300` for
/// `1e-3`), not a view anyone watches. The smallest factor is the run's duration over this.
pub const MAX_PACED_WALL_S: f64 = 86_400.0;

/// Sleeps shorter than this are skipped (the step runs up to this much early).
const MIN_SLEEP_S: f64 = 0.001;
/// Longest single sleep, so that Ctrl-C is noticed within it.
const MAX_SLEEP_S: f64 = 0.05;

/// Holds a run to `factor` simulated seconds per wall-clock second.
#[derive(Debug, Clone)]
pub struct Pacer {
    factor: f64,
    /// The wall clock and simulated time of the first step.
    start: Option<(Instant, f64)>,
}

impl Pacer {
    /// A pacer at `factor` (finite, > 0; checked by [`check`]).
    fn new(factor: f64) -> Self {
        Self {
            factor,
            start: None,
        }
    }

    /// Waits until the wall clock reaches the time of the step at simulated time `t_s`
    /// (the first call fixes the schedule and returns at once). Returns early once Ctrl-C
    /// was pressed.
    pub fn pace(&mut self, t_s: f64) {
        self.pace_with(t_s, crate::interrupt::requested);
    }

    fn pace_with(&mut self, t_s: f64, cancelled: impl Fn() -> bool) {
        let (start, t0) = *self.start.get_or_insert_with(|| (Instant::now(), t_s));
        let due_s = (t_s - t0) / self.factor;
        loop {
            let ahead_s = due_s - start.elapsed().as_secs_f64();
            // A NaN schedule (it cannot happen with a checked factor) never sleeps.
            if ahead_s.is_nan() || ahead_s < MIN_SLEEP_S || cancelled() {
                return;
            }
            std::thread::sleep(Duration::from_secs_f64(ahead_s.min(MAX_SLEEP_S)));
        }
    }
}

/// Paces the step at `t_s` if the run is paced.
pub fn pace(pacer: &mut Option<Pacer>, t_s: f64) {
    if let Some(p) = pacer {
        p.pace(t_s);
    }
}

/// Checks the flags (before anything is opened) for a run of `duration_s` simulated seconds
/// and returns the run's pacer (`None` without `--realtime`).
pub fn check(args: &PaceArgs, duration_s: f64) -> anyhow::Result<Option<Pacer>> {
    if let Some(t) = args.wait_timeout_s
        && !(t.is_finite() && t >= 0.0)
    {
        return Err(input_error(format!(
            "--wait-timeout-s {t} is not allowed: a finite number of seconds >= 0"
        )));
    }
    let min_factor = duration_s / MAX_PACED_WALL_S;
    match args.realtime {
        None => Ok(None),
        Some(f) if f.is_finite() && f > 0.0 && duration_s / f <= MAX_PACED_WALL_S => {
            Ok(Some(Pacer::new(f)))
        }
        Some(f) if f.is_finite() && f > 0.0 => Err(input_error(format!(
            "--realtime {} is not allowed: it would pace the {duration_s} s run over {:.3e} s \
             of wall-clock time; a paced run lasts at most {MAX_PACED_WALL_S} s (24 h), so the \
             factor must be >= {min_factor:.3e} (the duration over 24 h)",
            shown(f),
            duration_s / f
        ))),
        Some(f) => Err(input_error(format!(
            "--realtime {f} is not allowed: a finite factor > 0 (simulated seconds per \
             wall-clock second: 1 is real time, 0.01 is 100 times slower) and >= \
             {min_factor:.3e} (the run's duration over 24 h)"
        ))),
    }
}

/// A factor as the user would write it: `1e-300` rather than three hundred zeros.
fn shown(f: f64) -> String {
    if f != 0.0 && !(1e-4..1e6).contains(&f.abs()) {
        format!("{f:e}")
    } else {
        f.to_string()
    }
}

/// With `--wait-for-client`, blocks until a client of the run's live Foxglove server has
/// subscribed to a channel, saying on stderr that it waits and where. `foxglove` is the
/// `--foxglove` address (for the host in the URL). After Ctrl-C it returns at once and the
/// run stops at its first step.
pub fn wait_for_client(
    args: &PaceArgs,
    foxglove: Option<&str>,
    rec: Option<&Recorder>,
) -> anyhow::Result<()> {
    if !args.wait_for_client {
        return Ok(());
    }
    let (Some(addr), Some(port)) = (foxglove, rec.and_then(Recorder::foxglove_port)) else {
        return Ok(());
    };
    let host = addr.rsplit_once(':').map_or(addr, |(h, _)| h);
    let url = format!("ws://{host}:{port}");
    crate::output::note(&format!(
        "waiting for a Foxglove client at {url} to connect and subscribe (Open connection in \
         the Foxglove app; Ctrl-C to stop)"
    ));
    let timeout = args.wait_timeout_s.map(Duration::from_secs_f64);
    let Some(rec) = rec else {
        return Ok(());
    };
    match rec.wait_for_live_client(timeout, crate::interrupt::requested) {
        LiveWait::Subscribed => crate::output::note("a Foxglove client subscribed; running"),
        LiveWait::TimedOut { connected } => crate::output::note(&format!(
            "no Foxglove client subscribed within {} s{}; running anyway",
            args.wait_timeout_s.unwrap_or_default(),
            if connected {
                " (a client connected but subscribed to nothing)"
            } else {
                ""
            }
        )),
        LiveWait::Cancelled => {}
        LiveWait::NoServer => {
            return Err(anyhow::anyhow!(
                "internal: no live Foxglove server on port {port} to wait on"
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(realtime: Option<f64>, wait_timeout_s: Option<f64>) -> PaceArgs {
        PaceArgs {
            realtime,
            wait_for_client: false,
            wait_timeout_s,
        }
    }

    #[test]
    fn checks_the_factor() {
        assert!(check(&args(None, None), 1.0).unwrap().is_none());
        assert!(check(&args(Some(0.01), Some(0.0)), 1.0).unwrap().is_some());
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let e = check(&args(Some(bad), None), 1.0).unwrap_err();
            assert_eq!(crate::error::exit_code(&e), crate::error::EXIT_BAD_INPUT);
            let text = e.to_string();
            assert!(
                text.contains("--realtime") && text.contains("> 0"),
                "{text}"
            );
        }
        let e = check(&args(None, Some(-1.0)), 1.0).unwrap_err().to_string();
        assert!(e.contains("--wait-timeout-s -1"), "{e}");
    }

    #[test]
    fn bounds_the_paced_wall_time() {
        // A 1 s run may be paced over at most a day: factor 1/86400 is the slowest.
        let slowest = 1.0 / MAX_PACED_WALL_S;
        assert!(check(&args(Some(slowest), None), 1.0).unwrap().is_some());
        for (factor, duration_s) in [(1e-300, 1.0), (slowest * 0.99, 1.0), (1e-3, 100.0)] {
            let e = check(&args(Some(factor), None), duration_s).unwrap_err();
            assert_eq!(crate::error::exit_code(&e), crate::error::EXIT_BAD_INPUT);
            let text = e.to_string();
            assert!(
                text.contains(&format!("--realtime {}", shown(factor))) && text.contains("24 h"),
                "{text}"
            );
        }
    }

    #[test]
    fn follows_the_wall_clock_without_drift() {
        // 0.2 simulated seconds at factor 2: 0.1 s of wall time, in 1000 steps whose sleeps
        // (each below the minimum) would be lost if they were not measured from the start.
        let mut p = Pacer::new(2.0);
        let start = Instant::now();
        for k in 0..=1000 {
            p.pace_with(0.5 + f64::from(k) * 2e-4, || false);
        }
        let wall = start.elapsed().as_secs_f64();
        assert!(wall >= 0.1 - MIN_SLEEP_S, "{wall}");
    }

    #[test]
    fn stops_waiting_when_cancelled() {
        let mut p = Pacer::new(1e-9);
        p.pace_with(0.0, || true);
        let start = Instant::now();
        p.pace_with(1.0, || true);
        assert!(start.elapsed() < Duration::from_secs(1));
    }
}
