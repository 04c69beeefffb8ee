//! Kinematics as a model file writes them ([`KinematicsSpec`], degrees at this edge), checked
//! field by field and turned into [`Kinematics`] (a measured table into its splines, stroke
//! reversals and acceleration fractions).

use serde::{Deserialize, Serialize};

use crate::error::{Result, Validator};
use crate::kinematics::acceleration::measure_acceleration_fractions;
use crate::kinematics::shape::{Shape, TableShape};
use crate::kinematics::twist::TwistSpec;
use crate::kinematics::wingbeat::Kinematics;
use crate::pitch_flip::FlipShape;
use crate::spline::PeriodicSpline;

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
        /// The wing's spanwise twist: the feathering at further stations along the span, the
        /// table's `pitch_deg` being the feathering at its reference station
        /// (`crate::kinematics` `twist`); absent: a rigid wing.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        twist: Option<TwistSpec>,
    },
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
                    phase_offset: 0.0,
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
                phase_offset: 0.0,
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
                phase_offset: 0.0,
            }),
            KinematicsSpec::Tabulated {
                t_s,
                stroke_deg,
                pitch_deg,
                deviation_deg,
                twist,
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
                let twist = twist
                    .as_ref()
                    .map(|t| t.build(v, &f("twist"), &phases, &rad(pitch_deg)))
                    .transpose()?;
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
                        twist,
                    })),
                    freq_hz: 1.0 / period,
                    amplitude_rad: amplitude,
                    mean_stroke_rad: mean,
                    pitch_bias_rad: 0.0,
                    phase_offset: 0.0,
                })
            }
        }
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
