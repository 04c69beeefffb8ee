//! Log outputs of `simulate` and `hover`: the flags, the default file names under `logs/`,
//! and opening the [`flightlog::Recorder`] before the simulation starts (so an unwritable
//! path fails at once, with exit code 2).

use std::path::{Path, PathBuf};

use flightlog::{Level, LogOptions, Recorder, RunInfo};

use crate::error::input_error;
use crate::vehicle::VehicleSource;

/// Log flags shared by the commands that fly a vehicle.
#[derive(Debug, Clone, clap::Args)]
pub struct LogArgs {
    /// Write the MCAP log here (default: logs/<command>-<UTC timestamp>.mcap).
    #[arg(long, value_name = "FILE")]
    pub mcap: Option<PathBuf>,
    /// Write a Rerun recording here (`hover` writes logs/hover-<timestamp>.rrd by default).
    #[arg(long, value_name = "FILE")]
    pub rrd: Option<PathBuf>,
    /// Write no log files at all.
    #[arg(long = "no-log", conflicts_with_all = ["mcap", "rrd"])]
    pub no_log: bool,
    /// Spawn a Rerun viewer (`rerun` on PATH) and stream the run to it.
    #[arg(long)]
    pub spawn: bool,
    /// Stream to a running Rerun viewer at this gRPC URL (e.g. rerun+http://127.0.0.1:9876/proxy).
    #[arg(long, value_name = "URL")]
    pub connect: Option<String>,
    /// Serve the run live to the Foxglove app over its WebSocket protocol (Open connection,
    /// ws://ADDR) while it runs; ADDR is host:port, port 0 picks a free one.
    #[arg(long, value_name = "ADDR", num_args = 0..=1, default_missing_value = "127.0.0.1:8765")]
    pub foxglove: Option<String>,
    /// Log samples per second of simulated time.
    #[arg(
        long = "log-rate-hz",
        default_value_t = 2000.0,
        conflicts_with = "full_rate"
    )]
    pub log_rate_hz: f64,
    /// Log every simulation step.
    #[arg(long = "full-rate")]
    pub full_rate: bool,
    /// Replace existing log files.
    #[arg(long)]
    pub force: bool,
    /// Print `flushed: N samples to t = T s` on stderr each time logged samples reach the
    /// MCAP file, for a supervisor of a run that may be killed: a kill after such a line
    /// leaves a log that `flapwing replay` reads to at least those N samples.
    #[arg(long = "report-flushed")]
    pub report_flushed: bool,
}

/// The current UTC date and time (year, month, day, hour, minute, second), by civil-from-days
/// (H. Hinnant).
pub fn utc_civil_now() -> (i64, i64, i64, i64, i64, i64) {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs())
        .unwrap_or(0) as i64;
    let (days, rem) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    (y, m, d, rem / 3600, rem % 3600 / 60, rem % 60)
}

/// A UTC timestamp `YYYYMMDD-HHMMSS` for default file names.
pub fn utc_stamp() -> String {
    let (y, m, d, hh, mm, ss) = utc_civil_now();
    format!("{y:04}{m:02}{d:02}-{hh:02}{mm:02}{ss:02}")
}

/// A fresh default path `logs/<command>-<stamp>[-k].<ext>` (never an existing file).
fn default_path(command: &str, ext: &str, stamp: &str) -> PathBuf {
    let mut p = PathBuf::from(format!("logs/{command}-{stamp}.{ext}"));
    let mut k = 1;
    while p.exists() {
        p = PathBuf::from(format!("logs/{command}-{stamp}-{k}.{ext}"));
        k += 1;
    }
    p
}

fn check_target(path: &Path, force: bool) -> anyhow::Result<()> {
    if path.is_dir() {
        return Err(input_error(format!(
            "log file `{}` is a directory; give a file name",
            path.display()
        )));
    }
    if path.exists() && !force {
        return Err(input_error(format!(
            "refusing to overwrite the existing log `{}` (pass --force to replace it)",
            path.display()
        )));
    }
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| {
            input_error(format!(
                "cannot create the log folder `{}`: {e}",
                dir.display()
            ))
        })?;
    }
    Ok(())
}

