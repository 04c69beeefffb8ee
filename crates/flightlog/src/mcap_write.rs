//! A small MCAP writer for the recorder: the records the `mcap` crate's writer writes for a
//! flapwing log (header, metadata, the model attachment, zstd chunks with their message
//! indexes, the summary with schemas, channels, statistics and indexes, the footer), with the
//! same CRCs, written the way logging at every step needs it:
//!
//! - the simulation thread encodes the messages of a chunk straight into one buffer as MCAP
//!   message records ([`RawChunk`]); the writer thread compresses that buffer in one zstd
//!   call ([`ChunkBuilder`]) and writes the chunk, its message indexes and (at the end) the
//!   summary ([`McapWriter`]). The `mcap` crate's writer feeds zstd one small write per record
//!   field, and the foxglove SDK's writer, which goes through it, took about twice as long
//!   (`writer_ratio` in `benches/logging.rs`) and reports write errors only as
//!   `tracing::warn!`: hence this writer;
//! - zstd runs with parameters picked for speed ([`zstd_params`]);
//! - each chunk is compressed in memory and written whole when it closes, so the file only
//!   grows by whole chunks (a killed run keeps every closed chunk).
//!
//! The output is checked with the `mcap` crate's readers in the tests (CRCs, summary,
//! indexed reading).

use std::collections::BTreeMap;
use std::io::{self, Write};

use crc32fast::Hasher;
use zstd::zstd_safe::{CCtx, CParameter, Strategy};

use crate::sample::Encoded;

const MAGIC: &[u8] = b"\x89MCAP0\r\n";

mod op {
    pub const HEADER: u8 = 0x01;
    pub const FOOTER: u8 = 0x02;
    pub const SCHEMA: u8 = 0x03;
    pub const CHANNEL: u8 = 0x04;
    pub const MESSAGE: u8 = 0x05;
    pub const CHUNK: u8 = 0x06;
    pub const MESSAGE_INDEX: u8 = 0x07;
    pub const CHUNK_INDEX: u8 = 0x08;
    pub const ATTACHMENT: u8 = 0x09;
    pub const ATTACHMENT_INDEX: u8 = 0x0A;
    pub const STATISTICS: u8 = 0x0B;
    pub const METADATA: u8 = 0x0C;
    pub const METADATA_INDEX: u8 = 0x0D;
    pub const SUMMARY_OFFSET: u8 = 0x0E;
    pub const DATA_END: u8 = 0x0F;
}

/// Bytes of a message record before its data: opcode, length, channel id, sequence, log and
/// publish times.
pub(crate) const MESSAGE_HEADER_LEN: usize = 1 + 8 + 2 + 4 + 8 + 8;

/// The zstd parameters of the chunks: the "fast" strategy as in level 1, with a 64 KiB hash
/// table (hash log 14), a window that holds a whole chunk, a minimum match of 7 and an
/// acceleration factor of 8 (which also stores the literals without Huffman coding). Any
/// zstd decoder reads it (the window is 2 MiB).
///
/// Measured on the protobuf messages of a free flight at full rate (2026-12-02, one thread,
/// 2000 samples at once): these settings 0.97 us per sample for a ratio of 2.5; plain level 1
/// 2.07 us for 3.4; level -5 1.44 us for 2.5; hash log 12 with acceleration 32 0.59 us for
/// 1.5. In the files (200-sample chunks, record headers included) it is about 1.0 KB per
/// sample, against 1.8 KB of the JSON logs before, so the fastest setting that keeps the files
/// well below the old size was kept.
fn zstd_params(cctx: &mut CCtx<'static>) -> io::Result<()> {
    for p in [
        CParameter::CompressionLevel(1),
        CParameter::Strategy(Strategy::ZSTD_fast),
        CParameter::WindowLog(21),
        CParameter::HashLog(14),
        CParameter::MinMatch(7),
        CParameter::TargetLength(8),
        CParameter::ChecksumFlag(false),
    ] {
        cctx.set_parameter(p).map_err(zstd_error)?;
    }
    Ok(())
}

