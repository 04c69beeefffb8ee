//! Frequency response of a tethered actuated vehicle: for each drive frequency (and
//! voltage), both wings are driven from rest until the response is periodic, then measured
//! over whole drive periods. MAV builders pick the drive frequency from it.
//!
//! Per point: stroke and pitch amplitude (half the peak-to-peak), the pitch-to-stroke
//! phase from the fundamental Fourier components, in the convention of wingforce's
//! harmonic kinematics (`pitch_phase_deg`: 0 is symmetric rotation, positive is rotation
//! advanced ahead of stroke reversal, negative delayed), all measured by
//! [`super::motion::WingMotion`] on the left wing's record; mean lift (body z, both wings)
//! and lift per volt.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use wingforce::BodyMotion;

use super::driven::DrivenPair;
use super::motion::{MotionSample, WingMotion};
use crate::error::{Error, Result};
use crate::model::Vehicle;

/// What to sweep and how long to run each point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ResponseOptions {
    /// Drive frequencies, Hz.
    pub freqs_hz: Vec<f64>,
    /// Drive amplitudes, V (the model's when empty).
    pub amplitudes_v: Vec<f64>,
    /// Drive periods run before measuring.
    pub settle_cycles: usize,
    /// Drive periods measured.
    pub measure_cycles: usize,
    /// Steps per drive period.
    pub steps_per_cycle: usize,
}

impl Default for ResponseOptions {
    fn default() -> Self {
        Self {
            freqs_hz: Vec::new(),
            amplitudes_v: Vec::new(),
            settle_cycles: 30,
            measure_cycles: 4,
            steps_per_cycle: 100,
        }
    }
}

/// One frequency and voltage.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ResponsePoint {
    /// Drive frequency, Hz.
    pub freq_hz: f64,
    /// Drive amplitude, V.
    pub amplitude_v: f64,
    /// Stroke amplitude (half peak-to-peak, left wing), deg.
    pub stroke_amplitude_deg: f64,
    /// Pitch amplitude (half peak-to-peak, left wing), deg.
    pub pitch_amplitude_deg: f64,
    /// Pitch-to-stroke phase, deg (0 symmetric rotation, positive advanced).
    pub pitch_phase_deg: f64,
    /// Phase of the stroke behind the drive voltage's fundamental, deg (90 at resonance
    /// for a lightly damped system).
    pub stroke_lag_deg: f64,
    /// Mean lift of both wings (body z), N.
    pub mean_lift_n: f64,
    /// Mean lift over the drive amplitude, N/V.
    pub lift_per_volt_n_v: f64,
    /// Mean lift over the weight.
    pub lift_to_weight: f64,
    /// Re of the left wing from its measured stroke.
    pub reynolds: f64,
    /// Whether the measured wake-capture inputs fell outside the fitted range (clamped).
    pub wake_capture_out_of_range: bool,
    /// Why the point stopped early (the hinge hit its stops, the state blew up), if it did.
    pub failed: Option<String>,
}

/// The whole sweep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FrequencyResponse {
    /// Undamped natural frequency of the stroke system from the model, Hz.
    pub stroke_natural_freq_hz: f64,
    /// Natural frequency of the pitch mode with the stroke held, Hz.
    pub pitch_natural_freq_hz: f64,
    /// The points, frequency-major.
    pub points: Vec<ResponsePoint>,
}

