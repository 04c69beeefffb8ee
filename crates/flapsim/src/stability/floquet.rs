//! The Floquet analysis: the monodromy matrix of the full periodic system over one
//! wingbeat, from full simulations of perturbed starts, its multipliers, exponents and
//! eigenvectors, and the check that the one-wingbeat map is smooth where its derivatives are
//! taken.

use nalgebra::{DMatrix, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};
use wingforce::inflow::InflowState;

use super::eigen::{complex_eigenvector, normalized, rows};
use crate::error::Result;
use crate::model::Vehicle;
use crate::sim::{Mode as SimMode, Simulation, State};
use crate::trim::Trim;

/// A Floquet multiplier, its exponent and its eigenvector.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FloquetMode {
    /// Multiplier mu (real, imaginary): an eigenvalue of the monodromy matrix.
    pub multiplier: (f64, f64),
    /// Exponent ln(mu) / T: (real 1/s, imaginary rad/s), so mu = exp(exponent T).
    pub exponent: (f64, f64),
    /// The eigenvector v of the monodromy matrix (Phi v = mu v), one complex entry (real,
    /// imaginary) per state of [`FloquetAnalysis::states`], in those states' units; unit
    /// 2-norm, its largest entry real and positive. The perturbation that comes back
    /// multiplied by mu after each wingbeat.
    pub eigenvector: Vec<(f64, f64)>,
}

/// The Floquet analysis of the longitudinal motion about the trim.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FloquetAnalysis {
    /// State names of the monodromy matrix's rows and columns: the body's (vx_m_s, vz_m_s,
    /// pitch_err_rad, q_rad_s) and, for an actuated vehicle, the wings' (symmetric) offsets
    /// from their periodic motion.
    pub states: Vec<String>,
    /// The wingbeat period T, s.
    pub period_s: f64,
    /// The monodromy matrix Phi, row-major: a perturbation y at the start of a wingbeat is
    /// Phi y one wingbeat later (central differences of full simulations).
    pub monodromy: Vec<Vec<f64>>,
    /// The multipliers, exponents and eigenvectors, sorted by real exponent, largest first.
    pub modes: Vec<FloquetMode>,
    /// One warning per column of the monodromy whose one-sided differences disagree (the
    /// one-wingbeat map has a jump or a kink at the orbit: they part by more than 0.1 of a
    /// perturbation, `SMOOTH_GAP`); empty when it is smooth.
    pub nonsmooth: Vec<String>,
}

/// State names of [`FloquetAnalysis::states`]: the body's four.
pub const FLOQUET_BODY_STATES: [&str; 4] = ["vx_m_s", "vz_m_s", "pitch_err_rad", "q_rad_s"];
/// The wing states an actuated vehicle adds (offsets from the periodic motion, both wings).
pub const FLOQUET_WING_STATES: [&str; 4] = [
    "stroke_rad",
    "wing_pitch_rad",
    "stroke_rate_rad_s",
    "wing_pitch_rate_rad_s",
];

/// Longitudinal state (vx, vz, pitch error, q) of a simulation state relative to trim (at
/// the trim's velocity `v_trim`, world).
fn lon_state(s: &State, q_trim: &UnitQuaternion<f64>, v_trim: &Vector3<f64>) -> [f64; 4] {
    let delta = (q_trim.inverse() * s.world_from_body).scaled_axis();
    [
        s.velocity_m_s.x - v_trim.x,
        s.velocity_m_s.z - v_trim.z,
        delta.y,
        s.angular_velocity_body_rad_s.y,
    ]
}

