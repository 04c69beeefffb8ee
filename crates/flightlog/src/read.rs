//! Reading an MCAP file record by record, the way a killed run left it (see [`crate::replay`]):
//! every intact record, each chunk whole or not at all, and a decoder per channel.

use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

use mcap::records::{Metadata, Record};
use mcap::sans_io::{LinearReadEvent, LinearReader, LinearReaderOptions};

use crate::decode::Decoder;
use crate::json::Json;
use crate::schema;
use serde::Serialize;

use crate::error::{Error, Result};

/// One channel of a log.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct ChannelSummary {
    /// Topic.
    pub topic: String,
    /// Schema name (empty for none).
    pub schema_name: String,
    /// Schema encoding (`protobuf`; `jsonschema` in logs before issue #16).
    pub schema_encoding: String,
    /// Message encoding (`protobuf`; `json` in logs before issue #16).
    pub message_encoding: String,
    /// Messages read.
    pub message_count: u64,
}

/// An attachment of a log.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct AttachmentSummary {
    /// File name.
    pub name: String,
    /// Media type.
    pub media_type: String,
    /// Size, bytes.
    pub bytes: u64,
}

/// Largest uncompressed chunk accepted, bytes (a guard against corrupt headers).
pub(crate) const MAX_CHUNK_BYTES: u64 = 256 << 20;

/// One message as read.
#[derive(Debug, Clone)]
pub(crate) struct RawMessage {
    pub channel_id: u16,
    pub log_time: u64,
    pub data: Vec<u8>,
}

/// Everything read from a file.
#[derive(Debug, Clone)]
pub(crate) struct LogFile {
    pub path: PathBuf,
    pub file_bytes: u64,
    pub channels: BTreeMap<u16, ChannelSummary>,
    decoders: HashMap<u16, Decoder>,
    pub messages: Vec<RawMessage>,
    pub metadata: Vec<Metadata>,
    pub attachments: Vec<AttachmentSummary>,
    pub complete: bool,
    pub damage: Option<String>,
}

impl LogFile {
    /// The `flapwing` metadata record.
    pub fn run_metadata(&self) -> &BTreeMap<String, String> {
        // read_log guarantees it exists.
        static EMPTY: BTreeMap<String, String> = BTreeMap::new();
        self.metadata
            .iter()
            .find(|m| m.name == schema::METADATA_RUN)
            .map_or(&EMPTY, |m| &m.metadata)
    }

    pub(crate) fn channel_id(&self, topic: &str) -> Option<u16> {
        self.channels
            .iter()
            .find(|(_, c)| c.topic == topic)
            .map(|(id, _)| *id)
    }

    /// The message encoding of a topic's channel.
    pub fn message_encoding(&self, topic: &str) -> Option<&str> {
        let id = self.channel_id(topic)?;
        self.channels.get(&id).map(|c| c.message_encoding.as_str())
    }

    /// Messages of a topic, in file order.
    pub fn on<'a>(&'a self, topic: &str) -> impl Iterator<Item = &'a RawMessage> + 'a {
        let id = self.channel_id(topic);
        self.messages
            .iter()
            .filter(move |m| Some(m.channel_id) == id)
    }

    /// A message as a tree (JSON or protobuf, see [`crate::decode`]); `None` if it does not
    /// decode.
    pub fn parse(&self, m: &RawMessage) -> Option<Json> {
        self.decoders.get(&m.channel_id)?.decode(&m.data)
    }

    /// Why the messages of a channel cannot be decoded, if they cannot.
    pub fn undecodable(&self, channel_id: u16) -> Option<&str> {
        match self.decoders.get(&channel_id) {
            Some(crate::decode::Decoder::Unknown(why)) => Some(why),
            _ => None,
        }
    }

    pub(crate) fn topics(&self) -> String {
        self.channels
            .values()
            .map(|c| c.topic.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    }
}

#[derive(Default)]
struct Scan {
    /// Per schema id: name, encoding, data.
    schemas: HashMap<u16, (String, String, Vec<u8>)>,
    decoders: HashMap<u16, Decoder>,
    channels: BTreeMap<u16, ChannelSummary>,
    messages: Vec<RawMessage>,
}

