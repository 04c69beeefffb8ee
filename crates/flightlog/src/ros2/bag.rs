//! Reading any MCAP file record by record (a ROS 2 bag, or any other writer's file), the way
//! a killed recorder left it: every intact record, each chunk whole or not at all.

use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

use mcap::records::Record;

use crate::error::{Error, Result};
use crate::read::{ScanState, channel_schema, walk_records};

/// Schema encoding of ROS 2 `.msg` definitions.
pub const SCHEMA_ROS2MSG: &str = "ros2msg";
/// Message encoding of ROS 2 messages.
pub const MESSAGE_CDR: &str = "cdr";

/// One channel of a bag.
#[derive(Debug, Clone)]
pub struct BagChannel {
    /// Topic.
    pub topic: String,
    /// Schema name: the message type (`geometry_msgs/msg/PoseStamped`); empty for none.
    pub schema_name: String,
    /// Schema encoding (`ros2msg` for ROS 2).
    pub schema_encoding: String,
    /// Message encoding (`cdr` for ROS 2).
    pub message_encoding: String,
    /// Schema data (for `ros2msg`, the concatenated `.msg` definitions).
    pub schema_data: Vec<u8>,
}

impl BagChannel {
    /// True for a ROS 2 channel: a `ros2msg` or `ros2idl` schema and CDR messages.
    pub fn is_ros2(&self) -> bool {
        (self.schema_encoding == SCHEMA_ROS2MSG
            || self.schema_encoding == super::idl::SCHEMA_ROS2IDL)
            && self.message_encoding == MESSAGE_CDR
    }
}

/// One message as read.
#[derive(Debug, Clone)]
pub struct BagMessage {
    /// Its channel.
    pub channel_id: u16,
    /// Log time, ns.
    pub log_time_ns: u64,
    /// The encoded message.
    pub data: Vec<u8>,
}

/// Everything read from a file.
#[derive(Debug, Clone)]
pub struct Bag {
    /// The file.
    pub path: PathBuf,
    /// Its size, bytes.
    pub file_bytes: u64,
    /// The writer named in the MCAP header.
    pub library: String,
    /// Channels by id.
    pub channels: BTreeMap<u16, BagChannel>,
    /// Messages in file order.
    pub messages: Vec<BagMessage>,
    /// True when the file is whole (data end, summary section, closing magic).
    pub complete: bool,
    /// What was lost, for a truncated or damaged file.
    pub damage: Option<String>,
}

impl Bag {
    /// True if any channel is a ROS 2 channel.
    pub fn has_ros2(&self) -> bool {
        self.channels.values().any(BagChannel::is_ros2)
    }

    /// The id of the channel of `topic`.
    pub fn channel_id(&self, topic: &str) -> Option<u16> {
        self.channels
            .iter()
            .find(|(_, c)| c.topic == topic)
            .map(|(id, _)| *id)
    }

    /// Every topic, comma separated.
    pub fn topics(&self) -> String {
        let t: Vec<&str> = self.channels.values().map(|c| c.topic.as_str()).collect();
        t.join(", ")
    }
}

#[derive(Default)]
struct Scan {
    schemas: HashMap<u16, (String, String, Vec<u8>)>,
    channels: BTreeMap<u16, BagChannel>,
    messages: Vec<BagMessage>,
}

impl Scan {
    fn apply(&mut self, rec: Record<'_>, at: u64) -> std::result::Result<(), String> {
        match rec {
            Record::Schema { header, data } => {
                self.schemas
                    .insert(header.id, (header.name, header.encoding, data.into_owned()));
            }
            Record::Channel(c) => {
                let (schema_name, schema_encoding, schema_data) =
                    channel_schema(&self.schemas, &c, at)?;
                self.channels.insert(
                    c.id,
                    BagChannel {
                        topic: c.topic,
                        schema_name,
                        schema_encoding,
                        message_encoding: c.message_encoding,
                        schema_data,
                    },
                );
            }
            Record::Message { header, data } => {
                if !self.channels.contains_key(&header.channel_id) {
                    return Err(format!(
                        "message at byte {at} on unknown channel {}",
                        header.channel_id
                    ));
                }
                self.messages.push(BagMessage {
                    channel_id: header.channel_id,
                    log_time_ns: header.log_time,
                    data: data.into_owned(),
                });
            }
            _ => {}
        }
        Ok(())
    }
}

/// Reads every intact record of the MCAP file at `path`. A file that is not MCAP is an
/// error; a truncated or damaged one yields what came before the damage, with
/// [`Bag::damage`] saying how much was recovered.
pub fn read_bag(path: &Path) -> Result<Bag> {
    let bytes = std::fs::read(path).map_err(|e| Error::io("cannot read", path, e))?;
    parse_bag(path, &bytes)
}

/// [`read_bag`] of the file's bytes.
pub(crate) fn parse_bag(path: &Path, bytes: &[u8]) -> Result<Bag> {
    let len = bytes.len() as u64;
    if !bytes.starts_with(mcap::MAGIC) {
        return Err(Error::NotMcap {
            path: path.to_owned(),
            detail: "it does not start with the MCAP magic".into(),
        });
    }
    let mut scan = Scan::default();
    let walk = walk_records(bytes, &mut scan, false, |_| {});
    let recovered = scan.messages.len();
    let chunks = walk.chunks;
    let library = walk.library.clone();
    let (complete, damage) = walk.damage(bytes, recovered, |at, why| {
        format!(
            "file truncated or damaged at byte {at} of {len}: {why}; recovered {recovered} \
             messages from {chunks} complete chunks before it"
        )
    });
    Ok(Bag {
        path: path.to_owned(),
        file_bytes: len,
        library,
        channels: scan.channels,
        messages: scan.messages,
        complete,
        damage,
    })
}

impl ScanState for Scan {
    fn apply(&mut self, rec: Record<'_>, at: u64) -> std::result::Result<(), String> {
        Scan::apply(self, rec, at)
    }

    fn clone_meta(&self) -> Scan {
        Scan {
            schemas: self.schemas.clone(),
            channels: self.channels.clone(),
            messages: Vec::new(),
        }
    }

    fn keep(&mut self, mut trial: Scan) {
        self.schemas = trial.schemas;
        self.channels = trial.channels;
        self.messages.append(&mut trial.messages);
    }
}
