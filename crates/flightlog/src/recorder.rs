//! The recorder: one object that writes a run to MCAP and/or Rerun.

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use flapsim::{Controls, StepOutput, Vehicle};
use mcap::records::{MessageHeader, Metadata};
use mcap::{Attachment, Compression, WriteOptions, Writer};

use crate::messages::{self, WingStatic};
use crate::schema::{self, CHANNELS, MESSAGE_ENCODING, SCHEMA_ENCODING};
use crate::{Error, Level, LogOptions, Result, RunInfo};

/// Close the current chunk (so a killed run keeps it) at least this often, simulated time.
const FLUSH_INTERVAL_NS: u64 = 50_000_000;
/// Target uncompressed chunk size, bytes.
const CHUNK_SIZE: u64 = 512 * 1024;
/// Index of the /events channel in [`CHANNELS`].
const EVENTS: usize = 10;

/// Picks the steps to log: with a rate `r`, step k (time t_k) is logged when
/// `floor(t_k r)` differs from that of the last logged step (the first step is always
/// logged), so samples are at most one step late on a grid of 1/r seconds. With no rate,
/// every step is logged. `flapwing replay --check` uses the same rule.
#[derive(Debug, Clone, PartialEq)]
pub struct Decimator {
    rate_hz: Option<f64>,
    last_bucket: Option<i64>,
}

impl Decimator {
    /// A decimator for `rate_hz` (`None`: every step).
    pub fn new(rate_hz: Option<f64>) -> Self {
        Self {
            rate_hz,
            last_bucket: None,
        }
    }

    /// True when the step at `t_s` is to be logged (call once per step, in order).
    pub fn take(&mut self, t_s: f64) -> bool {
        let Some(rate) = self.rate_hz else {
            return true;
        };
        let b = (t_s * rate).floor();
        let bucket = if b.is_finite() { b as i64 } else { i64::MIN };
        if self.last_bucket == Some(bucket) {
            false
        } else {
            self.last_bucket = Some(bucket);
            true
        }
    }
}

/// What a finished recording holds.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize)]
pub struct LogStats {
    /// Steps handed to [`Recorder::record`].
    pub steps_seen: u64,
    /// Steps logged after decimation.
    pub samples: u64,
    /// MCAP messages written (all channels, events included).
    pub mcap_messages: u64,
    /// Events written.
    pub events: u64,
    /// The MCAP file, if any.
    pub mcap_path: Option<PathBuf>,
    /// Its size, bytes.
    pub mcap_bytes: u64,
    /// The .rrd file, if any.
    pub rrd_path: Option<PathBuf>,
    /// Time of the last logged sample, s.
    pub last_t_s: f64,
}

struct McapSink {
    writer: Writer<BufWriter<File>>,
    path: PathBuf,
    channel_ids: [u16; 11],
    sequences: [u32; 11],
    last_flush_ns: u64,
}

impl McapSink {
    fn write(&mut self, index: usize, t_ns: u64, data: &[u8]) -> Result<()> {
        let header = MessageHeader {
            channel_id: self.channel_ids[index],
            sequence: self.sequences[index],
            log_time: t_ns,
            publish_time: t_ns,
        };
        self.sequences[index] = self.sequences[index].wrapping_add(1);
        self.writer.write_to_known_channel(&header, data)?;
        Ok(())
    }
}

/// Records a run to MCAP and/or Rerun.
///
/// Create it with [`Recorder::create`] before the run, feed it every step with
/// [`Recorder::record`], report warnings and errors with [`Recorder::event`], and **call
/// [`Recorder::finish`]**, also after a divergence or Ctrl-C: it writes the MCAP summary
/// (without it the file is still readable up to its last complete chunk, see
/// [`crate::replay`]) and the Rerun footer. Dropping an unfinished recorder finishes it as a
/// best effort and ignores errors.
pub struct Recorder {
    mcap: Option<McapSink>,
    #[cfg(feature = "rerun")]
    rerun: Option<crate::rerun_sink::RerunSink>,
    rrd_path: Option<PathBuf>,
    decimator: Decimator,
    wings: [WingStatic; 2],
    weight_n: f64,
    vehicle: Vehicle,
    controls: Option<Controls>,
    wake_warned: [bool; 2],
    stats: LogStats,
    finished: bool,
}

