//! Wing kinematics: stroke (flapping) angle phi, pitch angle theta and deviation eta as
//! periodic functions of the wingbeat phase, with analytic first and second derivatives.
//!
//! Conventions (see MODEL.md section 1 and 3):
//! - phase is measured in wingbeats (cycles); phase 0 is the stroke reversal that starts the
//!   first downstroke, during which phi increases (the wing moves forward).
//! - theta is the angle between the leading-edge chord direction and the forward stroke
//!   tangent, rotating towards the stroke-plane normal: mid-downstroke theta = alpha_m,
//!   mid-upstroke theta = pi - alpha_m, so the geometric angle of attack is alpha_m in both.
//! - A pitch bias adds to theta in both half strokes (raising the downstroke angle of attack
//!   and lowering the upstroke one).

use std::f64::consts::PI;

use serde::{Deserialize, Serialize};

use crate::error::{Result, Validator};
use crate::pitch_flip::FlipShape;
pub use crate::spline::PeriodicSpline;

/// Wing angles and their time derivatives (rad, rad/s, rad/s^2).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct WingAngles {
    /// Stroke angle.
    pub phi: f64,
    /// Pitch angle.
    pub theta: f64,
    /// Deviation angle (out of the stroke plane, positive towards the stroke-plane normal).
    pub eta: f64,
    /// d phi / dt.
    pub phi_dot: f64,
    /// d theta / dt.
    pub theta_dot: f64,
    /// d eta / dt.
    pub eta_dot: f64,
    /// d2 phi / dt2.
    pub phi_ddot: f64,
    /// d2 theta / dt2.
    pub theta_ddot: f64,
    /// d2 eta / dt2.
    pub eta_ddot: f64,
}

/// Where in the wingbeat a phase lies.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct StrokePhase {
    /// Half strokes completed since phase 0 (0 = first downstroke, 1 = first upstroke, ...).
    pub half_stroke: i64,
    /// Time since the last stroke reversal over the period T (the paper's t*).
    pub t_star: f64,
    /// True in a downstroke (phi increasing).
    pub downstroke: bool,
}

/// Kinematics as written in a model file (degrees at this edge, radians inside).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "family", rename_all = "snake_case", deny_unknown_fields)]
pub enum KinematicsSpec {
    /// The paper's trapezoidal stroke with cosine ramps and a cosine pitch flip.
    Trapezoidal {
        /// Wingbeat frequency, Hz (give this or `peak_rg_speed_m_s`).
        freq_hz: Option<f64>,
        /// Peak stroke speed at the radius of gyration, m/s; sets the frequency.
        peak_rg_speed_m_s: Option<f64>,
        /// Peak-to-peak stroke amplitude, deg.
        amplitude_deg: f64,
        /// Angle of attack held mid-stroke, deg.
        mid_stroke_aoa_deg: f64,
        /// Acceleration time at the start of each half stroke, as a fraction of T.
        dtau_a: f64,
        /// Deceleration time at the end of each half stroke, as a fraction of T.
        dtau_d: f64,
        /// Mean stroke angle, deg.
        #[serde(default)]
        mean_stroke_deg: f64,
        /// Pitch bias added to theta in both half strokes, deg.
        #[serde(default)]
        pitch_bias_deg: f64,
    },
    /// Sinusoidal stroke and pitch (and optional figure-of-eight deviation at 2f).
    Harmonic {
        /// Wingbeat frequency, Hz.
        freq_hz: f64,
        /// Peak-to-peak stroke amplitude, deg.
        amplitude_deg: f64,
        /// Angle of attack at mid-stroke, deg.
        mid_stroke_aoa_deg: f64,
        /// Phase lead of pitch rotation over stroke, deg (positive = advanced rotation).
        #[serde(default)]
        pitch_phase_deg: f64,
        /// Deviation amplitude (at twice the wingbeat frequency), deg.
        #[serde(default)]
        deviation_amplitude_deg: f64,
        /// Mean stroke angle, deg.
        #[serde(default)]
        mean_stroke_deg: f64,
        /// Pitch bias, deg.
        #[serde(default)]
        pitch_bias_deg: f64,
    },
    /// Sun's group's CFD kinematics (Sun & Lan 2004, eq. 1-2; Sun & Xiong 2005): a
    /// simple-harmonic stroke, a constant angle of attack in each half stroke and a pitch
    /// flip of given duration and timing whose rate follows 1 - cos ([`crate::pitch_flip`]).
    HarmonicFlip {
        /// Wingbeat frequency, Hz.
        freq_hz: f64,
        /// Peak-to-peak stroke amplitude, deg.
        amplitude_deg: f64,
        /// Angle of attack held in the middle of the downstroke, deg.
        downstroke_aoa_deg: f64,
        /// Angle of attack held in the middle of the upstroke, deg.
        upstroke_aoa_deg: f64,
        /// Flip duration as a fraction of the period, [0.01, 0.5].
        flip_duration: f64,
        /// Flip midpoint minus stroke reversal, fraction of the period (negative: advanced).
        #[serde(default)]
        flip_offset: f64,
        /// Mean stroke angle, deg.
        #[serde(default)]
        mean_stroke_deg: f64,
        /// Pitch bias, deg.
        #[serde(default)]
        pitch_bias_deg: f64,
    },
    /// Measured periodic kinematics (e.g. from high-speed video), interpolated by periodic
    /// cubic splines. The table covers one period: `t_s` starts at 0 and ends at the period,
    /// and the last row must repeat the first.
    Tabulated {
        /// Sample times, s, strictly increasing from 0 to the period.
        t_s: Vec<f64>,
        /// Stroke angle at each time, deg.
        stroke_deg: Vec<f64>,
        /// Pitch angle (theta) at each time, deg.
        pitch_deg: Vec<f64>,
        /// Deviation angle at each time, deg (zeros if absent).
        #[serde(default)]
        deviation_deg: Option<Vec<f64>>,
    },
}