fn zstd_error(code: usize) -> io::Error {
    io::Error::other(format!("zstd: {}", zstd::zstd_safe::get_error_name(code)))
}

fn put_u16(b: &mut Vec<u8>, v: u16) {
    b.extend_from_slice(&v.to_le_bytes());
}
fn put_u32(b: &mut Vec<u8>, v: u32) {
    b.extend_from_slice(&v.to_le_bytes());
}
fn put_u64(b: &mut Vec<u8>, v: u64) {
    b.extend_from_slice(&v.to_le_bytes());
}
fn put_str(b: &mut Vec<u8>, s: &str) {
    put_u32(b, s.len() as u32);
    b.extend_from_slice(s.as_bytes());
}
fn put_map(b: &mut Vec<u8>, m: &BTreeMap<String, String>) {
    let len: usize = m.iter().map(|(k, v)| 8 + k.len() + v.len()).sum();
    put_u32(b, len as u32);
    for (k, v) in m {
        put_str(b, k);
        put_str(b, v);
    }
}

/// Starts a record in `b`: opcode and a length to patch with [`end_record`]; returns where
/// the record starts.
fn begin_record(b: &mut Vec<u8>, opcode: u8) -> usize {
    let at = b.len();
    b.push(opcode);
    put_u64(b, 0);
    at
}

fn end_record(b: &mut [u8], at: usize) {
    let len = (b.len() - at - 9) as u64;
    b[at + 1..at + 9].copy_from_slice(&len.to_le_bytes());
}

/// Writes the header of a message record (see [`MESSAGE_HEADER_LEN`]) for `data_len` bytes
/// of data into `out`.
pub(crate) fn message_header(
    out: &mut [u8; MESSAGE_HEADER_LEN],
    channel_id: u16,
    sequence: u32,
    t_ns: u64,
    data_len: usize,
) {
    out[0] = op::MESSAGE;
    out[1..9].copy_from_slice(&((MESSAGE_HEADER_LEN - 9 + data_len) as u64).to_le_bytes());
    out[9..11].copy_from_slice(&channel_id.to_le_bytes());
    out[11..15].copy_from_slice(&sequence.to_le_bytes());
    out[15..23].copy_from_slice(&t_ns.to_le_bytes());
    out[23..31].copy_from_slice(&t_ns.to_le_bytes());
}

struct Schema {
    id: u16,
    name: String,
    encoding: String,
    data: Vec<u8>,
}

struct Channel {
    id: u16,
    schema_id: u16,
    topic: String,
    message_encoding: String,
}

struct ChunkIndex {
    start: u64,
    end: u64,
    offset: u64,
    length: u64,
    message_index_offsets: Vec<(u16, u64)>,
    message_index_length: u64,
    compressed_size: u64,
    uncompressed_size: u64,
}

/// The records of a chunk not yet compressed: message records appended one by one (on the
/// simulation thread), with what the chunk record and its message indexes need.
#[derive(Debug, Default)]
pub(crate) struct RawChunk {
    records: Vec<u8>,
    bounds: Option<(u64, u64)>,
    /// Per channel id: (log time, offset in the uncompressed chunk) of each message.
    index: Vec<Vec<(u64, u64)>>,
}

impl RawChunk {
    /// True when the chunk holds no record.
    pub fn is_empty(&self) -> bool {
        self.records.is_empty()
    }

    /// Empties the chunk, keeping its buffers.
    pub fn clear(&mut self) {
        self.records.clear();
        self.bounds = None;
        self.index.iter_mut().for_each(Vec::clear);
    }

    /// Appends a message record of `data` (encoded straight into the chunk).
    pub fn message(&mut self, channel_id: u16, sequence: u32, t_ns: u64, data: &dyn Encoded) {
        let mut head = [0u8; MESSAGE_HEADER_LEN];
        message_header(&mut head, channel_id, sequence, t_ns, data.len());
        widen(&mut self.bounds, t_ns);
        let c = usize::from(channel_id);
        if self.index.len() <= c {
            self.index.resize_with(c + 1, Vec::new);
        }
        self.index[c].push((t_ns, self.records.len() as u64));
        self.records.extend_from_slice(&head);
        data.put(&mut self.records);
    }

