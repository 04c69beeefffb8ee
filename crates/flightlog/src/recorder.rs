//! The recorder: one object that writes a run to MCAP and/or Rerun.
//!
//! Threads: [`Recorder`] runs on the simulation thread. It decimates, counts, and queues the
//! logged steps (copies of [`StepOutput`], in batches) to a writer thread that owns the
//! outputs: it serializes the messages and writes the MCAP file (zstd chunks) and the Rerun
//! streams. Events travel through the same queue, so everything stays in order. On a
//! two-core machine the writing then costs the simulation little wall time. When the writer
//! thread falls behind (logging every step), the simulation thread takes work over: with an
//! MCAP file only, it serializes and compresses a whole chunk itself whenever a chunk starts
//! while the writer thread still has at least [`BUILD_AT`] raw samples to serialize (so the
//! writer thread stays busy meanwhile, and the share of chunks built here settles where the
//! two threads are equally busy), and only compressed bytes of that chunk cross between the
//! cores (the JSON itself crossing cost a third of the simulation thread's time when the two
//! cores did not share a cache); with a Rerun output, it serializes single samples. The bytes
//! are the same either way.
//!
//! Chunks are closed from the simulation thread's side, from the samples alone (every
//! [`FLUSH_INTERVAL_NS`] of simulated time, every [`CHUNK_SAMPLES`] samples, before and
//! after every event). At a close `record` waits until all but the [`MAX_UNACKED`] newest
//! chunks are in the file (and at an event, until every chunk is), so the writer thread
//! works through a backlog of up to two chunks while the simulation fills the next, and a
//! killed run loses at most its three newest chunks. Each
//! chunk is compressed in memory and written whole, so the file grows by whole chunks only.
//! The file's bytes do not depend on thread timing.
//!
//! Waiting: a thread asleep on a queue must be woken by the other one, which costs tens of
//! microseconds on a virtual machine. So the idle writer thread polls the queue every
//! [`POLL`] (the simulation thread only wakes it for a job it waits for), both threads poll
//! briefly before sleeping where the other answers quickly, and a full queue is polled too.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::mpsc::{self, Receiver, RecvError, Sender, SyncSender, TryRecvError, TrySendError};
use std::sync::{Arc, Mutex, OnceLock};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use flapsim::{Controls, StepOutput, Vehicle};

use crate::mcap_write::{BuiltChunk, ChunkBuilder, McapWriter};
use crate::messages::{self, Built, SAMPLE_MESSAGES, SampleJson, WingStatic};
use crate::schema::{self, CHANNELS, MESSAGE_ENCODING, SCHEMA_ENCODING};
use crate::{Error, Level, LogOptions, Result, RunInfo};

/// Close the current chunk (so a killed run keeps it) at least this often, simulated time.
const FLUSH_INTERVAL_NS: u64 = 50_000_000;
/// Close the current chunk after this many samples (about 1.2 MB of JSON; the MCAP
/// writer's own size limit is off so that only the simulation thread decides).
const CHUNK_SAMPLES: u64 = 200;
/// Index of the /events channel in [`CHANNELS`].
const EVENTS: usize = 10;
/// Samples per batch sent to the writer thread at most.
const BATCH: usize = 8;
/// Batches queued for the writer thread at most (room for [`BUILD_AT`] raw samples and a
/// whole chunk more).
const QUEUE: usize = 64;
/// With this many batches not yet written, the simulation thread serializes samples itself.
const HELP_AT: usize = 2;
/// With this many raw samples not yet serialized by the writer thread when a chunk starts,
/// the simulation thread builds that chunk itself (MCAP only; at the default rate the writer
/// thread is never this far behind). A chunk built here takes the simulation thread about as
/// long as the writer thread needs for this backlog, so the writer thread stays busy while
/// the simulation thread builds, and the simulation thread builds only the share of the
/// chunks that balances the two threads (about one in three at full rate).
const BUILD_AT: usize = 200;
/// Chunk closes not yet in the file that `record` lets pass: at a close it waits until all
/// but this many are written. One would stall the simulation thread whenever the writer
/// thread's backlog exceeds a chunk, which [`BUILD_AT`] needs.
const MAX_UNACKED: usize = 2;
/// Batches are sent at once from this many samples before a chunk close.
const NEAR: u64 = 2;
/// How long the writer thread polls for the close that follows an early batch, and the
/// simulation thread for the writer's acknowledgement, before they sleep (waking a sleeping
/// thread takes tens of microseconds on a virtual machine).
const WRITER_SPIN: Duration = Duration::from_micros(300);
const ACK_SPIN: Duration = Duration::from_micros(500);
/// How long the simulation thread polls a full queue without sleeping.
const SEND_SPIN: Duration = Duration::from_micros(20);