/// The shape of a kinematics family, independent of frequency, amplitude, mean and bias.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// See [`KinematicsSpec::Trapezoidal`]; angles in radians.
    Trapezoidal {
        /// Mid-stroke angle of attack, rad.
        mid_aoa_rad: f64,
        /// Acceleration fraction of T.
        dtau_a: f64,
        /// Deceleration fraction of T.
        dtau_d: f64,
    },
    /// See [`KinematicsSpec::Harmonic`]; angles in radians.
    Harmonic {
        /// Mid-stroke angle of attack, rad.
        mid_aoa_rad: f64,
        /// Pitch phase lead, rad.
        pitch_phase_rad: f64,
        /// Deviation amplitude, rad.
        deviation_amplitude_rad: f64,
    },
    /// See [`KinematicsSpec::HarmonicFlip`].
    HarmonicFlip(FlipShape),
    /// A measured table.
    Tabulated(Box<TableShape>),
}

/// Periodic splines of a measured wingbeat, on the phase interval [0, 1).
#[derive(Debug, Clone, PartialEq)]
pub struct TableShape {
    stroke: PeriodicSpline,
    pitch: PeriodicSpline,
    deviation: PeriodicSpline,
    /// Mean of the stroke table, rad.
    stroke_mean_rad: f64,
    /// Peak-to-peak of the stroke table, rad.
    stroke_amplitude_rad: f64,
    /// Phases of the stroke reversals in [0, 1): (phase, downstroke starts here).
    reversals: Vec<(f64, bool)>,
    /// Peak |d stroke / d phase| of the table, rad per cycle.
    peak_rate_per_cycle: f64,
    /// (dtau_A, dtau_D) measured by the half-peak rule (amplitude and frequency do not change them).
    accel_fractions: (f64, f64),
}

/// Kinematics of one wing: a shape plus the parameters a controller changes between wingbeats.
#[derive(Debug, Clone, PartialEq)]
pub struct Kinematics {
    /// The family and its shape parameters.
    pub shape: Shape,
    /// Wingbeat frequency, Hz.
    pub freq_hz: f64,
    /// Peak-to-peak stroke amplitude, rad.
    pub amplitude_rad: f64,
    /// Mean stroke angle, rad.
    pub mean_stroke_rad: f64,
    /// Pitch bias added to theta, rad.
    pub pitch_bias_rad: f64,
}

/// Resolves a `peak_rg_speed_m_s` into a frequency once the radius of gyration is known.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FrequencySpec {
    /// Frequency given directly.
    Hz(f64),
    /// Peak stroke speed at R_g given; frequency follows from the planform.
    PeakRgSpeed(f64),
}

