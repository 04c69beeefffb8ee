//! Reading flapwing MCAP logs: summaries, CSV export and (feature `rerun`) conversion to a
//! Rerun recording.
//!
//! Files are scanned record by record from the start, the way a killed run left them: each
//! chunk is decompressed and CRC-checked whole and kept only if all of it is good, and the
//! scan stops at the first incomplete or damaged record. A complete file (summary section
//! and closing magic present) is read the same way. A truncated file therefore yields every
//! message of every complete chunk before the cut, and [`ReplaySummary::damage`] says what
//! was lost. A file that is not MCAP, or MCAP without the `flapwing` metadata record, is an
//! error. Nothing here panics on any input.

use std::collections::{BTreeMap, HashMap};
use std::fmt;
use std::io::Write;
use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::json::Json;
use crate::schema::{self, TOPIC_EVENTS, TOPIC_FORCES_LEFT, TOPIC_FORCES_RIGHT, TOPIC_STATE};
use crate::{Error, Level, Result, SimSettings};

pub use crate::read::{AttachmentSummary, ChannelSummary, linear_records};
use crate::read::{LogFile, read_log};

/// A run event (from /events).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EventSummary {
    /// Simulation time, s.
    pub t_s: f64,
    /// Level name (DEBUG, INFO, WARNING, ERROR, FATAL; UNKNOWN otherwise).
    pub level: String,
    /// The message.
    pub message: String,
}

/// Cycle-mean loads over the complete wingbeats of the log.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CycleMean {
    /// Complete wingbeats averaged (the one in progress at the end is left out, as in
    /// flapsim's `SummaryBuilder`).
    pub wingbeats: u64,
    /// Mean of both wings' total aerodynamic force, body frame, N (from /wing/*/forces).
    pub force_body_n: [f64; 3],
    /// Mean of their moment about the centre of mass, body frame, N m.
    pub moment_body_nm: [f64; 3],
    /// Mean world-vertical applied force over the weight (from /vehicle/state).
    pub lift_over_weight: Option<f64>,
}

/// What a log holds.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ReplaySummary {
    /// The file.
    pub path: PathBuf,
    /// Its size, bytes.
    pub file_bytes: u64,
    /// True when the file is whole: data end, summary section and closing magic present.
    pub complete: bool,
    /// What was lost, for a truncated or damaged file.
    pub damage: Option<String>,
    /// Messages read (all channels).
    pub message_count: u64,
    /// First and last message time, s.
    pub start_s: f64,
    /// Last message time, s.
    pub end_s: f64,
    /// `end_s - start_s`.
    pub duration_s: f64,
    /// Every channel, by topic.
    pub channels: Vec<ChannelSummary>,
    /// The `flapwing` metadata record (version, command, command_line, model_toml,
    /// model_origin, settings, ...).
    pub metadata: BTreeMap<String, String>,
    /// The `flapwing.end` record written by `Recorder::finish` (absent if the run was killed).
    pub end_metadata: Option<BTreeMap<String, String>>,
    /// Attachments.
    pub attachments: Vec<AttachmentSummary>,
    /// Run events, in time order.
    pub events: Vec<EventSummary>,
    /// /vehicle/state samples.
    pub samples: u64,
    /// Cycle means (`None` without a complete wingbeat).
    pub cycle_mean: Option<CycleMean>,
    /// Largest distance from the first logged position, m.
    pub max_excursion_m: f64,
    /// Last logged position, m.
    pub final_position_m: Option<[f64; 3]>,
}

impl ReplaySummary {
    /// The settings of a `simulate` run, if the metadata holds them.
    pub fn settings(&self) -> Option<SimSettings> {
        self.metadata
            .get("settings")
            .and_then(|s| SimSettings::from_json(s).ok())
    }
}