    /// Appends a whole record that is not a message (a schema, a channel).
    fn record(&mut self, record: &[u8]) {
        self.records.extend_from_slice(record);
    }
}

/// A chunk closed and compressed, ready to be written (see [`McapWriter::write_chunk`]).
#[derive(Debug)]
pub(crate) struct BuiltChunk {
    compressed: Vec<u8>,
    /// Uncompressed bytes and their CRC.
    size: u64,
    crc: u32,
    bounds: Option<(u64, u64)>,
    /// (channel id, entries) of the channels with messages, by id.
    index: Vec<(u16, Vec<(u64, u64)>)>,
}

/// Compresses chunks: one zstd frame per chunk, the same bytes whichever thread runs it.
pub(crate) struct ChunkBuilder {
    cctx: CCtx<'static>,
}

impl ChunkBuilder {
    pub fn new() -> io::Result<Self> {
        let mut cctx = CCtx::try_create().ok_or_else(|| io::Error::other("zstd: no context"))?;
        zstd_params(&mut cctx)?;
        Ok(Self { cctx })
    }

    /// The chunk `raw` compressed (in one call: zstd gets the whole chunk at once).
    pub fn compress(&mut self, raw: &RawChunk) -> io::Result<BuiltChunk> {
        let mut compressed = Vec::with_capacity(zstd::zstd_safe::compress_bound(raw.records.len()));
        self.cctx
            .compress2(&mut compressed, &raw.records)
            .map_err(zstd_error)?;
        let index = raw
            .index
            .iter()
            .enumerate()
            .filter(|(_, e)| !e.is_empty())
            .map(|(c, e)| (c as u16, e.clone()))
            .collect();
        Ok(BuiltChunk {
            compressed,
            size: raw.records.len() as u64,
            crc: crc32fast::hash(&raw.records),
            bounds: raw.bounds,
            index,
        })
    }
}

/// Writes an MCAP file to `W` (see the module docs).
pub(crate) struct McapWriter<W: Write> {
    out: W,
    /// Bytes written to `out`, and the CRC of all of them (the data section's CRC).
    pos: u64,
    crc: Hasher,
    /// The chunk this writer builds from the records given to it, and its compressor.
    open: RawChunk,
    builder: ChunkBuilder,
    rec: Vec<u8>,
    schemas: Vec<Schema>,
    channels: Vec<Channel>,
    chunk_indexes: Vec<ChunkIndex>,
    /// (offset, length, log time, create time, data size, name, media type).
    attachment_indexes: Vec<(u64, u64, u64, u64, u64, String, String)>,
    /// (offset, length, name).
    metadata_indexes: Vec<(u64, u64, String)>,
    bounds: Option<(u64, u64)>,
    counts: BTreeMap<u16, u64>,
}

fn widen(bounds: &mut Option<(u64, u64)>, t: u64) {
    *bounds = Some(match *bounds {
        None => (t, t),
        Some((a, b)) => (a.min(t), b.max(t)),
    });
}

impl<W: Write> McapWriter<W> {
    /// Writes the magic and the header record.
    pub fn new(out: W, profile: &str, library: &str) -> io::Result<Self> {
        let mut w = Self {
            out,
            pos: 0,
            crc: Hasher::new(),
            open: RawChunk::default(),
            builder: ChunkBuilder::new()?,
            rec: Vec::with_capacity(4096),
            schemas: Vec::new(),
            channels: Vec::new(),
            chunk_indexes: Vec::new(),
            attachment_indexes: Vec::new(),
            metadata_indexes: Vec::new(),
            bounds: None,
            counts: BTreeMap::new(),
        };
        w.emit(MAGIC)?;
        let mut b = std::mem::take(&mut w.rec);
        b.clear();
        let at = begin_record(&mut b, op::HEADER);
        put_str(&mut b, profile);
        put_str(&mut b, library);
        end_record(&mut b, at);
        let res = w.emit(&b);
        w.rec = b;
        res.map(|()| w)
    }

