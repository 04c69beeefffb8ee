//! # flapwing-identify
//!
//! Fits vehicle-model parameters (inertia, centre-of-mass offset, air density, C_rot,
//! stroke-plane tilt, mass) and sensor biases to a logged flight by nonlinear least squares,
//! with standard errors, 95 % confidence intervals and an identifiability verdict per
//! parameter, and writes the fitted model file.
//!
//! Data: a flapwing MCAP log with sensors ([`FlightData::from_mcap`]) or a motion-capture
//! CSV with the commands ([`FlightData::from_csv`]; format in README.md). The method
//! (segments restarted from known states, residuals weighted by the sensors' noise,
//! Levenberg-Marquardt with central-difference Jacobians, covariance sigma^2 (J^T J)^-1) is
//! described in [`fit`].
//!
//! ```no_run
//! use flapwing_identify::{FitOptions, FlightData, Param, identify};
//! let data = FlightData::from_mcap("hover.mcap")?;
//! let opts = FitOptions {
//!     params: Param::parse_list("inertia_yy_kg_m2,com_offset_x_m,com_offset_z_m")?,
//!     ..FitOptions::default()
//! };
//! let report = identify(&data, &opts, &mut |_| true)?;
//! println!("{report}");
//! let fitted = flapwing_identify::fitted_model_toml(&data.model_toml, &report, "flapwing identify")?;
//! # let _ = fitted;
//! # Ok::<(), flapwing_identify::Error>(())
//! ```

pub mod bag;
pub mod conventions;
pub mod csv;
pub mod data;
mod error;
pub mod fit;
mod frames;
pub mod model_out;
pub mod params;
pub mod synthetic;

pub use bag::BagRoles;
pub use conventions::{BodyConvention, Conventions, QuaternionOrder, WorldConvention};
pub use data::FlightData;
pub use error::{Error, Result};
pub use fit::resim::{ResimOptions, Resimulation, SegmentSummary, resimulate};
pub use fit::{FitOptions, FitReport, ParamResult, Progress, StartStates, identify};
pub use model_out::fitted_model_toml;
pub use params::Param;