impl fmt::Display for ReplaySummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let md = |k: &str| self.metadata.get(k).map(String::as_str).unwrap_or("?");
        writeln!(f, "log        {}", self.path.display())?;
        writeln!(
            f,
            "written by flapwing {} `{}` ({})",
            md("version"),
            md("command"),
            md("command_line")
        )?;
        writeln!(
            f,
            "model      {} ({}, {} lines, attached)",
            md("vehicle"),
            md("model_origin"),
            md("model_toml").lines().count()
        )?;
        writeln!(f, "settings   {}", md("settings"))?;
        let rate = md("log_rate_hz");
        let unit = if rate.parse::<f64>().is_ok() {
            " Hz"
        } else {
            ""
        };
        writeln!(f, "log rate   {rate}{unit}")?;
        match &self.damage {
            None => writeln!(f, "file       {} bytes, complete", self.file_bytes)?,
            Some(d) => writeln!(f, "file       {} bytes, DAMAGED: {d}", self.file_bytes)?,
        }
        if self.end_metadata.is_none() {
            writeln!(
                f,
                "           no `flapwing.end` record: the run did not finish its log"
            )?;
        }
        writeln!(
            f,
            "time       {:.6} s to {:.6} s ({:.6} s), {} samples, {} messages",
            self.start_s, self.end_s, self.duration_s, self.samples, self.message_count
        )?;
        writeln!(f, "channels")?;
        for c in &self.channels {
            writeln!(
                f,
                "  {:<24} {:<26} {:>8} messages",
                c.topic, c.schema_name, c.message_count
            )?;
        }
        for a in &self.attachments {
            writeln!(
                f,
                "attachment {} ({}, {} bytes)",
                a.name, a.media_type, a.bytes
            )?;
        }
        match &self.cycle_mean {
            Some(m) => {
                writeln!(
                    f,
                    "cycle mean over {} wingbeats (both wings, body frame)",
                    m.wingbeats
                )?;
                writeln!(
                    f,
                    "  force  N    [{:+.6e}, {:+.6e}, {:+.6e}]",
                    m.force_body_n[0], m.force_body_n[1], m.force_body_n[2]
                )?;
                writeln!(
                    f,
                    "  moment N m  [{:+.6e}, {:+.6e}, {:+.6e}]",
                    m.moment_body_nm[0], m.moment_body_nm[1], m.moment_body_nm[2]
                )?;
                if let Some(l) = m.lift_over_weight {
                    writeln!(f, "  lift / weight {l:.4}")?;
                }
            }
            None => writeln!(f, "cycle mean (no complete wingbeat logged)")?,
        }
        writeln!(
            f,
            "excursion  {:.6e} m max from the start",
            self.max_excursion_m
        )?;
        if self.events.is_empty() {
            writeln!(f, "events     none")?;
        } else {
            writeln!(f, "events")?;
            for e in &self.events {
                writeln!(f, "  {:>10.6} s {:<7} {}", e.t_s, e.level, e.message)?;
            }
        }
        Ok(())
    }
}

/// Mean over complete wingbeats of per-wingbeat means. `samples` are (phase, values) in
/// time order; the wingbeat in progress at the end is left out.
fn cycle_mean<const N: usize>(samples: &[(f64, [f64; N])]) -> Option<(u64, [f64; N])> {
    let mut sum = [0.0; N];
    let mut cycles = 0u64;
    let mut current: Option<i64> = None;
    let mut acc = [0.0; N];
    let mut n = 0u64;
    for (phase, v) in samples {
        let c = phase.floor();
        let c = if c.is_finite() { c as i64 } else { continue };
        if current != Some(c) {
            if current.is_some() && n > 0 {
                for k in 0..N {
                    sum[k] += acc[k] / n as f64;
                }
                cycles += 1;
            }
            current = Some(c);
            acc = [0.0; N];
            n = 0;
        }
        for k in 0..N {
            acc[k] += v[k];
        }
        n += 1;
    }
    if cycles == 0 {
        return None;
    }
    Some((cycles, sum.map(|s| s / cycles as f64)))
}

