//! The built-in bumblebee beside Sun & Xiong (2005, "Dynamic flight stability of a hovering
//! bumblebee", J. Exp. Biol. 208:447-459): their table of non-dimensional longitudinal
//! derivatives from CFD, the axes they are given in, and the modes those derivatives give.
//!
//! The table (docs/research/issue24-sources.md, section 3) was read from the journal's own
//! page of the paper's table (journals.biologists.com, "Non-dimensional aerodynamic
//! derivatives"); the page names no paper, so it is identified by its modes: with the
//! model's mass and pitch inertia at the paper's reference speed, these nine numbers give the
//! abstract's four mode times within 10% (checked by a test), which no other table would.
//!
//! Axes. Sun & Xiong linearise about hover in axes that are level at equilibrium, x forward
//! and, as their group writes the vertical balance Z_e = -m g, z down, with q and M positive
//! nose up. flapwing's averaged model uses x forward, z up and q > 0 nose down
//! ([`crate::derivatives`]). So Z, w, M and q change sign between the two, and a derivative's
//! sign flips when exactly one of its load and its state does: X_w, X_q, Z_u and M_u.

use nalgebra::DMatrix;

use crate::derivatives::{LONGITUDINAL, Reference, reference};
use crate::error::{Error, Result};
use crate::model::Vehicle;
use crate::stability::{ModeInfo, ModeKind, StabilityReport, modes};

/// Where the derivative table comes from.
pub const TABLE_SOURCE: &str = "Sun & Xiong 2005 (J. Exp. Biol. 208:447), table of non-dimensional aerodynamic derivatives of the hovering bumblebee (CFD), read from the journal's table page; identified by its modes (notes 3)";

/// Where the mode times come from.
pub const MODES_SOURCE: &str = "Sun & Xiong 2005, abstract";

/// Sun & Xiong's non-dimensional derivatives in their axes (x forward, z down, q and M nose
/// up), as tabulated: X_u, Z_u, M_u, X_w, Z_w, M_w, X_q, Z_q, M_q.
pub const DERIVATIVES: [(&str, f64); 9] = [
    ("X_u", -0.785),
    ("Z_u", -0.031),
    ("M_u", 2.389),
    ("X_w", 0.050),
    ("Z_w", -1.033),
    ("M_w", -0.190),
    ("X_q", -0.090),
    ("Z_q", -0.031),
    ("M_q", -0.883),
];

/// The abstract's mode times, s: the unstable oscillatory mode's period and doubling time,
/// the fast and the slow subsidence's half times.
pub const MODE_TIMES_S: [f64; 4] = [0.32, 0.1, 0.024, 0.37];

/// The names of [`MODE_TIMES_S`], with units.
pub const MODE_TIME_NAMES: [&str; 4] = [
    "bumblebee unstable oscillatory mode: period, s",
    "bumblebee unstable oscillatory mode: doubling time, s",
    "bumblebee fast subsidence: half time, s",
    "bumblebee slow subsidence: half time, s",
];

/// The factor that takes a derivative from flapwing's axes (x forward, z up, q > 0 nose
/// down) to Sun & Xiong's (z down, q nose up): -1 where exactly one of the load (Z, M) and
/// the state (w, q) changes sign.
pub fn to_sun_axes(name: &str) -> f64 {
    let load_flips = name.starts_with('Z') || name.starts_with('M');
    let state_flips = name.ends_with('w') || name.ends_with('q');
    if load_flips == state_flips { 1.0 } else { -1.0 }
}

/// The published value of the derivative `name` (Sun & Xiong's axes).
pub fn published(name: &str) -> Option<f64> {
    DERIVATIVES
        .iter()
        .find(|(n, _)| *n == name)
        .map(|&(_, v)| v)
}

/// The model's non-dimensional derivatives from its stability report, in Sun & Xiong's axes,
/// in the table's order.
pub fn model_derivatives(report: &StabilityReport) -> Result<Vec<(&'static str, f64)>> {
    DERIVATIVES
        .iter()
        .map(|&(name, _)| {
            report
                .nondimensional
                .iter()
                .find(|d| d.name == name)
                .map(|d| (name, d.nondimensional * to_sun_axes(name)))
                .ok_or_else(|| Error::Analysis(format!("the stability report has no {name}")))
        })
        .collect()
}

