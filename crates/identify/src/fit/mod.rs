//! The fit: segments, residuals, the Levenberg-Marquardt solve and the statistics.
//!
//! **Segments** (multiple shooting). A hover log is flown closed loop around an unstable
//! vehicle, so its controls replayed open loop over a whole second diverge from the
//! measurements whatever the parameters. The flight is cut into segments of
//! [`FitOptions::segment_wingbeats`] wingbeats, each started at a wingbeat start with a known
//! state ([`crate::data::WingbeatStart`]: the log's `/vehicle/state` there, or an estimate
//! from the motion capture) and flown on the logged controls of its wingbeats; segments do
//! not overlap (a start inside the previous segment is skipped). A log at the default 2000 Hz
//! holds the state at the first step of about one wingbeat in eleven (the decimation's
//! buckets do not line up with the wingbeats); `--full-rate` logs have all.
//!
//! **Start states** ([`FitOptions::start_states`]). A log's `/vehicle/state` is the truth
//! and is held. A state estimated from the motion capture (a CSV flight) misses the
//! within-wingbeat oscillation of the velocities, and a replay from it starts off the true
//! state: then each segment's start state gets 12 unknowns too (corrections of position,
//! attitude as a body-axes rotation vector, velocity and body rates), fitted with the
//! parameters (full multiple shooting). A correction moves only its segment's residuals, so
//! its Jacobian column flies that segment alone. The parameters' covariance is then the
//! parameter block of the whole inverse, so the start states' uncertainty widens their
//! intervals, and the degrees of freedom are m minus all the unknowns.
//!
//! **Residuals**, each divided by its sensor's noise standard deviation from the model's
//! `[sensors]` (so the cost is a chi-square): for each motion-capture frame in a segment,
//! the simulated position (plus `mocap_bias_*`) minus the measured one (3, over
//! `position_noise_m`) and the rotation vector of measured^-1 * simulated attitude (3, body
//! axes, over `attitude_noise_deg`); with the IMU, each sample's simulated body rate (plus
//! `gyro_bias_*`) minus the gyroscope's (over the white noise per sample, density x
//! sqrt(rate)) and simulated specific force R^T (a - g) (plus `accel_bias_*`) minus the
//! accelerometer's, a being the change of velocity over the step before, as flapsim's IMU
//! computes it. The random walk of the biases is not modelled (constant biases).
//!
//! **Solver**: `levenberg-marquardt` (rust-cv's port of MINPACK's lmder, with its scaling and
//! trust region), chosen over argmin because argmin has no Levenberg-Marquardt (only
//! Gauss-Newton) and this one is the reference algorithm for small dense problems like this.
//! It works on the parameters divided by their scales ([`crate::params::Param::scale`]). The
//! Jacobian is by central differences with a step of [`FitOptions::fd_step`] (default 1e-3,
//! 1e-2 for wings with hinge stops: [`STOPS_FD_STEP`]) of each parameter's scale: 0.1 % of an inertia, 25 nm of a fruit fly's CoM offset; the
//! truncation error is second order in it (1e-6 relative) and the simulation is
//! deterministic, so no noise is differenced. Each evaluation runs every segment, in
//! parallel (rayon).
//!
//! **Scanned starts.** A parameter whose cost has several minima (a stop's restitution,
//! which changes the strikes a wing makes: [`crate::Param::scan_values`]) is first flown at
//! each value of a scan over its range, the others at their start, and the solver starts
//! from the scanned value of lowest cost when that is below the model's (the report gives
//! it as `scanned_start`).
//!
//! **Statistics** at the solution, with m residuals and n parameters: sigma^2 = SSR / (m -
//! n), covariance sigma^2 (J^T J)^-1 (through an SVD of J with normalized columns), standard
//! errors its diagonal's roots, 95 % confidence intervals fitted +- t(0.975, m - n) SE with
//! Student's t ([`t_quantile`], from flapstudy's `stats::student_t_cdf`). A parameter is
//! reported **not identifiable** when the measurements do not depend on it (its Jacobian
//! column below 1e-8 of the largest), when its column is (nearly) a combination of the others
//! (variance inflation factor above 1e6, i.e. a standard error inflated a thousandfold, or a
//! zero singular value), or when its 95 % half-width exceeds both its fitted value's
//! magnitude and its scale.
//!
//! A segment whose simulation diverges for trial parameters keeps its last finite state for
//! its remaining measurements (a large, finite cost the solver backs away from); a model the
//! trial parameters make invalid (a negative inertia) gets residuals of [`PENALTY`] each.