/// Reads a log and summarizes it (see the module docs for truncated files).
pub fn read_summary(path: impl AsRef<Path>) -> Result<ReplaySummary> {
    let log = read_log(path.as_ref())?;
    Ok(summarize(&log))
}

fn summarize(log: &LogFile) -> ReplaySummary {
    let (mut start, mut end) = (u64::MAX, 0u64);
    for m in &log.messages {
        start = start.min(m.log_time);
        end = end.max(m.log_time);
    }
    if log.messages.is_empty() {
        start = 0;
    }
    let mut events: Vec<EventSummary> = log
        .on(TOPIC_EVENTS)
        .filter_map(|m| {
            let v = log.parse(m)?;
            let level = v
                .get("level")
                .and_then(Json::as_i64)
                .and_then(Level::from_int)
                .map_or("UNKNOWN", Level::name);
            Some(EventSummary {
                t_s: m.log_time as f64 * 1e-9,
                level: level.to_owned(),
                message: v
                    .get("message")
                    .and_then(Json::as_str)
                    .unwrap_or("")
                    .to_owned(),
            })
        })
        .collect();
    events.sort_by(|a, b| a.t_s.total_cmp(&b.t_s));

    // States: excursion and lift over weight.
    let mut first_pos: Option<[f64; 3]> = None;
    let mut last_pos = None;
    let mut max_exc = 0.0f64;
    let mut lift = Vec::new();
    let mut samples = 0u64;
    for m in log.on(TOPIC_STATE) {
        let Some(v) = log.parse(m) else { continue };
        samples += 1;
        if let Some(p) = v.vec3_at("position_m") {
            let p0 = *first_pos.get_or_insert(p);
            let d =
                ((p[0] - p0[0]).powi(2) + (p[1] - p0[1]).powi(2) + (p[2] - p0[2]).powi(2)).sqrt();
            if d.is_finite() {
                max_exc = max_exc.max(d);
            }
            last_pos = Some(p);
        }
        if let (Some(ph), Some(l)) = (v.f64_at("phase"), v.f64_at("lift_over_weight")) {
            lift.push((ph, [l]));
        }
    }

    // Forces: both wings' totals at each sample time.
    let mut per_time: BTreeMap<u64, (f64, [f64; 6], u8)> = BTreeMap::new();
    for (topic, bit) in [(TOPIC_FORCES_LEFT, 1u8), (TOPIC_FORCES_RIGHT, 2u8)] {
        for m in log.on(topic) {
            let Some(v) = log.parse(m) else { continue };
            let (Some(ph), Some(f), Some(mo)) = (
                v.f64_at("phase"),
                v.vec3_at("total.force_n"),
                v.vec3_at("total.moment_nm"),
            ) else {
                continue;
            };
            let e = per_time.entry(m.log_time).or_insert((ph, [0.0; 6], 0));
            if e.2 & bit == 0 {
                for k in 0..3 {
                    e.1[k] += f[k];
                    e.1[3 + k] += mo[k];
                }
                e.2 |= bit;
            }
        }
    }
    let loads: Vec<(f64, [f64; 6])> = per_time
        .values()
        .filter(|(_, _, seen)| *seen == 3)
        .map(|(ph, v, _)| (*ph, *v))
        .collect();
    let cycle = cycle_mean(&loads).map(|(n, v)| CycleMean {
        wingbeats: n,
        force_body_n: [v[0], v[1], v[2]],
        moment_body_nm: [v[3], v[4], v[5]],
        lift_over_weight: cycle_mean(&lift).map(|(_, l)| l[0]),
    });

    let end_metadata = log
        .metadata
        .iter()
        .find(|m| m.name == schema::METADATA_END)
        .map(|m| m.metadata.clone());
    let start_s = start as f64 * 1e-9;
    let end_s = end.max(start) as f64 * 1e-9;
    ReplaySummary {
        path: log.path.clone(),
        file_bytes: log.file_bytes,
        complete: log.complete,
        damage: log.damage.clone(),
        message_count: log.messages.len() as u64,
        start_s,
        end_s,
        duration_s: end_s - start_s,
        channels: log.channels.values().cloned().collect(),
        metadata: log.run_metadata().clone(),
        end_metadata,
        attachments: log.attachments.clone(),
        events,
        samples,
        cycle_mean: cycle,
        max_excursion_m: max_exc,
        final_position_m: last_pos,
    }
}

