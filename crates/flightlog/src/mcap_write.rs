//! A small MCAP writer for the recorder: the records the `mcap` crate's writer writes for a
//! flapwing log (header, metadata, the model attachment, zstd chunks with their message
//! indexes, the summary with schemas, channels, statistics and indexes, the footer), with the
//! same CRCs, written the way logging at every step needs it:
//!
//! - the simulation thread encodes the messages of a chunk straight into one buffer as MCAP
//!   message records ([`crate::chunk::RawChunk`]); the writer thread compresses that buffer
//!   in one zstd call ([`crate::chunk::ChunkBuilder`]) and writes the chunk, its message
//!   indexes and (at the end) the summary ([`McapWriter`]). The `mcap` crate's writer feeds zstd one small write
//!   per record field, and the foxglove SDK's writer, which goes through it, took about twice
//!   as long (`writer_ratio` in `benches/logging.rs`) and reports write errors only as
//!   `tracing::warn!`: hence this writer;
//! - each chunk is compressed in memory and written whole when it closes, so the file only
//!   grows by whole chunks (a killed run keeps every closed chunk).
//!
//! The output is checked with the `mcap` crate's readers in the tests (CRCs, summary,
//! indexed reading).

use std::collections::BTreeMap;
use std::io::{self, Write};

use crc32fast::Hasher;

use crate::chunk::{BuiltChunk, ChunkBuilder, RawChunk, widen};

const MAGIC: &[u8] = b"\x89MCAP0\r\n";

mod op {
    pub const HEADER: u8 = 0x01;
    pub const FOOTER: u8 = 0x02;
    pub const SCHEMA: u8 = 0x03;
    pub const CHANNEL: u8 = 0x04;
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
