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

/// Result with the wing set's [`Error`].
pub type Result<T> = std::result::Result<T, Error>;
