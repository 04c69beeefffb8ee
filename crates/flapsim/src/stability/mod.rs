//! Stability in hover or at a flight condition ([`crate::flight`]): the averaged model's
//! system matrices, eigenvalues, eigenvectors and modes (the method of Sun and Xiong 2005;
//! Xiong and Sun 2008 in forward flight), and a Floquet analysis of the full time-periodic
//! system (the monodromy matrix over one wingbeat by finite differences of full
//! simulations) to compare with.

use nalgebra::{Complex, DMatrix, DVector};
use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::flight::FlightCondition;
use crate::linear::{AveragedModel, LATERAL, LONGITUDINAL, N_STATES, STATE_NAMES, submatrix};
use crate::model::Vehicle;
use crate::trim::{Trim, trim_at, trimmed_vehicle};

mod eigen;
mod floquet;

use eigen::{complex_eigenvector, rows};

pub use floquet::{
    FLOQUET_BODY_STATES, FLOQUET_WING_STATES, FloquetAnalysis, FloquetMode, floquet_analysis,
    floquet_longitudinal,
};

/// How a mode behaves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ModeKind {
    /// Complex pair.
    Oscillatory,
    /// Real eigenvalue (a subsidence if stable, a divergence if not).
    Real,
}

/// One mode (a real eigenvalue or one member of a complex pair with Im > 0).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModeInfo {
    /// Oscillatory or real.
    pub kind: ModeKind,
    /// Real part, 1/s.
    pub re_per_s: f64,
    /// Imaginary part, rad/s.
    pub im_rad_s: f64,
    /// Re < 0.
    pub stable: bool,
    /// Period 2 pi / Im, s (oscillatory only).
    pub period_s: Option<f64>,
    /// ln 2 / |Re|, s: time to half (stable) or to double (unstable); `None` for a neutral
    /// mode (an eigenvalue at round-off level: it neither grows nor decays).
    pub time_to_half_or_double_s: Option<f64>,
    /// Eigenvector magnitudes normalised to the largest, one per state, with names.
    pub eigenvector: Vec<(String, f64)>,
    /// Words: e.g. "unstable oscillatory", "stable subsidence".
    pub description: String,
}

/// The full stability analysis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StabilityReport {
    /// The hover trim analysed.
    pub trim: Trim,
    /// Longitudinal state names.
    pub longitudinal_states: Vec<String>,
    /// Longitudinal system matrix, row-major.
    pub a_longitudinal: Vec<Vec<f64>>,
    /// Lateral state names.
    pub lateral_states: Vec<String>,
    /// Lateral system matrix, row-major.
    pub a_lateral: Vec<Vec<f64>>,
    /// Longitudinal modes of the averaged model.
    pub longitudinal_modes: Vec<ModeInfo>,
    /// Lateral modes of the averaged model.
    pub lateral_modes: Vec<ModeInfo>,
    /// Longitudinal Floquet multipliers, exponents and eigenvectors (when computed).
    pub floquet_longitudinal: Vec<FloquetMode>,
    /// State names of the Floquet eigenvectors and monodromy matrix (empty when not
    /// computed).
    pub floquet_states: Vec<String>,
    /// The longitudinal monodromy matrix, row-major (empty when not computed).
    pub floquet_monodromy: Vec<Vec<f64>>,
    /// The wingbeat period of the Floquet analysis, s (when computed).
    pub floquet_period_s: Option<f64>,
    /// Where the Floquet analysis's one-wingbeat map is not smooth, one warning per state
    /// ([`FloquetAnalysis::nonsmooth`]); empty when it is, or when not computed.
    pub floquet_warnings: Vec<String>,
    /// Dimensional derivatives of the averaged longitudinal model, d(accel)/d(state).
    pub derivatives: Vec<(String, f64)>,
    /// The reference quantities of [`StabilityReport::nondimensional`].
    pub nondimensional_reference: crate::derivatives::Reference,
    /// The longitudinal force and moment derivatives, dimensional and non-dimensional
    /// (Sun & Xiong 2005's form; [`crate::derivatives`]).
    pub nondimensional: Vec<crate::derivatives::Derivative>,
}