/// How the writer thread waits for work when idle: it polls every [`POLL`] for up to
/// [`IDLE_POLL`] since its last job, then sleeps on the queue. A thread sleeping on the queue
/// must be woken by the sender, which costs the simulation thread tens of microseconds per
/// batch on a virtual machine; polling puts that cost (less of it) on the writer's side.
const POLL: Duration = Duration::from_micros(100);
const IDLE_POLL: Duration = Duration::from_millis(20);

/// The writer thread's next job (see [`POLL`]); `spin`: poll without sleeping for a while
/// first.
fn next_job<T>(rx: &Receiver<T>, spin: bool) -> std::result::Result<T, RecvError> {
    if spin && let Some(r) = recv_spinning_for(rx, WRITER_SPIN) {
        return r;
    }
    let idle = Instant::now();
    loop {
        match rx.try_recv() {
            Ok(v) => return Ok(v),
            Err(TryRecvError::Disconnected) => return Err(RecvError),
            Err(TryRecvError::Empty) => {}
        }
        if idle.elapsed() >= IDLE_POLL {
            return rx.recv();
        }
        // Woken early by the simulation thread for a job it waits for.
        std::thread::park_timeout(POLL);
    }
}

/// Polls `rx` for up to `spin`: `None` if nothing came.
fn recv_spinning_for<T>(
    rx: &Receiver<T>,
    spin: Duration,
) -> Option<std::result::Result<T, RecvError>> {
    let start = Instant::now();
    loop {
        for _ in 0..64 {
            match rx.try_recv() {
                Ok(v) => return Some(Ok(v)),
                Err(TryRecvError::Disconnected) => return Some(Err(RecvError)),
                Err(TryRecvError::Empty) => std::hint::spin_loop(),
            }
        }
        if start.elapsed() >= spin {
            return None;
        }
    }
}

/// `rx.recv()`, polling for up to `spin` first.
fn recv_spinning<T>(rx: &Receiver<T>, spin: Duration) -> std::result::Result<T, RecvError> {
    recv_spinning_for(rx, spin).unwrap_or_else(|| rx.recv())
}

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
    writer: McapWriter<BufWriter<File>>,
    path: PathBuf,
    channel_ids: [u16; 11],
    sequences: [u32; 11],
}

impl McapSink {
    #[inline]
    fn write(&mut self, index: usize, t_ns: u64, data: &[u8]) -> Result<()> {
        let sequence = self.sequences[index];
        self.sequences[index] = sequence.wrapping_add(1);
        let res = self
            .writer
            .message(self.channel_ids[index], sequence, t_ns, data);
        res.map_err(|e| self.io_error(e))
    }

    fn io_error(&self, e: std::io::Error) -> Error {
        Error::io("cannot write", &self.path, e)
    }

    /// Writes a chunk the simulation thread built, of `samples` samples.
    fn write_built(&mut self, chunk: &BuiltChunk, samples: u32) -> Result<()> {
        let res = self.writer.write_chunk(chunk);
        res.map_err(|e| self.io_error(e))?;
        for s in &mut self.sequences[..SAMPLE_MESSAGES] {
            *s = s.wrapping_add(samples);
        }
        Ok(())
    }

    /// Closes the open chunk and writes it to the file.
    fn flush(&mut self) -> Result<()> {
        let res = self.writer.flush();
        res.map_err(|e| self.io_error(e))
    }
}

/// One logged step, as the simulation thread hands it to the writer thread: the step's
/// output, or its messages already serialized into the batch's `bytes`.
enum Item {
    Raw(StepOutput),
    Built(Built),
}

/// Consecutive samples for the writer thread.
struct Batch {
    items: Vec<Item>,
    /// The [`Item::Raw`] items among them (counted in [`Shared::raw_backlog`]).
    raw: usize,
    /// The messages of the [`Item::Built`] items.
    bytes: Vec<u8>,
    /// A whole chunk the simulation thread built and compressed itself, and its number of
    /// samples (the batch has no items then).
    built: Option<(BuiltChunk, u32)>,
    /// Close the MCAP chunk after the last item and acknowledge.
    close: bool,
    /// More comes soon (a close, or the next batch of a run that keeps the writer thread
    /// busy): poll for it instead of sleeping.
    poll_next: bool,
}

impl Batch {
    fn new() -> Self {
        Self {
            items: Vec::with_capacity(BATCH),
            raw: 0,
            bytes: Vec::new(),
            built: None,
            close: false,
            poll_next: false,
        }
    }
}

/// What the simulation thread sends to the writer thread, in recording order.
enum Job {
    Samples(Batch),
    /// An event: written, its chunk closed, then (with `ack`) acknowledged.
    Event {
        t_ns: u64,
        level: Level,
        message: String,
        ack: bool,
    },
    /// Write the `flapwing.end` metadata (these keys) and finish every output.
    Finish(BTreeMap<String, String>),
}