/// What [`export_csv`] wrote.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct CsvStats {
    /// Data rows (one per message).
    pub rows: u64,
    /// Columns, the first being `log_time_ns`.
    pub columns: u64,
    /// Messages that were not valid JSON and were left out.
    pub skipped: u64,
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_owned()
    }
}

/// The messages of one topic as a table (what [`export_csv`] writes and the Python
/// bindings turn into arrays): one row per message, the first column `log_time_ns`, then
/// one column per leaf of the decoded message named by its dotted path
/// (`pose.position.x`) in first-seen order; each cell the value's text exactly as logged
/// (numbers, true/false, strings), `None` where a message lacks the field.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Table {
    /// Column names.
    pub columns: Vec<String>,
    /// Rows, each with one cell per column.
    pub rows: Vec<Vec<Option<String>>>,
    /// Messages that could not be decoded and were left out.
    pub skipped: u64,
}

/// Reads the messages of `topic` of the log at `path` into a [`Table`].
pub fn read_table(path: impl AsRef<Path>, topic: &str) -> Result<Table> {
    let path = path.as_ref();
    let log = read_log(path)?;
    let Some(id) = log.channel_id(topic) else {
        return Err(Error::UnknownTopic {
            path: path.to_owned(),
            topic: topic.to_owned(),
            available: log.topics(),
        });
    };
    if let Some(why) = log.undecodable(id) {
        return Err(Error::Embedded(format!(
            "`{}`: the messages of `{topic}` cannot be decoded: {why}",
            path.display()
        )));
    }
    let mut columns: Vec<String> = vec!["log_time_ns".into()];
    let mut index: HashMap<String, usize> = HashMap::new();
    let mut sparse: Vec<Vec<(usize, String)>> = Vec::new();
    let mut skipped = 0u64;
    for m in log.on(topic) {
        let Some(v) = log.parse(m) else {
            skipped += 1;
            continue;
        };
        let mut flat = Vec::new();
        v.flatten("", &mut flat);
        let mut row = vec![(0, m.log_time.to_string())];
        for (k, val) in flat {
            let k = if k.is_empty() { "value".to_owned() } else { k };
            let i = *index.entry(k.clone()).or_insert_with(|| {
                columns.push(k);
                columns.len() - 1
            });
            row.push((i, val));
        }
        sparse.push(row);
    }
    let rows = sparse
        .into_iter()
        .map(|r| {
            let mut cells = vec![None; columns.len()];
            for (i, v) in r {
                cells[i] = Some(v);
            }
            cells
        })
        .collect();
    Ok(Table {
        columns,
        rows,
        skipped,
    })
}

/// Writes the messages of `topic` to a CSV file at `out` (replaced if it exists): the
/// [`Table`] of [`read_table`], a field missing from a message left empty, numbers exactly
/// as logged, booleans as true/false.
pub fn export_csv(path: impl AsRef<Path>, topic: &str, out: impl AsRef<Path>) -> Result<CsvStats> {
    let out = out.as_ref();
    let table = read_table(path, topic)?;
    let file = std::fs::File::create(out).map_err(|e| Error::io("cannot create", out, e))?;
    let mut w = std::io::BufWriter::new(file);
    let werr = |e| Error::io("cannot write", out, e);
    let header: Vec<String> = table.columns.iter().map(|c| csv_field(c)).collect();
    writeln!(w, "{}", header.join(",")).map_err(werr)?;
    for row in &table.rows {
        let cells: Vec<String> = row
            .iter()
            .map(|c| c.as_deref().map(csv_field).unwrap_or_default())
            .collect();
        writeln!(w, "{}", cells.join(",")).map_err(werr)?;
    }
    w.flush().map_err(werr)?;
    Ok(CsvStats {
        rows: table.rows.len() as u64,
        columns: table.columns.len() as u64,
        skipped: table.skipped,
    })
}