/// The peak-to-peak stroke amplitude the trimmed vehicle flaps with: its kinematics', or an
/// actuated vehicle's from its periodic motion at the trim.
fn stroke_amplitude_rad(v: &Vehicle) -> Result<f64> {
    if v.actuation.is_none() {
        return Ok(v.wings[0].kinematics().amplitude_rad);
    }
    let p = crate::actuated::periodic::settle(v, &wingforce::BodyMotion::default())?;
    let (lo, hi) = p
        .samples
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| {
            (lo.min(s[0].angles.phi), hi.max(s[0].angles.phi))
        });
    Ok(hi - lo)
}

/// Eigenvector magnitudes of `a` for eigenvalue `l`, normalised to the largest.
fn eigenvector(a: &DMatrix<f64>, l: Complex<f64>) -> DVector<f64> {
    let n = a.nrows();
    let v: Vec<f64> = complex_eigenvector(a, l).iter().map(|c| c.norm()).collect();
    let max = v.iter().cloned().fold(0.0, f64::max).max(1e-300);
    DVector::from_iterator(n, v.into_iter().map(|x| x / max))
}

/// The state a (normalised) eigenvector is mostly made of, in words. A neutral vector of
/// the attitude angles alone, roll and yaw (no rate, no velocity), turns the body without
/// turning gravity in its frame, so it turns about the vertical: the heading, whichever
/// body axis it mostly lies along (a body pitched up by theta sees it as roll sin(theta)
/// and yaw cos(theta)).
fn dominant(names: &[&str], ev: &DVector<f64>) -> String {
    let heading_only = names.iter().zip(ev.iter()).all(|(n, x)| {
        matches!(*n, "roll_err_rad" | "yaw_err_rad") || x.abs() < HEADING_ONLY_FRACTION
    });
    if heading_only && names.contains(&"yaw_err_rad") {
        return "heading, a turn about the vertical".into();
    }
    let k = ev
        .iter()
        .enumerate()
        .fold(0, |best, (i, x)| if *x > ev[best] { i } else { best });
    match names.get(k).copied() {
        Some("x_m" | "y_m" | "z_m") => "position".into(),
        Some(n) => n.to_owned(),
        None => "the state".into(),
    }
}

/// Largest share of the largest entry that a neutral eigenvector may hold outside the
/// roll and yaw angles and still count as the heading (the finite-difference derivatives
/// leave round-off there).
const HEADING_ONLY_FRACTION: f64 = 1e-6;

/// Modes of a real matrix with state names.
pub fn modes(a: &DMatrix<f64>, names: &[&str]) -> Vec<ModeInfo> {
    let eig = a.complex_eigenvalues();
    let scale = eig.iter().map(|l| l.norm()).fold(0.0, f64::max);
    let mut out: Vec<ModeInfo> = Vec::new();
    for l in eig.iter() {
        // Eigenvalues at round-off level are neutral (e.g. heading: nothing restores yaw).
        // The threshold, 1e-6 of the fastest mode, is far above the finite differences'
        // noise and far below any mode that matters (a time constant a million times the
        // fastest one's).
        let neutral = l.norm() <= 1e-6 * scale.max(1e-300);
        if l.im < -1e-9 * l.norm().max(1e-12) {
            continue; // keep one of each pair
        }
        let oscillatory = l.im.abs() > 1e-9 * l.norm().max(1e-12);
        let stable = l.re < 0.0 && !neutral;
        let t = std::f64::consts::LN_2 / l.re.abs().max(1e-300);
        let ev = eigenvector(a, *l);
        out.push(ModeInfo {
            kind: if oscillatory {
                ModeKind::Oscillatory
            } else {
                ModeKind::Real
            },
            re_per_s: l.re,
            im_rad_s: if oscillatory { l.im } else { 0.0 },
            stable,
            period_s: oscillatory.then(|| 2.0 * std::f64::consts::PI / l.im),
            time_to_half_or_double_s: (!neutral).then_some(t),
            eigenvector: names
                .iter()
                .zip(ev.iter())
                .map(|(n, x)| (n.to_string(), *x))
                .collect(),
            description: match (oscillatory, stable) {
                _ if neutral => format!(
                    "neutral: {} (nothing restores it, nothing drives it)",
                    dominant(names, &ev)
                ),
                (true, true) => "stable oscillatory".into(),
                (true, false) => "unstable oscillatory".into(),
                (false, true) => "stable subsidence".into(),
                (false, false) => "unstable divergence".into(),
            },
        });
    }
    out.sort_by(|a, b| b.re_per_s.total_cmp(&a.re_per_s));
    out
}

