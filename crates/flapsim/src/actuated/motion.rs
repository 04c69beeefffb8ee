//! The wing motion an actuated wing produced, measured from a record of whole drive periods:
//! what `flapwing simulate` reports of an actuated vehicle, what each point of the frequency
//! response ([`super::response`]) is made of, and what `flapwing validate` compares with
//! bench data. One measurement, used by all three.
//!
//! Conventions (those of wingforce's harmonic kinematics, whose `pitch_phase_deg` this
//! measures on a dynamic wing):
//! - amplitudes are half the peak-to-peak excursion over the record;
//! - the pitch-stroke phase is taken between the fundamental Fourier components of pitch and
//!   stroke: 0 is symmetric rotation (the wing passes through vertical, theta = 90 deg, at
//!   stroke reversal, and its pitch deflection is in phase with the stroke velocity);
//!   **positive = pitch advanced** (the wing rotates ahead of stroke reversal), **negative =
//!   pitch delayed** (it rotates after reversal, as high-speed video shows RoboBee-class
//!   passive hinges do); +-90 deg means the pitch follows the stroke acceleration instead;
//! - the stroke lag is the phase of the stroke's fundamental behind the drive voltage's (90 deg
//!   at resonance for a lightly damped system);
//! - the mid-stroke angle of attack is the geometric angle between the chord and the stroke
//!   direction at the instants the stroke crosses its mid angle (linear interpolation between
//!   samples): theta on the downstroke (phi increasing), 180 deg - theta on the upstroke, so
//!   a wing that leads with its leading edge has a positive angle (body at rest, no inflow);
//! - the drive is what the wing got: the voltage's mean (bias) and the amplitude of its
//!   fundamental, at the record's frequency.

use std::f64::consts::PI;

use serde::{Deserialize, Serialize};
use wingforce::WingAngles;

/// One sample of an actuated wing's record.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct MotionSample {
    /// Time, s (any origin; uniform steps).
    pub t_s: f64,
    /// Stroke angle phi, rad.
    pub phi: f64,
    /// Pitch angle theta, rad (90 deg: wing plane normal to the stroke plane).
    pub theta: f64,
    /// d phi / dt, rad/s.
    pub phi_dot: f64,
    /// d2 phi / dt2, rad/s^2.
    pub phi_ddot: f64,
    /// Drive voltage, V.
    pub voltage_v: f64,
}

impl MotionSample {
    /// A sample from a step's angles and voltage.
    pub fn new(t_s: f64, a: &WingAngles, voltage_v: f64) -> Self {
        Self {
            t_s,
            phi: a.phi,
            theta: a.theta,
            phi_dot: a.phi_dot,
            phi_ddot: a.phi_ddot,
            voltage_v,
        }
    }
}

/// The wing motion over a record of whole drive periods (module doc: conventions).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WingMotion {
    /// Drive frequency of the record, Hz.
    pub freq_hz: f64,
    /// Amplitude of the drive voltage's fundamental, V.
    pub drive_amplitude_v: f64,
    /// Mean of the drive voltage (bias), V.
    pub drive_bias_v: f64,
    /// Stroke amplitude (half peak-to-peak), deg.
    pub stroke_amplitude_deg: f64,
    /// Mean stroke angle (mid of the extremes), deg.
    pub mean_stroke_deg: f64,
    /// Pitch amplitude (half peak-to-peak), deg.
    pub pitch_amplitude_deg: f64,
    /// Pitch-stroke phase, deg: 0 symmetric rotation, positive = pitch advanced, negative =
    /// pitch delayed (behind stroke reversal).
    pub pitch_phase_deg: f64,
    /// Phase of the stroke behind the drive voltage, deg.
    pub stroke_lag_deg: f64,
    /// Mid-stroke angle of attack, mean of both half strokes, deg (NaN if the stroke never
    /// crossed its mid angle).
    pub mid_stroke_aoa_deg: f64,
    /// Mid-downstroke (phi increasing) angle of attack, deg.
    pub mid_downstroke_aoa_deg: f64,
    /// Mid-upstroke angle of attack, deg.
    pub mid_upstroke_aoa_deg: f64,
    /// Correlation of the pitch deflection with the stroke velocity (1: pitch follows the
    /// stroke speed, as an aerodynamically loaded hinge does).
    pub pitch_stroke_velocity_correlation: f64,
    /// Correlation of the pitch deflection with the stroke acceleration (+-1: pitch follows
    /// the wing's own inertia, the signature of an advanced +-90 deg phase).
    pub pitch_stroke_acceleration_correlation: f64,
    /// Drive periods in the record.
    pub cycles: f64,
}