/// The optional channels a run's MCAP log declares.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Channels {
    /// `/sensors/imu` and `/sensors/mocap`.
    pub sensors: bool,
    /// `/wind` (runs with a wind field).
    pub wind: bool,
    /// `/estimate` (runs flown on the state estimate).
    pub estimate: bool,
}

/// Opens the recorder for a run (or `None` with `--no-log`). `rrd_by_default` makes the
/// command write a Rerun recording under `logs/` when `--rrd` is not given; `channels`
/// says which optional channels the MCAP log declares.
pub fn open(
    args: &LogArgs,
    command: &str,
    src: &VehicleSource,
    vehicle: &flapsim::Vehicle,
    settings_json: String,
    rrd_by_default: bool,
    channels: Channels,
) -> anyhow::Result<Option<Recorder>> {
    if !(args.log_rate_hz.is_finite() && args.log_rate_hz > 0.0) {
        return Err(input_error(format!(
            "--log-rate-hz {} is not allowed: a rate > 0",
            args.log_rate_hz
        )));
    }
    // The recorder logs the same warnings as events (flagging the log); say them once here.
    for w in range_warnings(vehicle) {
        crate::output::note(&format!("warning: {w}"));
    }
    if args.no_log && !args.spawn && args.connect.is_none() && args.foxglove.is_none() {
        return Ok(None);
    }
    let stamp = utc_stamp();
    let mcap = if args.no_log {
        None
    } else {
        Some(
            args.mcap
                .clone()
                .unwrap_or_else(|| default_path(command, "mcap", &stamp)),
        )
    };
    let rrd = match (&args.rrd, args.no_log, rrd_by_default) {
        (Some(p), _, _) => Some(p.clone()),
        (None, false, true) => Some(default_path(command, "rrd", &stamp)),
        _ => None,
    };
    // Both outputs are checked together first: one path for both, or the model file.
    let inputs = crate::outputs::model_input(&src.origin);
    let outputs: Vec<crate::outputs::Named<'_>> = [("--mcap", &mcap), ("--rrd", &rrd)]
        .into_iter()
        .filter_map(|(flag, p)| p.as_deref().map(|p| crate::outputs::Named::new(flag, p)))
        .collect();
    crate::outputs::check(&inputs, &outputs, args.force)?;
    for p in mcap.iter().chain(rrd.iter()) {
        check_target(p, args.force)?;
    }
    let options = LogOptions {
        mcap,
        rrd,
        rerun_spawn: args.spawn,
        rerun_connect: args.connect.clone(),
        log_rate_hz: if args.full_rate {
            None
        } else {
            Some(args.log_rate_hz)
        },
        foxglove: args.foxglove.clone(),
        sensors: channels.sensors,
        wind: channels.wind,
        estimate: channels.estimate,
        // A vehicle whose wake answers logs its pairs' inflow states (issue #38).
        inflow: vehicle.inflow_model() == wingforce::InflowModel::Dynamic,
    };
    let command_line = std::env::args().collect::<Vec<_>>().join(" ");
    let info = RunInfo::new(
        command,
        command_line,
        src.text.clone(),
        src.origin.clone(),
        settings_json,
    );
    let rec = Recorder::create(&options, &info, vehicle)
        .map_err(|e| input_error(format!("cannot open the logs: {e}")))?;
    for p in options.mcap.iter().chain(options.rrd.iter()) {
        crate::output::note(&format!("logging to {}", p.display()));
    }
    if let (Some(addr), Some(port)) = (&options.foxglove, rec.foxglove_port()) {
        let host = addr.rsplit_once(':').map_or(addr.as_str(), |(h, _)| h);
        crate::output::note(&format!(
            "serving the run live to Foxglove at ws://{host}:{port}"
        ));
    }
    Ok(Some(rec))
}

