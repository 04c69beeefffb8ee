//! A ROS 2 bag's summary (what `flapwing replay BAG.mcap` prints) and a topic as CSV.

use std::collections::HashMap;
use std::fmt;
use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::error::{Error, Result};
use crate::ros2::bag::{Bag, BagChannel};
use crate::ros2::cdr::MessageType;
use crate::tabulate::{TableBuilder, write_csv};

/// One topic of a bag.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TopicSummary {
    /// Topic.
    pub topic: String,
    /// Message type (the schema name, `geometry_msgs/msg/PoseStamped`).
    pub message_type: String,
    /// Schema encoding (`ros2msg`).
    pub schema_encoding: String,
    /// Message encoding (`cdr`).
    pub message_encoding: String,
    /// Messages read.
    pub message_count: u64,
    /// First message's log time, ns (None without messages).
    pub start_ns: Option<u64>,
    /// Last message's log time, ns.
    pub end_ns: Option<u64>,
    /// First message's log time, s (None without messages).
    pub start_s: Option<f64>,
    /// Last message's log time, s.
    pub end_s: Option<f64>,
    /// `end_s - start_s`, s (0 with fewer than two messages).
    pub span_s: f64,
    /// Mean rate, (count - 1) / span, Hz (None with fewer than two messages or a zero span).
    pub rate_hz: Option<f64>,
    /// Messages that do not decode against the type.
    pub undecodable: u64,
    /// Why the type or its first undecodable message cannot be decoded, if so.
    pub problem: Option<String>,
}

/// What a ROS 2 bag holds.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BagSummary {
    /// The file.
    pub path: PathBuf,
    /// Its size, bytes.
    pub file_bytes: u64,
    /// The writer named in the MCAP header.
    pub library: String,
    /// True when the file is whole.
    pub complete: bool,
    /// What was lost, for a truncated or damaged file.
    pub damage: Option<String>,
    /// Messages read (all topics).
    pub message_count: u64,
    /// First message's log time, ns.
    pub start_ns: Option<u64>,
    /// Last message's log time, ns.
    pub end_ns: Option<u64>,
    /// First message's log time, s.
    pub start_s: Option<f64>,
    /// Last message's log time, s.
    pub end_s: Option<f64>,
    /// Every topic, in channel order.
    pub topics: Vec<TopicSummary>,
}

/// Nanoseconds as exact decimal seconds (`1700000000.123456789`).
fn ns_text(ns: u64) -> String {
    format!("{}.{:09}", ns / 1_000_000_000, ns % 1_000_000_000)
}

fn ns_to_s(ns: u64) -> f64 {
    ns as f64 * 1e-9
}

/// The decoder of a channel, or why there is none.
fn message_type(c: &BagChannel) -> std::result::Result<MessageType, String> {
    if !c.is_ros2() {
        return Err(format!(
            "schema encoding `{}` with message encoding `{}` is not decoded (allowed: \
             `ros2msg` or `ros2idl` schemas with `cdr` messages)",
            c.schema_encoding, c.message_encoding
        ));
    }
    let text = std::str::from_utf8(&c.schema_data)
        .map_err(|e| format!("the schema is not UTF-8 text: {e}"))?;
    if c.schema_encoding == super::idl::SCHEMA_ROS2IDL {
        let bundle = super::idl::msg_bundle(&c.schema_name, text)?;
        return MessageType::parse(&c.schema_name, &bundle);
    }
    MessageType::parse(&c.schema_name, text)
}

/// Summarises every topic of a bag, decoding every message of its ROS 2 topics.
pub fn summarize(bag: &Bag) -> BagSummary {
    let mut topics = Vec::new();
    let mut index: HashMap<u16, usize> = HashMap::new();
    let mut types = Vec::new();
    let mut times: Vec<(u64, u64)> = Vec::new();
    for (id, c) in &bag.channels {
        index.insert(*id, topics.len());
        let ty = message_type(c);
        topics.push(TopicSummary {
            topic: c.topic.clone(),
            message_type: c.schema_name.clone(),
            schema_encoding: c.schema_encoding.clone(),
            message_encoding: c.message_encoding.clone(),
            message_count: 0,
            start_ns: None,
            end_ns: None,
            start_s: None,
            end_s: None,
            span_s: 0.0,
            rate_hz: None,
            undecodable: 0,
            problem: ty.as_ref().err().cloned(),
        });
        types.push(ty.ok());
        times.push((u64::MAX, 0));
    }
    for m in &bag.messages {
        let Some(&i) = index.get(&m.channel_id) else {
            continue;
        };
        let t = &mut topics[i];
        t.message_count += 1;
        times[i] = (times[i].0.min(m.log_time_ns), times[i].1.max(m.log_time_ns));
        if let Some(ty) = &types[i]
            && let Err(e) = ty.decode(&m.data)
        {
            t.undecodable += 1;
            if t.problem.is_none() {
                t.problem = Some(format!(
                    "message {} (log time {} ns): {e}",
                    t.message_count - 1,
                    m.log_time_ns
                ));
            }
        }
    }
    for (t, (first, last)) in topics.iter_mut().zip(&times) {
        if t.message_count == 0 {
            continue;
        }
        t.start_ns = Some(*first);
        t.end_ns = Some(*last);
        t.start_s = Some(ns_to_s(*first));
        t.end_s = Some(ns_to_s(*last));
        t.span_s = (last - first) as f64 * 1e-9;
        if t.message_count > 1 && last > first {
            t.rate_hz = Some((t.message_count - 1) as f64 / t.span_s);
        }
    }
    let first = bag.messages.iter().map(|m| m.log_time_ns).min();
    let last = bag.messages.iter().map(|m| m.log_time_ns).max();
    BagSummary {
        path: bag.path.clone(),
        file_bytes: bag.file_bytes,
        library: bag.library.clone(),
        complete: bag.complete,
        damage: bag.damage.clone(),
        message_count: bag.messages.len() as u64,
        start_ns: first,
        end_ns: last,
        start_s: first.map(ns_to_s),
        end_s: last.map(ns_to_s),
        topics,
    }
}