/// What [`to_rrd`] wrote.
#[cfg(feature = "rerun")]
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct RrdStats {
    /// Samples converted (times with a state, both wing transforms and both wings' forces).
    pub frames: u64,
    /// Events converted.
    pub events: u64,
    /// `/estimate` messages converted (those with a state at their log time).
    pub estimates: u64,
    /// `/wind` messages converted.
    pub winds: u64,
}

/// Converts a log to a Rerun recording at `out` (replaced if it exists), with the entities
/// of a live recording (the estimate against the truth and the wing winds of logs that
/// have `/estimate` and `/wind`). The wing meshes come from the embedded model.
#[cfg(feature = "rerun")]
pub fn to_rrd(path: impl AsRef<Path>, out: impl AsRef<Path>) -> Result<RrdStats> {
    use crate::sample::FrameData;
    use crate::schema::{FORCE_PARTS, TOPIC_TF_WING_LEFT, TOPIC_TF_WING_RIGHT};

    let path = path.as_ref();
    let log = read_log(path)?;
    let md = log.run_metadata();
    let toml = md.get("model_toml").map(String::as_str).unwrap_or("");
    let origin = md
        .get("model_origin")
        .map(String::as_str)
        .unwrap_or("model");
    let vehicle = flapsim::Vehicle::from_toml(toml, origin).map_err(|e| {
        Error::Embedded(format!(
            "the model embedded in `{}` does not load: {e}",
            path.display()
        ))
    })?;

    // Assemble samples by log time; bit flags say which parts arrived.
    let mut frames: BTreeMap<u64, (FrameData, u8)> = BTreeMap::new();
    fn slot(frames: &mut BTreeMap<u64, (FrameData, u8)>, t: u64) -> &mut (FrameData, u8) {
        frames.entry(t).or_insert_with(|| {
            (
                FrameData {
                    t_ns: t,
                    ..FrameData::default()
                },
                0,
            )
        })
    }
    for m in log.on(TOPIC_STATE) {
        let Some(v) = log.parse(m) else { continue };
        let (Some(p), Some(q)) = (v.vec3_at("position_m"), v.quat_at("attitude")) else {
            continue;
        };
        let s = slot(&mut frames, m.log_time);
        s.0.position = p;
        s.0.attitude = q;
        s.0.euler_deg = [
            v.f64_at("euler_deg.roll").unwrap_or(0.0),
            v.f64_at("euler_deg.pitch").unwrap_or(0.0),
            v.f64_at("euler_deg.yaw").unwrap_or(0.0),
        ];
        s.0.lift_over_weight = v.f64_at("lift_over_weight").unwrap_or(0.0);
        s.1 |= 1;
    }
    for (i, topic) in [TOPIC_TF_WING_LEFT, TOPIC_TF_WING_RIGHT].iter().enumerate() {
        for m in log.on(topic) {
            let Some(v) = log.parse(m) else { continue };
            let (Some(t), Some(q)) = (v.vec3_at("translation"), v.quat_at("rotation")) else {
                continue;
            };
            let s = slot(&mut frames, m.log_time);
            s.0.wing_hinge[i] = t;
            s.0.wing_rotation[i] = q;
            s.1 |= 2 << i;
        }
    }
    for (i, topic) in [TOPIC_FORCES_LEFT, TOPIC_FORCES_RIGHT].iter().enumerate() {
        for m in log.on(topic) {
            let Some(v) = log.parse(m) else { continue };
            let s = slot(&mut frames, m.log_time);
            let mut ok = true;
            for (j, part) in FORCE_PARTS.iter().enumerate() {
                match (
                    v.vec3_at(&format!("{part}.force_n")),
                    v.f64_at(&format!("{part}.c_l")),
                    v.f64_at(&format!("{part}.c_d")),
                ) {
                    (Some(f), Some(cl), Some(cd)) => {
                        s.0.force_n[i][j] = f;
                        s.0.c_l[i][j] = cl;
                        s.0.c_d[i][j] = cd;
                    }
                    _ => ok = false,
                }
            }
            if ok {
                s.1 |= 8 << i;
            }
        }
    }
    let out = out.as_ref();
    let stream = crate::rerun_sink::RerunSink::file_stream(out)?;
    let sink = crate::rerun_sink::RerunSink::new(vec![stream], &vehicle)?;
    let mut n = 0u64;
    for (frame, seen) in frames.values() {
        if *seen == 0b11111 {
            sink.frame(frame)?;
            n += 1;
        }
    }
    let mut estimates = 0u64;
    for m in log.on(crate::schema::TOPIC_ESTIMATE) {
        let Some(v) = log.parse(m) else { continue };
        let Some((truth, _)) = frames.get(&m.log_time).filter(|(_, seen)| seen & 1 == 1) else {
            continue;
        };
        let (Some(p), Some(q)) = (v.vec3_at("position_world_m"), v.quat_at("attitude")) else {
            continue;
        };
        let fin = |x: f64| if x.is_finite() { x } else { 0.0 };
        let view = crate::estimate_msg::EstimateView {
            t_ns: m.log_time,
            position: p.map(fin),
            true_position: truth.position.map(fin),
            attitude: q.map(fin),
            euler_deg: ["roll", "pitch", "yaw"]
                .map(|a| fin(v.f64_at(&format!("euler_deg.{a}")).unwrap_or(0.0))),
            true_euler_deg: truth.euler_deg.map(fin),
            position_std: v
                .vec3_at("std.position_world_m")
                .unwrap_or_default()
                .map(fin),
        };
        sink.estimate(&view, estimates == 0)?;
        estimates += 1;
    }
    let mut winds = 0u64;
    for m in log.on(crate::schema::TOPIC_WIND) {
        let Some(v) = log.parse(m) else { continue };
        let Some(Json::Arr(items)) = v.get("wing_winds_world_m_s") else {
            continue;
        };
        let w: Vec<nalgebra::Vector3<f64>> = items
            .iter()
            .map(|w| {
                let c = |k: &str| w.f64_at(k).unwrap_or(0.0);
                nalgebra::Vector3::new(c("x"), c("y"), c("z"))
            })
            .collect();
        sink.wind(m.log_time, &w)?;
        winds += 1;
    }
    let mut events = 0u64;
    for m in log.on(TOPIC_EVENTS) {
        let Some(v) = log.parse(m) else { continue };
        let level = v
            .get("level")
            .and_then(Json::as_i64)
            .and_then(Level::from_int)
            .unwrap_or(Level::Info);
        sink.event(
            m.log_time,
            level,
            v.get("message").and_then(Json::as_str).unwrap_or(""),
        )?;
        events += 1;
    }
    sink.finish()?;
    Ok(RrdStats {
        frames: n,
        events,
        estimates,
        winds,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cycle_mean_leaves_out_the_last_wingbeat() {
        let s = [
            (0.0, [1.0]),
            (0.5, [3.0]),
            (1.0, [10.0]),
            (1.5, [20.0]),
            (2.0, [100.0]),
        ];
        assert_eq!(cycle_mean(&s), Some((2, [(2.0 + 15.0) / 2.0])));
        assert_eq!(cycle_mean(&s[..2]), None);
    }
}
