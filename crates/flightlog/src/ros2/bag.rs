//! Reading any MCAP file record by record (a ROS 2 bag, or any other writer's file), the way
//! a killed recorder left it: every intact record, each chunk whole or not at all.

use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

use mcap::records::Record;
use mcap::sans_io::{LinearReader, LinearReaderOptions};

use crate::error::{Error, Result};
use crate::read::{MAX_CHUNK_BYTES, linear_records};

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
    /// True for a ROS 2 channel: a `ros2msg` schema and CDR messages.
    pub fn is_ros2(&self) -> bool {
        self.schema_encoding == SCHEMA_ROS2MSG && self.message_encoding == MESSAGE_CDR
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
                let (schema_name, schema_encoding, schema_data) = if c.schema_id == 0 {
                    Default::default()
                } else {
                    self.schemas.get(&c.schema_id).cloned().ok_or_else(|| {
                        format!(
                            "channel `{}` at byte {at} uses unknown schema {}",
                            c.topic, c.schema_id
                        )
                    })?
                };
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
    let mut library = String::new();
    let mut chunks = 0u64;
    let mut pos = mcap::MAGIC.len();
    let mut data_end = false;
    let mut problem: Option<(u64, String)> = None;
    while problem.is_none() {
        let at = pos as u64;
        let rest = &bytes[pos..];
        if rest.len() < 9 {
            let why = if rest.is_empty() {
                "the file ends before the data-end record"
            } else {
                "the file ends inside a record header"
            };
            problem = Some((at, why.into()));
            break;
        }
        let op = rest[0];
        let mut n = [0u8; 8];
        n.copy_from_slice(&rest[1..9]);
        let rec_len = u64::from_le_bytes(n);
        if rec_len > (rest.len() - 9) as u64 {
            let need = rec_len.saturating_add(9);
            let why = format!(
                "the record there (opcode 0x{op:02x}) needs {need} bytes but only {} remain",
                rest.len()
            );
            problem = Some((at, why));
            break;
        }
        let next = pos + 9 + rec_len as usize;
        let rec = match mcap::parse_record(op, &rest[9..9 + rec_len as usize]) {
            Ok(r) => r,
            Err(e) => {
                problem = Some((at, format!("the record there is corrupt: {e}")));
                break;
            }
        };
        match rec {
            Record::Header(h) => library = h.library,
            Record::Chunk { header, .. } => {
                if header.uncompressed_size > MAX_CHUNK_BYTES {
                    let why = format!(
                        "the chunk there claims {} bytes uncompressed (limit {MAX_CHUNK_BYTES})",
                        header.uncompressed_size
                    );
                    problem = Some((at, why));
                    break;
                }
                let whole = &bytes[pos..next];
                let limit = (MAX_CHUNK_BYTES as usize).max(whole.len());
                let reader = LinearReader::new_with_options(
                    LinearReaderOptions::default()
                        .with_skip_start_magic(true)
                        .with_skip_end_magic(true)
                        .with_prevalidate_chunk_crcs(true)
                        .with_record_length_limit(limit),
                );
                let records = match linear_records(reader, whole) {
                    Ok(r) => r,
                    Err(e) => {
                        problem = Some((at, format!("the chunk there is damaged: {e}")));
                        break;
                    }
                };
                // All or nothing: a chunk is kept only if every record in it is valid.
                let mut trial = scan.clone_meta();
                for r in records {
                    if let Err(e) = trial.apply(r, at) {
                        problem = Some((at, format!("the chunk there is inconsistent: {e}")));
                        break;
                    }
                }
                if problem.is_some() {
                    break;
                }
                scan.schemas = trial.schemas;
                scan.channels = trial.channels;
                scan.messages.append(&mut trial.messages);
                chunks += 1;
            }
            Record::DataEnd(_) => {
                data_end = true;
                pos = next;
                break;
            }
            Record::Footer(_) => {
                problem = Some((at, "a footer before the data-end record".into()));
                break;
            }
            r @ (Record::Schema { .. } | Record::Channel(_) | Record::Message { .. }) => {
                if let Err(e) = scan.apply(r, at) {
                    problem = Some((at, e));
                    break;
                }
            }
            _ => {}
        }
        pos = next;
    }
    let recovered = scan.messages.len();
    let mut complete = false;
    let damage = if let Some((at, why)) = problem {
        Some(format!(
            "file truncated or damaged at byte {at} of {len}: {why}; recovered {recovered} \
             messages from {chunks} complete chunks before it"
        ))
    } else if data_end {
        match mcap::Summary::read(bytes) {
            Ok(_) if bytes.ends_with(mcap::MAGIC) => {
                complete = true;
                None
            }
            Ok(_) => Some(format!(
                "the data section is whole but the file does not end with the MCAP magic \
                 (byte {pos} of {len}); all {recovered} messages recovered"
            )),
            Err(e) => Some(format!(
                "the data section is whole but the summary section after byte {pos} is \
                 damaged ({e}); all {recovered} messages recovered"
            )),
        }
    } else {
        None
    };
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

impl Scan {
    /// The schemas and channels, without the messages.
    fn clone_meta(&self) -> Scan {
        Scan {
            schemas: self.schemas.clone(),
            channels: self.channels.clone(),
            messages: Vec::new(),
        }
    }
}