/// Trims `vehicle` in hover, linearises the averaged model and classifies the modes; with
/// `floquet`, also computes the longitudinal monodromy matrix from full simulations.
pub fn analyze(vehicle: &Vehicle, floquet: bool) -> Result<StabilityReport> {
    analyze_at(vehicle, &FlightCondition::HOVER, floquet)
}

/// [`analyze`] at a flight condition: trimmed there on the model's lift variable.
pub fn analyze_at(
    vehicle: &Vehicle,
    condition: &FlightCondition,
    floquet: bool,
) -> Result<StabilityReport> {
    let t = trim_at(vehicle, vehicle.trim_lift, condition)?;
    analyze_trim(vehicle, &t, floquet)
}

/// The trim state of the averaged model: zero but for the velocity of the flight condition.
pub fn trim_state(t: &Trim) -> DVector<f64> {
    let mut x0 = DVector::zeros(N_STATES);
    x0.rows_mut(3, 3)
        .copy_from(&t.condition.velocity_world_m_s());
    x0
}

/// [`analyze`] about a trim already found (of `vehicle` at `t.condition`).
pub fn analyze_trim(vehicle: &Vehicle, t: &Trim, floquet: bool) -> Result<StabilityReport> {
    let t = t.clone();
    let v = trimmed_vehicle(vehicle, &t)?;
    let model = AveragedModel::new(&v, t.attitude(), t.controls, 200);
    let (a, _) = model.linearize(&trim_state(&t))?;
    let lon_names: Vec<&str> = LONGITUDINAL.iter().map(|&i| STATE_NAMES[i]).collect();
    let lat_names: Vec<&str> = LATERAL.iter().map(|&i| STATE_NAMES[i]).collect();
    let a_lon = submatrix(&a, &LONGITUDINAL);
    let a_lat = submatrix(&a, &LATERAL);
    let mut derivatives = Vec::new();
    for (i, ni) in lon_names.iter().enumerate() {
        for (j, nj) in lon_names.iter().enumerate() {
            derivatives.push((format!("d({ni})/dt / d({nj})"), a_lon[(i, j)]));
        }
    }
    let (nondimensional_reference, nondimensional) =
        crate::derivatives::longitudinal(&v, &a_lon, stroke_amplitude_rad(&v)?);
    let f = if floquet {
        Some(floquet_analysis(&v, &t)?)
    } else {
        None
    };
    Ok(StabilityReport {
        trim: t,
        longitudinal_states: lon_names.iter().map(|s| s.to_string()).collect(),
        a_longitudinal: rows(&a_lon),
        lateral_states: lat_names.iter().map(|s| s.to_string()).collect(),
        a_lateral: rows(&a_lat),
        longitudinal_modes: modes(&a_lon, &lon_names),
        lateral_modes: modes(&a_lat, &lat_names),
        floquet_period_s: f.as_ref().map(|f| f.period_s),
        floquet_states: f.as_ref().map(|f| f.states.clone()).unwrap_or_default(),
        floquet_monodromy: f.as_ref().map(|f| f.monodromy.clone()).unwrap_or_default(),
        floquet_warnings: f.as_ref().map(|f| f.nonsmooth.clone()).unwrap_or_default(),
        floquet_longitudinal: f.map(|f| f.modes).unwrap_or_default(),
        derivatives,
        nondimensional_reference,
        nondimensional,
    })
}