    /// Writes bytes to the file (data section: counted in its CRC).
    fn emit(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.out.write_all(bytes)?;
        self.crc.update(bytes);
        self.pos += bytes.len() as u64;
        Ok(())
    }

    /// Writes the record built in `self.rec`; returns its offset and length.
    fn emit_rec(&mut self) -> io::Result<(u64, u64)> {
        let b = std::mem::take(&mut self.rec);
        let at = self.pos;
        let res = self.emit(&b);
        let len = b.len() as u64;
        self.rec = b;
        res.map(|()| (at, len))
    }

    /// A metadata record (closes the open chunk first).
    pub fn metadata(&mut self, name: &str, metadata: &BTreeMap<String, String>) -> io::Result<()> {
        self.close_chunk()?;
        let mut b = std::mem::take(&mut self.rec);
        b.clear();
        let at = begin_record(&mut b, op::METADATA);
        put_str(&mut b, name);
        put_map(&mut b, metadata);
        end_record(&mut b, at);
        self.rec = b;
        let (offset, length) = self.emit_rec()?;
        self.metadata_indexes
            .push((offset, length, name.to_owned()));
        Ok(())
    }

    /// An attachment record (closes the open chunk first).
    pub fn attachment(
        &mut self,
        log_time: u64,
        create_time: u64,
        name: &str,
        media_type: &str,
        data: &[u8],
    ) -> io::Result<()> {
        self.close_chunk()?;
        let mut b = std::mem::take(&mut self.rec);
        b.clear();
        let at = begin_record(&mut b, op::ATTACHMENT);
        put_u64(&mut b, log_time);
        put_u64(&mut b, create_time);
        put_str(&mut b, name);
        put_str(&mut b, media_type);
        put_u64(&mut b, data.len() as u64);
        b.extend_from_slice(data);
        let crc = crc32fast::hash(&b[at + 9..]);
        put_u32(&mut b, crc);
        end_record(&mut b, at);
        self.rec = b;
        let (offset, length) = self.emit_rec()?;
        self.attachment_indexes.push((
            offset,
            length,
            log_time,
            create_time,
            data.len() as u64,
            name.to_owned(),
            media_type.to_owned(),
        ));
        Ok(())
    }

    /// Adds a schema (written into the open chunk); the id of an identical one if any.
    pub fn add_schema(&mut self, name: &str, encoding: &str, data: &[u8]) -> io::Result<u16> {
        if let Some(s) = self
            .schemas
            .iter()
            .find(|s| s.name == name && s.encoding == encoding && s.data == data)
        {
            return Ok(s.id);
        }
        let id = self.schemas.len() as u16 + 1;
        let s = Schema {
            id,
            name: name.to_owned(),
            encoding: encoding.to_owned(),
            data: data.to_owned(),
        };
        let mut b = std::mem::take(&mut self.rec);
        b.clear();
        schema_record(&mut b, &s);
        self.schemas.push(s);
        let res = self.chunk_record(&b);
        self.rec = b;
        res.map(|()| id)
    }

    /// Adds a channel (written into the open chunk); its id.
    pub fn add_channel(
        &mut self,
        schema_id: u16,
        topic: &str,
        message_encoding: &str,
    ) -> io::Result<u16> {
        let id = self.channels.len() as u16 + 1;
        let c = Channel {
            id,
            schema_id,
            topic: topic.to_owned(),
            message_encoding: message_encoding.to_owned(),
        };
        let mut b = std::mem::take(&mut self.rec);
        b.clear();
        channel_record(&mut b, &c);
        self.channels.push(c);
        let res = self.chunk_record(&b);
        self.rec = b;
        res.map(|()| id)
    }

    /// Appends a whole record to the open chunk.
    fn chunk_record(&mut self, record: &[u8]) -> io::Result<()> {
        self.open.record(record);
        Ok(())
    }

