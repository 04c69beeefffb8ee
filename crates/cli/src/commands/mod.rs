//! One module per subcommand, each with a `run(args) -> anyhow::Result<()>`.

pub mod analyze;
pub mod contour;
pub mod envelope;
pub mod envelope_plot;
pub mod fit_wake;
pub mod forces;
pub mod forces_plot;
pub mod forces_vehicle;
pub mod frequency_response;
pub mod frequency_response_plot;
pub mod hover;
pub mod identify;
pub mod optimize;
pub mod replay;
pub mod resimulate;
pub mod simulate;
pub mod stability;
pub mod status;
pub mod submit;
pub mod sweep;
pub mod sweep_merge;
pub mod trim;
pub mod validate;
pub mod wake_capture;