impl KinematicsSpec {
    /// Validates the spec; `field` is its dotted path in the file. The frequency is resolved
    /// by [`Kinematics::from_spec`] once R_g is known.
    pub fn build(&self, v: &Validator<'_>, field: &str, r_gyration_m: f64) -> Result<Kinematics> {
        let f = |name: &str| format!("{field}.{name}");
        let aoa = |x: f64| -> Result<f64> {
            Ok(v.within(&f("mid_stroke_aoa_deg"), x, 0.0, 90.0)?
                .to_radians())
        };
        let amp = |x: f64| -> Result<f64> {
            Ok(v.within_open_low(&f("amplitude_deg"), x, 0.0, 180.0)?
                .to_radians())
        };
        let mean = |x: f64| -> Result<f64> {
            Ok(v.within(&f("mean_stroke_deg"), x, -90.0, 90.0)?
                .to_radians())
        };
        let bias = |x: f64| -> Result<f64> {
            Ok(v.within(&f("pitch_bias_deg"), x, -45.0, 45.0)?.to_radians())
        };
        match self {
            KinematicsSpec::Trapezoidal {
                freq_hz,
                peak_rg_speed_m_s,
                amplitude_deg,
                mid_stroke_aoa_deg,
                dtau_a,
                dtau_d,
                mean_stroke_deg,
                pitch_bias_deg,
            } => {
                let amplitude_rad = amp(*amplitude_deg)?;
                let mid_aoa_rad = aoa(*mid_stroke_aoa_deg)?;
                let da = v.within_open_low(&f("dtau_a"), *dtau_a, 0.0, 0.5)?;
                let dd = v.within_open_low(&f("dtau_d"), *dtau_d, 0.0, 0.5)?;
                if da + dd > 0.5 {
                    return Err(v.invalid(
                        &f("dtau_a + dtau_d"),
                        da + dd,
                        "at most 0.5 (both ramps fit in one half stroke)",
                    ));
                }
                let freq = match (freq_hz, peak_rg_speed_m_s) {
                    (Some(hz), None) => v.positive(&f("freq_hz"), *hz)?,
                    (None, Some(speed)) => {
                        let speed = v.positive(&f("peak_rg_speed_m_s"), *speed)?;
                        // Peak stroke rate = f * Omega with Omega = A / (0.5 - (da + dd)/2).
                        let omega_per_cycle = amplitude_rad / (0.5 - 0.5 * (da + dd));
                        speed / r_gyration_m / omega_per_cycle
                    }
                    _ => {
                        return Err(v.invalid(
                            &f("freq_hz"),
                            format!("{freq_hz:?} with peak_rg_speed_m_s {peak_rg_speed_m_s:?}"),
                            "exactly one of freq_hz and peak_rg_speed_m_s",
                        ));
                    }
                };
                Ok(Kinematics {
                    shape: Shape::Trapezoidal {
                        mid_aoa_rad,
                        dtau_a: da,
                        dtau_d: dd,
                    },
                    freq_hz: freq,
                    amplitude_rad,
                    mean_stroke_rad: mean(*mean_stroke_deg)?,
                    pitch_bias_rad: bias(*pitch_bias_deg)?,
                })
            }
            KinematicsSpec::Harmonic {
                freq_hz,
                amplitude_deg,
                mid_stroke_aoa_deg,
                pitch_phase_deg,
                deviation_amplitude_deg,
                mean_stroke_deg,
                pitch_bias_deg,
            } => Ok(Kinematics {
                shape: Shape::Harmonic {
                    mid_aoa_rad: aoa(*mid_stroke_aoa_deg)?,
                    pitch_phase_rad: v
                        .within(&f("pitch_phase_deg"), *pitch_phase_deg, -90.0, 90.0)?
                        .to_radians(),
                    deviation_amplitude_rad: v
                        .within(
                            &f("deviation_amplitude_deg"),
                            *deviation_amplitude_deg,
                            0.0,
                            45.0,
                        )?
                        .to_radians(),
                },
                freq_hz: v.positive(&f("freq_hz"), *freq_hz)?,
                amplitude_rad: amp(*amplitude_deg)?,
                mean_stroke_rad: mean(*mean_stroke_deg)?,
                pitch_bias_rad: bias(*pitch_bias_deg)?,
            }),
            KinematicsSpec::HarmonicFlip {
                freq_hz,
                amplitude_deg,
                downstroke_aoa_deg,
                upstroke_aoa_deg,
                flip_duration,
                flip_offset,
                mean_stroke_deg,
                pitch_bias_deg,
            } => Ok(Kinematics {
                shape: Shape::HarmonicFlip(FlipShape {
                    downstroke_aoa_rad: v
                        .within(&f("downstroke_aoa_deg"), *downstroke_aoa_deg, 0.0, 90.0)?
                        .to_radians(),
                    upstroke_aoa_rad: v
                        .within(&f("upstroke_aoa_deg"), *upstroke_aoa_deg, 0.0, 90.0)?
                        .to_radians(),
                    // At least 1% of the period: a shorter flip is a jump in pitch whose
                    // rate (2 x the swept angle over the duration) no step resolves.
                    flip_duration: v.within(&f("flip_duration"), *flip_duration, 0.01, 0.5)?,
                    flip_offset: v.within(&f("flip_offset"), *flip_offset, -0.25, 0.25)?,
                }),
                freq_hz: v.positive(&f("freq_hz"), *freq_hz)?,
                amplitude_rad: amp(*amplitude_deg)?,
                mean_stroke_rad: mean(*mean_stroke_deg)?,
                pitch_bias_rad: bias(*pitch_bias_deg)?,
            }),
            KinematicsSpec::Tabulated {
                t_s,
                stroke_deg,
                pitch_deg,
                deviation_deg,
            } => {
                let n = t_s.len();
                if n < 5 {
                    return Err(v.invalid(
                        &f("t_s"),
                        format!("{n} samples"),
                        "at least 5 samples over one period",
                    ));
                }
                let zeros = vec![0.0; n];
                let dev = deviation_deg.as_ref().unwrap_or(&zeros);
                for (name, list) in [
                    ("stroke_deg", stroke_deg),
                    ("pitch_deg", pitch_deg),
                    ("deviation_deg", dev),
                ] {
                    if list.len() != n {
                        return Err(v.invalid(
                            &f(name),
                            format!("{} values", list.len()),
                            &format!("one value per time in t_s ({n})"),
                        ));
                    }
                    for (i, &x) in list.iter().enumerate() {
                        v.within(&format!("{}[{i}]", f(name)), x, -360.0, 360.0)?;
                    }
                }
                if t_s[0] != 0.0 {
                    return Err(v.invalid(&f("t_s[0]"), t_s[0], "0 (the table starts a period)"));
                }
                for i in 1..n {
                    v.finite(&format!("{}[{i}]", f("t_s")), t_s[i])?;
                    if t_s[i] <= t_s[i - 1] {
                        return Err(v.invalid(
                            &format!("{}[{i}]", f("t_s")),
                            t_s[i],
                            &format!(
                                "strictly greater than the previous time ({}): times must increase",
                                t_s[i - 1]
                            ),
                        ));
                    }
                }
                for (name, list) in [
                    ("stroke_deg", stroke_deg),
                    ("pitch_deg", pitch_deg),
                    ("deviation_deg", dev),
                ] {
                    if (list[n - 1] - list[0]).abs() > 1e-6 {
                        return Err(v.invalid(
                            &format!("{}[{}]", f(name), n - 1),
                            list[n - 1],
                            &format!("equal to the first value ({}): the table must be periodic, its last row repeating the first", list[0]),
                        ));
                    }
                }
                let period = t_s[n - 1];
                let phases: Vec<f64> = t_s.iter().map(|t| t / period).collect();
                let rad = |l: &[f64]| l.iter().map(|d| d.to_radians()).collect::<Vec<_>>();
                let stroke = PeriodicSpline::new(&phases, &rad(stroke_deg));
                let pitch = PeriodicSpline::new(&phases, &rad(pitch_deg));
                let deviation = PeriodicSpline::new(&phases, &rad(dev));
                let (lo, hi) = stroke_deg[..n - 1]
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                        (a.min(x), b.max(x))
                    });
                let amplitude = (hi - lo).to_radians();
                if amplitude <= 0.0 {
                    return Err(v.invalid(
                        &f("stroke_deg"),
                        "a constant",
                        "a stroke that moves (amplitude > 0)",
                    ));
                }
                let reversals = find_reversals(&stroke);
                if reversals.len() != 2 {
                    return Err(v.invalid(
                        &f("stroke_deg"),
                        format!("{} stroke reversals per period", reversals.len()),
                        "exactly one downstroke and one upstroke per period (2 reversals)",
                    ));
                }
                let mean = (0..2000)
                    .map(|i| stroke.value(i as f64 / 2000.0))
                    .sum::<f64>()
                    / 2000.0;
                let peak_rate_per_cycle = (0..4000)
                    .map(|i| stroke.derivative(i as f64 / 4000.0).abs())
                    .fold(0.0, f64::max);
                let accel_fractions = measure_acceleration_fractions(
                    |p| stroke.derivative(p),
                    [reversals[0], reversals[1]],
                );
                Ok(Kinematics {
                    shape: Shape::Tabulated(Box::new(TableShape {
                        stroke,
                        pitch,
                        deviation,
                        stroke_mean_rad: mean,
                        stroke_amplitude_rad: amplitude,
                        reversals,
                        peak_rate_per_cycle,
                        accel_fractions,
                    })),
                    freq_hz: 1.0 / period,
                    amplitude_rad: amplitude,
                    mean_stroke_rad: mean,
                    pitch_bias_rad: 0.0,
                })
            }
        }
    }
}

