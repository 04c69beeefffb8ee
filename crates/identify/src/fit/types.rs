//! What a fit takes and gives: its options, its progress, each parameter's result and the
//! report (below the fit's parts, which all use them).

use serde::Serialize;

use crate::data::StartSource;
use crate::error::{Error, Result};
use crate::params::Param;

/// A Jacobian column below this fraction of the largest: the measurements do not depend on
/// the parameter.
pub const NO_EFFECT: f64 = 1e-8;

/// The residual given to each measurement when trial parameters make the model invalid.
pub const PENALTY: f64 = 1e3;

/// The Jacobian's central-difference step, a fraction of each parameter's scale.
pub const DEFAULT_FD_STEP: f64 = 1e-3;

/// The step for wings with hinge stops. Their strikes fall inside steps, so the simulated
/// motion is a jagged function of the parameters on a fine scale: on the hummingbird's
/// 0.2 s hover (measured with crates/identify/tests/recovery.rs, which flew 0.2 s then), a step of 1e-3 gave the torque
/// constant a standard error 3.3x smaller than steps of 1e-2 and 3e-2 (which agree to
/// 20 %), and its true value fell 3.5 standard errors from the fit; at 1e-2 it lies inside
/// its interval.
pub const STOPS_FD_STEP: f64 = 1e-2;

/// Whether the segments' start states are unknowns of the fit too.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StartStates {
    /// Fitted when they are estimates (from the motion capture), fixed when logged.
    #[default]
    Auto,
    /// Held at the logged or estimated states.
    Fixed,
    /// Twelve unknowns per segment (position, attitude, velocity, body rates), fitted with
    /// the parameters: full multiple shooting.
    Fitted,
}

impl StartStates {
    /// Whether the start states are fitted for data whose starts come from `source`.
    pub fn fitted(self, source: StartSource) -> bool {
        match self {
            StartStates::Auto => source == StartSource::Mocap,
            StartStates::Fixed => false,
            StartStates::Fitted => true,
        }
    }
}

/// How to fit.
#[derive(Debug, Clone, PartialEq)]
pub struct FitOptions {
    /// The parameters to fit.
    pub params: Vec<Param>,
    /// Wingbeats per segment (see the module docs).
    pub segment_wingbeats: u32,
    /// Use the IMU's samples as measurements too.
    pub use_imu: bool,
    /// Central-difference step, fraction of each parameter's scale (`None`:
    /// [`DEFAULT_FD_STEP`], or [`STOPS_FD_STEP`] for wings with hinge stops).
    pub fd_step: Option<f64>,
    /// The solver's patience: it stops after this many times (n + 1) residual evaluations.
    pub patience: usize,
    /// Fit only the first `max_duration_s` of the flight (`None`: all of it).
    pub max_duration_s: Option<f64>,
    /// Whether the segments' start states are fitted too (see the module docs).
    pub start_states: StartStates,
}

impl Default for FitOptions {
    fn default() -> Self {
        Self {
            params: vec![Param::InertiaYy, Param::ComOffsetX, Param::ComOffsetZ],
            segment_wingbeats: 4,
            use_imu: false,
            fd_step: None,
            patience: 30,
            max_duration_s: None,
            start_states: StartStates::Auto,
        }
    }
}

impl FitOptions {
    /// Checks the settings, a parameter to fit among them.
    pub fn check(&self) -> Result<()> {
        self.check_settings()?;
        if self.params.is_empty() {
            return Err(Error::Setting("no parameter to fit".into()));
        }
        Ok(())
    }

