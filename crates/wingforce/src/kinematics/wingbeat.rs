//! A wing's kinematics (a shape plus the parameters a controller changes between wingbeats)
//! and what they give at any phase: the angles with their first and second derivatives, the
//! half stroke and t*, the peak stroke rate and the acceleration fractions.

use std::f64::consts::PI;

use serde::{Deserialize, Serialize};

use crate::kinematics::shape::{Shape, trapezoid_pitch, trapezoid_sweep};
use crate::kinematics::twist::TwistAt;
use crate::pitch_flip::FlipShape;

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
    /// Phase lead over the wingbeat clock, in wingbeats (cycles): the wing is evaluated at
    /// `phase + phase_offset`, so its reversals, angles and t* come this fraction of a
    /// wingbeat earlier. 0 for every wing of a single pair; a vehicle's further wing pairs
    /// (a dragonfly's hindwings) carry their lead over the first pair here, so every place
    /// that evaluates the wing (the wing set, cycle means, trim) sees it.
    pub phase_offset: f64,
}

impl Kinematics {
    /// Period T = 1/f, s.
    pub fn period_s(&self) -> f64 {
        1.0 / self.freq_hz
    }

    /// The wing's own phase at wingbeat-clock `phase`: `phase + phase_offset` (exactly
    /// `phase` when the offset is 0, so a wing without one is evaluated bit for bit as before).
    #[inline]
    pub fn own_phase(&self, phase: f64) -> f64 {
        if self.phase_offset == 0.0 {
            phase
        } else {
            phase + self.phase_offset
        }
    }

    /// Angles and derivatives at wingbeat-clock `phase` (in wingbeats; any real number; the
    /// wing's [`Kinematics::phase_offset`] is added).
    pub fn angles(&self, phase: f64) -> WingAngles {
        let phase = self.own_phase(phase);
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

    /// The wing's spanwise twist at wingbeat-clock `phase` (the wing's phase offset added),
    /// `None` for a rigid wing (`crate::kinematics` `twist`).
    pub fn twist_at(&self, phase: f64) -> Option<TwistAt> {
        let Shape::Tabulated(t) = &self.shape else {
            return None;
        };
        let twist = t.twist.as_ref()?;
        let phase = self.own_phase(phase);
        Some(twist.at(phase - phase.floor()))
    }

    /// Which half stroke wingbeat-clock `phase` lies in (the wing's phase offset added), and
    /// t* since its reversal.
    pub fn stroke_phase(&self, phase: f64) -> StrokePhase {
        let phase = self.own_phase(phase);
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
