//! The error type of the study tools.

/// Everything that can stop a fit, a design or a sweep. Every variant built from user input
/// names where the input came from (a file path or a description) and what to fix.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StudyError {
    /// A data table (CSV) is malformed: names the file, the line and, when one is at fault,
    /// the column.
    #[error("{origin}, line {line}{}: {message}", column_text(.column))]
    Table {
        /// File (or other source) of the table.
        origin: String,
        /// 1-based line number in the file.
        line: usize,
        /// Column name (and position) at fault, if any.
        column: Option<String>,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// A study file or a design request is invalid.
    #[error("{origin}: {message}")]
    Invalid {
        /// File (or other source) of the study.
        origin: String,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// A fit could not be made (too few or degenerate data).
    #[error("{0}")]
    Fit(String),
    /// A case of a study could not be built or evaluated.
    #[error("case {case} ({settings}): {source}")]
    Case {
        /// Case index (0-based, as in the CSV `case` column).
        case: usize,
        /// The factor settings of the case, `path = value` joined by commas.
        settings: String,
        /// The model error.
        source: flapsim::Error,
    },
    /// Every design a search tried failed (no periodic motion, diverged, refused by the
    /// model): the study's box holds nothing to optimize from. Names how many were tried and
    /// the first reason.
    #[error(
        "every design tried failed ({tried} designs: the centre of the factor box and a grid around it), so there is nothing to optimize from; the first failure, at the box centre ({settings}): {reason}"
    )]
    AllFailed {
        /// Designs tried.
        tried: usize,
        /// The factor settings of the first design tried.
        settings: String,
        /// Why it failed.
        reason: String,
    },
}

fn column_text(column: &Option<String>) -> String {
    match column {
        Some(c) => format!(", column {c}"),
        None => String::new(),
    }
}

/// Result with [`StudyError`].
pub type StudyResult<T> = std::result::Result<T, StudyError>;