/// One wingbeat of the full simulation (longitudinal degrees of freedom) from a
/// longitudinal perturbation `y` of the trim state. For an actuated vehicle, `y` goes on
/// with the wing states (stroke, pitch and their rates, the same on both wings: a symmetric
/// perturbation) as offsets from the periodic motion `periodic` starts at.
fn one_wingbeat(
    v: &Vehicle,
    periodic: Option<&crate::actuated::PeriodicWings>,
    wing_states: &[usize],
    inflow: Option<&[InflowState]>,
    q_trim: &UnitQuaternion<f64>,
    v_trim: &Vector3<f64>,
    y: &[f64],
) -> Result<Vec<f64>> {
    crate::cancel::check()?;
    let mut sim = Simulation::new(v.clone(), SimMode::LONGITUDINAL);
    let s = State {
        position_m: Vector3::zeros(),
        world_from_body: q_trim * UnitQuaternion::from_scaled_axis(Vector3::new(0.0, y[2], 0.0)),
        velocity_m_s: v_trim + Vector3::new(y[0], 0.0, y[1]),
        angular_velocity_body_rad_s: Vector3::new(0.0, y[3], 0.0),
    };
    sim.set_state(&s);
    let reference = periodic.map(|p| {
        sim.start_wings_from(p);
        p.dynamic[0].state()
    });
    if let Some(w0) = reference {
        let mut d = [0.0; 4];
        for (k, &i) in wing_states.iter().enumerate() {
            d[i] = y[4 + k];
        }
        let w = crate::actuated::WingState {
            phi_rad: w0.phi_rad + d[0],
            theta_rad: w0.theta_rad + d[1],
            phi_dot_rad_s: w0.phi_dot_rad_s + d[2],
            theta_dot_rad_s: w0.theta_dot_rad_s + d[3],
        };
        sim.set_wing_states([w, w]);
    }
    // The inflow's longitudinal states (mean and fore-aft gradient of each pair) go on
    // after the wings'.
    let n_inflow = 4 + wing_states.len();
    if let Some(states) = inflow {
        let perturbed: Vec<InflowState> = states
            .iter()
            .enumerate()
            .map(|(p, s)| InflowState {
                mean_m_s: s.mean_m_s + y[n_inflow + 2 * p],
                gradient_m_s: s.gradient_m_s + nalgebra::Vector2::new(y[n_inflow + 2 * p + 1], 0.0),
            })
            .collect();
        sim.set_inflow_states(&perturbed)?;
    }
    for _ in 0..v.sim.steps_per_wingbeat {
        sim.step()?;
    }
    let mut out = lon_state(&sim.state(), q_trim, v_trim).to_vec();
    if let (Some(w0), Some([w, _])) = (reference, sim.wing_states()) {
        let d = [
            w.phi_rad - w0.phi_rad,
            w.theta_rad - w0.theta_rad,
            w.phi_dot_rad_s - w0.phi_dot_rad_s,
            w.theta_dot_rad_s - w0.theta_dot_rad_s,
        ];
        out.extend(wing_states.iter().map(|&i| d[i]));
    }
    if let Some(states) = inflow {
        for (s0, s) in states.iter().zip(sim.wing_set().inflow_states()) {
            out.push(s.mean_m_s - s0.mean_m_s);
            out.push(s.gradient_m_s.x - s0.gradient_m_s.x);
        }
    }
    Ok(out)
}

/// Floquet multipliers, exponents and eigenvectors of the longitudinal motion about the
/// trim (see [`floquet_analysis`]).
pub fn floquet_longitudinal(v: &Vehicle, t: &Trim) -> Result<Vec<FloquetMode>> {
    floquet_analysis(v, t).map(|f| f.modes)
}

