//! The wing set's error type.

/// Everything that can stop a wing set from being built or stepped, and (as `flapsim::Error`,
/// the same type) a vehicle model from loading or an analysis from finding its answer.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// A wing's model is malformed or a value is out of range (names field and value).
    #[error(transparent)]
    Model(#[from] wingforce::Error),
    /// The wings' dynamics left the physically meaningful region and the step was stopped.
    #[error("run diverged at t = {t_s:.6} s (step {step}): {reason}")]
    Diverged {
        /// Time of the step that failed, s.
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
    /// Controls or a drive the wings cannot follow (a control mapping that refuses them, an
    /// actuated wing that cannot start), or an analysis (trim, stability) that could not find
    /// what it looked for, in words.
    #[error("{0}")]
    Analysis(String),
}

/// How the reason of a step refused for overflowing loads begins ([`Error::is_load_overflow`]).
pub(crate) const LOAD_OVERFLOW: &str = "the loads overflow";

impl Error {
    /// Whether this is a step the set refused because the body state or wind it was given
    /// makes the loads overflow (a speed through the air far beyond flight, e.g. 1e300 m/s):
    /// an [`Error::Diverged`] for a host that integrated that state itself, a bad input for a
    /// host whose states come from its user (the C ABI, Python's `WingSet`).
    pub fn is_load_overflow(&self) -> bool {
        matches!(self, Error::Diverged { reason, .. } if reason.starts_with(LOAD_OVERFLOW))
    }

    /// The reason of a refused step alone (what follows "run diverged at ...: "), or the
    /// message.
    pub fn reason(&self) -> String {
        match self {
            Error::Diverged { reason, .. } => reason.clone(),
            e => e.to_string(),
        }
    }
}

/// Result with the wing set's [`Error`].
pub type Result<T> = std::result::Result<T, Error>;
