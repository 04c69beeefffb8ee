//! Errors of flapwing-identify. Every message names the file (or the model), the field or
//! column, the value and what is allowed.

use std::path::PathBuf;

/// What went wrong.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The log or CSV could not be read as flight data.
    #[error("`{path}`: {detail}")]
    Log {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        detail: String,
    },
    /// A line of a CSV file is malformed.
    #[error("`{path}` line {line}: {detail}")]
    Csv {
        /// The file.
        path: PathBuf,
        /// 1-based line number (the header is line 1).
        line: usize,
        /// What is wrong, naming the column and value.
        detail: String,
    },
    /// The vehicle model does not load or a parameter value makes it invalid.
    #[error("model: {0}")]
    Model(String),
    /// A parameter name or fit setting is not allowed.
    #[error("{0}")]
    Setting(String),
    /// The data cannot support a fit (too few measurements, no segment).
    #[error("{0}")]
    Data(String),
    /// Reading or writing a file failed.
    #[error("cannot {what} `{path}`: {source}")]
    Io {
        /// "read", "write".
        what: &'static str,
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
}

impl Error {
    /// True when the error is the user's input (bad file, bad setting), not a failed run.
    pub fn is_bad_input(&self) -> bool {
        !matches!(self, Error::Io { what: "write", .. })
    }
}

/// The crate's result.
pub type Result<T> = std::result::Result<T, Error>;