/// The longitudinal matrix (flapwing's states u, w, pitch, q) with Sun & Xiong's derivatives
/// in place of the model's: the model's mass, pitch inertia and gravity column, the
/// derivatives made dimensional with the model's reference at the paper's stroke amplitude
/// (`reference`).
pub fn published_matrix(
    vehicle: &Vehicle,
    a_model: &DMatrix<f64>,
    reference: &Reference,
) -> DMatrix<f64> {
    let mut a = a_model.clone();
    for &(name, i, j, moment, _) in &LONGITUDINAL {
        let k = if moment {
            vehicle.inertia_kg_m2[(1, 1)]
        } else {
            vehicle.mass_kg
        };
        let value = published(name).unwrap_or(0.0) * to_sun_axes(name);
        a[(i, j)] = value / reference.scale(j, moment) / k;
    }
    a
}

/// The four mode times (as [`MODE_TIMES_S`]) of a set of longitudinal modes: one unstable
/// oscillatory mode and two stable real ones, as Sun & Xiong found.
pub fn mode_times(modes: &[ModeInfo]) -> Result<[f64; 4]> {
    let osc = modes
        .iter()
        .find(|m| m.kind == ModeKind::Oscillatory)
        .ok_or_else(|| Error::Analysis("no oscillatory longitudinal mode".into()))?;
    let mut halves: Vec<f64> = modes
        .iter()
        .filter(|m| m.kind == ModeKind::Real && m.stable)
        .filter_map(|m| m.time_to_half_or_double_s)
        .collect();
    halves.sort_by(f64::total_cmp);
    if halves.len() != 2 {
        return Err(Error::Analysis(format!(
            "{} stable real longitudinal modes, Sun & Xiong 2005 found 2",
            halves.len()
        )));
    }
    Ok([
        osc.period_s.unwrap_or(f64::NAN),
        osc.time_to_half_or_double_s.unwrap_or(f64::NAN),
        halves[0],
        halves[1],
    ])
}

