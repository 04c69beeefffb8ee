//! MCAP chunks: the message records of a chunk as the simulation's samples are encoded into
//! it ([`RawChunk`]), and the chunk compressed with zstd in one call ([`ChunkBuilder`]) for
//! [`crate::mcap_write::McapWriter::write_chunk`].

use std::io;

use zstd::zstd_safe::{CCtx, CParameter, Strategy};

use crate::pb::Pb;
use crate::sample::Encoded;

/// The opcode of a message record.
const OP_MESSAGE: u8 = 0x05;

/// Bytes of a message record before its data: opcode, length, channel id, sequence, log and
/// publish times.
pub(crate) const MESSAGE_HEADER_LEN: usize = 1 + 8 + 2 + 4 + 8 + 8;

/// Writes the header of a message record (see [`MESSAGE_HEADER_LEN`]) for `data_len` bytes
/// of data into `out`.
pub(crate) fn message_header(
    out: &mut [u8; MESSAGE_HEADER_LEN],
    channel_id: u16,
    sequence: u32,
    t_ns: u64,
    data_len: usize,
) {
    out[0] = OP_MESSAGE;
    out[1..9].copy_from_slice(&((MESSAGE_HEADER_LEN - 9 + data_len) as u64).to_le_bytes());
    out[9..11].copy_from_slice(&channel_id.to_le_bytes());
    out[11..15].copy_from_slice(&sequence.to_le_bytes());
    out[15..23].copy_from_slice(&t_ns.to_le_bytes());
    out[23..31].copy_from_slice(&t_ns.to_le_bytes());
}

/// The zstd parameters of the chunks: the "fast" strategy as in level 1, with a 128 KiB hash
/// table (hash log 15), a window that holds a whole chunk, a minimum match of 7 and an
/// acceleration factor of 4 (small enough that zstd Huffman-codes the literals: the exponent
/// bytes of the doubles repeat). Any zstd decoder reads it (the window is 2 MiB).
///
/// Measured on the chunks of a 0.5 s free flight at full rate (2026-12-02, instructions
/// counted with callgrind, 21.4 MB of records with the force arrows): these settings 7.66 MB,
/// 23.3 k instructions per sample; the acceleration factor 8 of before 9.24 MB (hash log
/// 15) or 9.45 MB (hash log 14) for 19.1 k; factor 5 8.17 MB for 22.4 k; hash log 16 and 17
/// gain under 1 %. Factors 6 and above store the literals raw. The files are about 7 % (at
/// 2000 Hz) and 15 % (full rate) smaller than with the settings before, force arrows
/// included, for about 20 % more time of the writer thread, which at full rate still has
/// more time than the simulation thread needs to fill the chunks.
fn zstd_params(cctx: &mut CCtx<'static>) -> io::Result<()> {
    for p in [
        CParameter::CompressionLevel(1),
        CParameter::Strategy(Strategy::ZSTD_fast),
        CParameter::WindowLog(21),
        CParameter::HashLog(15),
        CParameter::MinMatch(7),
        CParameter::TargetLength(4),
        CParameter::ChecksumFlag(false),
    ] {
        cctx.set_parameter(p).map_err(zstd_error)?;
    }
    Ok(())
}

fn zstd_error(code: usize) -> io::Error {
    io::Error::other(format!("zstd: {}", zstd::zstd_safe::get_error_name(code)))
}

pub(crate) fn widen(bounds: &mut Option<(u64, u64)>, t: u64) {
    *bounds = Some(match *bounds {
        None => (t, t),
        Some((a, b)) => (a.min(t), b.max(t)),
    });
}

/// The records of a chunk not yet compressed: message records appended one by one, with what
/// the chunk record and its message indexes need.
///
/// The records are the first `used` bytes of `buf`, which only grows (zero-filled once): a
/// message is encoded straight into the room after them, so the buffer is neither cleared
/// nor filled again for each message.
#[derive(Debug, Default)]
pub(crate) struct RawChunk {
    buf: Vec<u8>,
    used: usize,
    bounds: Option<(u64, u64)>,
    /// Per channel id: (log time, offset in the uncompressed chunk) of each message.
    index: Vec<Vec<(u64, u64)>>,
}