/// State shared by the two threads.
#[derive(Debug, Default)]
struct Shared {
    /// Sample batches sent and not yet written.
    in_flight: AtomicUsize,
    /// Raw samples sent and not yet serialized (the writer thread's backlog).
    raw_backlog: AtomicUsize,
    /// The writer thread stopped on an error (kept in `error` until reported).
    failed: AtomicBool,
    error: Mutex<Option<Error>>,
}

/// The outputs, owned by the writer thread.
struct Sinks {
    /// The MCAP file until the writer thread has written its start, then its writer.
    mcap_start: Option<McapStart>,
    mcap: Option<McapSink>,
    #[cfg(feature = "rerun")]
    rerun: Option<crate::rerun_sink::RerunSink>,
    json: SampleJson,
    buf: Vec<u8>,
}

impl Sinks {
    fn any(&self) -> bool {
        #[cfg(feature = "rerun")]
        if self.rerun.is_some() {
            return true;
        }
        self.mcap.is_some() || self.mcap_start.is_some()
    }

    fn sample(&mut self, bytes: &[u8], s: &Built) -> Result<()> {
        if let Some(m) = &mut self.mcap {
            for i in 0..SAMPLE_MESSAGES {
                m.write(i, s.t_ns, s.message(bytes, i))?;
            }
        }
        #[cfg(feature = "rerun")]
        if let Some(r) = &self.rerun {
            r.frame(&s.frame)?;
        }
        Ok(())
    }

    fn batch(&mut self, batch: &mut Batch) -> Result<()> {
        if let Some((chunk, samples)) = batch.built.take()
            && let Some(m) = &mut self.mcap
        {
            m.write_built(&chunk, samples)?;
        }
        for item in &batch.items {
            match item {
                Item::Raw(out) => {
                    let mut buf = std::mem::take(&mut self.buf);
                    buf.clear();
                    let s = self.json.build(out, &mut buf);
                    let res = self.sample(&buf, &s);
                    self.buf = buf;
                    res?;
                }
                Item::Built(s) => self.sample(&batch.bytes, s)?,
            }
        }
        if let Some(m) = &mut self.mcap {
            if batch.close {
                m.flush()?;
            } else {
                // Compress what came. Never flush zstd mid-chunk: a flush ends a zstd block,
                // and a chunk must be the same bytes whichever thread builds it.
                let res = m.writer.pump();
                res.map_err(|e| m.io_error(e))?;
            }
        }
        Ok(())
    }

    fn event(&mut self, t_ns: u64, level: Level, message: &str) -> Result<()> {
        if let Some(m) = &mut self.mcap {
            let data = messages::log_message(t_ns, level as u8, message)?;
            // An event gets a chunk of its own: the samples before it are in a chunk that
            // either thread may have built.
            m.flush()?;
            m.write(EVENTS, t_ns, &data)?;
            m.flush()?;
        }
        #[cfg(feature = "rerun")]
        if let Some(r) = &self.rerun {
            r.event(t_ns, level, message)?;
        }
        Ok(())
    }

