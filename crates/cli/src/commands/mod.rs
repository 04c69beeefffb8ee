//! One module per subcommand, each with a `run(args) -> anyhow::Result<()>`.

pub mod contour;
pub mod fit_wake;
pub mod forces;
pub mod forces_plot;
pub mod frequency_response;
pub mod frequency_response_plot;
pub mod hover;
pub mod replay;
pub mod simulate;
pub mod stability;
pub mod sweep;
pub mod trim;
pub mod validate;
pub mod wake_capture;
