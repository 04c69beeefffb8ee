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
//! Jacobian is by central differences with a step of [`FitOptions::fd_step`] (default 1e-3)
//! of each parameter's scale: 0.1 % of an inertia, 25 nm of a fruit fly's CoM offset; the
//! truncation error is second order in it (1e-6 relative) and the simulation is
//! deterministic, so no noise is differenced. Each evaluation runs every segment, in
//! parallel (rayon).
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

use flapsim::{Controls, Mode, Simulation, State, Vehicle, VehicleSpec};
use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt};
use nalgebra::{DMatrix, DVector, Vector3};
use nalgebra_lm::{Dyn, Owned};
use rayon::prelude::*;
use serde::Serialize;

use crate::data::{FlightData, StartSource, controlled_wingbeats, timing};
use crate::error::{Error, Result};
use crate::params::Param;

/// A Jacobian column below this fraction of the largest: the measurements do not depend on
/// the parameter.
pub const NO_EFFECT: f64 = 1e-8;

/// The residual given to each measurement when trial parameters make the model invalid.
pub const PENALTY: f64 = 1e3;

/// How to fit.
#[derive(Debug, Clone, PartialEq)]
pub struct FitOptions {
    /// The parameters to fit.
    pub params: Vec<Param>,
    /// Wingbeats per segment (see the module docs).
    pub segment_wingbeats: u32,
    /// Use the IMU's samples as measurements too.
    pub use_imu: bool,
    /// Central-difference step, fraction of each parameter's scale.
    pub fd_step: f64,
    /// The solver's patience: it stops after this many times (n + 1) residual evaluations.
    pub patience: usize,
    /// Fit only the first `max_duration_s` of the flight (`None`: all of it).
    pub max_duration_s: Option<f64>,
}

impl Default for FitOptions {
    fn default() -> Self {
        Self {
            params: vec![Param::InertiaYy, Param::ComOffsetX, Param::ComOffsetZ],
            segment_wingbeats: 4,
            use_imu: false,
            fd_step: 1e-3,
            patience: 30,
            max_duration_s: None,
        }
    }
}