    /// Writes the end metadata and finishes every output; the MCAP file's size.
    fn finish(&mut self, end: BTreeMap<String, String>) -> Result<u64> {
        let mut first_error = None;
        let mut mcap_bytes = 0;
        if let Some(mut m) = self.mcap.take() {
            let res = (|| -> std::io::Result<u64> {
                m.writer.metadata(schema::METADATA_END, &end)?;
                m.writer.finish()?;
                let mut file = m
                    .writer
                    .into_inner()
                    .into_inner()
                    .map_err(|e| e.into_error())?;
                file.flush()?;
                Ok(file.metadata()?.len())
            })()
            .map_err(|e| Error::io("cannot write", &m.path, e));
            match res {
                Ok(len) => mcap_bytes = len,
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
            None => Ok(mcap_bytes),
        }
    }
}

/// The writer thread: writes every job in order until [`Job::Finish`]. On an error it keeps
/// it in `shared` and stops; the simulation thread reports it. Returns the MCAP file's size
/// after a successful finish.
fn writer_thread(
    mut sinks: Sinks,
    jobs: Receiver<Job>,
    recycle: Sender<Batch>,
    acks: Sender<()>,
    shared: Arc<Shared>,
) -> Option<u64> {
    let mut run = || -> Result<Option<u64>> {
        if let Some(start) = sinks.mcap_start.take() {
            sinks.mcap = Some(open_mcap(start)?);
        }
        let mut spin = false;
        loop {
            let job = next_job(&jobs, spin);
            let Ok(job) = job else { break };
            spin = false;
            match job {
                Job::Samples(mut batch) => {
                    sinks.batch(&mut batch)?;
                    spin = batch.poll_next;
                    shared.raw_backlog.fetch_sub(batch.raw, Ordering::Release);
                    shared.in_flight.fetch_sub(1, Ordering::Release);
                    if batch.close {
                        // The simulation thread waits for it: nothing is queued behind.
                        let _ = acks.send(());
                    }
                    batch.items.clear();
                    batch.raw = 0;
                    batch.bytes.clear();
                    batch.close = false;
                    batch.poll_next = false;
                    let _ = recycle.send(batch);
                }
                Job::Event {
                    t_ns,
                    level,
                    message,
                    ack,
                } => {
                    sinks.event(t_ns, level, &message)?;
                    if ack {
                        let _ = acks.send(());
                    }
                }
                Job::Finish(end) => return sinks.finish(end).map(Some),
            }
        }
        // The recorder went away without finishing (it always sends Finish, even when
        // dropped): nothing more to do.
        Ok(None)
    };
    match run() {
        Ok(bytes) => bytes,
        Err(e) => {
            if let Ok(mut slot) = shared.error.lock() {
                *slot = Some(e);
            }
            shared.failed.store(true, Ordering::Release);
            // `jobs` and `acks` drop on return: a waiting simulation thread wakes up and
            // finds the error.
            None
        }
    }
}

/// The simulation thread's end of the writer thread.
struct Pipe {
    jobs: SyncSender<Job>,
    /// Emptied batches coming back (in a Mutex only to keep the recorder `Sync`).
    recycle: Mutex<Receiver<Batch>>,
    acks: Mutex<Receiver<()>>,
    shared: Arc<Shared>,
    thread: Option<JoinHandle<Option<u64>>>,
    /// The batch being filled.
    batch: Batch,
    /// Serializes samples on this thread while the writer thread lags behind.
    json: SampleJson,
    mcap: bool,
    /// MCAP without Rerun: while the writer thread lags behind, this thread builds whole
    /// chunks itself (serialized and compressed here; only compressed bytes cross to the
    /// writer thread) instead of serializing single samples for it.
    builder: Option<ChunkBuilder>,
    /// The current chunk is built here.
    self_build: bool,
    /// Samples recorded so far (the sequence number of each sample's messages), and samples
    /// in the chunk built here.
    samples: u32,
    built_samples: u32,
    /// One sample's JSON, for the chunk built here.
    scratch: Vec<u8>,
    /// Chunk closes sent and not yet acknowledged (at most one after `send_batch`).
    unacked: usize,
    /// Chunk rule state (see [`Recorder::record`]): time of the last periodic close, samples
    /// written to the open chunk, time of the previous sample.
    last_close_ns: u64,
    chunk_samples: u64,
    prev_t_ns: u64,
    /// The text of the first error reported, for the errors that follow it.
    reported: Option<String>,
    /// Where errors are said to be.
    path: PathBuf,
}

impl Pipe {
    /// The writer thread's error, or one saying it stopped.
    fn error(&mut self) -> Error {
        let first = self
            .shared
            .error
            .lock()
            .ok()
            .and_then(|mut slot| slot.take());
        if let Some(e) = first {
            self.reported = Some(e.to_string());
            return e;
        }
        let why = match &self.reported {
            Some(first) => format!("the log writer stopped after an earlier error: {first}"),
            None => "the log writer thread stopped unexpectedly".to_owned(),
        };
        Error::io("cannot write", &self.path, std::io::Error::other(why))
    }

    fn check(&mut self) -> Result<()> {
        if self.shared.failed.load(Ordering::Acquire) {
            return Err(self.error());
        }
        Ok(())
    }

    /// Queues `job`. While the queue is full it polls rather than sleeping on the queue, so
    /// that the writer thread never has to wake it (see [`POLL`]).
    fn send(&mut self, job: Job) -> Result<()> {
        let mut job = job;
        let mut waited = None;
        loop {
            match self.jobs.try_send(job) {
                Ok(()) => return Ok(()),
                Err(TrySendError::Disconnected(_)) => return Err(self.error()),
                Err(TrySendError::Full(j)) => job = j,
            }
            let since = *waited.get_or_insert_with(Instant::now);
            if since.elapsed() < SEND_SPIN {
                std::hint::spin_loop();
            } else {
                std::thread::sleep(POLL);
            }
        }
    }

    /// Sends a job the simulation thread then waits for, waking the writer thread if it is
    /// between polls.
    fn send_urgent(&mut self, job: Job) -> Result<()> {
        self.send(job)?;
        if let Some(t) = &self.thread {
            t.thread().unpark();
        }
        Ok(())
    }

    /// Waits until the writer thread has done everything sent so far.
    fn wait(&mut self) -> Result<()> {
        let res = match self.acks.lock() {
            Ok(acks) => recv_spinning(&acks, ACK_SPIN).is_ok(),
            Err(_) => false,
        };
        if !res {
            return Err(self.error());
        }
        self.check()
    }

    /// Sends the batch being filled (if any); with `close`, also closes the MCAP chunk and
    /// waits for the writer thread.
    fn flush(&mut self, close: bool) -> Result<()> {
        self.send_batch(close, false)
    }