/// Sweeps drive frequency (and amplitude) on the tethered vehicle; `on_point` is called as
/// each point finishes (from worker threads), for a progress bar.
pub fn frequency_response(
    vehicle: &Vehicle,
    options: &ResponseOptions,
    on_point: &(dyn Fn() + Sync),
) -> Result<FrequencyResponse> {
    let act = vehicle.actuation.as_ref().ok_or_else(|| {
        Error::Analysis(format!(
            "{} has prescribed kinematics, no [actuation] section: a frequency response needs an actuated vehicle",
            vehicle.name
        ))
    })?;
    if options.freqs_hz.is_empty() || options.measure_cycles == 0 || options.steps_per_cycle < 20 {
        return Err(Error::Analysis(
            "a frequency response needs at least one frequency, one measured cycle and 20 steps per cycle".into(),
        ));
    }
    let amps = if options.amplitudes_v.is_empty() {
        vec![act.drives[0].amplitude_v]
    } else {
        options.amplitudes_v.clone()
    };
    let jobs: Vec<(f64, f64)> = options
        .freqs_hz
        .iter()
        .flat_map(|&f| amps.iter().map(move |&a| (f, a)))
        .collect();
    let points = jobs
        .par_iter()
        .map(|&(f, a)| {
            let p = point(vehicle, options, f, a);
            on_point();
            p
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(FrequencyResponse {
        stroke_natural_freq_hz: act.dynamics.stroke_natural_freq_hz(),
        pitch_natural_freq_hz: act.dynamics.pitch_natural_freq_hz(),
        points,
    })
}

/// A tethered run of both wings at one drive: the left wing's record over the measured
/// periods, and the mean lift over them.
#[derive(Debug, Clone)]
pub struct TetheredRun {
    /// Drive frequency, Hz.
    pub freq_hz: f64,
    /// Drive amplitude, V.
    pub amplitude_v: f64,
    /// The left wing's samples over the measured periods.
    pub samples: Vec<MotionSample>,
    /// The left wing's motion measured from them ([`WingMotion::measure`]).
    pub motion: WingMotion,
    /// Mean lift of both wings (body z) over the measured periods, N (NaN if the run failed).
    pub mean_lift_n: f64,
    /// The air's damping of the left wing's stroke over the measured periods, as a fraction
    /// of critical: the energy-equivalent linear damping c = -(integral of M_phi dphi/dt) /
    /// (integral of (dphi/dt)^2), M_phi the aerodynamic moment about the stroke axis (its
    /// added-mass part, in quadrature with the rate, does no work over a period), over
    /// 2 sqrt(k I) with the stroke's stiffness k and inertia I (wing and actuator, without
    /// the air's added inertia). NaN if the run failed.
    pub stroke_damping_ratio: f64,
    /// The wings at the end (Re, wake-capture inputs measured on the way).
    pub wings: [wingforce::Wing; 2],
    /// Why the run stopped early (the hinge hit its stops, the state blew up), if it did.
    pub failed: Option<String>,
}

/// Drives both wings of the tethered actuated `vehicle` from rest at `freq_hz` and a common
/// amplitude `amplitude_v` (the model's left-right difference kept) for
/// `o.settle_cycles` periods, then records `o.measure_cycles` more.
pub fn run_tethered(
    vehicle: &Vehicle,
    o: &ResponseOptions,
    freq_hz: f64,
    amplitude_v: f64,
) -> Result<TetheredRun> {
    let act = vehicle.actuation.as_ref().ok_or_else(|| {
        Error::Analysis(format!(
            "{} has prescribed kinematics, no [actuation] section",
            vehicle.name
        ))
    })?;
    let mut drives = [act.drives[0], act.drives[1]];
    for d in &mut drives {
        d.freq_hz = freq_hz;
        // Keep the left-right difference of the model; scale the common amplitude.
        d.amplitude_v = amplitude_v + (d.amplitude_v - act.drives[0].amplitude_v);
    }
    let mut pair = DrivenPair::new(vehicle, drives)?;
    let n = o.steps_per_cycle;
    let dt = 1.0 / (freq_hz * n as f64);
    let body = BodyMotion::default();
    let total = (o.settle_cycles + o.measure_cycles) * n;
    let start = o.settle_cycles * n;
    let mut samples = Vec::with_capacity(o.measure_cycles * n);
    let mut lift = 0.0;
    let (mut work, mut rate_sq) = (0.0, 0.0);
    let mut failed = None;
    for k in 0..total {
        match pair.step(&body, dt) {
            Ok(s) => {
                if k >= start {
                    let l = &s[0];
                    samples.push(MotionSample::new(
                        k as f64 * dt,
                        &l.angles,
                        l.actuator.voltage_v,
                    ));
                    lift += s[0].forces.total.force_n.z + s[1].forces.total.force_n.z;
                    work += l.aero_axis.stroke_nm * l.angles.phi_dot;
                    rate_sq += l.angles.phi_dot * l.angles.phi_dot;
                }
            }
            Err(e) => {
                failed = Some(e.to_string());
                break;
            }
        }
    }
    let m = (o.measure_cycles * n) as f64;
    let motion = WingMotion::measure(&samples, freq_hz);
    Ok(TetheredRun {
        freq_hz,
        amplitude_v,
        samples,
        motion,
        mean_lift_n: if failed.is_some() { f64::NAN } else { lift / m },
        stroke_damping_ratio: if failed.is_some() {
            f64::NAN
        } else {
            let d = &act.dynamics;
            -work
                / rate_sq
                / (2.0 * (d.stroke_stiffness_nm_rad() * d.stroke_inertia_kg_m2()).sqrt())
        },
        wings: pair.wings,
        failed,
    })
}

fn point(
    vehicle: &Vehicle,
    o: &ResponseOptions,
    freq_hz: f64,
    amplitude_v: f64,
) -> Result<ResponsePoint> {
    let run = run_tethered(vehicle, o, freq_hz, amplitude_v)?;
    let (failed, mean_lift, mo) = (run.failed, run.mean_lift_n, run.motion);
    let re = run.wings[0].reynolds();
    let oor = run.wings[0]
        .wake_capture()
        .map(|p| p.flags.any())
        .unwrap_or(false);
    // A point that stopped has no steady response: its measured figures are NaN (null in
    // JSON), and `failed` says why.
    let measured = |x: f64| if failed.is_some() { f64::NAN } else { x };
    Ok(ResponsePoint {
        freq_hz,
        amplitude_v,
        stroke_amplitude_deg: measured(mo.stroke_amplitude_deg),
        pitch_amplitude_deg: measured(mo.pitch_amplitude_deg),
        pitch_phase_deg: measured(mo.pitch_phase_deg),
        stroke_lag_deg: measured(mo.stroke_lag_deg),
        mean_lift_n: mean_lift,
        lift_per_volt_n_v: mean_lift / amplitude_v,
        lift_to_weight: mean_lift / vehicle.weight_n(),
        reynolds: re,
        wake_capture_out_of_range: oor,
        failed,
    })
}