fn wrap(x: f64) -> f64 {
    (x + PI).rem_euclid(2.0 * PI) - PI
}

/// Fundamental Fourier component sum x e^{-i w t}, as (re, im).
fn fundamental(samples: &[MotionSample], w: f64, x: impl Fn(&MotionSample) -> f64) -> (f64, f64) {
    let mut z = (0.0, 0.0);
    for s in samples {
        let (sn, cs) = (w * s.t_s).sin_cos();
        let v = x(s);
        z.0 += v * cs;
        z.1 -= v * sn;
    }
    z
}

fn correlation(
    samples: &[MotionSample],
    a: impl Fn(&MotionSample) -> f64,
    b: impl Fn(&MotionSample) -> f64,
) -> f64 {
    let n = samples.len() as f64;
    let ma = samples.iter().map(&a).sum::<f64>() / n;
    let mb = samples.iter().map(&b).sum::<f64>() / n;
    let (mut ab, mut aa, mut bb) = (0.0, 0.0, 0.0);
    for s in samples {
        let (x, y) = (a(s) - ma, b(s) - mb);
        ab += x * y;
        aa += x * x;
        bb += y * y;
    }
    ab / (aa * bb).sqrt()
}

impl WingMotion {
    /// Measures a record spanning whole periods of a drive at `freq_hz`, sampled at equal
    /// steps (the sums are plain means over the samples). NaN figures for an empty record.
    pub fn measure(samples: &[MotionSample], freq_hz: f64) -> Self {
        let w = 2.0 * PI * freq_hz;
        let (mut phi_min, mut phi_max) = (f64::INFINITY, f64::NEG_INFINITY);
        let (mut th_min, mut th_max) = (f64::INFINITY, f64::NEG_INFINITY);
        let mut v_sum = 0.0;
        for s in samples {
            phi_min = phi_min.min(s.phi);
            phi_max = phi_max.max(s.phi);
            th_min = th_min.min(s.theta);
            th_max = th_max.max(s.theta);
            v_sum += s.voltage_v;
        }
        let n = samples.len() as f64;
        let phi1 = fundamental(samples, w, |s| s.phi);
        let th1 = fundamental(samples, w, |s| s.theta);
        let v1 = fundamental(samples, w, |s| s.voltage_v);
        let arg = |z: (f64, f64)| z.1.atan2(z.0);
        // Mid-stroke instants: the stroke crosses the mid of its extremes.
        let mid = 0.5 * (phi_min + phi_max);
        let (mut down, mut up) = (Vec::new(), Vec::new());
        for p in samples.windows(2) {
            let (a, b) = (p[0].phi - mid, p[1].phi - mid);
            if (a < 0.0) != (b < 0.0) && a != b {
                let f = a / (a - b);
                let theta = p[0].theta + f * (p[1].theta - p[0].theta);
                if b > a {
                    down.push(theta);
                } else {
                    up.push(PI - theta);
                }
            }
        }
        let mean_deg = |v: &[f64]| (v.iter().sum::<f64>() / v.len() as f64).to_degrees();
        let (d, u) = (mean_deg(&down), mean_deg(&up));
        let both = if down.is_empty() || up.is_empty() {
            f64::NAN
        } else {
            0.5 * (d + u)
        };
        Self {
            freq_hz,
            drive_amplitude_v: 2.0 * (v1.0 * v1.0 + v1.1 * v1.1).sqrt() / n,
            drive_bias_v: v_sum / n,
            stroke_amplitude_deg: 0.5 * (phi_max - phi_min).to_degrees(),
            mean_stroke_deg: mid.to_degrees(),
            pitch_amplitude_deg: 0.5 * (th_max - th_min).to_degrees(),
            pitch_phase_deg: wrap(arg(th1) - arg(phi1) + 0.5 * PI).to_degrees(),
            stroke_lag_deg: wrap(arg(v1) - arg(phi1)).to_degrees(),
            mid_stroke_aoa_deg: both,
            mid_downstroke_aoa_deg: d,
            mid_upstroke_aoa_deg: u,
            // The pitch deflection of a trailing wing is opposite to the stroke direction
            // (theta below 90 deg on the downstroke): correlate with -theta.
            pitch_stroke_velocity_correlation: correlation(samples, |s| -s.theta, |s| s.phi_dot),
            pitch_stroke_acceleration_correlation: correlation(
                samples,
                |s| -s.theta,
                |s| s.phi_ddot,
            ),
            cycles: samples_cycles(samples, freq_hz),
        }
    }

