//! The flapsim error type.

/// Everything that can stop a vehicle model from loading or a simulation from running.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// The model file is malformed or a value is out of range (names file, field, value).
    #[error(transparent)]
    Model(#[from] wingforce::Error),
    /// The simulation left the physically meaningful region and was stopped.
    #[error("run diverged at t = {t_s:.6} s (step {step}): {reason}")]
    Diverged {
        /// Simulation time of the step that failed, s.
        t_s: f64,
        /// Step index.
        step: u64,
        /// What went wrong, in words.
        reason: String,
    },
    /// A host gave the wing set something it cannot use (no wings, two wings at one place,
    /// a non-finite body state, ...), in words naming the value and what is allowed.
    #[error("{0}")]
    Input(String),
    /// An analysis (trim, stability) could not find what it looked for.
    #[error("{0}")]
    Analysis(String),
}

/// Result with flapsim's [`Error`].
pub type Result<T> = std::result::Result<T, Error>;

/// The wing set's errors are flapsim's, variant for variant, with the same messages.
impl From<wingset::Error> for Error {
    fn from(e: wingset::Error) -> Self {
        match e {
            wingset::Error::Model(m) => Error::Model(m),
            wingset::Error::Diverged { t_s, step, reason } => Error::Diverged { t_s, step, reason },
            wingset::Error::Input(m) => Error::Input(m),
            wingset::Error::Analysis(m) => Error::Analysis(m),
        }
    }
}

/// What a vehicle model's control mapping refuses reaches the wing set unchanged.
impl From<Error> for wingset::Error {
    fn from(e: Error) -> Self {
        match e {
            Error::Model(m) => wingset::Error::Model(m),
            Error::Diverged { t_s, step, reason } => wingset::Error::Diverged { t_s, step, reason },
            Error::Input(m) => wingset::Error::Input(m),
            Error::Analysis(m) => wingset::Error::Analysis(m),
        }
    }
}
