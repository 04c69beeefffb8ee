//! A log's summary: its run metadata, channels, events, cycle-mean lift and excursion, and
//! what a damaged file lost ([`read_summary`], shown by `flapwing replay`).

use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::error::Result;
use crate::json::Json;
use crate::options::{Level, SimSettings};
use crate::read::{AttachmentSummary, ChannelSummary, LogFile, read_log};
use crate::schema::{self, TOPIC_EVENTS, TOPIC_STATE, WingLayout};

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
    /// Mean of every wing's total aerodynamic force summed, body frame, N (from
    /// /wing/*/forces).
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
    /// The wings' labels, from the `/wing/{label}/forces` channels in channel order (`left`,
    /// `right`, then `pairs{k}_left`, `pairs{k}_right` of further pairs; see
    /// [`crate::schema::WingLayout`]).
    pub wings: Vec<String>,
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
        writeln!(
            f,
            "wings      {}: {}",
            self.wings.len(),
            if self.wings.is_empty() {
                "none logged".to_owned()
            } else {
                self.wings.join(", ")
            }
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
                let wings = match self.wings.len() {
                    2 => "both wings".to_owned(),
                    n => format!("all {n} wings"),
                };
                writeln!(
                    f,
                    "cycle mean over {} wingbeats ({wings}, body frame)",
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

    // Forces: every wing's totals at each sample time.
    let layout = WingLayout::from_topics(log.channels.values().map(|c| c.topic.as_str()));
    let labels = layout
        .as_ref()
        .map(|l| l.labels().to_vec())
        .unwrap_or_default();
    let mut per_time: BTreeMap<u64, (f64, [f64; 6], Vec<bool>)> = BTreeMap::new();
    for (i, label) in labels.iter().enumerate() {
        let topic = format!("/wing/{label}/forces");
        for m in log.on(&topic) {
            let Some(v) = log.parse(m) else { continue };
            let (Some(ph), Some(f), Some(mo)) = (
                v.f64_at("phase"),
                v.vec3_at("total.force_n"),
                v.vec3_at("total.moment_nm"),
            ) else {
                continue;
            };
            let e = per_time
                .entry(m.log_time)
                .or_insert_with(|| (ph, [0.0; 6], vec![false; labels.len()]));
            if !e.2[i] {
                for k in 0..3 {
                    e.1[k] += f[k];
                    e.1[3 + k] += mo[k];
                }
                e.2[i] = true;
            }
        }
    }
    let loads: Vec<(f64, [f64; 6])> = per_time
        .values()
        .filter(|(_, _, seen)| seen.iter().all(|&s| s))
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
        wings: labels,
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
