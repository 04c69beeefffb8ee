//! The flightlog error type.

use std::path::PathBuf;

/// Everything that can stop a log from being written, read, converted or checked.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A file could not be created, read or written.
    #[error("{action} `{}`: {source}", path.display())]
    Io {
        /// What was being done ("cannot create", "cannot read", ...).
        action: &'static str,
        /// The file.
        path: PathBuf,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
    /// The MCAP library refused a write (or a read of a well-formed part of a file).
    #[error("MCAP error: {0}")]
    Mcap(#[from] mcap::McapError),
    /// The file does not start with the MCAP magic bytes.
    #[error("`{}` is not an MCAP file ({detail})", path.display())]
    NotMcap {
        /// The file.
        path: PathBuf,
        /// What was found instead.
        detail: String,
    },
    /// The file is MCAP but was not written by flapwing (no `flapwing` metadata record), or
    /// it was cut before that record.
    #[error("`{}` is not a flapwing log: {detail}", path.display())]
    NotFlapwing {
        /// The file.
        path: PathBuf,
        /// Why.
        detail: String,
    },
    /// The log has no channel with the requested topic.
    #[error("`{}` has no channel `{topic}`; its channels are: {available}", path.display())]
    UnknownTopic {
        /// The file.
        path: PathBuf,
        /// The topic asked for.
        topic: String,
        /// The topics present, comma separated.
        available: String,
    },
    /// A channel of a ROS 2 bag cannot be decoded: its schema does not parse, names a type it
    /// does not define, uses an unsupported type, or is not `ros2msg` with CDR messages.
    #[error("`{}`: topic `{topic}` ({type_name}) cannot be decoded: {detail}", path.display())]
    Ros2Schema {
        /// The file.
        path: PathBuf,
        /// The topic.
        topic: String,
        /// Its message type.
        type_name: String,
        /// Which field is at fault and what is allowed.
        detail: String,
    },
    /// A message of a ROS 2 bag does not decode against its type (e.g. shorter than it).
    #[error(
        "`{}`: topic `{topic}` ({type_name}), message {index} (log time {log_time_ns} ns): {detail}",
        path.display()
    )]
    Ros2Message {
        /// The file.
        path: PathBuf,
        /// The topic.
        topic: String,
        /// Its message type.
        type_name: String,
        /// The message's index on its topic, from 0.
        index: u64,
        /// Its log time, ns.
        log_time_ns: u64,
        /// Which field could not be read and why.
        detail: String,
    },
    /// A recording option is out of range or needs a feature that is not compiled in.
    #[error("{0}")]
    Options(String),
    /// The log's embedded model or settings could not be used.
    #[error("{0}")]
    Embedded(String),
    /// The vehicle model failed to load (re-running a log).
    #[error(transparent)]
    Model(#[from] flapsim::Error),
    /// Rerun could not record, spawn a viewer or connect to one.
    #[error("Rerun: {0}")]
    Rerun(String),
    /// JSON serialization failed (a bug: every message is plain data).
    #[error("JSON: {0}")]
    Json(#[from] serde_json::Error),
}

/// Result with flightlog's [`Error`].
pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    pub(crate) fn io(
        action: &'static str,
        path: impl Into<PathBuf>,
        source: std::io::Error,
    ) -> Self {
        Error::Io {
            action,
            path: path.into(),
            source,
        }
    }

    /// True when the error is about what the user gave (a missing, non-MCAP, foreign or
    /// unusable file, a bad option), not a failure while running. The CLI maps these to
    /// exit code 2.
    pub fn is_bad_input(&self) -> bool {
        match self {
            Error::Io { action, source, .. } => {
                action.starts_with("cannot read")
                    || action.starts_with("cannot open")
                    || source.kind() == std::io::ErrorKind::NotFound
            }
            Error::NotMcap { .. }
            | Error::NotFlapwing { .. }
            | Error::UnknownTopic { .. }
            | Error::Ros2Schema { .. }
            | Error::Ros2Message { .. }
            | Error::Options(_)
            | Error::Embedded(_) => true,
            Error::Model(flapsim::Error::Model(_)) => true,
            _ => false,
        }
    }
}