impl std::fmt::Debug for Recorder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Recorder")
            .field("mcap", &self.mcap.as_ref().map(|m| &m.path))
            .field("rrd", &self.rrd_path)
            .field("decimator", &self.decimator)
            .field("stats", &self.stats)
            .finish_non_exhaustive()
    }
}

fn attachment_name(origin: &str) -> String {
    Path::new(origin)
        .file_name()
        .and_then(|n| n.to_str())
        .filter(|n| n.ends_with(".toml"))
        .unwrap_or("model.toml")
        .to_owned()
}

impl Recorder {
    /// Opens every output in `options` (files are created now, so a bad path fails before
    /// the run) and writes the run's metadata, the model attachment and the channel
    /// definitions. With no output asked for, returns a recorder that records nothing.
    ///
    /// Errors: an invalid `log_rate_hz` (not finite and > 0), an unwritable path, a Rerun
    /// option without the `rerun` feature, no Rerun viewer to spawn or connect to.
    pub fn create(options: &LogOptions, info: &RunInfo, vehicle: &Vehicle) -> Result<Self> {
        if let Some(r) = options.log_rate_hz
            && !(r.is_finite() && r > 0.0)
        {
            return Err(Error::Options(format!(
                "log rate {r} Hz is not allowed: a finite rate > 0 is required"
            )));
        }
        #[cfg(not(feature = "rerun"))]
        if options.rrd.is_some() || options.rerun_spawn || options.rerun_connect.is_some() {
            return Err(Error::Options(
                "Rerun output needs flightlog's `rerun` feature, which this build lacks".into(),
            ));
        }
        let wings = [0, 1].map(|i| {
            let w = &vehicle.wings[i];
            WingStatic {
                side: w.mount().side,
                hinge_in_body_m: w.mount().hinge_in_body_m,
                body_from_stroke: *w.body_from_stroke(),
            }
        });
        let mut rec = Recorder {
            mcap: None,
            #[cfg(feature = "rerun")]
            rerun: None,
            rrd_path: options.rrd.clone(),
            decimator: Decimator::new(options.log_rate_hz),
            wings,
            weight_n: vehicle.weight_n(),
            vehicle: vehicle.clone(),
            controls: None,
            wake_warned: [false; 2],
            stats: LogStats {
                mcap_path: options.mcap.clone(),
                rrd_path: options.rrd.clone(),
                ..LogStats::default()
            },
            finished: false,
        };
        // Viewers first (they fail most often), then files; on failure remove what was
        // created so a failed start leaves nothing behind.
        #[cfg(feature = "rerun")]
        {
            rec.rerun = crate::rerun_sink::RerunSink::open(options, vehicle)?;
        }
        if let Some(path) = &options.mcap {
            match open_mcap(path, info, vehicle, options.log_rate_hz) {
                Ok(m) => rec.mcap = Some(m),
                Err(e) => {
                    #[cfg(feature = "rerun")]
                    if let Some(r) = rec.rerun.take() {
                        let _ = r.finish();
                        if let Some(rrd) = &options.rrd {
                            let _ = std::fs::remove_file(rrd);
                        }
                    }
                    rec.finished = true;
                    return Err(e);
                }
            }
        }
        rec.check_wake_capture(0.0)?;
        Ok(rec)
    }

