//! Reading flapwing MCAP logs: summaries, CSV export and (feature `rerun`) conversion to a
//! Rerun recording.
//!
//! Files are scanned record by record from the start, the way a killed run left them: each
//! chunk is decompressed and CRC-checked whole and kept only if all of it is good, and the
//! scan stops at the first incomplete or damaged record. A complete file (summary section
//! and closing magic present) is read the same way. A truncated file therefore yields every
//! message of every complete chunk before the cut, and [`ReplaySummary::damage`] says what
//! was lost. A file that is not MCAP, or MCAP without the `flapwing` metadata record, is an
//! error. Nothing here panics on any input.
//!
//! `summary.rs` reads a log's summary, `table.rs` a channel as a table or CSV, and `rrd.rs`
//! (feature `rerun`) converts a log to a Rerun recording.
pub use crate::read::{AttachmentSummary, ChannelSummary, linear_records};

#[cfg(feature = "rerun")]
mod rrd;
mod summary;
mod table;

#[cfg(feature = "rerun")]
pub use rrd::{RrdStats, to_rrd};
pub use summary::{CycleMean, EventSummary, ReplaySummary, read_summary};
pub use table::{CsvStats, Table, export_csv, read_table};