    /// [`Pipe::flush`]; `close_soon`: a close follows in a few samples.
    fn send_batch(&mut self, close: bool, close_soon: bool) -> Result<()> {
        if self.batch.items.is_empty() && !close {
            return Ok(());
        }
        let fresh = match self.recycle.lock() {
            Ok(r) => r.try_recv().ok(),
            Err(_) => None,
        };
        let mut batch = std::mem::replace(&mut self.batch, fresh.unwrap_or_else(Batch::new));
        batch.close = close;
        if close && self.built_samples > 0 {
            let built = match self.builder.as_mut() {
                Some(b) => b.finish(),
                None => Ok(None),
            };
            let built = built.map_err(|e| Error::io("cannot write", &self.path, e))?;
            batch.built = built.map(|chunk| (chunk, self.built_samples));
            self.built_samples = 0;
        }
        self.shared
            .raw_backlog
            .fetch_add(batch.raw, Ordering::AcqRel);
        // After a close the writer thread waits for the next batch; if it has been lagging
        // behind, that batch comes at once.
        let behind = self.shared.in_flight.fetch_add(1, Ordering::AcqRel) >= HELP_AT;
        batch.poll_next = close_soon || (close && behind);
        if close {
            self.send_urgent(Job::Samples(batch))?;
        } else {
            self.send(Job::Samples(batch))?;
        }
        if close {
            self.chunk_samples = 0;
            // Wait for the closes before the MAX_UNACKED newest: the writer thread works
            // through its backlog while the simulation fills the next chunk.
            self.unacked += 1;
            while self.unacked > MAX_UNACKED {
                self.wait()?;
                self.unacked -= 1;
            }
        }
        Ok(())
    }

    /// Waits until every close sent so far is acknowledged.
    fn wait_all(&mut self) -> Result<()> {
        while self.unacked > 0 {
            self.wait()?;
            self.unacked -= 1;
        }
        Ok(())
    }

    fn sample(&mut self, out: &StepOutput) -> Result<()> {
        self.check()?;
        let t_ns = messages::time_ns(out.t_s);
        let behind = self.shared.in_flight.load(Ordering::Acquire) >= HELP_AT;
        if self.chunk_samples == 0 {
            // A chunk starts: while the writer thread has a backlog that keeps it busy as long
            // as building a chunk takes (logging every step), build this one here.
            self.self_build = self.builder.is_some()
                && self.shared.raw_backlog.load(Ordering::Acquire) >= BUILD_AT;
        }
        let sequence = self.samples;
        self.samples = self.samples.wrapping_add(1);
        if self.self_build {
            self.build_sample(out, t_ns, sequence)?;
        } else if behind && self.builder.is_none() {
            // While the writer thread lags behind, take over the serialization: both threads
            // write the same bytes.
            let s = self.json.build(out, &mut self.batch.bytes);
            self.batch.items.push(Item::Built(s));
        } else {
            self.batch.items.push(Item::Raw(*out));
            self.batch.raw += 1;
        }
        if !self.mcap {
            if self.batch.items.len() >= BATCH {
                self.flush(false)?;
            }
            return Ok(());
        }
        // Chunks close every FLUSH_INTERVAL_NS of simulated time and every CHUNK_SAMPLES
        // samples (decided here, from the samples alone: the file is the same whatever the
        // threads' timing).
        self.chunk_samples += 1;
        if self.prev_t_ns == u64::MAX {
            // The periodic clock starts at the first sample (a run may start at t > 0).
            self.last_close_ns = t_ns;
            self.prev_t_ns = t_ns;
        }
        let spacing = t_ns.saturating_sub(self.prev_t_ns);
        self.prev_t_ns = t_ns;
        if t_ns.saturating_sub(self.last_close_ns) >= FLUSH_INTERVAL_NS {
            self.last_close_ns = t_ns;
            return self.flush(true);
        }
        if self.chunk_samples >= CHUNK_SAMPLES {
            return self.flush(true);
        }
        // Send early when a close is near, so that the writer thread has little left to do
        // when the simulation thread waits for it.
        let near = self.chunk_samples + NEAR >= CHUNK_SAMPLES
            || t_ns + NEAR * spacing >= self.last_close_ns + FLUSH_INTERVAL_NS;
        if near || self.batch.items.len() >= BATCH {
            self.send_batch(false, near)?;
        }
        Ok(())
    }

    /// Adds a sample to the chunk built on this thread.
    fn build_sample(&mut self, out: &StepOutput, t_ns: u64, sequence: u32) -> Result<()> {
        let Some(builder) = self.builder.as_mut() else {
            return Ok(());
        };
        self.scratch.clear();
        let s = self.json.build(out, &mut self.scratch);
        for i in 0..SAMPLE_MESSAGES {
            let res = builder.message(channel_id(i), sequence, t_ns, s.message(&self.scratch, i));
            res.map_err(|e| Error::io("cannot write", &self.path, e))?;
        }
        self.built_samples += 1;
        Ok(())
    }