impl fmt::Display for BagSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let state = if self.complete {
            "complete"
        } else {
            "incomplete"
        };
        writeln!(
            f,
            "ROS 2 bag {} ({} bytes, {state}, written by `{}`)",
            self.path.display(),
            self.file_bytes,
            self.library
        )?;
        match (self.start_ns, self.end_ns) {
            (Some(a), Some(b)) => writeln!(
                f,
                "{} messages on {} topics, log time {} s to {} s ({:.6} s)",
                self.message_count,
                self.topics.len(),
                ns_text(a),
                ns_text(b),
                b.saturating_sub(a) as f64 * 1e-9
            )?,
            _ => writeln!(f, "no messages on {} topics", self.topics.len())?,
        }
        let w_topic = self.topics.iter().map(|t| t.topic.len()).max().unwrap_or(5);
        let w_type = self
            .topics
            .iter()
            .map(|t| t.message_type.len())
            .max()
            .unwrap_or(4);
        let (w_topic, w_type) = (w_topic.max(5), w_type.max(4));
        writeln!(
            f,
            "{:<w_topic$}  {:<w_type$}  {:>8}  {:>10}  {:>10}",
            "topic", "type", "messages", "rate_hz", "span_s"
        )?;
        for t in &self.topics {
            let rate = t.rate_hz.map_or("-".to_owned(), |r| format!("{r:.3}"));
            writeln!(
                f,
                "{:<w_topic$}  {:<w_type$}  {:>8}  {rate:>10}  {:>10.6}",
                t.topic, t.message_type, t.message_count, t.span_s
            )?;
        }
        for t in self.topics.iter().filter(|t| t.problem.is_some()) {
            let n = if t.undecodable > 0 {
                format!(
                    "{} of {} messages do not decode: ",
                    t.undecodable, t.message_count
                )
            } else {
                "cannot decode: ".to_owned()
            };
            writeln!(
                f,
                "note: {} ({}): {n}{}",
                t.topic,
                t.message_type,
                t.problem.as_deref().unwrap_or("")
            )?;
        }
        Ok(())
    }
}

/// What [`export_topic_csv`] wrote.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct TopicCsvStats {
    /// Data rows (one per message).
    pub rows: u64,
    /// Columns, the first being `log_time_ns`.
    pub columns: u64,
}

/// The messages of one topic as a table: `columns` (the first `log_time_ns`, then one per
/// field by dotted path in definition order, array elements `transforms.0.child_frame_id`)
/// and one row per message with one cell per column, `None` where a message lacks it (a
/// shorter sequence). What [`export_topic_csv`] writes, and what a reader of bags into
/// arrays (the Python bindings' `read_log`) needs.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct TopicTable {
    /// Column names.
    pub columns: Vec<String>,
    /// Rows, each with one cell per column.
    pub rows: Vec<Vec<Option<String>>>,
}

/// Decodes every message of `topic` into a [`TopicTable`]. An unknown topic, a type that
/// cannot be decoded or a message that does not decode is an error naming the topic and the
/// field.
pub fn read_topic_table(bag: &Bag, topic: &str) -> Result<TopicTable> {
    let path = bag.path.clone();
    let Some(id) = bag.channel_id(topic) else {
        return Err(Error::UnknownTopic {
            path,
            topic: topic.to_owned(),
            available: bag.topics(),
        });
    };
    let channel = &bag.channels[&id];
    let ty = message_type(channel).map_err(|detail| Error::Ros2Schema {
        path: path.clone(),
        topic: topic.to_owned(),
        type_name: channel.schema_name.clone(),
        detail,
    })?;
    let mut table = TableBuilder::new();
    let on_topic = bag.messages.iter().filter(|m| m.channel_id == id);
    for (i, m) in on_topic.enumerate() {
        let fields = ty.decode(&m.data).map_err(|detail| Error::Ros2Message {
            path: path.clone(),
            topic: topic.to_owned(),
            type_name: channel.schema_name.clone(),
            index: i as u64,
            log_time_ns: m.log_time_ns,
            detail,
        })?;
        table.push_row(m.log_time_ns, fields);
    }
    let (columns, rows) = table.finish();
    Ok(TopicTable { columns, rows })
}

/// Writes every message of `topic` to the CSV file `out` (replaced if it exists): the
/// [`TopicTable`] of [`read_topic_table`], a cell a message lacks left empty. On an error
/// nothing is written.
pub fn export_topic_csv(bag: &Bag, topic: &str, out: &Path) -> Result<TopicCsvStats> {
    let table = read_topic_table(bag, topic)?;
    write_csv(&table.columns, &table.rows, out)?;
    Ok(TopicCsvStats {
        rows: table.rows.len() as u64,
        columns: table.columns.len() as u64,
    })
}
