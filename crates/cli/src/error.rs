//! Exit codes and the error that marks a failure as the user's input.
//!
//! Commands return `anyhow::Result`. An error whose chain contains an [`InputError`] or a
//! [`wingforce::Error`] (bad model file, bad field) is bad input and exits with
//! [`EXIT_BAD_INPUT`]; any other error means the run failed and exits with [`EXIT_FAILED`].
//! Clap exits with 2 on its own for bad flags.

use std::fmt;

/// The run failed (including a `validate` case that does not reproduce).
pub const EXIT_FAILED: u8 = 1;
/// Bad input: bad flags, an unreadable or invalid model file, a refused overwrite.
pub const EXIT_BAD_INPUT: u8 = 2;

/// An error caused by what the user gave: the message says what to fix.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InputError(pub String);

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for InputError {}

/// An [`InputError`] as an `anyhow::Error`.
pub fn input_error(message: impl Into<String>) -> anyhow::Error {
    anyhow::Error::new(InputError(message.into()))
}

/// Marks the error of a result as bad input, with a message in front of its own.
pub trait InputContext<T> {
    /// On error: `<message>: <the error>`, classified as bad input.
    fn input_context(self, message: impl Into<String>) -> anyhow::Result<T>;
}

impl<T, E> InputContext<T> for Result<T, E>
where
    E: std::error::Error + Send + Sync + 'static,
{
    fn input_context(self, message: impl Into<String>) -> anyhow::Result<T> {
        self.map_err(|e| anyhow::Error::new(e).context(InputError(message.into())))
    }
}

/// The process exit code for an error returned by a command.
pub fn exit_code(error: &anyhow::Error) -> u8 {
    let bad_input = error.downcast_ref::<InputError>().is_some()
        || error.downcast_ref::<wingforce::Error>().is_some()
        || error
            .chain()
            .any(|e| e.is::<InputError>() || e.is::<wingforce::Error>());
    if bad_input {
        EXIT_BAD_INPUT
    } else {
        EXIT_FAILED
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use anyhow::Context;

    #[test]
    fn classifies_input_errors() {
        let wf = wingforce::Error::Parse {
            origin: "m.toml".into(),
            message: "oops".into(),
        };
        assert_eq!(exit_code(&anyhow::Error::new(wf.clone())), EXIT_BAD_INPUT);
        let wrapped = Err::<(), _>(wf).context("while loading");
        assert_eq!(
            exit_code(&wrapped.unwrap_err()),
            EXIT_BAD_INPUT,
            "context must not hide a wingforce error"
        );
        assert_eq!(exit_code(&input_error("bad")), EXIT_BAD_INPUT);
        let io = std::io::Error::new(std::io::ErrorKind::NotFound, "gone");
        let read: anyhow::Result<()> = Err(io).input_context("cannot read `x`");
        let e = read.unwrap_err();
        assert_eq!(exit_code(&e), EXIT_BAD_INPUT);
        assert_eq!(format!("{e:#}"), "cannot read `x`: gone");
        let io = std::io::Error::other("disk full");
        assert_eq!(exit_code(&anyhow::Error::new(io)), EXIT_FAILED);
        assert_eq!(exit_code(&anyhow::anyhow!("3 cases failed")), EXIT_FAILED);
    }
}
