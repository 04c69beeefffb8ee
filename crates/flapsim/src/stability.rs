//! Stability in hover or at a flight condition ([`crate::flight`]): the averaged model's
//! system matrices, eigenvalues, eigenvectors and modes (the method of Sun and Xiong 2005;
//! Xiong and Sun 2008 in forward flight), and a Floquet analysis of the full time-periodic
//! system (the monodromy matrix over one wingbeat by finite differences of full
//! simulations) to compare with.

use nalgebra::{Complex, DMatrix, DVector, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};
use wingforce::inflow::InflowState;

use crate::error::Result;
use crate::flight::FlightCondition;
use crate::linear::{AveragedModel, LATERAL, LONGITUDINAL, N_STATES, STATE_NAMES, submatrix};
use crate::model::Vehicle;
use crate::sim::{Mode as SimMode, Simulation, State};
use crate::trim::{Trim, trim_at, trimmed_vehicle};

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
    /// one-wingbeat map has a jump at the orbit: [`SMOOTH_GAP`]); empty when it is smooth.
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

fn rows(a: &DMatrix<f64>) -> Vec<Vec<f64>> {
    (0..a.nrows())
        .map(|i| a.row(i).iter().copied().collect())
        .collect()
}

/// Complex eigenvector of `a` for eigenvalue `l`: the null vector of a - l I by SVD (the
/// right singular vector of the smallest singular value), unit 2-norm.
fn complex_eigenvector(a: &DMatrix<f64>, l: Complex<f64>) -> DVector<Complex<f64>> {
    let n = a.nrows();
    let m = DMatrix::from_fn(n, n, |i, j| {
        Complex::new(a[(i, j)], 0.0) - if i == j { l } else { Complex::new(0.0, 0.0) }
    });
    let svd = m.svd(false, true);
    let Some(vt) = svd.v_t else {
        return DVector::zeros(n);
    };
    let k = svd
        .singular_values
        .iter()
        .enumerate()
        .fold(0, |best, (i, s)| {
            if *s < svd.singular_values[best] {
                i
            } else {
                best
            }
        });
    // The rows of V^H are the conjugated right singular vectors.
    DVector::from_iterator(n, vt.row(k).iter().map(|c| c.conj()))
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

/// `v` scaled to unit 2-norm with its largest entry real and positive, as (re, im) pairs.
fn normalized(v: &DVector<Complex<f64>>) -> Vec<(f64, f64)> {
    let k = v.iter().enumerate().fold(
        0,
        |best, (i, c)| if c.norm() > v[best].norm() { i } else { best },
    );
    let (norm, big) = (v.norm(), v[k]);
    let phase = if big.norm() > 0.0 && norm > 0.0 {
        big.conj() / (big.norm() * norm)
    } else {
        Complex::new(1.0, 0.0)
    };
    v.iter()
        .enumerate()
        .map(|(i, c)| {
            let z = c * phase;
            // The largest entry exactly real (its rotation leaves round-off in Im).
            if i == k {
                (z.norm(), 0.0)
            } else {
                (z.re, z.im)
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
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