#[cfg(test)]
mod tests {
    use super::eigen::normalized;
    use super::*;

    #[test]
    fn a_neutral_turn_of_a_pitched_body_about_the_vertical_is_its_heading() {
        // States (roll, yaw, p, r) of a body pitched up by theta: the angles' rates are p
        // and r; gravity restores the tilt cos(theta) roll - sin(theta) yaw (the part of the
        // attitude error that turns gravity in the body frame) and the rates are damped. The
        // zero eigenvalue's vector is (sin theta, cos theta, 0, 0): a turn about the
        // vertical, mostly roll at 57.5 deg (the bumblebee's hover pitch), named the heading.
        let th = 57.5_f64.to_radians();
        let (k, c) = (40.0, 3.0);
        let a = DMatrix::from_row_slice(
            4,
            4,
            &[
                0.0,
                0.0,
                1.0,
                0.0,
                0.0,
                0.0,
                0.0,
                1.0,
                -k * th.cos(),
                k * th.sin(),
                -c,
                0.0,
                0.0,
                0.0,
                0.0,
                -c,
            ],
        );
        let names = ["roll_err_rad", "yaw_err_rad", "p_rad_s", "r_rad_s"];
        let m = modes(&a, &names);
        let neutral: Vec<_> = m
            .iter()
            .filter(|m| m.description.starts_with("neutral"))
            .collect();
        assert_eq!(neutral.len(), 1, "{m:?}");
        let e = &neutral[0].eigenvector;
        assert!((e[1].1 / e[0].1 - 1.0 / th.tan()).abs() < 1e-9, "{e:?}");
        assert!(
            neutral[0].description.contains("heading"),
            "{}",
            neutral[0].description
        );
        // A neutral pitch (an angle that is not roll or yaw) is not the heading.
        let b = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 0.0, -2.0]);
        let m = modes(&b, &["pitch_err_rad", "q_rad_s"]);
        let n = m
            .iter()
            .find(|m| m.description.starts_with("neutral"))
            .unwrap();
        assert!(n.description.contains("pitch_err_rad"), "{}", n.description);
    }

    #[test]
    fn eigenvectors_of_a_scaled_rotation_are_the_analytic_ones() {
        // r R(theta) has eigenvalues r exp(+-i theta) with eigenvectors (1, -+i) / sqrt(2)
        // (R v = exp(i theta) v for v = (1, -i): cos + i sin = exp(i theta) on the first
        // entry, sin - i cos = -i exp(i theta) on the second).
        let (r, th) = (0.9_f64, 0.3_f64);
        let a = DMatrix::from_row_slice(
            2,
            2,
            &[r * th.cos(), -r * th.sin(), r * th.sin(), r * th.cos()],
        );
        let mu = Complex::from_polar(r, th);
        let v = normalized(&complex_eigenvector(&a, mu));
        let (v0, v1) = (Complex::new(v[0].0, v[0].1), Complex::new(v[1].0, v[1].1));
        // The direction: v1 / v0 = -i.
        assert!((v1 / v0 - Complex::new(0.0, -1.0)).norm() < 1e-12, "{v:?}");
        // Unit norm, and the largest entry (the two tie up to round-off) real and positive.
        assert!(((v0.norm_sqr() + v1.norm_sqr()).sqrt() - 1.0).abs() < 1e-12);
        let big = if v0.norm() >= v1.norm() { v0 } else { v1 };
        assert!(big.re > 0.0 && big.im.abs() < 1e-15, "{v:?}");
    }
}