impl Scan {
    fn apply(&mut self, rec: Record<'_>, at: u64) -> std::result::Result<(), String> {
        match rec {
            Record::Schema { header, data } => {
                if header.id == 0 {
                    return Err(format!("schema with id 0 at byte {at}"));
                }
                self.schemas
                    .insert(header.id, (header.name, header.encoding, data.into_owned()));
            }
            Record::Channel(c) => {
                let (schema_name, schema_encoding, schema_data) =
                    channel_schema(&self.schemas, &c, at)?;
                self.decoders.insert(
                    c.id,
                    Decoder::new(
                        &c.message_encoding,
                        &schema_name,
                        &schema_encoding,
                        &schema_data,
                    ),
                );
                self.channels.insert(
                    c.id,
                    ChannelSummary {
                        topic: c.topic,
                        schema_name,
                        schema_encoding,
                        message_encoding: c.message_encoding,
                        message_count: 0,
                    },
                );
            }
            Record::Message { header, data } => {
                let ch = self.channels.get_mut(&header.channel_id).ok_or_else(|| {
                    format!(
                        "message at byte {at} on unknown channel {}",
                        header.channel_id
                    )
                })?;
                ch.message_count += 1;
                self.messages.push(RawMessage {
                    channel_id: header.channel_id,
                    log_time: header.log_time,
                    data: data.into_owned(),
                });
            }
            _ => {}
        }
        Ok(())
    }
}

/// The schema (name, encoding, data) of channel `c`, read at byte `at`, from the schemas
/// read so far by id: empty for schema id 0, an error for an unknown one.
pub(crate) fn channel_schema(
    schemas: &HashMap<u16, (String, String, Vec<u8>)>,
    c: &mcap::records::Channel,
    at: u64,
) -> std::result::Result<(String, String, Vec<u8>), String> {
    if c.schema_id == 0 {
        return Ok((String::new(), String::new(), Vec::new()));
    }
    schemas.get(&c.schema_id).cloned().ok_or_else(|| {
        format!(
            "channel `{}` at byte {at} uses unknown schema {}",
            c.topic, c.schema_id
        )
    })
}

impl ScanState for Scan {
    fn apply(&mut self, rec: Record<'_>, at: u64) -> std::result::Result<(), String> {
        Scan::apply(self, rec, at)
    }

    fn clone_meta(&self) -> Self {
        Scan {
            schemas: self.schemas.clone(),
            decoders: self.decoders.clone(),
            channels: self.channels.clone(),
            messages: Vec::new(),
        }
    }

    fn keep(&mut self, mut trial: Self) {
        self.schemas = trial.schemas;
        self.decoders = trial.decoders;
        self.channels = trial.channels;
        self.messages.append(&mut trial.messages);
    }
}