impl FitOptions {
    /// Checks the settings.
    pub fn check(&self) -> Result<()> {
        if !(1..=1000).contains(&self.segment_wingbeats) {
            return Err(Error::Setting(format!(
                "segment length {} wingbeats is not allowed: an integer in [1, 1000]",
                self.segment_wingbeats
            )));
        }
        if !(self.fd_step.is_finite() && self.fd_step > 0.0 && self.fd_step <= 0.1) {
            return Err(Error::Setting(format!(
                "finite-difference step {} is not allowed: in (0, 0.1] of each parameter's scale",
                self.fd_step
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
        if self.params.is_empty() {
            return Err(Error::Setting("no parameter to fit".into()));
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

/// One segment of the flight.
#[derive(Debug, Clone)]
struct Segment {
    state: State,
    /// First global step.
    step0: u64,
    controls: Vec<Controls>,
    steps: usize,
    /// (local step, frame index).
    mocap: Vec<(usize, usize)>,
    imu: Vec<(usize, usize)>,
}

/// The first step at or after `t_s` as flapsim's sensors pick it (a sample falls due at the
/// step whose time is within `tol_s` of it or after).
fn step_at(t_s: f64, dt_s: f64, tol_s: f64) -> Option<u64> {
    let x = ((t_s - tol_s) / dt_s).ceil();
    if !(x.is_finite() && x > -1e15 && x < 1e15) {
        return None;
    }
    let mut s = x.max(0.0) as i64;
    while s > 0 && (s - 1) as f64 * dt_s >= t_s - tol_s {
        s -= 1;
    }
    while (s as f64) * dt_s < t_s - tol_s {
        s += 1;
    }
    Some(s as u64)
}

struct Weights {
    pos: f64,
    att: f64,
    gyro: f64,
    accel: f64,
}

/// Everything fixed during a fit.
struct Setup<'a> {
    data: &'a FlightData,
    base: VehicleSpec,
    params: Vec<Param>,
    scales: Vec<f64>,
    segments: Vec<Segment>,
    weights: Weights,
    dt_s: f64,
    gravity_m_s2: f64,
    m: usize,
}

impl Setup<'_> {
    fn values(&self, x: &[f64]) -> Vec<f64> {
        x.iter().zip(&self.scales).map(|(x, s)| x * s).collect()
    }

    /// Weighted residuals at scaled parameters `x`, and the segments that diverged
    /// (`usize::MAX` when the parameters make the model invalid).
    fn residuals(&self, x: &[f64]) -> (Vec<f64>, usize) {
        let values = self.values(x);
        let mut spec = self.base.clone();
        let mut mocap_bias = Vector3::zeros();
        let mut gyro_bias = Vector3::zeros();
        let mut accel_bias = Vector3::zeros();
        for (p, v) in self.params.iter().zip(&values) {
            p.apply(&mut spec, &self.base, *v);
            match p {
                Param::MocapBias(k) => mocap_bias[*k] = *v,
                Param::GyroBias(k) => gyro_bias[*k] = *v,
                Param::AccelBias(k) => accel_bias[*k] = *v,
                _ => {}
            }
        }
        let penalty = || (vec![PENALTY; self.m], usize::MAX);
        let vehicle = match spec.build(&self.data.model_origin) {
            Ok(v) => v,
            Err(e) => {
                if std::env::var_os("FLAPWING_IDENTIFY_DEBUG").is_some() {
                    eprintln!("identify: trial model invalid: {e}");
                }
                return penalty();
            }
        };
        let per_segment: Vec<(Vec<f64>, bool)> = self
            .segments
            .par_iter()
            .map(|seg| self.segment_residuals(&vehicle, seg, &mocap_bias, &gyro_bias, &accel_bias))
            .collect();
        let mut r = Vec::with_capacity(self.m);
        let mut diverged = 0;
        for (v, d) in per_segment {
            r.extend(v);
            diverged += usize::from(d);
        }
        if r.len() != self.m {
            return penalty();
        }
        for x in &mut r {
            if !x.is_finite() {
                *x = PENALTY;
            }
        }
        (r, diverged)
    }

    fn segment_residuals(
        &self,
        vehicle: &Vehicle,
        seg: &Segment,
        mocap_bias: &Vector3<f64>,
        gyro_bias: &Vector3<f64>,
        accel_bias: &Vector3<f64>,
    ) -> (Vec<f64>, bool) {
        let n_res = 6 * seg.mocap.len() + 6 * seg.imu.len();
        let fail = || (vec![PENALTY; n_res], true);
        // The vehicle starts with the first wingbeat's controls in force, its clock at the
        // segment's first step (the wing phases of the original run).
        let mut v = vehicle.clone();
        if v.apply_controls(&seg.controls[0]).is_err() {
            return fail();
        }
        let Ok(mut sim) = Simulation::try_new(v, Mode::Free) else {
            return fail();
        };
        if sim.start_at_step(seg.step0).is_err() {
            return fail();
        }
        sim.set_state(&seg.state);
        let per = vehicle.sim.steps_per_wingbeat;
        let mut states: Vec<State> = Vec::with_capacity(seg.steps);
        let mut diverged = false;
        let mut in_force = seg.controls[0];
        for j in 0..seg.steps {
            if j % per == 0 {
                let c = seg.controls[j / per];
                if self.data.controls_each_wingbeat || c != in_force {
                    sim.set_controls(c);
                    in_force = c;
                }
            }
            if let Some(g) = &self.data.gust {
                let t = (seg.step0 + j as u64) as f64 * self.dt_s;
                let on = t >= g.start_s && t < g.start_s + g.duration_s;
                sim.set_wind(if on {
                    Vector3::from(g.velocity_m_s)
                } else {
                    Vector3::zeros()
                });
            }
            match sim.step() {
                Ok(out) => states.push(out.state),
                Err(_) => {
                    diverged = true;
                    break;
                }
            }
        }
        let last = states.last().copied().unwrap_or(seg.state);
        let at = |j: usize| states.get(j).copied().unwrap_or(last);
        let w = &self.weights;
        let mut r = Vec::with_capacity(n_res);
        for &(j, i) in &seg.mocap {
            let f = &self.data.mocap[i];
            let s = at(j);
            let dp = (s.position_m + mocap_bias - f.position_m) / w.pos;
            let da = (f.attitude.inverse() * s.world_from_body).scaled_axis() / w.att;
            r.extend([dp.x, dp.y, dp.z, da.x, da.y, da.z]);
        }
        for &(j, i) in &seg.imu {
            let f = &self.data.imu[i];
            let s = at(j);
            let prev = at(j - 1);
            let a = (s.velocity_m_s - prev.velocity_m_s) / self.dt_s;
            let g = Vector3::new(0.0, 0.0, -self.gravity_m_s2);
            let spec_force = s.world_from_body.inverse() * (a - g);
            let dg = (s.angular_velocity_body_rad_s + gyro_bias - f.gyro_rad_s) / w.gyro;
            let da = (spec_force + accel_bias - f.accel_m_s2) / w.accel;
            r.extend([dg.x, dg.y, dg.z, da.x, da.y, da.z]);
        }
        (r, diverged)
    }
}

/// The quantile of Student's t with `nu` degrees of freedom at probability `p` in (0.5, 1),
/// by bisection of flapsim's `student_t_cdf` (to 1e-12).
pub fn t_quantile(p: f64, nu: f64) -> f64 {
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    while flapstudy::stats::student_t_cdf(hi, nu) < p && hi < 1e12 {
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if flapstudy::stats::student_t_cdf(mid, nu) < p {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo < 1e-12 * hi.max(1.0) {
            break;
        }
    }
    0.5 * (lo + hi)
}

type LmVector = nalgebra_lm::DVector<f64>;
type LmMatrix = nalgebra_lm::DMatrix<f64>;

/// The solver's view of the fit.
struct Problem<'s, 'a, 'o> {
    setup: &'s Setup<'a>,
    /// All parameters, scaled (those not free stay at their start).
    x: Vec<f64>,
    /// The parameters the solver varies (indices into `x`).
    free: Vec<usize>,
    r: RefCell<Option<Vec<f64>>>,
    h: f64,
    simulations: Cell<u64>,
    iterations: Cell<u64>,
    max_simulations: u64,
    observer: RefCell<&'o mut dyn FnMut(&Progress) -> bool>,
    stopped: Cell<bool>,
}

impl Problem<'_, '_, '_> {
    fn tell(&self, n: u64, cost: Option<f64>) {
        self.simulations.set(self.simulations.get() + n);
        let p = Progress {
            simulations: self.simulations.get(),
            max_simulations: self.max_simulations,
            cost,
        };
        if !(self.observer.borrow_mut())(&p) {
            self.stopped.set(true);
        }
    }

    /// The Jacobian of the residuals in the parameters `cols` at `x`.
    fn jacobian_at(&self, x: &[f64], which: &[usize]) -> DMatrix<f64> {
        let n = which.len();
        let m = self.setup.m;
        let (setup, h) = (self.setup, self.h);
        let (r0, _) = setup.residuals(x);
        // Central differences; one-sided where a side makes the model invalid (a parameter
        // at a bound of the model's validation, e.g. an inertia at the triangle inequality).
        let cols: Vec<Vec<f64>> = (0..n)
            .into_par_iter()
            .map(|c| {
                let i = which[c];
                let mut xp = x.to_vec();
                let mut xm = x.to_vec();
                xp[i] += h;
                xm[i] -= h;
                let (rp, dp) = setup.residuals(&xp);
                let (rm, dm) = setup.residuals(&xm);
                let (a, b, d) = match (dp == usize::MAX, dm == usize::MAX) {
                    (false, false) => (&rp, &rm, 2.0 * h),
                    (true, false) => (&r0, &rm, h),
                    (false, true) => (&rp, &r0, h),
                    (true, true) => (&r0, &r0, h),
                };
                a.iter().zip(b).map(|(a, b)| (a - b) / d).collect()
            })
            .collect();
        let mut j = DMatrix::zeros(m, n);
        for (i, c) in cols.iter().enumerate() {
            for (k, v) in c.iter().enumerate() {
                j[(k, i)] = *v;
            }
        }
        self.iterations.set(self.iterations.get() + 1);
        self.tell(2 * n as u64 + 1, None);
        j
    }
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for Problem<'_, '_, '_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, x: &LmVector) {
        for (&i, v) in self.free.iter().zip(x.iter()) {
            self.x[i] = *v;
        }
        *self.r.borrow_mut() = None;
    }

    fn params(&self) -> LmVector {
        let v: Vec<f64> = self.free.iter().map(|&i| self.x[i]).collect();
        LmVector::from_column_slice(&v)
    }

    fn residuals(&self) -> Option<LmVector> {
        if self.stopped.get() {
            return None;
        }
        if self.r.borrow().is_none() {
            let (r, _) = self.setup.residuals(&self.x);
            let cost: f64 = r.iter().map(|v| v * v).sum();
            *self.r.borrow_mut() = Some(r);
            self.tell(1, Some(cost));
        }
        let r = self.r.borrow();
        r.as_ref().map(|r| LmVector::from_column_slice(r))
    }

    fn jacobian(&self) -> Option<LmMatrix> {
        if self.stopped.get() {
            return None;
        }
        let j = self.jacobian_at(&self.x, &self.free);
        Some(LmMatrix::from_column_slice(
            j.nrows(),
            j.ncols(),
            j.as_slice(),
        ))
    }
}

/// Builds the segments and weights of a fit.
fn setup<'a>(data: &'a FlightData, opts: &FitOptions) -> Result<Setup<'a>> {
    opts.check()?;
    let origin = &data.model_origin;
    let base = VehicleSpec::from_toml(&data.model_toml, origin)
        .map_err(|e| Error::Model(format!("`{origin}` does not load: {e}")))?;
    let vehicle = base
        .build(origin)
        .map_err(|e| Error::Model(format!("`{origin}` does not load: {e}")))?;
    let sensors = vehicle.sensors.ok_or_else(|| {
        Error::Model(format!(
            "`{origin}` has no [sensors] table: the fit weighs each residual by the sensors' noise ([sensors.mocap] position_noise_m and attitude_noise_deg; see models/drosophila.toml)"
        ))
    })?;
    let mocap = sensors.mocap.ok_or_else(|| {
        Error::Model(format!(
            "`{origin}` has no [sensors.mocap] table: the fit weighs the motion-capture residuals by its position_noise_m and attitude_noise_deg"
        ))
    })?;
    let use_imu = opts.use_imu;
    if use_imu && data.imu.is_empty() {
        return Err(Error::Log {
            path: data.source.clone(),
            detail: "the IMU was asked for as a measurement but the data hold no IMU samples (`/sensors/imu` in a log, the gyro_*/accel_* columns of a CSV)".into(),
        });
    }
    if let Some(p) = opts.params.iter().find(|p| p.needs_imu())
        && !use_imu
    {
        return Err(Error::Setting(format!(
            "parameter `{}` is seen only by the IMU's samples: fit with the IMU (--imu)",
            p.name()
        )));
    }
    let (freq_hz, per) = timing(&vehicle);
    let dt_s = Simulation::try_new(vehicle.clone(), Mode::Free)
        .map_err(|e| Error::Model(format!("`{origin}`: {e}")))?
        .dt_s();
    let floor = 1e-12;
    let weights = Weights {
        pos: mocap.position_noise_m.max(floor),
        att: mocap.attitude_noise_rad.max(floor),
        gyro: (sensors.imu.gyro_noise_density * sensors.imu.rate_hz.sqrt()).max(floor),
        accel: (sensors.imu.accel_noise_density * sensors.imu.rate_hz.sqrt()).max(floor),
    };
    let mocap_tol = 1e-6 / mocap.rate_hz;
    let imu_tol = 1e-6 / sensors.imu.rate_hz;
    let controls = controlled_wingbeats(data);
    let end_t = opts.max_duration_s.unwrap_or(f64::INFINITY);
    let k = u64::from(opts.segment_wingbeats);
    let mut segments = Vec::new();
    let mut next_free = 0u64;
    for start in &data.starts {
        let w0 = start.wingbeat;
        if w0 < next_free {
            continue;
        }
        let mut ctl = Vec::new();
        for w in w0..w0 + k {
            let t_end = (w + 1) as f64 / freq_hz;
            match controls.get(&w) {
                Some(c) if t_end <= end_t + 1e-12 => ctl.push(*c),
                _ => break,
            }
        }
        if ctl.is_empty() {
            continue;
        }
        let step0 = w0 * per;
        let steps = ctl.len() * per as usize;
        let in_segment = |t: f64, tol: f64| -> Option<usize> {
            let s = step_at(t, dt_s, tol)?;
            (s >= step0 && s < step0 + steps as u64).then(|| (s - step0) as usize)
        };
        let t0 = step0 as f64 * dt_s;
        let t1 = (step0 + steps as u64) as f64 * dt_s;
        let lo = data.mocap.partition_point(|f| f.t_s < t0 - dt_s);
        let mut seg_mocap = Vec::new();
        for (i, f) in data.mocap.iter().enumerate().skip(lo) {
            if f.t_s > t1 + dt_s {
                break;
            }
            if let Some(j) = in_segment(f.t_s, mocap_tol) {
                seg_mocap.push((j, i));
            }
        }
        let mut seg_imu = Vec::new();
        if use_imu {
            let lo = data.imu.partition_point(|f| f.t_s < t0 - dt_s);
            for (i, f) in data.imu.iter().enumerate().skip(lo) {
                if f.t_s > t1 + dt_s {
                    break;
                }
                // The accelerometer needs the step before (the velocity change).
                if let Some(j) = in_segment(f.t_s, imu_tol).filter(|j| *j >= 1) {
                    seg_imu.push((j, i));
                }
            }
        }
        if seg_mocap.is_empty() && seg_imu.is_empty() {
            continue;
        }
        segments.push(Segment {
            state: start.state,
            step0,
            controls: ctl,
            steps,
            mocap: seg_mocap,
            imu: seg_imu,
        });
        next_free = w0 + k;
    }
    if segments.is_empty() {
        return Err(Error::Data(format!(
            "`{}`: no segment to fit: {} wingbeat starts with a known state, {} wingbeats with controls, {} motion-capture frames; a segment needs a wingbeat start with a state (a `/vehicle/state` sample at the wingbeat's first step, or {} motion-capture frames on each side), the controls of its wingbeats and a measurement",
            data.source.display(),
            data.starts.len(),
            controls.len(),
            data.mocap.len(),
            crate::data::START_FIT_FRAMES
        )));
    }
    let m: usize = segments
        .iter()
        .map(|s| 6 * s.mocap.len() + 6 * s.imu.len())
        .sum();
    let scales: Vec<f64> = opts.params.iter().map(|p| p.scale(&base)).collect();
    if m <= opts.params.len() {
        return Err(Error::Data(format!(
            "`{}`: {m} residuals cannot determine {} parameters (more measurements are needed)",
            data.source.display(),
            opts.params.len()
        )));
    }
    Ok(Setup {
        data,
        base,
        params: opts.params.clone(),
        scales,
        segments,
        weights,
        dt_s,
        gravity_m_s2: vehicle.gravity_m_s2,
        m,
    })
}

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
    let setup = setup(data, opts)?;
    let n = setup.params.len();
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
    let max_evals = (opts.patience * (n + 1)) as u64 + 1;
    let all: Vec<usize> = (0..n).collect();
    let mut problem = Problem {
        setup: &setup,
        x: x0.clone(),
        free: all.clone(),
        r: RefCell::new(None),
        h: opts.fd_step,
        simulations: Cell::new(0),
        iterations: Cell::new(0),
        // Each residual evaluation may come with a Jacobian (2 n more), and the final
        // statistics take one more Jacobian and evaluation.
        max_simulations: max_evals * (2 + 2 * n as u64) + 2 * n as u64 + 3,
        observer: RefCell::new(observer),
        stopped: Cell::new(false),
    };
    let (r0, _) = setup.residuals(&x0);
    problem.tell(1, None);
    let cost_before: f64 = r0.iter().map(|v| v * v).sum();
    // Parameters the measurements do not depend on at the start are held there (the
    // solver would wander along their flat direction) and reported as not identifiable.
    let j0 = problem.jacobian_at(&x0, &all);
    let norms: Vec<f64> = (0..n).map(|i| j0.column(i).norm()).collect();
    let max_norm = norms.iter().cloned().fold(0.0, f64::max);
    problem.free = all
        .iter()
        .copied()
        .filter(|&i| norms[i] > NO_EFFECT * max_norm)
        .collect();
    let (problem, lm_termination) = if problem.free.is_empty() {
        (problem, None::<levenberg_marquardt::TerminationReason>)
    } else {
        let (p, report) = LevenbergMarquardt::new()
            .with_patience(opts.patience)
            // The parameters are already scaled to O(1) (Param::scale): a trust region in
            // them keeps a parameter the data barely see from taking absurd trial values,
            // which MINPACK's column-norm scaling would allow.
            .with_scale_diag(false)
            .minimize(problem);
        (p, Some(report.termination))
    };
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
    let dof = m - n;
    let t = t_quantile(0.975, dof as f64);
    let sigma2 = cost_after / dof as f64;
    let fitted = setup.values(&x);
    let (params, condition_number) = match &j {
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
                })
                .collect(),
            f64::NAN,
        ),
    };
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
        fd_step: opts.fd_step,
        diverged_segments,
        interrupted,
        runtime_s: started.elapsed().as_secs_f64(),
        params,
    })
}