/// The monodromy matrix of the longitudinal motion about the trim (one wingbeat of full
/// simulations from perturbed starts, central differences) and its eigen-decomposition. For
/// an actuated vehicle the matrix also spans the wings' own states (stroke, pitch and their
/// rates, symmetric), whose memory from one wingbeat to the next couples into the body
/// modes: 8 multipliers, the body's 4 and the wings' 4, sorted by real exponent. For a wake
/// that answers (`[aero] inflow = "dynamic"`) it also spans each pair's mean and fore-aft
/// inflow, started on their periodic motion at the trim ([`crate::averaged::periodic_inflow`]).
pub fn floquet_analysis(v: &Vehicle, t: &Trim) -> Result<FloquetAnalysis> {
    let q = t.attitude();
    let v_trim = t.condition.velocity_world_m_s();
    let periodic = if v.actuation.is_some() {
        Some(crate::actuated::periodic::settle(
            v,
            &wingforce::BodyMotion {
                velocity_m_s: t.velocity_body_m_s(),
                angular_velocity_rad_s: Vector3::zeros(),
            },
        )?)
    } else {
        None
    };
    // The wing states the monodromy spans: all four, but a wing that starts the period
    // resting on an inelastic stop (restitution 0: a constraint) has its pitch and pitch
    // rate fixed there, so only its stroke and stroke rate are states (a perturbation into
    // the stop would be undone by the constraint, one out of it would not: no derivative).
    let wing_states: Vec<usize> = match periodic.as_ref().zip(v.actuation.as_ref()) {
        Some((p, a)) => {
            let w0 = p.dynamic[0].state();
            let h = &a.dynamics.hinge;
            let resting = h.contact.is_some_and(|c| {
                c.is_inelastic()
                    && c.beyond_rad(h.rest_rad, w0.theta_rad).1 >= 0.0
                    && w0.theta_dot_rad_s == 0.0
            });
            if resting {
                vec![0, 2]
            } else {
                vec![0, 1, 2, 3]
            }
        }
        None => Vec::new(),
    };
    // A dynamic inflow's periodic motion at the trim: its states at the wingbeat's start.
    // Actuated wings: the pair's inflow went round with them on their periodic motion.
    let inflow = match &periodic {
        Some(p) => p.inflow.as_ref().map(wingset::PairInflows::states),
        None => crate::averaged::periodic_inflow(
            v,
            &wingforce::BodyMotion {
                velocity_m_s: t.velocity_body_m_s(),
                angular_velocity_rad_s: Vector3::zeros(),
            },
            v.sim.steps_per_wingbeat as usize,
        )?
        .map(|p| p.states),
    };
    let speed = v.wings[0].v_ref_m_s();
    let mut eps = vec![speed * 1e-4, speed * 1e-4, 1e-5, 1e-3];
    let w = 2.0 * std::f64::consts::PI * v.freq_hz();
    eps.extend(
        wing_states
            .iter()
            .map(|&i| if i < 2 { 1e-5 } else { 1e-5 * w }),
    );
    if let Some(states) = &inflow {
        for s in states {
            eps.extend([1e-4 * s.mean_m_s, 1e-4 * s.mean_m_s]);
        }
    }
    let n = eps.len();
    let mut phi = DMatrix::zeros(n, n);
    let run = |y: &[f64]| {
        one_wingbeat(
            v,
            periodic.as_ref(),
            &wing_states,
            inflow.as_deref(),
            &q,
            &v_trim,
            y,
        )
    };
    // The unperturbed wingbeat, for the one-sided differences that check the map is smooth.
    let base = run(&vec![0.0; n])?;
    let mut jumps = Vec::with_capacity(n);
    for j in 0..n {
        let mut yp = vec![0.0; n];
        let mut ym = vec![0.0; n];
        yp[j] = eps[j];
        ym[j] = -eps[j];
        let (p, m) = (run(&yp)?, run(&ym)?);
        for i in 0..n {
            phi[(i, j)] = (p[i] - m[i]) / (2.0 * eps[j]);
        }
        jumps.push(one_sided_gap(&p, &base, &m, &eps));
    }
    let period = 1.0 / v.freq_hz();
    let mut out: Vec<FloquetMode> = phi
        .complex_eigenvalues()
        .iter()
        .map(|mu| {
            let ln = mu.ln();
            FloquetMode {
                multiplier: (mu.re, mu.im),
                exponent: (ln.re / period, ln.im / period),
                eigenvector: normalized(&complex_eigenvector(&phi, *mu)),
            }
        })
        .collect();
    out.sort_by(|a, b| b.exponent.0.total_cmp(&a.exponent.0));
    let mut states: Vec<String> = FLOQUET_BODY_STATES.iter().map(|s| s.to_string()).collect();
    states.extend(
        wing_states
            .iter()
            .map(|&i| FLOQUET_WING_STATES[i].to_string()),
    );
    for p in 0..inflow.as_ref().map_or(0, Vec::len) {
        let pair = if p == 0 {
            String::new()
        } else {
            format!("_{p}")
        };
        states.push(format!("inflow_mean_m_s{pair}"));
        states.push(format!("inflow_fore_m_s{pair}"));
    }
    let nonsmooth = jumps
        .iter()
        .enumerate()
        .filter(|(_, (gap, _))| *gap > SMOOTH_GAP)
        .map(|(j, (gap, i))| {
            format!(
                "the one-wingbeat map is not smooth at the periodic orbit along {}: its forward and backward differences disagree by {gap:.3} of a perturbation in {} (a smooth map: below {SMOOTH_GAP}), so it has a jump or a kink there and the exponents are not to be trusted at {} steps per wingbeat: run another count (--steps-per-wingbeat)",
                states[j], states[*i], v.sim.steps_per_wingbeat
            )
        })
        .collect();
    Ok(FloquetAnalysis {
        states,
        period_s: period,
        monodromy: rows(&phi),
        modes: out,
        nonsmooth,
    })
}

