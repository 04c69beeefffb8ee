//! What a log is told about its run: the run's identity ([`RunInfo`]), the logging options
//! ([`LogOptions`]), the simulation settings stored in the metadata ([`SimSettings`]) and
//! the levels of log messages ([`Level`]). Plain types below the recorder, the replay and the
//! sinks, which all take them.

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::json;

/// What produced a log: written into the MCAP `flapwing` metadata record.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct RunInfo {
    /// The CLI subcommand: "simulate", "hover", "forces", ... "simulate" and "hover" logs
    /// can be re-run by [`check::check_log`] (a hover on the state estimate when its sensors'
    /// seed is logged).
    pub command: String,
    /// The full command line, for people reading the log.
    pub command_line: String,
    /// The vehicle model file's full text (re-run by [`check::check_log`]).
    pub model_toml: String,
    /// Where the model came from (a path or a built-in name); appears in error messages.
    pub model_origin: String,
    /// The run settings as JSON: for "simulate" a [`SimSettings`] ([`SimSettings::to_json`]).
    pub settings_json: String,
}

impl RunInfo {
    /// All fields at once.
    pub fn new(
        command: impl Into<String>,
        command_line: impl Into<String>,
        model_toml: impl Into<String>,
        model_origin: impl Into<String>,
        settings_json: impl Into<String>,
    ) -> Self {
        Self {
            command: command.into(),
            command_line: command_line.into(),
            model_toml: model_toml.into(),
            model_origin: model_origin.into(),
            settings_json: settings_json.into(),
        }
    }
}

/// Where and how often to record.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LogOptions {
    /// Write an MCAP file here (replaced if it exists: callers decide about overwriting).
    pub mcap: Option<PathBuf>,
    /// Write a Rerun recording (.rrd) here (needs the `rerun` feature).
    pub rrd: Option<PathBuf>,
    /// Spawn a Rerun viewer (`rerun` on PATH) and stream to it (needs the `rerun` feature).
    pub rerun_spawn: bool,
    /// Stream to a running Rerun viewer at this gRPC URL, e.g.
    /// `rerun+http://127.0.0.1:9876/proxy` (needs the `rerun` feature).
    pub rerun_connect: Option<String>,
    /// Samples per second of simulated time; `None` logs every step. The CLI default is
    /// 2000 Hz (about 9 samples per drosophila wingbeat). See [`Decimator`].
    pub log_rate_hz: Option<f64>,
    /// Serve the run live over the Foxglove WebSocket protocol at this `host:port` (port 0:
    /// any free port, see [`Recorder::foxglove_port`]; needs the `live` feature).
    pub foxglove: Option<String>,
    /// Declare the sensor channels ([`schema::SENSOR_CHANNELS`]: `/sensors/imu`,
    /// `/sensors/mocap`) in the MCAP log, for [`Recorder::sensor`].
    pub sensors: bool,
    /// Declare the wind channel ([`schema::WIND_CHANNEL`]: `/wind`) in the MCAP log, for
    /// [`Recorder::wind`] (runs with a wind field).
    pub wind: bool,
    /// Declare the estimate channel ([`schema::ESTIMATE_CHANNEL`]: `/estimate`) in the MCAP
    /// log, for [`Recorder::estimate`] (runs flown on a state estimate).
    pub estimate: bool,
    /// Declare the induced-flow channel ([`schema::INFLOW_CHANNEL`]: `/inflow`) in the MCAP
    /// log, for [`Recorder::inflow`] (vehicles whose wake answers).
    pub inflow: bool,
}

impl LogOptions {
    /// True when at least one output is asked for.
    pub fn any(&self) -> bool {
        self.mcap.is_some()
            || self.rrd.is_some()
            || self.rerun_spawn
            || self.rerun_connect.is_some()
            || self.foxglove.is_some()
    }
}

/// The settings of a `simulate` run, stored as JSON in the metadata key `settings` so that
/// `flapwing replay --check` can re-run it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SimSettings {
    /// "free", "tethered" or "longitudinal" (see [`SimSettings::mode_value`]).
    pub mode: String,
    /// Simulated duration, s (rounded to whole steps by [`flapsim::Simulation::run_for`]).
    pub duration_s: f64,
    /// The log rate, Hz (`None`: every step).
    pub log_rate_hz: Option<f64>,
    /// Uniform wind, world frame, m/s ([`flapsim::Simulation::set_wind`]).
    pub wind_world_m_s: [f64; 3],
}