    /// Warns (once per wing until it changes back) when a wing's wake-capture inputs lie
    /// outside the fitted range of the regressions.
    fn check_wake_capture(&mut self, t_s: f64) -> Result<()> {
        for i in 0..2 {
            let flags = self.vehicle.wings[i]
                .wake_capture()
                .map(|p| p.flags)
                .unwrap_or_default();
            let out = flags.any();
            if out && !self.wake_warned[i] {
                let w = &self.vehicle.wings[i];
                let (da, dd) = w.kinematics().acceleration_fractions();
                let mut what = Vec::new();
                if flags.re_clamped {
                    what.push(format!("Re = {:.0}", w.reynolds()));
                }
                if flags.dtau_a_clamped {
                    what.push(format!("dtau_A = {da:.3}"));
                }
                if flags.dtau_d_clamped {
                    what.push(format!("dtau_D = {dd:.3}"));
                }
                let side = if i == 0 { "left" } else { "right" };
                self.event(
                    t_s,
                    Level::Warning,
                    &format!(
                        "{side} wing: wake-capture input outside its fitted range ({}); the regressions use the nearest fitted value",
                        what.join(", ")
                    ),
                )?;
            }
            self.wake_warned[i] = out;
        }
        Ok(())
    }

    /// Takes one step's output; logs it if the decimation picks it.
    pub fn record(&mut self, out: &StepOutput) -> Result<()> {
        self.stats.steps_seen += 1;
        if self.controls != Some(out.controls) {
            if self.controls.is_some() && self.vehicle.apply_controls(&out.controls).is_ok() {
                self.check_wake_capture(out.t_s)?;
            }
            self.controls = Some(out.controls);
        }
        if !self.decimator.take(out.t_s) {
            return Ok(());
        }
        let sample = messages::sample(out, &self.wings, self.weight_n)?;
        if let Some(m) = &mut self.mcap {
            for (index, data) in &sample.messages {
                m.write(*index, sample.t_ns, data)?;
                self.stats.mcap_messages += 1;
            }
            if sample.t_ns.saturating_sub(m.last_flush_ns) >= FLUSH_INTERVAL_NS {
                m.writer.flush()?;
                m.last_flush_ns = sample.t_ns;
            }
        }
        #[cfg(feature = "rerun")]
        if let Some(r) = &self.rerun {
            r.frame(&sample.frame)?;
        }
        self.stats.samples += 1;
        self.stats.last_t_s = out.t_s;
        Ok(())
    }

    /// Logs a run event (a `foxglove.Log` on /events, a Rerun TextLog) at simulation time
    /// `t_s`, and closes the current MCAP chunk so the event survives a crash.
    pub fn event(&mut self, t_s: f64, level: Level, message: &str) -> Result<()> {
        let t_ns = messages::time_ns(t_s);
        if let Some(m) = &mut self.mcap {
            let data = messages::log_message(t_ns, level as u8, message)?;
            m.write(EVENTS, t_ns, &data)?;
            m.writer.flush()?;
            self.stats.mcap_messages += 1;
        }
        #[cfg(feature = "rerun")]
        if let Some(r) = &self.rerun {
            r.event(t_ns, level, message)?;
        }
        self.stats.events += 1;
        Ok(())
    }

    /// What has been recorded so far.
    pub fn stats(&self) -> &LogStats {
        &self.stats
    }

    /// Finishes every output: writes the `flapwing.end` metadata, the MCAP summary and
    /// footer, and the Rerun footer; flushes the files. Call it at the end of every run,
    /// including after an error.
    pub fn finish(mut self) -> Result<LogStats> {
        self.finish_inner()
    }

