//! One error type for the whole crate.

/// Everything that can go wrong when building or evaluating a wing model.
///
/// Every variant that comes from user input names where it came from (`origin`: a file path or
/// `"<built-in>"`), the field, the value that was given and what would have been allowed, so
/// that a user can fix their file without reading this crate's source.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// The text is not valid TOML, or does not match the model's shape (unknown field, wrong
    /// type, missing field).
    #[error("{origin}: {message}")]
    Parse {
        /// File (or other source) the text came from.
        origin: String,
        /// The parser's explanation, including line and column.
        message: String,
    },
    /// A field has a value outside what the model allows.
    #[error("{origin}: field `{field}` = {value} is not allowed: {allowed}")]
    Invalid {
        /// File (or other source) the value came from.
        origin: String,
        /// Dotted path of the field, e.g. `wing.planform.chord_m`.
        field: String,
        /// The value as given (in the units of the file).
        value: String,
        /// What the field accepts.
        allowed: String,
    },
}

/// Result with this crate's [`Error`].
pub type Result<T> = std::result::Result<T, Error>;

/// Checks fields of one source (file) and builds [`Error::Invalid`] values that name it.
#[derive(Debug, Clone)]
pub struct Validator<'a> {
    origin: &'a str,
}

impl<'a> Validator<'a> {
    /// A validator for values that came from `origin` (a file path or a description).
    pub fn new(origin: &'a str) -> Self {
        Self { origin }
    }

    /// The source this validator reports.
    pub fn origin(&self) -> &str {
        self.origin
    }

    /// An [`Error::Invalid`] for `field` with `value` and the `allowed` range.
    pub fn invalid(&self, field: &str, value: impl std::fmt::Display, allowed: &str) -> Error {
        Error::Invalid {
            origin: self.origin.to_owned(),
            field: field.to_owned(),
            value: value.to_string(),
            allowed: allowed.to_owned(),
        }
    }

    /// `value` must be finite.
    pub fn finite(&self, field: &str, value: f64) -> Result<f64> {
        if value.is_finite() {
            Ok(value)
        } else {
            Err(self.invalid(field, value, "a finite number"))
        }
    }

    /// `value` must be finite and > 0.
    pub fn positive(&self, field: &str, value: f64) -> Result<f64> {
        if value.is_finite() && value > 0.0 {
            Ok(value)
        } else {
            Err(self.invalid(field, value, "a finite number > 0"))
        }
    }

    /// `value` must be finite and >= 0.
    pub fn non_negative(&self, field: &str, value: f64) -> Result<f64> {
        if value.is_finite() && value >= 0.0 {
            Ok(value)
        } else {
            Err(self.invalid(field, value, "a finite number >= 0"))
        }
    }

    /// `value` must lie in `[lo, hi]`.
    pub fn within(&self, field: &str, value: f64, lo: f64, hi: f64) -> Result<f64> {
        if value.is_finite() && value >= lo && value <= hi {
            Ok(value)
        } else {
            Err(self.invalid(field, value, &format!("a number in [{lo}, {hi}]")))
        }
    }

    /// `value` must lie in `(lo, hi]`.
    pub fn within_open_low(&self, field: &str, value: f64, lo: f64, hi: f64) -> Result<f64> {
        if value.is_finite() && value > lo && value <= hi {
            Ok(value)
        } else {
            Err(self.invalid(field, value, &format!("a number in ({lo}, {hi}]")))
        }
    }
}