use std::cell::{Cell, RefCell};

use levenberg_marquardt::LevenbergMarquardt;
use rayon::prelude::*;

use crate::data::FlightData;
use crate::error::Result;

mod problem;
mod report;
pub mod resim;
mod segments;
mod setup;
mod types;

pub use types::{
    DEFAULT_FD_STEP, FitOptions, FitReport, NO_EFFECT, PENALTY, ParamResult, Progress,
    STOPS_FD_STEP, StartStates,
};

use problem::Problem;
pub use report::t_quantile;
use report::{describe, statistics};
use setup::setup;

/// Fits `opts.params` to `data` (see the module docs). `observer` sees the progress after
/// every evaluation and stops the fit by returning false (the report then says
/// `interrupted`). Errors: bad settings, a model that does not load or has no sensor noise,
/// data without a segment to fit.
pub fn identify(
    data: &FlightData,
    opts: &FitOptions,
    observer: &mut dyn FnMut(&Progress) -> bool,
) -> Result<FitReport> {
    let started = std::time::Instant::now();
    opts.check()?;
    let setup = setup(data, opts)?;
    let starts: Vec<f64> = setup
        .params
        .iter()
        .map(|p| p.nominal(&setup.base))
        .collect();
    let x0: Vec<f64> = starts
        .iter()
        .zip(&setup.scales)
        .map(|(v, s)| v / s)
        .collect();
    // The start-state corrections (when fitted) follow the parameters, starting at zero.
    let mut x0 = x0;
    x0.resize(setup.unknowns(), 0.0);
    let n_all = x0.len();
    let all: Vec<usize> = (0..n_all).collect();
    let (problem, lm_termination, cost_before, scanned) = solve(&setup, x0, opts, observer);
    let interrupted = problem.stopped.get();
    let x = problem.x.clone();
    let (r, diverged_segments) = setup.residuals(&x);
    let diverged_segments = diverged_segments.min(setup.segments.len());
    let cost_after: f64 = r.iter().map(|v| v * v).sum();
    let j = if interrupted {
        None
    } else {
        Some(problem.jacobian_at(&x, &all))
    };
    problem.tell(1, Some(cost_after));
    let m = setup.m;
    let dof = m - n_all;
    let t = t_quantile(0.975, dof as f64);
    let sigma2 = cost_after / dof as f64;
    let fitted = setup.values(&x);
    let (mut params, condition_number) = match &j {
        Some(j) => statistics(&setup, j, &starts, &fitted, sigma2, t),
        None => (
            setup
                .params
                .iter()
                .zip(starts.iter().zip(&fitted))
                .map(|(p, (s, f))| ParamResult {
                    name: p.name(),
                    model_field: p.model_field(),
                    start: *s,
                    fitted: *f,
                    std_error: f64::NAN,
                    ci95: [f64::NAN; 2],
                    relative_ci: f64::NAN,
                    identifiable: false,
                    reason: Some("the fit was interrupted before its statistics".into()),
                    scanned_start: None,
                })
                .collect(),
            f64::NAN,
        ),
    };
    for (p, s) in params.iter_mut().zip(scanned) {
        p.scanned_start = s;
    }
    let termination = if interrupted {
        "interrupted (Ctrl-C)".to_owned()
    } else {
        match &lm_termination {
            Some(t) => describe(t, opts.patience * (problem.free.len() + 1)),
            None => "nothing to fit: the measurements depend on none of the parameters".into(),
        }
    };
    Ok(FitReport {
        source: data.source.display().to_string(),
        format: data.format,
        model: setup.base.name.clone(),
        start_source: data.start_source,
        start_states_fitted: setup.fit_states,
        segments: setup.segments.len(),
        segment_wingbeats: opts.segment_wingbeats,
        mocap_frames: setup.segments.iter().map(|s| s.mocap.len()).sum(),
        imu_samples: setup.segments.iter().map(|s| s.imu.len()).sum(),
        residuals: m,
        dof,
        simulations: problem.simulations.get(),
        iterations: problem.iterations.get(),
        cost_before,
        cost_after,
        rms_before: (cost_before / m as f64).sqrt(),
        rms_after: (cost_after / m as f64).sqrt(),
        converged: !interrupted
            && lm_termination
                .as_ref()
                .is_some_and(levenberg_marquardt::TerminationReason::was_successful),
        termination,
        condition_number,
        t_quantile: t,
        fd_step: setup.fd_step,
        diverged_segments,
        interrupted,
        runtime_s: started.elapsed().as_secs_f64(),
        params,
    })
}