    /// Closes the open chunk, if it holds anything: compresses it and writes the chunk record
    /// and its message indexes.
    pub fn close_chunk(&mut self) -> io::Result<()> {
        if self.open.is_empty() {
            return Ok(());
        }
        let chunk = self.builder.compress(&self.open)?;
        self.open.clear();
        self.write_chunk(&chunk)
    }

    /// Writes a chunk built elsewhere (by a [`ChunkBuilder`] of another thread) after closing
    /// the open one: the chunk record, its message indexes, and its part of the summary.
    pub fn write_chunk(&mut self, chunk: &BuiltChunk) -> io::Result<()> {
        self.close_chunk()?;
        let BuiltChunk {
            compressed,
            size,
            crc,
            bounds,
            index,
            ..
        } = chunk;
        for (channel, entries) in index.iter() {
            *self.counts.entry(*channel).or_insert(0) += entries.len() as u64;
        }
        let (start, end) = bounds.unwrap_or((0, 0));
        if bounds.is_some() {
            widen(&mut self.bounds, start);
            widen(&mut self.bounds, end);
        }
        let chunk_offset = self.pos;
        let mut b = std::mem::take(&mut self.rec);
        b.clear();
        b.push(op::CHUNK);
        let body = 8 + 8 + 8 + 4 + (4 + 4) + 8 + compressed.len();
        put_u64(&mut b, body as u64);
        put_u64(&mut b, start);
        put_u64(&mut b, end);
        put_u64(&mut b, *size);
        put_u32(&mut b, *crc);
        put_str(&mut b, "zstd");
        put_u64(&mut b, compressed.len() as u64);
        self.rec = b;
        self.emit_rec()?;
        self.emit(compressed)?;
        let chunk_length = self.pos - chunk_offset;
        // Message indexes, by channel id.
        let mut b = std::mem::take(&mut self.rec);
        b.clear();
        let index_start = self.pos;
        let mut offsets = Vec::with_capacity(index.len());
        for (channel, entries) in index.iter() {
            offsets.push((*channel, index_start + b.len() as u64));
            let at = begin_record(&mut b, op::MESSAGE_INDEX);
            put_u16(&mut b, *channel);
            put_u32(&mut b, (entries.len() * 16) as u32);
            for (t, off) in entries {
                put_u64(&mut b, *t);
                put_u64(&mut b, *off);
            }
            end_record(&mut b, at);
        }
        self.rec = b;
        let (_, index_length) = self.emit_rec()?;
        self.chunk_indexes.push(ChunkIndex {
            start,
            end,
            offset: chunk_offset,
            length: chunk_length,
            message_index_offsets: offsets,
            message_index_length: index_length,
            compressed_size: compressed.len() as u64,
            uncompressed_size: *size,
        });
        Ok(())
    }

    /// Closes the open chunk and flushes the file.
    pub fn flush(&mut self) -> io::Result<()> {
        self.close_chunk()?;
        self.out.flush()
    }