fn describe(t: &levenberg_marquardt::TerminationReason, max_evals: usize) -> String {
    use levenberg_marquardt::TerminationReason as T;
    match t {
        T::Converged { ftol, xtol } => match (ftol, xtol) {
            (true, true) => "converged (relative cost and step changes below tolerance)".into(),
            (true, false) => "converged (relative cost change below tolerance)".into(),
            _ => "converged (relative step below tolerance)".into(),
        },
        T::Orthogonal => "converged (residuals orthogonal to the Jacobian: gradient zero)".into(),
        T::ResidualsZero => "converged (residuals zero)".into(),
        T::LostPatience => format!(
            "did not converge: {max_evals} residual evaluations (the patience) used up; raise the patience or start closer"
        ),
        T::NoImprovementPossible(what) => {
            format!("did not converge: no improvement possible in {what} at machine precision")
        }
        T::Numerical(what) => format!("did not converge: non-finite numbers in the {what}"),
        T::User(what) => format!("stopped: the {what} could not be computed"),
        other => format!("did not converge: {other:?}"),
    }
}

/// Standard errors, intervals and identifiability from the Jacobian at the solution.
fn statistics(
    setup: &Setup<'_>,
    j: &DMatrix<f64>,
    starts: &[f64],
    fitted: &[f64],
    sigma2: f64,
    t: f64,
) -> (Vec<ParamResult>, f64) {
    let n = j.ncols();
    let norms: Vec<f64> = (0..n).map(|i| j.column(i).norm()).collect();
    let max_norm = norms.iter().cloned().fold(0.0, f64::max);
    let effective: Vec<usize> = (0..n)
        .filter(|&i| norms[i] > NO_EFFECT * max_norm && norms[i] > 0.0)
        .collect();
    // Column-normalized Jacobian of the parameters that have an effect.
    let mut jn = DMatrix::zeros(j.nrows(), effective.len());
    for (c, &i) in effective.iter().enumerate() {
        jn.set_column(c, &(j.column(i) / norms[i]));
    }
    let mut cov_n = DMatrix::from_element(effective.len(), effective.len(), f64::INFINITY);
    let mut vif = vec![f64::INFINITY; effective.len()];
    let mut condition = f64::INFINITY;
    let mut singular_dirs: Vec<DVector<f64>> = Vec::new();
    if !effective.is_empty() {
        let svd = jn.clone().svd(false, true);
        let s = &svd.singular_values;
        let smax = s.max();
        let smin = s.min();
        condition = if smin > 0.0 {
            smax / smin
        } else {
            f64::INFINITY
        };
        if let Some(vt) = &svd.v_t {
            let mut inv = DMatrix::zeros(effective.len(), effective.len());
            for k in 0..s.len() {
                let v = vt.row(k).transpose();
                if s[k] > 1e-12 * smax {
                    inv += &v * v.transpose() / (s[k] * s[k]);
                } else {
                    singular_dirs.push(v);
                }
            }
            for c in 0..effective.len() {
                vif[c] = inv[(c, c)];
            }
            cov_n = inv;
        }
    }
    let mut out = Vec::with_capacity(n);
    for (i, p) in setup.params.iter().enumerate() {
        let scale = setup.scales[i];
        let c = effective.iter().position(|&e| e == i);
        let in_null = c.is_some_and(|c| singular_dirs.iter().any(|v| v[c].abs() > 1e-3));
        let (se, reason) = match c {
            None => (
                f64::INFINITY,
                Some(format!(
                    "the measurements do not depend on it (Jacobian column norm {:.3e}, the largest {:.3e})",
                    norms[i], max_norm
                )),
            ),
            Some(c) => {
                let var = sigma2 * cov_n[(c, c)] / (norms[i] * norms[i]);
                let se = var.sqrt() * scale;
                let reason = if in_null || !vif[c].is_finite() {
                    Some(format!(
                        "its effect is a combination of the other parameters' (Jacobian singular, condition number {condition:.3e})"
                    ))
                } else if vif[c] > 1e6 {
                    Some(format!(
                        "its effect is nearly a combination of the other parameters' (variance inflation {:.3e}, condition number {condition:.3e})",
                        vif[c]
                    ))
                } else {
                    let half = t * se;
                    let size = fitted[i].abs().max(scale);
                    (half > size).then(|| {
                        format!(
                            "its 95 % interval +-{half:.3e} is wider than its size {size:.3e} (relative half-width {:.2})",
                            half / size
                        )
                    })
                };
                (if in_null { f64::INFINITY } else { se }, reason)
            }
        };
        let half = t * se;
        out.push(ParamResult {
            name: p.name(),
            model_field: p.model_field(),
            start: starts[i],
            fitted: fitted[i],
            std_error: se,
            ci95: [fitted[i] - half, fitted[i] + half],
            relative_ci: half / fitted[i].abs().max(scale),
            identifiable: reason.is_none(),
            reason,
        });
    }
    (out, condition)
}