impl RawChunk {
    /// True when the chunk holds no record.
    pub fn is_empty(&self) -> bool {
        self.used == 0
    }

    /// The records.
    pub fn records(&self) -> &[u8] {
        &self.buf[..self.used]
    }

    /// The `n` bytes after the records (growing the buffer when needed).
    fn room(&mut self, n: usize) -> &mut [u8] {
        let need = self.used + n;
        if self.buf.len() < need {
            self.buf
                .resize(need.max(2 * self.buf.len()).max(64 * 1024), 0);
        }
        &mut self.buf[self.used..need]
    }

    fn append(&mut self, bytes: &[u8]) {
        self.room(bytes.len()).copy_from_slice(bytes);
        self.used += bytes.len();
    }

    /// Empties the chunk, keeping its buffers.
    pub fn clear(&mut self) {
        self.used = 0;
        self.bounds = None;
        self.index.iter_mut().for_each(Vec::clear);
    }

    /// Records the index entry of a message record starting now.
    fn index_entry(&mut self, channel_id: u16, t_ns: u64) {
        widen(&mut self.bounds, t_ns);
        let c = usize::from(channel_id);
        if self.index.len() <= c {
            self.index.resize_with(c + 1, Vec::new);
        }
        self.index[c].push((t_ns, self.used as u64));
    }

    /// Appends a message record of `data` (encoded by prost: the planforms, events).
    pub fn message(&mut self, channel_id: u16, sequence: u32, t_ns: u64, data: &dyn Encoded) {
        let mut head = [0u8; MESSAGE_HEADER_LEN];
        message_header(&mut head, channel_id, sequence, t_ns, data.len());
        self.index_entry(channel_id, t_ns);
        let mut bytes = Vec::with_capacity(MESSAGE_HEADER_LEN + data.len());
        bytes.extend_from_slice(&head);
        data.put(&mut bytes);
        self.append(&bytes);
    }

    /// Appends a message record whose data `encode` writes, in at most `bound` bytes (the
    /// record's length is filled in afterwards).
    #[inline]
    pub fn message_with(
        &mut self,
        channel_id: u16,
        sequence: u32,
        t_ns: u64,
        bound: usize,
        encode: impl FnOnce(&mut Pb),
    ) {
        self.index_entry(channel_id, t_ns);
        let room = self.room(MESSAGE_HEADER_LEN + bound);
        let (head, data) = room.split_at_mut(MESSAGE_HEADER_LEN);
        let mut p = Pb::new(data);
        encode(&mut p);
        let len = p.len();
        let mut h = [0u8; MESSAGE_HEADER_LEN];
        message_header(&mut h, channel_id, sequence, t_ns, len);
        head.copy_from_slice(&h);
        self.used += MESSAGE_HEADER_LEN + len;
    }

    /// Appends a whole record that is not a message (a schema, a channel).
    pub(crate) fn record(&mut self, record: &[u8]) {
        self.append(record);
    }
}

/// A chunk closed and compressed, ready to be written (see
/// [`crate::mcap_write::McapWriter::write_chunk`]).
#[derive(Debug)]
pub(crate) struct BuiltChunk {
    pub compressed: Vec<u8>,
    /// Uncompressed bytes and their CRC.
    pub size: u64,
    pub crc: u32,
    pub bounds: Option<(u64, u64)>,
    /// (channel id, entries) of the channels with messages, by id.
    pub index: Vec<(u16, Vec<(u64, u64)>)>,
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
        let records = raw.records();
        let mut compressed = Vec::with_capacity(zstd::zstd_safe::compress_bound(records.len()));
        self.cctx
            .compress2(&mut compressed, records)
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
            size: records.len() as u64,
            crc: crc32fast::hash(records),
            bounds: raw.bounds,
            index,
        })
    }
}