/// The largest disagreement between the forward and the backward difference of column `j`
/// (from the runs perturbed by `+eps[j]` and `-eps[j]` and the unperturbed `base`), each
/// entry in units of its own state's perturbation (Phi's entries are then of order one: a
/// multiplier near 1 keeps a perturbation's size): |(p_i - b_i) - (b_i - m_i)| / eps_i. A
/// smooth map gives O(eps) (its curvature); a map with a jump at the orbit (a discrete event
/// that the perturbation moves across a step) gives the jump over eps_i, whatever eps_j.
/// Returns the gap and the row where it is largest.
fn one_sided_gap(p: &[f64], base: &[f64], m: &[f64], eps: &[f64]) -> (f64, usize) {
    (0..p.len())
        .map(|i| (((p[i] - base[i]) - (base[i] - m[i])).abs() / eps[i], i))
        .fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a })
}

/// Largest [`one_sided_gap`] of a smooth one-wingbeat map. Measured at the built-in
/// vehicles' own step counts: at most 1.3e-3 (the hummingbird; the fly 7e-5, the bumblebee
/// 3e-5, the RoboBee kinematics 2e-4); the hummingbird at 3200 steps per wingbeat, whose
/// exponents stand apart from those at 200-2800 (docs/speed.md row 30's method), 1.84 in
/// its vx and vz columns.
const SMOOTH_GAP: f64 = 0.1;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_sided_differences_tell_a_smooth_map_from_one_with_a_jump() {
        // x -> (a x + b x^2, c x) at x = 0 with perturbations eps = (1e-3, 1e-2): a smooth
        // map's forward and backward differences differ by 2 b eps_j^2 (its curvature), in
        // units of the row's eps 2 b eps_j^2 / eps_i; a jump J taken on one side only
        // (x > 0) adds J / eps_i whatever eps_j.
        let eps = [1e-3, 1e-2];
        let (a, b, c) = (0.9, 2.0, 0.5);
        let map = |x: f64, jump: f64| {
            let j = if x > 0.0 { jump } else { 0.0 };
            vec![a * x + b * x * x + j, c * x]
        };
        let gap = |jump: f64| {
            let (p, base, m) = (map(eps[0], jump), map(0.0, jump), map(-eps[0], jump));
            one_sided_gap(&p, &base, &m, &eps)
        };
        let (smooth, row) = gap(0.0);
        assert!(
            (smooth - 2.0 * b * eps[0]).abs() < 1e-12 && row == 0,
            "{smooth} {row}"
        );
        assert!(smooth < SMOOTH_GAP);
        let (jumped, row) = gap(1e-3);
        assert!((jumped - (1e-3 / eps[0] + 2.0 * b * eps[0])).abs() < 1e-12 && row == 0);
        assert!(jumped > SMOOTH_GAP);
    }
}