/// Levenberg-Marquardt over the unknowns of `setup` from `x0` (the parameters, then any
/// start-state corrections), or from the scanned starts ([`scan_starts`]): the problem at
/// the solution, the solver's termination (`None` when there was nothing to fit or Ctrl-C
/// stopped the scan), the cost at `x0` and the scanned starts. Parameters the measurements do not
/// depend on at the start are held there (the solver would wander along their flat
/// direction); when every parameter is held, nothing is fitted.
fn solve<'s, 'a, 'o>(
    setup: &'s segments::Setup<'a>,
    x0: Vec<f64>,
    opts: &FitOptions,
    observer: &'o mut dyn FnMut(&Progress) -> bool,
) -> (
    Problem<'s, 'a, 'o>,
    Option<levenberg_marquardt::TerminationReason>,
    f64,
    Vec<Option<f64>>,
) {
    let n = setup.params.len();
    let n_all = x0.len();
    let max_evals = (opts.patience * (n + 1)) as u64 + 1;
    let all: Vec<usize> = (0..n_all).collect();
    let mut problem = Problem {
        setup,
        x: x0.clone(),
        free: all.clone(),
        r: RefCell::new(None),
        h: setup.fd_step,
        simulations: Cell::new(0),
        iterations: Cell::new(0),
        // Each residual evaluation may come with a Jacobian, and the final statistics take
        // one more Jacobian and evaluation (filled in below).
        max_simulations: 0,
        observer: RefCell::new(observer),
        stopped: Cell::new(false),
    };
    let jacobian = problem.jacobian_cost(n_all);
    let scans: usize = setup
        .params
        .iter()
        .filter_map(|p| p.scan_values())
        .map(|v| v.len())
        .sum();
    problem.max_simulations = max_evals * (1 + jacobian) + jacobian + 2 + scans as u64;
    let (r0, _) = setup.residuals(&x0);
    problem.tell(1, None);
    let cost_before: f64 = r0.iter().map(|v| v * v).sum();
    let scanned = scan_starts(&mut problem, cost_before);
    let x0 = problem.x.clone();
    if n > 0 && !problem.stopped.get() {
        let j0 = problem.jacobian_at(&x0, &all);
        let norms: Vec<f64> = (0..n).map(|i| j0.column(i).norm()).collect();
        let max_norm = norms.iter().cloned().fold(0.0, f64::max);
        problem.free = all
            .iter()
            .copied()
            .filter(|&i| i >= n || norms[i] > NO_EFFECT * max_norm)
            .collect();
    }
    let nothing = problem.free.is_empty() || (n > 0 && problem.free.iter().all(|&i| i >= n));
    if nothing || problem.stopped.get() {
        return (problem, None, cost_before, scanned);
    }
    let (p, report) = LevenbergMarquardt::new()
        .with_patience(opts.patience)
        // The parameters are already scaled to O(1) (Param::scale): a trust region in
        // them keeps a parameter the data barely see from taking absurd trial values,
        // which MINPACK's column-norm scaling would allow.
        .with_scale_diag(false)
        .minimize(problem);
    (p, Some(report.termination), cost_before, scanned)
}

/// Moves the start of each parameter with [`crate::Param::scan_values`] to the scanned value
/// of lowest cost, when that is below the cost at the start (`cost`), one parameter after
/// the other with the others at their start: each parameter's start it moved to (`None`
/// where it kept the model's). The trial values are flown in parallel; Ctrl-C stops it.
fn scan_starts(problem: &mut Problem<'_, '_, '_>, mut cost: f64) -> Vec<Option<f64>> {
    let setup = problem.setup;
    let mut moved = vec![None; setup.params.len()];
    for (i, p) in setup.params.iter().enumerate() {
        let Some(values) = p.scan_values() else {
            continue;
        };
        let costs: Vec<(f64, f64)> = values
            .par_iter()
            .map(|&v| {
                let mut x = problem.x.clone();
                x[i] = v / setup.scales[i];
                let (r, diverged) = setup.residuals(&x);
                let c = if diverged == usize::MAX {
                    f64::INFINITY
                } else {
                    r.iter().map(|v| v * v).sum()
                };
                (v, c)
            })
            .collect();
        for &(_, c) in &costs {
            problem.tell(1, Some(c));
        }
        if problem.stopped.get() {
            break;
        }
        if let Some(&(v, c)) = costs.iter().min_by(|a, b| a.1.total_cmp(&b.1))
            && c < cost
        {
            problem.x[i] = v / setup.scales[i];
            moved[i] = Some(v);
            cost = c;
        }
    }
    moved
}
