//! The verdict of a re-run check ([`super::check_log`]).

use serde::Serialize;

/// The verdict of [`super::check_log`].
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "result", rename_all = "snake_case")]
pub enum CheckOutcome {
    /// Every logged sample equals the re-run bit for bit.
    Match {
        /// Samples compared.
        samples: u64,
        /// A remark (e.g. the log ends before the run's duration).
        note: Option<String>,
    },
    /// The first difference.
    Mismatch {
        /// Samples that matched before it.
        samples_matched: u64,
        /// What differs, with both values.
        detail: String,
    },
    /// The log cannot be re-run (another command, an unsupported mode, no samples, a hover
    /// on the state estimate logged before its sensors' seed was).
    NotCheckable {
        /// Why.
        reason: String,
    },
}