    /// Checks the settings other than the parameters (a resimulation fits none).
    pub(crate) fn check_settings(&self) -> Result<()> {
        if !(1..=1000).contains(&self.segment_wingbeats) {
            return Err(Error::Setting(format!(
                "segment length {} wingbeats is not allowed: an integer in [1, 1000]",
                self.segment_wingbeats
            )));
        }
        if let Some(h) = self.fd_step
            && !(h.is_finite() && h > 0.0 && h <= 0.1)
        {
            return Err(Error::Setting(format!(
                "finite-difference step {h} is not allowed: in (0, 0.1] of each parameter's scale"
            )));
        }
        if !(1..=10_000).contains(&self.patience) {
            return Err(Error::Setting(format!(
                "patience {} is not allowed: an integer in [1, 10000]",
                self.patience
            )));
        }
        if let Some(d) = self.max_duration_s
            && !(d.is_finite() && d > 0.0)
        {
            return Err(Error::Setting(format!(
                "duration {d} s is not allowed: a time > 0"
            )));
        }
        Ok(())
    }
}

/// What the fit reports of one parameter.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ParamResult {
    /// Name (with unit).
    pub name: String,
    /// The model field it changes (`None`: a measurement parameter, not written).
    pub model_field: Option<&'static str>,
    /// Start value (the model's).
    pub start: f64,
    /// Fitted value.
    pub fitted: f64,
    /// Standard error (infinite when not identifiable through dependence).
    pub std_error: f64,
    /// 95 % confidence interval.
    pub ci95: [f64; 2],
    /// Half-width of the interval over max(|fitted|, scale).
    pub relative_ci: f64,
    /// Whether the data determine it.
    pub identifiable: bool,
    /// Why not, when not.
    pub reason: Option<String>,
    /// The value the solver started from instead of `start`, when a scan of the parameter's
    /// range found a lower cost there (see [`crate::Param::scan_values`]).
    pub scanned_start: Option<f64>,
}

/// The outcome of a fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FitReport {
    /// The data file.
    pub source: String,
    /// "mcap" or "csv".
    pub format: &'static str,
    /// The model's name.
    pub model: String,
    /// Where the segments' start states came from.
    pub start_source: StartSource,
    /// Whether the segments' start states were fitted (12 unknowns each) or held.
    pub start_states_fitted: bool,
    /// Segments flown.
    pub segments: usize,
    /// Wingbeats per segment (at most).
    pub segment_wingbeats: u32,
    /// Motion-capture frames compared.
    pub mocap_frames: usize,
    /// IMU samples compared.
    pub imu_samples: usize,
    /// Residuals m.
    pub residuals: usize,
    /// Degrees of freedom m - n.
    pub dof: usize,
    /// Simulations of all segments run (residual evaluations, each Jacobian counts 2 n).
    pub simulations: u64,
    /// Jacobians evaluated (the solver's iterations).
    pub iterations: u64,
    /// Sum of squared weighted residuals at the start (chi-square).
    pub cost_before: f64,
    /// ... and at the end.
    pub cost_after: f64,
    /// sqrt(cost / m) at the start (1 for a model that fits to the noise).
    pub rms_before: f64,
    /// ... and at the end.
    pub rms_after: f64,
    /// True when the solver met its convergence test.
    pub converged: bool,
    /// The solver's termination reason.
    pub termination: String,
    /// Condition number of the column-normalized Jacobian (infinite when singular).
    pub condition_number: f64,
    /// Student's t quantile of the intervals.
    pub t_quantile: f64,
    /// Central-difference step, fraction of each scale.
    pub fd_step: f64,
    /// Segments whose simulation diverged at the fitted parameters.
    pub diverged_segments: usize,
    /// True when the observer stopped the fit (Ctrl-C).
    pub interrupted: bool,
    /// Wall-clock time, s.
    pub runtime_s: f64,
    /// Every parameter.
    pub params: Vec<ParamResult>,
}

/// Progress of a fit, handed to the observer after every evaluation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    /// Simulations of all segments so far.
    pub simulations: u64,
    /// An upper bound of the simulations the fit can take.
    pub max_simulations: u64,
    /// The cost of the last evaluation (for residual evaluations).
    pub cost: Option<f64>,
}