/// Warnings about a model outside its coefficient models' fitted ranges (once per run).
pub fn range_warnings(vehicle: &flapsim::Vehicle) -> Vec<String> {
    let mut out = Vec::new();
    for (i, w) in vehicle.wings.iter().enumerate() {
        let side = flapsim::Vehicle::wing_name(i);
        if let Some(p) = w.wake_capture() {
            let f = p.flags;
            if f.any() {
                let (da, dd) = w.kinematics().acceleration_fractions();
                out.push(format!(
                    "{side} wing: wake-capture inputs outside the fitted range (Re {:.1}, dtau_A {:.3}, dtau_D {:.3}; fitted Re 136-6800, dtau 0.06-0.18): clamped{}{}{}",
                    w.reynolds(),
                    da,
                    dd,
                    if f.re_clamped { " Re" } else { "" },
                    if f.dtau_a_clamped { " dtau_A" } else { "" },
                    if f.dtau_d_clamped { " dtau_D" } else { "" },
                ));
            }
        }
    }
    out.dedup_by(|a, b| a[a.find(':').unwrap_or(0)..] == b[b.find(':').unwrap_or(0)..]);
    out
}

/// Records one step of `sim` (`out`, the step's output, copied out of the simulation) with
/// every wing's forces from its wing set, if there is a recorder: any number of wings.
pub fn record_all(
    rec: &mut Option<Recorder>,
    out: &flapsim::StepOutput,
    sim: &flapsim::Simulation,
) -> anyhow::Result<()> {
    if let Some(r) = rec.as_mut() {
        r.record_wings(out, sim.wing_set().output())?;
    }
    Ok(())
}

/// Logs each wing's wind at the step at `t_s` if there is a recorder (see
/// [`Recorder::wind`]): the simulation's per-wing winds, or the uniform wind at every wing
/// when there is no wind field.
pub fn record_wind(
    rec: &mut Option<Recorder>,
    t_s: f64,
    sim: &flapsim::Simulation,
) -> anyhow::Result<()> {
    if let Some(r) = rec.as_mut() {
        let uniform = sim.uniform_wind_m_s();
        let winds = sim.wing_winds_m_s();
        if winds.is_empty() {
            r.wind(t_s, &uniform, &vec![uniform; sim.vehicle().wings.len()])?;
        } else {
            r.wind(t_s, &uniform, winds)?;
        }
    }
    Ok(())
}

/// With `--report-flushed`: says on stderr how much of the run newly reached the MCAP file
/// since the last report (`reported` holds the samples last said).
pub fn report_flushed(rec: &Option<Recorder>, reported: &mut u64) {
    if let Some(f) = rec.as_ref().and_then(Recorder::flushed)
        && f.samples > *reported
    {
        *reported = f.samples;
        crate::output::note(&format!(
            "flushed: {} samples to t = {:.6} s",
            f.samples, f.t_s
        ));
    }
}

/// Ends a run's logs: records why it ended early (divergence as an error event, Ctrl-C as
/// a warning) and finishes the files; then reports a log-writing failure, if any.
pub fn finish(
    rec: Option<Recorder>,
    t_s: f64,
    failure: Option<String>,
    interrupted: bool,
    log_error: Option<anyhow::Error>,
) -> anyhow::Result<()> {
    if let Some(mut r) = rec {
        match (&failure, interrupted && log_error.is_none()) {
            (Some(why), _) => r.event(t_s, Level::Error, why)?,
            (None, true) => r.event(t_s, Level::Warning, "interrupted (Ctrl-C)")?,
            _ => {}
        }
        r.finish()?;
    }
    match log_error {
        Some(e) => Err(e.context("writing the log failed")),
        None => Ok(()),
    }
}