    fn event(&mut self, t_ns: u64, level: Level, message: &str) -> Result<()> {
        self.check()?;
        // A chunk built here goes first, whole.
        self.flush(self.built_samples > 0)?;
        self.wait_all()?;
        self.send_urgent(Job::Event {
            t_ns,
            level,
            message: message.to_owned(),
            ack: true,
        })?;
        self.chunk_samples = 0;
        self.wait()
    }

    /// Sends the end and waits for the writer thread; the MCAP file's size.
    fn finish(&mut self, end: BTreeMap<String, String>) -> Result<u64> {
        let sent = self
            .flush(self.built_samples > 0)
            .and_then(|()| self.send_urgent(Job::Finish(end)));
        let joined = match self.thread.take() {
            Some(t) => t.join(),
            None => Ok(None),
        };
        // After the join the error (if any) is in the shared slot.
        match joined {
            Err(panic) => {
                let msg = panic
                    .downcast_ref::<&str>()
                    .map(|s| (*s).to_owned())
                    .or_else(|| panic.downcast_ref::<String>().cloned())
                    .unwrap_or_default();
                Err(Error::io(
                    "cannot write",
                    &self.path,
                    std::io::Error::other(format!("the log writer thread panicked: {msg}")),
                ))
            }
            Ok(Some(bytes)) if sent.is_ok() => Ok(bytes),
            Ok(_) => Err(self.error()),
        }
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
///
/// The files are written by a background thread: `record` only decimates and queues the
/// step (a bounded queue, so a slow disk slows the run instead of filling memory). An error
/// of the writer thread is returned by the next `record`/`event` call and by `finish`.
pub struct Recorder {
    pipe: Option<Pipe>,
    mcap_path: Option<PathBuf>,
    rrd_path: Option<PathBuf>,
    decimator: Decimator,
    vehicle: Vehicle,
    controls: Option<Controls>,
    wake_warned: [bool; 2],
    stats: LogStats,
    finished: bool,
}

impl std::fmt::Debug for Recorder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Recorder")
            .field("mcap", &self.mcap_path)
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
    /// the run) and starts the writer thread, which writes the run's metadata, the model
    /// attachment and the channel definitions first (an error there, e.g. a full disk, is
    /// returned by the next `record`/`event`/`finish`). With no output asked for, returns a
    /// recorder that records nothing (and starts no thread).
    ///
    /// Errors: an invalid `log_rate_hz` (not finite and > 0), an uncreatable file, a Rerun
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
        let mut sinks = Sinks {
            mcap_start: None,
            mcap: None,
            #[cfg(feature = "rerun")]
            rerun: None,
            json: SampleJson::new(wings, vehicle.weight_n(), vehicle.sim.steps_per_wingbeat),
            buf: Vec::with_capacity(8192),
        };
        // Viewers first (they fail most often), then files; on failure remove what was
        // created so a failed start leaves nothing behind.
        #[cfg(feature = "rerun")]
        {
            sinks.rerun = crate::rerun_sink::RerunSink::open(options, vehicle)?;
        }
        let cleanup = |sinks: &mut Sinks| {
            #[cfg(feature = "rerun")]
            if let Some(r) = sinks.rerun.take() {
                let _ = r.finish();
                if let Some(rrd) = &options.rrd {
                    let _ = std::fs::remove_file(rrd);
                }
            }
            let _ = sinks;
        };
        // The file is created here; the writer thread writes its start (metadata, model,
        // channels) while the simulation runs.
        if let Some(path) = &options.mcap {
            match File::create(path) {
                Ok(file) => {
                    sinks.mcap_start =
                        Some(mcap_start(file, path, info, vehicle, options.log_rate_hz))
                }
                Err(e) => {
                    cleanup(&mut sinks);
                    return Err(Error::io("cannot create", path, e));
                }
            }
        }
        let mut wake_warned = [false; 2];
        let warnings = wake_capture_warnings(vehicle, &mut wake_warned);
        let pipe = if sinks.any() {
            let path = options
                .mcap
                .clone()
                .or_else(|| options.rrd.clone())
                .unwrap_or_else(|| PathBuf::from("log writer"));
            let mcap = sinks.mcap_start.is_some();
            #[cfg(feature = "rerun")]
            let rerun = sinks.rerun.is_some();
            #[cfg(not(feature = "rerun"))]
            let rerun = false;
            let shared = Arc::new(Shared::default());
            let (jobs, jobs_rx) = mpsc::sync_channel(QUEUE);
            let (recycle_tx, recycle) = mpsc::channel();
            let (acks_tx, acks) = mpsc::channel();
            let thread_shared = Arc::clone(&shared);
            // The thread takes the sinks; if it cannot start, they come back to be cleaned up.
            let slot = Arc::new(Mutex::new(Some(sinks)));
            let thread_slot = Arc::clone(&slot);
            let spawned = std::thread::Builder::new()
                .name("flightlog-writer".into())
                .spawn(move || {
                    let sinks = thread_slot.lock().ok().and_then(|mut s| s.take());
                    match sinks {
                        Some(sinks) => {
                            writer_thread(sinks, jobs_rx, recycle_tx, acks_tx, thread_shared)
                        }
                        None => None,
                    }
                });
            let thread = match spawned {
                Ok(t) => t,
                Err(e) => {
                    if let Some(mut sinks) = slot.lock().ok().and_then(|mut s| s.take()) {
                        cleanup(&mut sinks);
                    }
                    if let Some(mcap) = &options.mcap {
                        let _ = std::fs::remove_file(mcap);
                    }
                    return Err(Error::io("cannot start the writer thread for", &path, e));
                }
            };
            let mut pipe = Pipe {
                jobs,
                recycle: Mutex::new(recycle),
                acks: Mutex::new(acks),
                shared,
                thread: Some(thread),
                batch: Batch::new(),
                json: SampleJson::new(wings, vehicle.weight_n(), vehicle.sim.steps_per_wingbeat),
                mcap,
                builder: if mcap && !rerun {
                    Some(ChunkBuilder::new().map_err(|e| Error::io("cannot write", &path, e))?)
                } else {
                    None
                },
                self_build: false,
                samples: 0,
                built_samples: 0,
                scratch: Vec::new(),
                unacked: 0,
                last_close_ns: 0,
                chunk_samples: 0,
                prev_t_ns: u64::MAX,
                reported: None,
                path,
            };
            // The warnings about the model itself come first, without waiting for them.
            for message in &warnings {
                pipe.send(Job::Event {
                    t_ns: 0,
                    level: Level::Warning,
                    message: message.clone(),
                    ack: false,
                })?;
            }
            Some(pipe)
        } else {
            None
        };
        let mcap_events = if options.mcap.is_some() {
            warnings.len() as u64
        } else {
            0
        };
        Ok(Recorder {
            pipe,
            mcap_path: options.mcap.clone(),
            rrd_path: options.rrd.clone(),
            decimator: Decimator::new(options.log_rate_hz),
            vehicle: vehicle.clone(),
            controls: None,
            wake_warned,
            stats: LogStats {
                events: warnings.len() as u64,
                mcap_messages: mcap_events,
                mcap_path: options.mcap.clone(),
                rrd_path: options.rrd.clone(),
                ..LogStats::default()
            },
            finished: false,
        })
    }
    /// Warns (once per wing until it changes back) when a wing's wake-capture inputs lie
    /// outside the fitted range of the regressions.
    fn check_wake_capture(&mut self, t_s: f64) -> Result<()> {
        for message in wake_capture_warnings(&self.vehicle, &mut self.wake_warned) {
            self.event(t_s, Level::Warning, &message)?;
        }
        Ok(())
    }