impl std::fmt::Display for FitReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "identified {} from {} ({}, model {})",
            self.params
                .iter()
                .map(|p| p.name.as_str())
                .collect::<Vec<_>>()
                .join(", "),
            self.source,
            self.format,
            self.model
        )?;
        let start = match self.start_source {
            StartSource::LoggedState => "the logged state",
            StartSource::Mocap => "the motion capture",
        };
        writeln!(
            f,
            "data: {} segments of up to {} wingbeats (starts from {start}), {} motion-capture frames, {} IMU samples, {} residuals",
            self.segments,
            self.segment_wingbeats,
            self.mocap_frames,
            self.imu_samples,
            self.residuals
        )?;
        writeln!(
            f,
            "{}: {} iterations, {} simulations, {:.2} s",
            self.termination, self.iterations, self.simulations, self.runtime_s
        )?;
        writeln!(
            f,
            "cost (chi-square) {:.6e} -> {:.6e}; rms weighted residual {:.4} -> {:.4} (1 = the sensors' noise)",
            self.cost_before, self.cost_after, self.rms_before, self.rms_after
        )?;
        if self.diverged_segments > 0 {
            writeln!(
                f,
                "warning: {} segments diverge at the fitted parameters",
                self.diverged_segments
            )?;
        }
        writeln!(
            f,
            "{:<24} {:>13} {:>13} {:>11} {:>29}  identifiable",
            "parameter", "start", "fitted", "std error", "95% interval"
        )?;
        for p in &self.params {
            writeln!(
                f,
                "{:<24} {:>13.6e} {:>13.6e} {:>11.3e} [{:>13.6e}, {:>13.6e}]  {}",
                p.name,
                p.start,
                p.fitted,
                p.std_error,
                p.ci95[0],
                p.ci95[1],
                if p.identifiable { "yes" } else { "NO" }
            )?;
            if let Some(r) = &p.reason {
                writeln!(f, "    not identifiable: {r}")?;
            }
        }
        writeln!(
            f,
            "condition number {:.3e}, t(0.975, {}) = {:.4}",
            self.condition_number, self.dof, self.t_quantile
        )
    }
}