impl SimSettings {
    /// Settings for `mode` (any [`flapsim::Mode::Locked`] other than
    /// [`flapsim::Mode::LONGITUDINAL`] is stored as "locked" and cannot be re-run).
    pub fn new(
        mode: flapsim::Mode,
        duration_s: f64,
        log_rate_hz: Option<f64>,
        wind_world_m_s: [f64; 3],
    ) -> Self {
        Self {
            mode: mode_name(mode).to_owned(),
            duration_s,
            log_rate_hz,
            wind_world_m_s,
        }
    }

    /// The JSON text stored in the metadata.
    pub fn to_json(&self) -> String {
        // Plain data: serialization cannot fail (non-finite numbers become null).
        serde_json::to_string(self).unwrap_or_default()
    }

    /// Parses the metadata text. Numbers are read with a correctly rounded parser, so they
    /// come back bit for bit (serde_json's default float parsing may not).
    pub fn from_json(text: &str) -> Result<Self> {
        let bad = |why: &str| {
            Error::Embedded(format!(
                "the `settings` metadata is not SimSettings JSON ({why}): {text}"
            ))
        };
        let v = json::parse(text.as_bytes()).map_err(|e| bad(&e))?;
        let mode = v
            .get("mode")
            .and_then(json::Json::as_str)
            .ok_or_else(|| bad("no string `mode`"))?
            .to_owned();
        let duration_s = v
            .f64_at("duration_s")
            .ok_or_else(|| bad("no number `duration_s`"))?;
        let log_rate_hz = match v.get("log_rate_hz") {
            None | Some(json::Json::Null) => None,
            Some(r) => Some(
                r.as_f64()
                    .ok_or_else(|| bad("`log_rate_hz` is not a number"))?,
            ),
        };
        let wind = match v.get("wind_world_m_s") {
            Some(json::Json::Arr(a)) if a.len() == 3 => {
                let mut w = [0.0; 3];
                for (o, x) in w.iter_mut().zip(a) {
                    *o = x
                        .as_f64()
                        .ok_or_else(|| bad("`wind_world_m_s` is not 3 numbers"))?;
                }
                w
            }
            _ => return Err(bad("`wind_world_m_s` is not 3 numbers")),
        };
        Ok(Self {
            mode,
            duration_s,
            log_rate_hz,
            wind_world_m_s: wind,
        })
    }

    /// The mode as flapsim's enum.
    pub fn mode_value(&self) -> Result<flapsim::Mode> {
        match self.mode.as_str() {
            "free" => Ok(flapsim::Mode::Free),
            "tethered" => Ok(flapsim::Mode::Tethered),
            "longitudinal" => Ok(flapsim::Mode::LONGITUDINAL),
            other => Err(Error::Embedded(format!(
                "unknown simulation mode `{other}` in the settings (free, tethered or longitudinal)"
            ))),
        }
    }
}

/// "free", "tethered", "longitudinal" or "locked".
pub fn mode_name(mode: flapsim::Mode) -> &'static str {
    match mode {
        flapsim::Mode::Free => "free",
        flapsim::Mode::Tethered => "tethered",
        m if m == flapsim::Mode::LONGITUDINAL => "longitudinal",
        flapsim::Mode::Locked { .. } => "locked",
    }
}

/// Severity of a run event (the `level` integer of `foxglove.Log`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Level {
    /// 1.
    Debug = 1,
    /// 2.
    Info = 2,
    /// 3: e.g. a wake-capture input outside its fitted range.
    Warning = 3,
    /// 4: e.g. divergence.
    Error = 4,
    /// 5.
    Fatal = 5,
}

impl Level {
    /// From the foxglove.Log integer (unknown values give `None`).
    pub fn from_int(level: i64) -> Option<Self> {
        Some(match level {
            1 => Level::Debug,
            2 => Level::Info,
            3 => Level::Warning,
            4 => Level::Error,
            5 => Level::Fatal,
            _ => return None,
        })
    }

    /// "DEBUG", "INFO", "WARNING", "ERROR", "FATAL".
    pub fn name(self) -> &'static str {
        match self {
            Level::Debug => "DEBUG",
            Level::Info => "INFO",
            Level::Warning => "WARNING",
            Level::Error => "ERROR",
            Level::Fatal => "FATAL",
        }
    }
}