    /// The motion as a one-line text, for reports.
    pub fn describe(&self) -> String {
        format!(
            "stroke +-{:.1} deg (mean {:+.1}), pitch +-{:.1} deg, pitch-stroke phase {:+.1} deg ({}), mid-stroke angle of attack {:.1} deg (down {:.1}, up {:.1}); drive {:.2} Hz, {:.2} V amplitude, {:+.2} V bias",
            self.stroke_amplitude_deg,
            self.mean_stroke_deg,
            self.pitch_amplitude_deg,
            self.pitch_phase_deg,
            phase_word(self.pitch_phase_deg),
            self.mid_stroke_aoa_deg,
            self.mid_downstroke_aoa_deg,
            self.mid_upstroke_aoa_deg,
            self.freq_hz,
            self.drive_amplitude_v,
            self.drive_bias_v
        )
    }
}

/// "advanced", "delayed" or "symmetric" for a pitch-stroke phase in deg.
pub fn phase_word(phase_deg: f64) -> &'static str {
    if phase_deg > 0.0 {
        "advanced"
    } else if phase_deg < 0.0 {
        "delayed"
    } else {
        "symmetric"
    }
}

fn samples_cycles(samples: &[MotionSample], freq_hz: f64) -> f64 {
    match (samples.first(), samples.get(1)) {
        (Some(a), Some(b)) => samples.len() as f64 * (b.t_s - a.t_s) * freq_hz,
        _ => 0.0,
    }
}

/// Keeps the last complete drive periods of a stream of steps and measures them: what a run
/// summary needs without storing the whole run. A period is complete when the stream's
/// wingbeat phase (cycles) crosses the next whole number.
#[derive(Debug, Clone, Default)]
pub struct MotionRecorder {
    cycle: Option<i64>,
    current: [Vec<MotionSample>; 2],
    last: Option<[WingMotion; 2]>,
    previous: Option<[WingMotion; 2]>,
    freq_hz: f64,
    t0: Option<(f64, f64)>,
    /// The period being recorded began at a whole phase (it will be complete).
    whole: bool,
}

/// What a [`MotionRecorder`] measured: each wing's motion over the last complete drive
/// period, and how much its amplitudes changed from the period before (the motion is
/// periodic when that is small).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RecordedMotion {
    /// Left and right wing over the last complete period.
    pub wings: [WingMotion; 2],
    /// Largest change of a stroke or pitch amplitude from the period before, deg (NaN with
    /// only one complete period).
    pub amplitude_change_deg: f64,
}

/// Largest amplitude change from one period to the next for a [`RecordedMotion`] to count as
/// periodic, deg.
pub const SETTLED_CHANGE_DEG: f64 = 0.1;

impl RecordedMotion {
    /// Whether the amplitudes changed by at most [`SETTLED_CHANGE_DEG`] over the last period
    /// (false with only one complete period).
    pub fn is_settled(&self) -> bool {
        self.amplitude_change_deg <= SETTLED_CHANGE_DEG
    }
}

impl MotionRecorder {
    /// An empty recorder.
    pub fn new() -> Self {
        Self::default()
    }

    /// Takes one step: its time, wingbeat phase (cycles) and each wing's angles and voltage.
    pub fn observe(&mut self, t_s: f64, phase: f64, wings: [(&WingAngles, f64); 2]) {
        let (t0, p0) = *self.t0.get_or_insert((t_s, phase));
        if t_s > t0 {
            self.freq_hz = (phase - p0) / (t_s - t0);
        }
        // Steps land on whole phases up to rounding (k dt f = 0.999999...): a period is the
        // steps whose phase rounds into it, so each holds exactly one period of samples.
        let cycle = (phase + 1e-6).floor() as i64;
        if self.cycle != Some(cycle) {
            if self.whole && self.current[0].len() > 1 && self.freq_hz > 0.0 {
                let m = [
                    WingMotion::measure(&self.current[0], self.freq_hz),
                    WingMotion::measure(&self.current[1], self.freq_hz),
                ];
                self.previous = self.last.replace(m);
            }
            // A run that starts at phase 0 records its first period whole.
            self.whole = self.cycle.is_some() || (phase + 1e-6).fract() < 2e-6;
            self.cycle = Some(cycle);
            for c in &mut self.current {
                c.clear();
            }
        }
        for (c, (a, v)) in self.current.iter_mut().zip(wings) {
            c.push(MotionSample::new(t_s, a, v));
        }
    }

