//! The shape of each kinematics family, independent of frequency, amplitude, mean stroke and
//! pitch bias: the trapezoidal stroke and pitch profiles, the harmonic parameters, the pitch
//! flip, and a measured table's splines.

use std::f64::consts::PI;

use crate::kinematics::twist::TableTwist;
use crate::pitch_flip::FlipShape;
use crate::spline::PeriodicSpline;

/// The shape of a kinematics family, independent of frequency, amplitude, mean and bias.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// See [`crate::KinematicsSpec::Trapezoidal`]; angles in radians.
    Trapezoidal {
        /// Mid-stroke angle of attack, rad.
        mid_aoa_rad: f64,
        /// Acceleration fraction of T.
        dtau_a: f64,
        /// Deceleration fraction of T.
        dtau_d: f64,
    },
    /// See [`crate::KinematicsSpec::Harmonic`]; angles in radians.
    Harmonic {
        /// Mid-stroke angle of attack, rad.
        mid_aoa_rad: f64,
        /// Pitch phase lead, rad.
        pitch_phase_rad: f64,
        /// Deviation amplitude, rad.
        deviation_amplitude_rad: f64,
    },
    /// See [`crate::KinematicsSpec::HarmonicFlip`].
    HarmonicFlip(FlipShape),
    /// A measured table.
    Tabulated(Box<TableShape>),
}

/// Periodic splines of a measured wingbeat, on the phase interval [0, 1).
#[derive(Debug, Clone, PartialEq)]
pub struct TableShape {
    pub(super) stroke: PeriodicSpline,
    pub(super) pitch: PeriodicSpline,
    pub(super) deviation: PeriodicSpline,
    /// Mean of the stroke table, rad.
    pub(super) stroke_mean_rad: f64,
    /// Peak-to-peak of the stroke table, rad.
    pub(super) stroke_amplitude_rad: f64,
    /// Phases of the stroke reversals in [0, 1): (phase, downstroke starts here).
    pub(super) reversals: Vec<(f64, bool)>,
    /// Peak |d stroke / d phase| of the table, rad per cycle.
    pub(super) peak_rate_per_cycle: f64,
    /// (dtau_A, dtau_D) measured by the half-peak rule (amplitude and frequency do not change them).
    pub(super) accel_fractions: (f64, f64),
    /// The wing's spanwise twist, when the table gives the feathering at several stations.
    pub(super) twist: Option<TableTwist>,
}

/// Per-unit-phase stroke profile of the trapezoidal family in one half stroke:
/// returns (sweep so far, d/dtau, d2/dtau2) for tau in [0, 0.5], sweep normalised to 1.
pub(super) fn trapezoid_sweep(tau: f64, da: f64, dd: f64) -> (f64, f64, f64) {
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

/// Pitch of the trapezoidal family: holds alpha_m (downstroke) and pi - alpha_m (upstroke),
/// flipping with a cosine profile from the start of deceleration to the end of the next
/// acceleration. Returns (theta, d/dtau, d2/dtau2).
pub(super) fn trapezoid_pitch(tau: f64, alpha: f64, da: f64, dd: f64) -> (f64, f64, f64) {
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