    fn finish_inner(&mut self) -> Result<LogStats> {
        if self.finished {
            return Ok(self.stats.clone());
        }
        self.finished = true;
        let mut first_error = None;
        if let Some(mut m) = self.mcap.take() {
            let end = BTreeMap::from([
                ("steps_seen".to_owned(), self.stats.steps_seen.to_string()),
                ("samples".to_owned(), self.stats.samples.to_string()),
                ("messages".to_owned(), self.stats.mcap_messages.to_string()),
                ("events".to_owned(), self.stats.events.to_string()),
                ("last_t_s".to_owned(), self.stats.last_t_s.to_string()),
            ]);
            let res = (|| -> Result<u64> {
                m.writer.write_metadata(&Metadata {
                    name: schema::METADATA_END.into(),
                    metadata: end,
                })?;
                m.writer.finish()?;
                let mut file = m
                    .writer
                    .into_inner()
                    .into_inner()
                    .map_err(|e| Error::io("cannot write", &m.path, e.into_error()))?;
                file.flush()
                    .map_err(|e| Error::io("cannot write", &m.path, e))?;
                let len = file
                    .metadata()
                    .map_err(|e| Error::io("cannot write", &m.path, e))?
                    .len();
                Ok(len)
            })();
            match res {
                Ok(len) => self.stats.mcap_bytes = len,
                Err(e) => first_error = Some(e),
            }
        }
        #[cfg(feature = "rerun")]
        if let Some(r) = self.rerun.take()
            && let Err(e) = r.finish()
            && first_error.is_none()
        {
            first_error = Some(e);
        }
        match first_error {
            Some(e) => Err(e),
            None => Ok(self.stats.clone()),
        }
    }
}

impl Drop for Recorder {
    /// Best-effort finish; errors are ignored (call [`Recorder::finish`] to see them).
    fn drop(&mut self) {
        let _ = self.finish_inner();
    }
}

fn open_mcap(
    path: &Path,
    info: &RunInfo,
    vehicle: &Vehicle,
    log_rate_hz: Option<f64>,
) -> Result<McapSink> {
    let file = File::create(path).map_err(|e| Error::io("cannot create", path, e))?;
    let mut writer = WriteOptions::new()
        .compression(Some(Compression::Zstd))
        // Level 1: about half the CPU of zstd's default level 3 for a few percent more bytes;
        // logging must not slow the simulation much (see the logging benchmark).
        .compression_level(1)
        .compression_threads(0)
        .chunk_size(Some(CHUNK_SIZE))
        .library(format!("flapwing-flightlog/{}", env!("CARGO_PKG_VERSION")))
        .create(BufWriter::new(file))?;
    let metadata = BTreeMap::from([
        ("version".to_owned(), env!("CARGO_PKG_VERSION").to_owned()),
        ("command".to_owned(), info.command.clone()),
        ("command_line".to_owned(), info.command_line.clone()),
        ("model_toml".to_owned(), info.model_toml.clone()),
        ("model_origin".to_owned(), info.model_origin.clone()),
        ("settings".to_owned(), info.settings_json.clone()),
        ("vehicle".to_owned(), vehicle.name.clone()),
        (
            "log_rate_hz".to_owned(),
            log_rate_hz.map_or_else(|| "every step".to_owned(), |r| r.to_string()),
        ),
        (
            "dt_s".to_owned(),
            (1.0 / (vehicle.freq_hz() * vehicle.sim.steps_per_wingbeat as f64)).to_string(),
        ),
        ("weight_n".to_owned(), vehicle.weight_n().to_string()),
        ("wing_frame".to_owned(), schema::wing_frame_doc().to_owned()),
    ]);
    writer.write_metadata(&Metadata {
        name: schema::METADATA_RUN.into(),
        metadata,
    })?;
    writer.attach(&Attachment {
        log_time: 0,
        create_time: 0,
        name: attachment_name(&info.model_origin),
        media_type: "application/toml".into(),
        data: Cow::Borrowed(info.model_toml.as_bytes()),
    })?;
    let mut channel_ids = [0u16; 11];
    for (i, (topic, schema_name)) in CHANNELS.iter().enumerate() {
        let text = schema::schema_text(schema_name).unwrap_or_default();
        let schema_id = writer.add_schema(schema_name, SCHEMA_ENCODING, text.as_bytes())?;
        channel_ids[i] =
            writer.add_channel(schema_id, topic, MESSAGE_ENCODING, &BTreeMap::new())?;
    }
    // The channel definitions get a chunk of their own right away.
    writer.flush()?;
    Ok(McapSink {
        writer,
        path: path.to_owned(),
        channel_ids,
        sequences: [0; 11],
        last_flush_ns: 0,
    })
}
