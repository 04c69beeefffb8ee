//! The MCAP writer thread: compresses the chunks the simulation thread fills and writes them.
//!
//! The simulation thread encodes a chunk's samples (a few microseconds of work per sample
//! at most, [`crate::encode`]); compressing them with zstd costs more than that, so it runs
//! here, on the machine's second core.
//!
//! Jobs travel on a bounded queue of [`QUEUE`] chunk besides the one the thread is writing, so
//! `record` blocks only while the thread is two closed chunks behind (a slow disk slows the
//! run instead of filling memory), and a killed run loses at most those two chunks and the one
//! being filled. Why: the thread takes chunk k-1 off the queue only after chunk k-2 is written
//! and flushed, and queuing chunk k returns only once the queue has room, that is once chunk
//! k-1 was taken; so when the close of chunk k returns, every chunk before k-1 is in the file,
//! whatever the two threads' speeds. The thread also publishes, after each flush, how many
//! samples are in the file ([`Flushed`], `Recorder::flushed`), which a supervisor can report
//! and a kill can never undo. Emptied chunk
//! buffers come back for reuse. The first error of the thread ends it; the next call here
//! returns it, and later calls say that the writer stopped because of it.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{self, Receiver, Sender, SyncSender};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;

use crate::chunk::{ChunkBuilder, RawChunk};
use crate::error::{Error, Result};
use crate::mcap_write::McapWriter;
use crate::schema;

/// Chunks waiting for the writer thread at most, besides the one it is writing (the queue
/// of `sync_channel(QUEUE)` holds jobs the thread has not taken yet).
const QUEUE: usize = 1;

enum Job {
    /// A closed chunk, and the run's samples up to its end (what is safe once it is written).
    Chunk(RawChunk, Flushed),
    /// Answer once everything before is in the file.
    Sync(Sender<()>),
    /// Write the end metadata, the summary and the footer; answer with the file size.
    Finish(BTreeMap<String, String>),
}

type File64 = McapWriter<BufWriter<File>>;

/// How much of a run is in the MCAP file: a kill at this moment keeps at least this much.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Flushed {
    /// Samples (logged steps) whose chunks are written whole and flushed to the file.
    pub samples: u64,
    /// Time of the newest of them, s (0 before the first).
    pub t_s: f64,
}

/// The newest [`Flushed`], written by the writer thread after each chunk reaches the file and
/// read by the simulation thread (two atomics: the samples are never newer than the time's
/// sample, since the thread stores the time first and the reader loads the samples first).
#[derive(Debug, Default)]
struct FlushedCell {
    samples: AtomicU64,
    t_bits: AtomicU64,
}

impl FlushedCell {
    fn store(&self, f: Flushed) {
        self.t_bits.store(f.t_s.to_bits(), Ordering::Release);
        self.samples.store(f.samples, Ordering::Release);
    }

    fn load(&self) -> Flushed {
        let samples = self.samples.load(Ordering::Acquire);
        let t_s = f64::from_bits(self.t_bits.load(Ordering::Acquire));
        Flushed { samples, t_s }
    }
}

/// The simulation thread's handle on the writer thread.
pub(crate) struct Writer {
    jobs: Option<SyncSender<Job>>,
    /// Emptied chunks coming back (a Mutex: the recorder is `Sync`).
    spare: Mutex<Receiver<RawChunk>>,
    thread: Option<JoinHandle<Result<u64>>>,
    /// The writer thread's error, once it stopped.
    failed: Option<String>,
    path: PathBuf,
    flushed: Arc<FlushedCell>,
}