/// What a scan of an MCAP file's records builds: the schemas, channels and messages of
/// [`walk_records`].
pub(crate) trait ScanState: Sized {
    /// Applies a schema, channel or message record found at byte `at`; an error says what
    /// is inconsistent.
    fn apply(&mut self, rec: Record<'_>, at: u64) -> std::result::Result<(), String>;
    /// The schemas and channels without the messages: what a chunk is applied to, so that it
    /// is kept whole or not at all.
    fn clone_meta(&self) -> Self;
    /// Keeps a [`ScanState::clone_meta`] copy a whole chunk was applied to.
    fn keep(&mut self, trial: Self);
}

/// How far [`walk_records`] got.
pub(crate) struct Walk {
    /// The writer named in the MCAP header.
    pub library: String,
    /// Chunks kept.
    pub chunks: u64,
    /// The byte after the data-end record, or where the walk stopped.
    pub pos: usize,
    /// True if the data-end record was read.
    pub data_end: bool,
    /// Where and what is wrong, if the walk stopped before the data-end record.
    pub problem: Option<(u64, String)>,
}

/// Walks the records of an MCAP file (`bytes`, starting with the magic) up to the data-end
/// record or the first incomplete or damaged record: schema, channel and message records
/// (also inside chunks, each chunk whole or not at all) go to `scan`, any other record but
/// the header, chunks, data end and footer to `other`. With `header_first` the first record
/// must be the MCAP header, and only that one names the library.
pub(crate) fn walk_records<S: ScanState>(
    bytes: &[u8],
    scan: &mut S,
    header_first: bool,
    mut other: impl FnMut(Record<'_>),
) -> Walk {
    let mut library = String::new();
    let mut chunks = 0u64;
    let mut pos = mcap::MAGIC.len();
    let mut data_end = false;
    // (byte offset, what is wrong)
    let mut problem: Option<(u64, String)> = None;
    let mut first = true;
    while problem.is_none() {
        let at = pos as u64;
        let rest = &bytes[pos..];
        if rest.is_empty() {
            problem = Some((at, "the file ends before the data-end record".into()));
            break;
        }
        if rest.len() < 9 {
            problem = Some((at, "the file ends inside a record header".into()));
            break;
        }
        let op = rest[0];
        let rec_len = u64_le(&rest[1..9]);
        if rec_len > (rest.len() - 9) as u64 {
            problem = Some((
                at,
                format!(
                    "the record there (opcode 0x{op:02x}) needs {} bytes but only {} remain",
                    rec_len.saturating_add(9),
                    rest.len()
                ),
            ));
            break;
        }
        let body = &rest[9..9 + rec_len as usize];
        let next = pos + 9 + rec_len as usize;
        let rec = match mcap::parse_record(op, body) {
            Ok(r) => r,
            Err(e) => {
                problem = Some((at, format!("the record there is corrupt: {e}")));
                break;
            }
        };
        if first {
            first = false;
            match &rec {
                Record::Header(h) => library = h.library.clone(),
                _ if header_first => {
                    problem = Some((at, "the first record is not an MCAP header".into()));
                    break;
                }
                _ => {}
            }
        }
        match rec {
            Record::Header(h) if !header_first => library = h.library,
            Record::Chunk { header, .. } => {
                if header.uncompressed_size > MAX_CHUNK_BYTES {
                    problem = Some((
                        at,
                        format!(
                            "the chunk there claims {} bytes uncompressed (limit {MAX_CHUNK_BYTES})",
                            header.uncompressed_size
                        ),
                    ));
                    break;
                }
                let records = match read_chunk(&bytes[pos..next]) {
                    Ok(r) => r,
                    Err(e) => {
                        problem = Some((at, format!("the chunk there is damaged: {e}")));
                        break;
                    }
                };
                // All or nothing: apply to a copy, keep it only if every record is valid.
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
                scan.keep(trial);
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
            r => other(r),
        }
        pos = next;
    }
    Walk {
        library,
        chunks,
        pos,
        data_end,
        problem,
    }
}

impl Walk {
    /// Whether the file is complete, and what was lost if not: `truncated(at, why)` for a
    /// walk stopped at byte `at`; else, after the data end, what is wrong with the summary
    /// section or the closing magic (`recovered` messages having been read).
    pub(crate) fn damage(
        self,
        bytes: &[u8],
        recovered: usize,
        truncated: impl FnOnce(u64, String) -> String,
    ) -> (bool, Option<String>) {
        let (pos, len) = (self.pos, bytes.len());
        if let Some((at, why)) = self.problem {
            (false, Some(truncated(at, why)))
        } else if self.data_end {
            match mcap::Summary::read(bytes) {
                Ok(_) if bytes.ends_with(mcap::MAGIC) => (true, None),
                Ok(_) => (
                    false,
                    Some(format!(
                        "the data section is whole but the file does not end with the MCAP \
                         magic (byte {pos} of {len}); all {recovered} messages recovered"
                    )),
                ),
                Err(e) => (
                    false,
                    Some(format!(
                        "the data section is whole but the summary section after byte {pos} \
                         is damaged ({e}); all {recovered} messages recovered"
                    )),
                ),
            }
        } else {
            (false, None)
        }
    }
}

/// The records of one chunk record (opcode, length and body), all or nothing: the chunk is
/// decompressed whole and its CRC checked before any record is parsed, and no record may be
/// longer than [`MAX_CHUNK_BYTES`] (so a corrupt length cannot ask for absurd memory).
fn read_chunk(whole: &[u8]) -> mcap::McapResult<Vec<Record<'static>>> {
    let limit = (MAX_CHUNK_BYTES as usize).max(whole.len());
    let reader = LinearReader::new_with_options(
        LinearReaderOptions::default()
            .with_skip_start_magic(true)
            .with_skip_end_magic(true)
            .with_prevalidate_chunk_crcs(true)
            .with_record_length_limit(limit),
    );
    linear_records(reader, whole)
}

/// Every record `reader` (the `mcap` crate's linear reader, with its options) finds in
/// `bytes`, parsed and owned; the first error ends the reading.
pub fn linear_records(
    mut reader: LinearReader,
    bytes: &[u8],
) -> mcap::McapResult<Vec<Record<'static>>> {
    let mut buf = bytes;
    let mut out = Vec::new();
    while let Some(event) = reader.next_event() {
        match event? {
            LinearReadEvent::ReadRequest(need) => {
                let n = need.min(buf.len());
                reader.insert(n).copy_from_slice(&buf[..n]);
                reader.notify_read(n);
                buf = &buf[n..];
            }
            LinearReadEvent::Record { opcode, data } => {
                out.push(mcap::parse_record(opcode, data)?.into_owned());
            }
        }
    }
    Ok(out)
}

fn u64_le(b: &[u8]) -> u64 {
    let mut a = [0u8; 8];
    a.copy_from_slice(&b[..8]);
    u64::from_le_bytes(a)
}

/// Reads every intact record of a flapwing MCAP file.
pub(crate) fn read_log(path: &Path) -> Result<LogFile> {
    let bytes = std::fs::read(path).map_err(|e| Error::io("cannot read", path, e))?;
    parse_log(path, &bytes)
}

fn parse_log(path: &Path, bytes: &[u8]) -> Result<LogFile> {
    let len = bytes.len() as u64;
    if bytes.len() < mcap::MAGIC.len() || &bytes[..mcap::MAGIC.len()] != mcap::MAGIC {
        let detail = if bytes.is_empty() {
            "the file is empty".to_owned()
        } else if mcap::MAGIC.starts_with(bytes) {
            format!("the file is only {len} bytes, shorter than the MCAP magic")
        } else {
            let head: Vec<String> = bytes.iter().take(8).map(|b| format!("{b:02x}")).collect();
            format!(
                "it starts with bytes {} instead of the MCAP magic 89 4d 43 41 50 30 0d 0a",
                head.join(" ")
            )
        };
        return Err(Error::NotMcap {
            path: path.to_owned(),
            detail,
        });
    }
    let mut scan = Scan::default();
    let mut metadata = Vec::new();
    let mut attachments = Vec::new();
    let walk = walk_records(bytes, &mut scan, true, |rec| match rec {
        Record::Metadata(m) => metadata.push(m),
        Record::Attachment { header, data, .. } => attachments.push(AttachmentSummary {
            name: header.name,
            media_type: header.media_type,
            bytes: data.len() as u64,
        }),
        _ => {}
    });
    let recovered = scan.messages.len();
    let chunks = walk.chunks;
    let library = walk.library.clone();
    let (complete, damage) = walk.damage(bytes, recovered, |at, why| {
        format!(
            "file truncated or damaged at byte {at} of {len}: {why}; summary section missing; \
             recovered {recovered} messages from {chunks} complete chunks"
        )
    });
    if !metadata.iter().any(|m| m.name == schema::METADATA_RUN) {
        let who = if library.is_empty() {
            String::new()
        } else {
            format!(" (written by `{library}`)")
        };
        let detail = match &damage {
            Some(d) if !complete && metadata.is_empty() && recovered == 0 => {
                format!("no `flapwing` metadata record could be read{who}: {d}")
            }
            _ => format!("the file has no `flapwing` metadata record{who}"),
        };
        return Err(Error::NotFlapwing {
            path: path.to_owned(),
            detail,
        });
    }
    Ok(LogFile {
        path: path.to_owned(),
        file_bytes: len,
        channels: scan.channels,
        decoders: scan.decoders,
        messages: scan.messages,
        metadata,
        attachments,
        complete,
        damage,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn garbage_is_not_mcap() {
        let p = Path::new("x.mcap");
        for bytes in [&b""[..], b"\x89MC", b"hello world, not mcap"] {
            assert!(matches!(parse_log(p, bytes), Err(Error::NotMcap { .. })));
        }
        // The magic alone: MCAP, but nothing flapwing in it.
        let e = parse_log(p, mcap::MAGIC).unwrap_err();
        assert!(matches!(e, Error::NotFlapwing { .. }), "{e}");
        // The magic and a header claiming an absurd length.
        let mut b = mcap::MAGIC.to_vec();
        b.push(0x01);
        b.extend_from_slice(&u64::MAX.to_le_bytes());
        assert!(matches!(parse_log(p, &b), Err(Error::NotFlapwing { .. })));
    }
}