    /// Takes one step's output; logs it if the decimation picks it.
    ///
    /// A logged step is queued for the writer thread (this call blocks only while the
    /// queue is full, and when an MCAP chunk is closed: every 0.05 s of simulated time and
    /// every 128 samples, it waits until the chunk is in the file). Errors of the writer
    /// thread, e.g. a full disk, are returned here.
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
        if let Some(p) = &mut self.pipe {
            p.sample(out)?;
            if p.mcap {
                self.stats.mcap_messages += SAMPLE_MESSAGES as u64;
            }
        }
        self.stats.samples += 1;
        self.stats.last_t_s = out.t_s;
        Ok(())
    }

    /// Logs a run event (a `foxglove.Log` on /events, a Rerun TextLog) at simulation time
    /// `t_s`, and closes the current MCAP chunk so the event survives a crash (it returns
    /// once the event is in the file).
    pub fn event(&mut self, t_s: f64, level: Level, message: &str) -> Result<()> {
        let t_ns = messages::time_ns(t_s);
        if let Some(p) = &mut self.pipe {
            p.event(t_ns, level, message)?;
            if p.mcap {
                self.stats.mcap_messages += 1;
            }
        }
        self.stats.events += 1;
        Ok(())
    }

    /// What has been recorded so far (counted when handed to the writer thread; the file
    /// size is known after [`Recorder::finish`]).
    pub fn stats(&self) -> &LogStats {
        &self.stats
    }

    /// Finishes every output: writes the `flapwing.end` metadata, the MCAP summary and
    /// footer, and the Rerun footer; flushes the files and ends the writer thread. Call it
    /// at the end of every run, including after an error.
    pub fn finish(mut self) -> Result<LogStats> {
        self.finish_inner()
    }