/// Stroke reversals (zeros of d phi / d phase) of a spline on [0, 1), by bisection on a fine grid.
fn find_reversals(stroke: &PeriodicSpline) -> Vec<(f64, bool)> {
    // Grid points sit between knots (a reversal exactly on a knot or at phase 0 is common in
    // measured tables) and wrap around the period.
    let n = 4000;
    let at = |i: usize| (i as f64 + 0.5) / n as f64;
    let mut out = Vec::new();
    for i in 0..n {
        let (a, b) = (at(i), at(i) + 1.0 / n as f64);
        let (da, db) = (stroke.derivative(a), stroke.derivative(b));
        if (da > 0.0) != (db > 0.0) {
            let rising = db > 0.0;
            let (mut lo, mut hi) = (a, b);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if (stroke.derivative(mid) > 0.0) == rising {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            let p = 0.5 * (lo + hi);
            out.push((p - p.floor(), rising));
        }
    }
    out.sort_by(|x, y| x.0.total_cmp(&y.0));
    out
}

/// Per-unit-phase stroke profile of the trapezoidal family in one half stroke:
/// returns (sweep so far, d/dtau, d2/dtau2) for tau in [0, 0.5], sweep normalised to 1.
fn trapezoid_sweep(tau: f64, da: f64, dd: f64) -> (f64, f64, f64) {
    let omega = 1.0 / (0.5 - 0.5 * (da + dd));
    let hold_end = 0.5 - dd;
    if tau < da {
        let k = PI / da;
        let (s, c) = (k * tau).sin_cos();
        (
            0.5 * omega * (tau - s / k),
            0.5 * omega * (1.0 - c),
            0.5 * omega * k * s,
        )
    } else if tau <= hold_end {
        (omega * (0.5 * da + (tau - da)), omega, 0.0)
    } else {
        let k = PI / dd;
        let s_t = tau - hold_end;
        let (s, c) = (k * s_t).sin_cos();
        (
            omega * (0.5 * da + (hold_end - da)) + 0.5 * omega * (s_t + s / k),
            0.5 * omega * (1.0 + c),
            -0.5 * omega * k * s,
        )
    }
}

impl Kinematics {
    /// Builds kinematics from a spec, resolving the frequency with the wing's R_g.
    pub fn from_spec(
        spec: &KinematicsSpec,
        v: &Validator<'_>,
        field: &str,
        r_gyration_m: f64,
    ) -> Result<Self> {
        spec.build(v, field, r_gyration_m)
    }

    /// Period T = 1/f, s.
    pub fn period_s(&self) -> f64 {
        1.0 / self.freq_hz
    }

    /// Angles and derivatives at `phase` (in wingbeats; any real number).
    pub fn angles(&self, phase: f64) -> WingAngles {
        let f = self.freq_hz;
        let tau = phase - phase.floor();
        let (phi_u, dphi_u, ddphi_u, theta, dtheta_u, ddtheta_u, eta, deta_u, ddeta_u) =
            match &self.shape {
                Shape::Trapezoidal {
                    mid_aoa_rad,
                    dtau_a,
                    dtau_d,
                } => {
                    let (da, dd) = (*dtau_a, *dtau_d);
                    let a = self.amplitude_rad;
                    let (phi, dphi, ddphi) = if tau < 0.5 {
                        let (s, ds, dds) = trapezoid_sweep(tau, da, dd);
                        (self.mean_stroke_rad - 0.5 * a + a * s, a * ds, a * dds)
                    } else {
                        let (s, ds, dds) = trapezoid_sweep(tau - 0.5, da, dd);
                        (self.mean_stroke_rad + 0.5 * a - a * s, -a * ds, -a * dds)
                    };
                    let (th, dth, ddth) = trapezoid_pitch(tau, *mid_aoa_rad, da, dd);
                    (phi, dphi, ddphi, th, dth, ddth, 0.0, 0.0, 0.0)
                }
                Shape::Harmonic {
                    mid_aoa_rad,
                    pitch_phase_rad,
                    deviation_amplitude_rad,
                } => {
                    let w = 2.0 * PI;
                    let half_a = 0.5 * self.amplitude_rad;
                    let (s, c) = (w * tau).sin_cos();
                    let phi = self.mean_stroke_rad - half_a * c;
                    let k = 0.5 * PI - mid_aoa_rad;
                    let (sp, cp) = (w * tau + pitch_phase_rad).sin_cos();
                    let (se, ce) = (2.0 * w * tau).sin_cos();
                    let da = *deviation_amplitude_rad;
                    (
                        phi,
                        half_a * w * s,
                        half_a * w * w * c,
                        0.5 * PI - k * sp,
                        -k * w * cp,
                        k * w * w * sp,
                        da * se,
                        da * 2.0 * w * ce,
                        -da * 4.0 * w * w * se,
                    )
                }
                Shape::HarmonicFlip(flip) => {
                    let a = self.amplitude_rad;
                    let (s, ds, dds) = FlipShape::stroke(tau);
                    let (th, dth, ddth) = flip.pitch(tau);
                    (
                        self.mean_stroke_rad + a * s,
                        a * ds,
                        a * dds,
                        th,
                        dth,
                        ddth,
                        0.0,
                        0.0,
                        0.0,
                    )
                }
                Shape::Tabulated(t) => {
                    let scale = self.amplitude_rad / t.stroke_amplitude_rad;
                    (
                        self.mean_stroke_rad + scale * (t.stroke.value(tau) - t.stroke_mean_rad),
                        scale * t.stroke.derivative(tau),
                        scale * t.stroke.second_derivative(tau),
                        t.pitch.value(tau),
                        t.pitch.derivative(tau),
                        t.pitch.second_derivative(tau),
                        t.deviation.value(tau),
                        t.deviation.derivative(tau),
                        t.deviation.second_derivative(tau),
                    )
                }
            };
        WingAngles {
            phi: phi_u,
            theta: theta + self.pitch_bias_rad,
            eta,
            phi_dot: f * dphi_u,
            theta_dot: f * dtheta_u,
            eta_dot: f * deta_u,
            phi_ddot: f * f * ddphi_u,
            theta_ddot: f * f * ddtheta_u,
            eta_ddot: f * f * ddeta_u,
        }
    }

    /// Which half stroke `phase` lies in, and t* since its reversal.
    pub fn stroke_phase(&self, phase: f64) -> StrokePhase {
        match &self.shape {
            Shape::Tabulated(t) => {
                let cycle = phase.floor();
                let tau = phase - cycle;
                // Reversals sorted by phase: the last one at or before tau starts this half stroke.
                let (r0, down0) = t.reversals[0];
                let (r1, down1) = t.reversals[1];
                let (start, down, idx) = if tau >= r1 {
                    (r1, down1, 1)
                } else if tau >= r0 {
                    (r0, down0, 0)
                } else {
                    (r1 - 1.0, down1, -1)
                };
                StrokePhase {
                    half_stroke: 2 * cycle as i64 + idx,
                    t_star: tau - start,
                    downstroke: down,
                }
            }
            _ => {
                let halves = (2.0 * phase).floor();
                StrokePhase {
                    half_stroke: halves as i64,
                    t_star: 0.5 * (2.0 * phase - halves),
                    downstroke: (halves as i64).rem_euclid(2) == 0,
                }
            }
        }
    }

    /// Peak |d phi / dt| over the wingbeat, rad/s.
    pub fn peak_stroke_rate_rad_s(&self) -> f64 {
        match &self.shape {
            Shape::Trapezoidal { dtau_a, dtau_d, .. } => {
                self.freq_hz * self.amplitude_rad / (0.5 - 0.5 * (dtau_a + dtau_d))
            }
            Shape::Harmonic { .. } | Shape::HarmonicFlip(_) => {
                self.freq_hz * PI * self.amplitude_rad
            }
            Shape::Tabulated(t) => {
                self.freq_hz * self.amplitude_rad / t.stroke_amplitude_rad * t.peak_rate_per_cycle
            }
        }
    }

    /// The acceleration and deceleration fractions (dtau_A, dtau_D) that the wake-capture
    /// model needs.
    ///
    /// Trapezoidal kinematics carry them. For any other stroke-rate profile they are measured
    /// by the half-peak rule: in each half stroke, dtau_A is twice the time (over T) from the
    /// reversal until |phi_dot| first reaches half its peak in that half stroke, and dtau_D
    /// twice the time from when it last exceeds half its peak to the next reversal; both are
    /// averaged over the two half strokes. For a cosine ramp the half-peak point is exactly
    /// mid-ramp, so the rule returns the trapezoid's own values (tested).
    pub fn acceleration_fractions(&self) -> (f64, f64) {
        match &self.shape {
            Shape::Trapezoidal { dtau_a, dtau_d, .. } => (*dtau_a, *dtau_d),
            // A pure cosine stroke: |sin| first reaches half its peak T/12 after a reversal.
            Shape::Harmonic { .. } | Shape::HarmonicFlip(_) => (1.0 / 6.0, 1.0 / 6.0),
            Shape::Tabulated(t) => t.accel_fractions,
        }
    }

    /// These kinematics with the mid-stroke angle of attack of both half strokes moved by
    /// `delta_rad` (the control Sun & Xiong 2005 trimmed their bumblebee's weight support
    /// with), or `None` for a measured table, whose pitch has no mid-stroke angle to move.
    pub fn with_aoa_offset(&self, delta_rad: f64) -> Option<Kinematics> {
        let shape = match &self.shape {
            Shape::Trapezoidal {
                mid_aoa_rad,
                dtau_a,
                dtau_d,
            } => Shape::Trapezoidal {
                mid_aoa_rad: mid_aoa_rad + delta_rad,
                dtau_a: *dtau_a,
                dtau_d: *dtau_d,
            },
            Shape::Harmonic {
                mid_aoa_rad,
                pitch_phase_rad,
                deviation_amplitude_rad,
            } => Shape::Harmonic {
                mid_aoa_rad: mid_aoa_rad + delta_rad,
                pitch_phase_rad: *pitch_phase_rad,
                deviation_amplitude_rad: *deviation_amplitude_rad,
            },
            Shape::HarmonicFlip(flip) => Shape::HarmonicFlip(flip.with_aoa_offset(delta_rad)),
            Shape::Tabulated(_) => return None,
        };
        Some(Kinematics {
            shape,
            ..self.clone()
        })
    }

    /// The mid-stroke angles of attack (downstroke, upstroke), rad, of a parametric family
    /// (`None` for a measured table).
    pub fn mid_stroke_aoa_rad(&self) -> Option<(f64, f64)> {
        match &self.shape {
            Shape::Trapezoidal { mid_aoa_rad, .. } | Shape::Harmonic { mid_aoa_rad, .. } => {
                Some((*mid_aoa_rad, *mid_aoa_rad))
            }
            Shape::HarmonicFlip(f) => Some((f.downstroke_aoa_rad, f.upstroke_aoa_rad)),
            Shape::Tabulated(_) => None,
        }
    }

    /// The stroke reversals in [0, 1): (phase, a downstroke starts there).
    pub fn stroke_reversals(&self) -> [(f64, bool); 2] {
        match &self.shape {
            Shape::Tabulated(t) => [t.reversals[0], t.reversals[1]],
            _ => [(0.0, true), (0.5, false)],
        }
    }
}

/// The half-peak rule of [`Kinematics::acceleration_fractions`], for any stroke-rate function
/// of the phase and its two reversals: the function sampled at 40,000 points over the period
/// from the first reversal, then [`sampled_acceleration_fractions`] on that profile.
pub fn measure_acceleration_fractions(
    rate: impl Fn(f64) -> f64,
    reversals: [(f64, bool); 2],
) -> (f64, f64) {
    let n = 40_000;
    let start = reversals[0].0;
    let phase: Vec<f64> = (0..n).map(|i| start + i as f64 / n as f64).collect();
    let samples: Vec<f64> = phase.iter().map(|&x| rate(x)).collect();
    sampled_acceleration_fractions(&phase, &samples, reversals)
}

/// The half-peak rule on a sampled periodic stroke-rate profile, linearly interpolated
/// between samples (`phase` increasing over one period, `rate` the stroke rate there) and
/// zero at the two `reversals`: in each half stroke, the acceleration fraction is twice the
/// time from the reversal to the first crossing of half the half stroke's peak rate, the
/// deceleration fraction twice the time from the last crossing to the next reversal (both in
/// periods), averaged over the two half strokes; the crossings are found exactly on the
/// interpolant. A dynamic wing calls it every wingbeat on its own 100 samples.
pub fn sampled_acceleration_fractions(
    phase: &[f64],
    rate: &[f64],
    reversals: [(f64, bool); 2],
) -> (f64, f64) {
    let mut sum_a = 0.0;
    let mut sum_d = 0.0;
    for k in 0..2 {
        let start = reversals[k].0;
        let end = if k == 0 {
            reversals[1].0
        } else {
            reversals[0].0 + 1.0
        };
        // The half stroke's points: the reversal, the samples inside (one period on), the
        // next reversal.
        let mut pts: Vec<(f64, f64)> = vec![(start, 0.0)];
        for shift in [0.0, 1.0] {
            pts.extend(
                phase
                    .iter()
                    .zip(rate)
                    .map(|(&x, &r)| (x + shift, r.abs()))
                    .filter(|&(x, _)| x > start && x < end),
            );
        }
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        pts.push((end, 0.0));
        let half = 0.5 * pts.iter().fold(0.0f64, |m, p| m.max(p.1));
        let cross = |a: (f64, f64), b: (f64, f64)| {
            if b.1 == a.1 {
                a.0
            } else {
                a.0 + (half - a.1) / (b.1 - a.1) * (b.0 - a.0)
            }
        };
        let first = pts
            .windows(2)
            .find(|w| w[1].1 >= half)
            .map(|w| cross(w[0], w[1]))
            .unwrap_or(start);
        let last = pts
            .windows(2)
            .rev()
            .find(|w| w[0].1 >= half)
            .map(|w| cross(w[1], w[0]))
            .unwrap_or(end);
        sum_a += 2.0 * (first - start);
        sum_d += 2.0 * (end - last);
    }
    (0.5 * sum_a, 0.5 * sum_d)
}

/// Pitch of the trapezoidal family: holds alpha_m (downstroke) and pi - alpha_m (upstroke),
/// flipping with a cosine profile from the start of deceleration to the end of the next
/// acceleration. Returns (theta, d/dtau, d2/dtau2).
fn trapezoid_pitch(tau: f64, alpha: f64, da: f64, dd: f64) -> (f64, f64, f64) {
    let dur = da + dd;
    let flip = |s: f64, from: f64, to: f64| {
        let k = PI / dur;
        let (sn, cs) = (k * s).sin_cos();
        let delta = to - from;
        (
            from + 0.5 * delta * (1.0 - cs),
            0.5 * delta * k * sn,
            0.5 * delta * k * k * cs,
        )
    };
    let up = PI - alpha;
    if tau < da {
        flip(tau + dd, up, alpha)
    } else if tau < 0.5 - dd {
        (alpha, 0.0, 0.0)
    } else if tau < 0.5 + da {
        flip(tau - (0.5 - dd), alpha, up)
    } else if tau < 1.0 - dd {
        (up, 0.0, 0.0)
    } else {
        flip(tau - (1.0 - dd), up, alpha)
    }
}
