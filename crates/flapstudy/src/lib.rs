//! Parameter studies and the statistics behind them.
//!
//! - [`fit_wake`]: refit the seed paper's wake-capture regressions (eq 17-19) to a table of
//!   runs and write the result as a `wingforce::WakeCaptureModel`;
//! - [`taguchi`]: the L9, L18 (the paper's Table 2) and L27 orthogonal arrays, the SNR of
//!   eq 15 and its companions, main effects;
//! - [`regression`] and [`stats`]: the full second-order regression of eq 16 with standard
//!   errors, t values and p-values (Student's t via the regularized incomplete beta);
//! - [`spec`], [`responses`], [`sweep`]: study files, tethered hover responses of each case
//!   (no rigid-body simulation: [`flapsim::averaged::mean_loads`] and the wings' cycle means),
//!   parallel sweeps with deterministic CSV output (a case whose analysis fails is a row
//!   with its reason, [`sweep::CaseOutcome`]), shards and their merge;
//! - [`shard`] and [`slurm`]: the study content hash, atomic shard files and their merge, and
//!   the Slurm job-array script that runs one shard per task;
//! - [`optimize`]: Nelder-Mead, and lift per power under a weight-support penalty;
//! - [`envelope`]: trims, power, limit margins and modes over a grid of flight conditions.

pub mod envelope;
pub mod error;
pub mod fit_wake;
pub mod optimize;
pub mod regression;
pub mod responses;
pub mod shard;
pub mod slurm;
pub mod spec;
pub mod stats;
pub mod sweep;
pub mod table;
pub mod taguchi;

pub use error::{StudyError, StudyResult};
pub use fit_wake::{WakeCaptureData, WakeCaptureFit, fit_wake_capture};
pub use responses::{HoverResponses, Response, hover_responses};
pub use spec::{DesignKind, Study, StudySpec};
pub use sweep::{CaseOutcome, CaseResult, FailedCase, merge_csv};
pub use taguchi::{OrthogonalArray, SnrKind};