    /// The last complete period's motion, `None` before one has completed.
    pub fn finish(&self) -> Option<RecordedMotion> {
        let last = self.last?;
        let change = match &self.previous {
            Some(p) => last
                .iter()
                .zip(p)
                .flat_map(|(a, b)| {
                    [
                        (a.stroke_amplitude_deg - b.stroke_amplitude_deg).abs(),
                        (a.pitch_amplitude_deg - b.pitch_amplitude_deg).abs(),
                    ]
                })
                .fold(0.0, f64::max),
            None => f64::NAN,
        };
        Some(RecordedMotion {
            wings: last,
            amplitude_change_deg: change,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// wingforce's harmonic kinematics (phi = -A cos wt, theta = 90 deg - k sin(wt + psi)),
    /// sampled at `n` steps per period over `cycles` periods, driven by
    /// V = bias + amp sin(wt - lag) .
    fn harmonic(psi_deg: f64, n: usize, cycles: usize) -> Vec<MotionSample> {
        let (f, a, k) = (120.0, 50f64.to_radians(), 40f64.to_radians());
        let w = 2.0 * PI * f;
        let psi = psi_deg.to_radians();
        (0..n * cycles)
            .map(|i| {
                let t = i as f64 / (f * n as f64);
                MotionSample {
                    t_s: t,
                    phi: -a * (w * t).cos(),
                    theta: 0.5 * PI - k * (w * t + psi).sin(),
                    phi_dot: a * w * (w * t).sin(),
                    phi_ddot: a * w * w * (w * t).cos(),
                    voltage_v: 10.0 + 150.0 * (w * t + 0.5 * PI).sin(),
                }
            })
            .collect()
    }

    #[test]
    fn harmonic_kinematics_measure_as_their_parameters() {
        for psi in [-30.0, -5.0, 0.0, 20.0] {
            let m = WingMotion::measure(&harmonic(psi, 200, 3), 120.0);
            assert!((m.pitch_phase_deg - psi).abs() < 1e-9, "{m:?}");
            assert!((m.stroke_amplitude_deg - 50.0).abs() < 1e-3, "{m:?}");
            // The sampled extremes of theta sit within one step of the true ones.
            assert!((m.pitch_amplitude_deg - 40.0).abs() < 1e-2, "{m:?}");
            // Mid-stroke: theta = 90 - 40 cos(psi) on the downstroke, 90 + 40 cos(psi) up.
            let aoa = 90.0 - 40.0 * psi.to_radians().cos();
            assert!((m.mid_downstroke_aoa_deg - aoa).abs() < 1e-3, "{m:?}");
            assert!((m.mid_upstroke_aoa_deg - aoa).abs() < 1e-3, "{m:?}");
            assert!((m.drive_bias_v - 10.0).abs() < 1e-9);
            assert!((m.drive_amplitude_v - 150.0).abs() < 1e-9);
            // The voltage leads phi's fundamental (-cos) by 90 + 90 deg: the stroke lags 180.
            assert!((m.stroke_lag_deg.abs() - 180.0).abs() < 1e-9, "{m:?}");
            assert!((m.cycles - 3.0).abs() < 1e-12);
        }
        // Symmetric rotation follows the stroke velocity; +-90 deg follows the acceleration.
        let sym = WingMotion::measure(&harmonic(0.0, 200, 1), 120.0);
        assert!(sym.pitch_stroke_velocity_correlation > 0.999, "{sym:?}");
        assert!(
            sym.pitch_stroke_acceleration_correlation.abs() < 1e-9,
            "{sym:?}"
        );
        let adv = WingMotion::measure(&harmonic(90.0, 200, 1), 120.0);
        assert!(
            adv.pitch_stroke_acceleration_correlation.abs() > 0.999,
            "{adv:?}"
        );
        assert_eq!(phase_word(-3.0), "delayed");
        assert_eq!(phase_word(3.0), "advanced");
    }

    #[test]
    fn the_recorder_measures_the_last_whole_period() {
        let s = harmonic(-15.0, 100, 5);
        let mut r = MotionRecorder::new();
        assert!(r.finish().is_none());
        for x in &s {
            let a = WingAngles {
                phi: x.phi,
                theta: x.theta,
                phi_dot: x.phi_dot,
                phi_ddot: x.phi_ddot,
                ..Default::default()
            };
            // The phase as a simulation computes it, with its rounding.
            r.observe(x.t_s, x.t_s * 120.0, [(&a, x.voltage_v), (&a, x.voltage_v)]);
        }
        // Four whole periods have completed (the fifth is in progress at the end).
        let m = r.finish().unwrap();
        assert!((m.wings[0].pitch_phase_deg + 15.0).abs() < 1e-6, "{m:?}");
        assert!((m.wings[1].cycles - 1.0).abs() < 1e-9, "{m:?}");
        assert!((m.wings[0].drive_amplitude_v - 150.0).abs() < 1e-6, "{m:?}");
        assert!(m.amplitude_change_deg < 1e-9 && m.is_settled(), "{m:?}");
    }
}