fn run(
    mut w: File64,
    path: &Path,
    jobs: Receiver<Job>,
    spare: Sender<RawChunk>,
    flushed: &FlushedCell,
) -> Result<u64> {
    let io = |e| Error::io("cannot write", path, e);
    let mut zstd = ChunkBuilder::new().map_err(io)?;
    for job in jobs {
        match job {
            Job::Chunk(mut raw, upto) => {
                let chunk = zstd.compress(&raw).map_err(io)?;
                w.write_chunk(&chunk).map_err(io)?;
                // Each chunk reaches the file whole before the next one starts.
                w.flush().map_err(io)?;
                flushed.store(upto);
                raw.clear();
                let _ = spare.send(raw);
            }
            Job::Sync(done) => {
                let _ = done.send(());
            }
            Job::Finish(end) => {
                w.metadata(schema::METADATA_END, &end).map_err(io)?;
                w.finish().map_err(io)?;
                return Ok(w.position());
            }
        }
    }
    // The recorder went away without finishing (dropped after an error): end the file anyway.
    w.finish().map_err(io)?;
    Ok(w.position())
}

impl Writer {
    /// Starts the thread with a file whose start is written.
    pub fn start(w: File64, path: &Path) -> Result<Self> {
        let (jobs, jobs_rx) = mpsc::sync_channel(QUEUE);
        let (spare_tx, spare) = mpsc::channel();
        let thread_path = path.to_owned();
        let flushed = Arc::new(FlushedCell::default());
        let cell = Arc::clone(&flushed);
        let thread = std::thread::Builder::new()
            .name("flightlog-writer".into())
            .spawn(move || run(w, &thread_path, jobs_rx, spare_tx, &cell))
            .map_err(|e| Error::io("cannot start the writer thread for", path, e))?;
        Ok(Self {
            jobs: Some(jobs),
            spare: Mutex::new(spare),
            thread: Some(thread),
            failed: None,
            path: path.to_owned(),
            flushed,
        })
    }

    /// What is in the file now (see [`Flushed`]).
    pub fn flushed(&self) -> Flushed {
        self.flushed.load()
    }

    /// The error of a writer that stopped: the thread's own error the first time, then a
    /// reminder of it.
    fn stopped(&mut self) -> Error {
        if let Some(why) = &self.failed {
            return Error::io(
                "cannot write",
                &self.path,
                std::io::Error::other(format!("the writer stopped after an error: {why}")),
            );
        }
        self.jobs = None;
        let e = match self.thread.take().map(JoinHandle::join) {
            Some(Ok(Err(e))) => e,
            _ => Error::io(
                "cannot write",
                &self.path,
                std::io::Error::other("the writer thread ended unexpectedly"),
            ),
        };
        self.failed = Some(e.to_string());
        e
    }

    fn send(&mut self, job: Job) -> Result<()> {
        match &self.jobs {
            Some(jobs) if self.failed.is_none() => match jobs.send(job) {
                Ok(()) => Ok(()),
                Err(_) => Err(self.stopped()),
            },
            _ => Err(self.stopped()),
        }
    }

    /// An empty chunk to fill (one the thread has written, when there is one).
    pub fn spare_chunk(&self) -> RawChunk {
        let spare = self.spare.lock().ok().and_then(|r| r.try_recv().ok());
        spare.unwrap_or_default()
    }

    /// Queues a closed chunk that ends the run's samples at `upto`.
    pub fn chunk(&mut self, raw: RawChunk, upto: Flushed) -> Result<()> {
        self.send(Job::Chunk(raw, upto))
    }

    /// Returns once every chunk queued so far is in the file.
    pub fn sync(&mut self) -> Result<()> {
        let (tx, rx) = mpsc::channel();
        self.send(Job::Sync(tx))?;
        rx.recv().map_err(|_| self.stopped())
    }

    /// Ends the file with the `flapwing.end` metadata and the summary; the file size.
    pub fn finish(&mut self, end: BTreeMap<String, String>) -> Result<u64> {
        self.send(Job::Finish(end))?;
        self.jobs = None;
        match self.thread.take().map(JoinHandle::join) {
            Some(Ok(res)) => res,
            _ => Err(self.stopped()),
        }
    }
}

impl Drop for Writer {
    /// Lets the thread end the file and waits for it.
    fn drop(&mut self) {
        self.jobs = None;
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}