    /// Writes the data end, the summary, the footer and the closing magic; flushes.
    pub fn finish(&mut self) -> io::Result<()> {
        self.close_chunk()?;
        let mut b = std::mem::take(&mut self.rec);
        b.clear();
        let at = begin_record(&mut b, op::DATA_END);
        put_u32(&mut b, self.crc.clone().finalize());
        end_record(&mut b, at);
        self.rec = b;
        self.emit_rec()?;

        // The summary, built in memory.
        let summary_start = self.pos;
        let mut s = Vec::with_capacity(64 * 1024);
        let mut groups: Vec<(u8, u64, u64)> = Vec::new();
        let mut group = |s: &Vec<u8>, opcode: u8, from: usize| {
            if s.len() > from {
                groups.push((opcode, summary_start + from as u64, (s.len() - from) as u64));
            }
        };
        let from = s.len();
        for sc in &self.schemas {
            schema_record(&mut s, sc);
        }
        group(&s, op::SCHEMA, from);
        let from = s.len();
        for c in &self.channels {
            channel_record(&mut s, c);
        }
        group(&s, op::CHANNEL, from);
        let from = s.len();
        let at = begin_record(&mut s, op::STATISTICS);
        put_u64(&mut s, self.counts.values().sum());
        put_u16(&mut s, self.schemas.len() as u16);
        put_u32(&mut s, self.channels.len() as u32);
        put_u32(&mut s, self.attachment_indexes.len() as u32);
        put_u32(&mut s, self.metadata_indexes.len() as u32);
        put_u32(&mut s, self.chunk_indexes.len() as u32);
        let (start, end) = self.bounds.unwrap_or((0, 0));
        put_u64(&mut s, start);
        put_u64(&mut s, end);
        put_u32(&mut s, (self.counts.len() * 10) as u32);
        for (id, n) in &self.counts {
            put_u16(&mut s, *id);
            put_u64(&mut s, *n);
        }
        end_record(&mut s, at);
        group(&s, op::STATISTICS, from);
        let from = s.len();
        for ci in &self.chunk_indexes {
            let at = begin_record(&mut s, op::CHUNK_INDEX);
            put_u64(&mut s, ci.start);
            put_u64(&mut s, ci.end);
            put_u64(&mut s, ci.offset);
            put_u64(&mut s, ci.length);
            put_u32(&mut s, (ci.message_index_offsets.len() * 10) as u32);
            for (id, off) in &ci.message_index_offsets {
                put_u16(&mut s, *id);
                put_u64(&mut s, *off);
            }
            put_u64(&mut s, ci.message_index_length);
            put_str(&mut s, "zstd");
            put_u64(&mut s, ci.compressed_size);
            put_u64(&mut s, ci.uncompressed_size);
            end_record(&mut s, at);
        }
        group(&s, op::CHUNK_INDEX, from);
        let from = s.len();
        for (offset, length, log_time, create_time, size, name, media) in &self.attachment_indexes {
            let at = begin_record(&mut s, op::ATTACHMENT_INDEX);
            put_u64(&mut s, *offset);
            put_u64(&mut s, *length);
            put_u64(&mut s, *log_time);
            put_u64(&mut s, *create_time);
            put_u64(&mut s, *size);
            put_str(&mut s, name);
            put_str(&mut s, media);
            end_record(&mut s, at);
        }
        group(&s, op::ATTACHMENT_INDEX, from);
        let from = s.len();
        for (offset, length, name) in &self.metadata_indexes {
            let at = begin_record(&mut s, op::METADATA_INDEX);
            put_u64(&mut s, *offset);
            put_u64(&mut s, *length);
            put_str(&mut s, name);
            end_record(&mut s, at);
        }
        group(&s, op::METADATA_INDEX, from);
        let summary_offset_start = summary_start + s.len() as u64;
        for (opcode, start, length) in groups {
            let at = begin_record(&mut s, op::SUMMARY_OFFSET);
            s.push(opcode);
            put_u64(&mut s, start);
            put_u64(&mut s, length);
            end_record(&mut s, at);
        }
        // The footer; its CRC covers the summary and the footer up to the CRC itself.
        s.push(op::FOOTER);
        put_u64(&mut s, 8 + 8 + 4);
        put_u64(&mut s, summary_start);
        put_u64(&mut s, summary_offset_start);
        let crc = crc32fast::hash(&s);
        put_u32(&mut s, crc);
        s.extend_from_slice(MAGIC);
        self.emit(&s)?;
        self.out.flush()
    }

    /// Bytes written so far.
    pub fn position(&self) -> u64 {
        self.pos
    }
}

fn schema_record(b: &mut Vec<u8>, s: &Schema) {
    let at = begin_record(b, op::SCHEMA);
    put_u16(b, s.id);
    put_str(b, &s.name);
    put_str(b, &s.encoding);
    put_u32(b, s.data.len() as u32);
    b.extend_from_slice(&s.data);
    end_record(b, at);
}

fn channel_record(b: &mut Vec<u8>, c: &Channel) {
    let at = begin_record(b, op::CHANNEL);
    put_u16(b, c.id);
    put_u16(b, c.schema_id);
    put_str(b, &c.topic);
    put_str(b, &c.message_encoding);
    put_u32(b, 0);
    end_record(b, at);
}