/// The bumblebee's analysis beside the paper: the model's mode times and derivatives, and
/// the mode times of the published derivatives with the model's mass and inertia.
#[derive(Debug, Clone)]
pub struct Comparison {
    /// The model's averaged-model stability report at its hover trim.
    pub report: StabilityReport,
    /// The model's four mode times, s.
    pub model_times_s: [f64; 4],
    /// The mode times of Sun & Xiong's derivatives with the model's mass, I_y and gravity.
    pub published_derivative_times_s: [f64; 4],
    /// The model's non-dimensional derivatives in Sun & Xiong's axes.
    pub model_derivatives: Vec<(&'static str, f64)>,
    /// The reference quantities at the paper's stroke amplitude, which make the published
    /// derivatives dimensional.
    pub paper_reference: Reference,
}

/// Analyses `bee` (the built-in bumblebee or a variant) beside Sun & Xiong 2005.
pub fn compare(bee: &Vehicle) -> Result<Comparison> {
    let report = crate::stability::analyze(bee, false)?;
    let a_model = DMatrix::from_fn(4, 4, |i, j| report.a_longitudinal[i][j]);
    let names: Vec<&str> = report
        .longitudinal_states
        .iter()
        .map(String::as_str)
        .collect();
    let model_times_s = mode_times(&report.longitudinal_modes)?;
    // The paper's reference: its stroke amplitude (the model's before trim, 116 deg).
    let paper = reference(bee, bee.wings[0].kinematics().amplitude_rad);
    let a_published = published_matrix(bee, &a_model, &paper);
    let published_derivative_times_s = mode_times(&modes(&a_published, &names))?;
    let model_derivatives = model_derivatives(&report)?;
    Ok(Comparison {
        report,
        model_times_s,
        published_derivative_times_s,
        model_derivatives,
        paper_reference: paper,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_axes_flip_the_derivatives_with_one_sign_change() {
        let flipped: Vec<&str> = DERIVATIVES
            .iter()
            .map(|&(n, _)| n)
            .filter(|n| to_sun_axes(n) < 0.0)
            .collect();
        assert_eq!(flipped, ["Z_u", "M_u", "X_w", "X_q"]);
    }

    /// The table as transcribed, made dimensional with the built-in bumblebee's mass, pitch
    /// inertia and the paper's reference speed (U = 2 Phi n r_2 at its 116 deg, 155 Hz),
    /// gives the four mode times of the paper's abstract (0.32 s period and 0.1 s doubling of
    /// the oscillatory mode, 0.024 s and 0.37 s half times) within 10%: this identifies the
    /// table as Sun & Xiong 2005's and checks the axes and the non-dimensional forms. (The
    /// remaining few per cent are the estimated I_y and air density, which the abstract does
    /// not give.) The model's own M_u is nose-up with forward speed in the paper's axes, the
    /// coupling the abstract names as the cause of the instability.
    #[test]
    fn the_published_derivatives_give_the_published_modes() {
        let text = crate::builtin_model("bumblebee").unwrap();
        let bee = Vehicle::from_toml(text, "bumblebee").unwrap();
        let c = compare(&bee).unwrap();
        for i in 0..4 {
            let err = c.published_derivative_times_s[i] / MODE_TIMES_S[i] - 1.0;
            assert!(err.abs() < 0.10, "{}: {err:+.3}", MODE_TIME_NAMES[i]);
        }
        let m_u = c
            .model_derivatives
            .iter()
            .find(|(n, _)| *n == "M_u")
            .unwrap()
            .1;
        assert!(m_u > 0.0, "{m_u}");
        assert_eq!(c.model_derivatives.len(), 9);
    }
}

/// The heave damping Z_w in N s/m under the frozen and the dynamic wake, beside the CFD's
/// and momentum theory's linear result for a responsive disc (issue #38): the frozen wake's
/// Z_w times m / (2m + k), m = 2 rho A w_h the mass flow through the disc the wings sweep at
/// the frozen trim and k = -Z_w (frozen) the wings' thrust sensitivity to the flow through it
/// (`crates/flapsim/tests/responsive_wake` checks the dynamic wake against it).
///
/// Dimensional, because each wake's trim flaps its own stroke and so has its own
/// non-dimensional reference; the CFD's derivative is made dimensional at the paper's stroke
/// ([`Comparison::paper_reference`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Heave {
    /// Z_w with the wake frozen, N s/m (flapwing's axes, z up).
    pub frozen_n_s_m: f64,
    /// Z_w with the wake that answers, N s/m.
    pub dynamic_n_s_m: f64,
    /// Sun & Xiong's, N s/m.
    pub cfd_n_s_m: f64,
    /// m / (2m + k).
    pub momentum_ratio: f64,
    /// The stroke at which the CFD's derivative is made dimensional, rad.
    pub paper_stroke_rad: f64,
}

impl Heave {
    /// Measures it from the bumblebee with its wake frozen and the two comparisons.
    pub fn measure(
        frozen_bee: &Vehicle,
        frozen: &Comparison,
        dynamic: &Comparison,
    ) -> Result<Self> {
        let si = |c: &Comparison| {
            c.report
                .nondimensional
                .iter()
                .find(|d| d.name == "Z_w")
                .map(|d| d.value)
                .ok_or_else(|| Error::Analysis("the stability report has no Z_w".into()))
        };
        let frozen_n_s_m = si(frozen)?;
        let (_, _, column, moment, _) = LONGITUDINAL
            .iter()
            .copied()
            .find(|d| d.0 == "Z_w")
            .ok_or_else(|| Error::Analysis("no Z_w among the derivatives".into()))?;
        let cfd_n_s_m = published("Z_w").unwrap_or(f64::NAN) * to_sun_axes("Z_w")
            / frozen.paper_reference.scale(column, moment);
        let trimmed = crate::trim::trimmed_vehicle(frozen_bee, &frozen.report.trim)?;
        let w = &trimmed.wings[0];
        let rho = w.fluid().density_kg_m3;
        let area = w.kinematics().amplitude_rad * w.geometry().r_tip_m.powi(2);
        let mass_flow = (2.0 * rho * area * frozen_bee.weight_n()).sqrt();
        let k = -frozen_n_s_m;
        Ok(Self {
            paper_stroke_rad: frozen.paper_reference.stroke_amplitude_rad,
            frozen_n_s_m,
            dynamic_n_s_m: si(dynamic)?,
            cfd_n_s_m,
            momentum_ratio: mass_flow / (2.0 * mass_flow + k),
        })
    }

    /// The ratios in words.
    pub fn describe(&self) -> String {
        format!(
            "in N s/m the dynamic wake's Z_w is {:.3} of the frozen wake's, where momentum theory's responsive disc gives m / (2m + k) = {:.3}, and the CFD's is {:.2} of it (made dimensional at the paper's {:.0} deg stroke)",
            self.dynamic_n_s_m / self.frozen_n_s_m,
            self.momentum_ratio,
            self.cfd_n_s_m / self.frozen_n_s_m,
            self.paper_stroke_rad.to_degrees(),
        )
    }
}