    fn finish_inner(&mut self) -> Result<LogStats> {
        if self.finished {
            return Ok(self.stats.clone());
        }
        self.finished = true;
        if let Some(mut p) = self.pipe.take() {
            let end = BTreeMap::from([
                ("steps_seen".to_owned(), self.stats.steps_seen.to_string()),
                ("samples".to_owned(), self.stats.samples.to_string()),
                ("messages".to_owned(), self.stats.mcap_messages.to_string()),
                ("events".to_owned(), self.stats.events.to_string()),
                ("last_t_s".to_owned(), self.stats.last_t_s.to_string()),
            ]);
            let bytes = p.finish(end)?;
            if p.mcap {
                self.stats.mcap_bytes = bytes;
            }
        }
        Ok(self.stats.clone())
    }
}

impl Drop for Recorder {
    /// Best-effort finish; errors are ignored (call [`Recorder::finish`] to see them).
    fn drop(&mut self) {
        let _ = self.finish_inner();
    }
}

/// The warnings for wings whose wake-capture inputs lie outside the fitted range of the
/// regressions (once per wing until it changes back; `wake_warned` keeps track).
fn wake_capture_warnings(vehicle: &Vehicle, wake_warned: &mut [bool; 2]) -> Vec<String> {
    let mut out_messages = Vec::new();
    for i in 0..2 {
        let flags = vehicle.wings[i]
            .wake_capture()
            .map(|p| p.flags)
            .unwrap_or_default();
        let out = flags.any();
        if out && !wake_warned[i] {
            let w = &vehicle.wings[i];
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
            out_messages.push(format!(
                    "{side} wing: wake-capture input outside its fitted range ({}); the regressions use the nearest fitted value",
                    what.join(", ")
                ));
        }
        wake_warned[i] = out;
    }
    out_messages
}

/// The schema text of each of [`CHANNELS`], built once per process (building them is a good
/// part of the cost of opening a log).
fn schema_texts() -> &'static [String; 11] {
    static TEXTS: OnceLock<[String; 11]> = OnceLock::new();
    TEXTS.get_or_init(|| CHANNELS.map(|(_, name)| schema::schema_text(name).unwrap_or_default()))
}

/// An MCAP file created by [`Recorder::create`] and what the writer thread writes first.
struct McapStart {
    file: File,
    path: PathBuf,
    metadata: BTreeMap<String, String>,
    attachment_name: String,
    model_toml: String,
}

fn mcap_start(
    file: File,
    path: &Path,
    info: &RunInfo,
    vehicle: &Vehicle,
    log_rate_hz: Option<f64>,
) -> McapStart {
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
    McapStart {
        file,
        path: path.to_owned(),
        metadata,
        attachment_name: attachment_name(&info.model_origin),
        model_toml: info.model_toml.clone(),
    }
}

/// Writes the start of the file: header, the `flapwing` metadata, the model attachment and
/// the channel definitions (in a chunk of their own).
fn open_mcap(start: McapStart) -> Result<McapSink> {
    let McapStart {
        file,
        path,
        metadata,
        attachment_name,
        model_toml,
    } = start;
    let io = |e| Error::io("cannot write", &path, e);
    // Chunks are written whole (about 130 kB each at full rate): the buffer only gathers the
    // small records.
    let mut writer = McapWriter::new(
        BufWriter::with_capacity(64 * 1024, file),
        "",
        &format!("flapwing-flightlog/{}", env!("CARGO_PKG_VERSION")),
    )
    .map_err(io)?;
    writer
        .metadata(schema::METADATA_RUN, &metadata)
        .map_err(io)?;
    writer
        .attachment(
            0,
            0,
            &attachment_name,
            "application/toml",
            model_toml.as_bytes(),
        )
        .map_err(io)?;
    let mut channel_ids = [0u16; 11];
    for (i, ((topic, schema_name), text)) in CHANNELS.iter().zip(schema_texts()).enumerate() {
        let schema_id = writer
            .add_schema(schema_name, SCHEMA_ENCODING, text.as_bytes())
            .map_err(io)?;
        channel_ids[i] = writer
            .add_channel(schema_id, topic, MESSAGE_ENCODING)
            .map_err(io)?;
    }
    if (0..channel_ids.len()).any(|i| channel_ids[i] != channel_id(i)) {
        return Err(io(std::io::Error::other(
            "internal: MCAP channel ids out of the expected order",
        )));
    }
    // The channel definitions get a chunk of their own right away.
    writer.flush().map_err(io)?;
    Ok(McapSink {
        writer,
        path,
        channel_ids,
        sequences: [0; 11],
    })
}

/// The MCAP channel id of channel `index` of [`CHANNELS`] (added in order, numbered from 1).
fn channel_id(index: usize) -> u16 {
    index as u16 + 1
}

#[cfg(test)]
mod tests {
    #[test]
    fn recorder_can_move_between_threads() {
        fn send_sync<T: Send + Sync>() {}
        send_sync::<super::Recorder>();
    }
}
