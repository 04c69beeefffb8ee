//! Responses of a study case, evaluated tethered at the hover attitude: the body is held
//! still (no linear or angular velocity) at the attitude of the model's `initial.attitude_deg`
//! (for the built-in drosophila, pitched up 45 deg so the stroke plane is horizontal), and
//! the wings flap through one wingbeat sampled at `steps` equally spaced phases.
//!
//! Definitions (all cycle means over one wingbeat):
//! - `cl_mean_<term>`, `cd_mean_<term>` (term = translational, rotational, added_mass,
//!   wake_capture, total): the wing's lift and drag coefficients on the reference scale of
//!   eq 11-12 (0.5 rho V_ref^2 S of one wing), averaged over the cycle and over both wings
//!   ([`wingforce::cycle::CycleMean`]);
//! - `lift_over_weight`: the world-vertical component of the mean total aerodynamic force
//!   of both wings ([`flapsim::averaged::mean_loads`]) over the weight m g;
//! - `aero_power_w`: the aerodynamic power, the cycle mean of
//!   P(t) = - sum over wings of M_hinge(t) . omega_wing(t), where M_hinge is the moment of
//!   the wing's aerodynamic force (all four terms) about its hinge and omega_wing the wing's
//!   angular velocity relative to the (still) body, both in body axes. It is the power the
//!   wing drive spends against the air; the wings' own inertia is not included, and the
//!   added-mass term's reactive power averages out over a periodic cycle;
//! - `lift_per_power_n_per_w`: the vertical force of `lift_over_weight` (N) over
//!   `aero_power_w`;
//! - `mean_pitch_moment_nm`: the body-y component of the mean aerodynamic moment about the
//!   centre of mass (positive nose up, body y to the left);
//! - `wake_capture_peak_cl`: the peak of the instantaneous wake-capture lift coefficient of
//!   eq 23, 0.3 dCL_bar / (mu* sqrt(2 pi)) at t* = mu*, from the (clamped) regressions the
//!   wing uses; 0 when the model switches the term off.
//!
//! Every CSV row also carries `reynolds` (the paper's Re = V_ref c_bar / nu of the wing) and
//! `wake_capture_clamped` (1 when Re, dtau_A or dtau_D lay outside the wake-capture model's
//! fitted range and were clamped, else 0).

use nalgebra::Vector3;
use wingforce::cycle::CycleMean;
use wingforce::{BodyMotion, Term};

use flapsim::averaged::{FrozenState, mean_loads};
use flapsim::model::Vehicle;

/// One response a study can ask for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Response {
    /// Cycle-mean C_L of one term (`None` = the total).
    ClMean(Option<Term>),
    /// Cycle-mean C_D of one term (`None` = the total).
    CdMean(Option<Term>),
    /// Vertical force over weight.
    LiftOverWeight,
    /// Aerodynamic power, W.
    AeroPowerW,
    /// Vertical force per aerodynamic power, N/W.
    LiftPerPowerNPerW,
    /// Mean pitch moment about the CoM, N m.
    MeanPitchMomentNm,
    /// Peak wake-capture C_L of eq 23.
    WakeCapturePeakCl,
    /// 1 when a hover trim exists (`flapsim::trim::trim` converges within its allowed range),
    /// else 0. Only computed when a study asks for it (it costs a trim per case).
    TrimFeasible,
}

impl Response {
    /// Every response, in a fixed order.
    pub fn all() -> Vec<Response> {
        let mut v = Vec::new();
        for t in Term::ALL.map(Some).into_iter().chain([None]) {
            v.push(Response::ClMean(t));
        }
        for t in Term::ALL.map(Some).into_iter().chain([None]) {
            v.push(Response::CdMean(t));
        }
        v.extend([
            Response::LiftOverWeight,
            Response::AeroPowerW,
            Response::LiftPerPowerNPerW,
            Response::MeanPitchMomentNm,
            Response::WakeCapturePeakCl,
            Response::TrimFeasible,
        ]);
        v
    }

    /// Every response name.
    pub fn all_names() -> Vec<String> {
        Self::all().iter().map(|r| r.name()).collect()
    }

    /// The name used in study files and CSV headers.
    pub fn name(&self) -> String {
        let term = |t: &Option<Term>| t.map_or("total", |t| t.name());
        match self {
            Response::ClMean(t) => format!("cl_mean_{}", term(t)),
            Response::CdMean(t) => format!("cd_mean_{}", term(t)),
            Response::LiftOverWeight => "lift_over_weight".to_owned(),
            Response::AeroPowerW => "aero_power_w".to_owned(),
            Response::LiftPerPowerNPerW => "lift_per_power_n_per_w".to_owned(),
            Response::MeanPitchMomentNm => "mean_pitch_moment_nm".to_owned(),
            Response::WakeCapturePeakCl => "wake_capture_peak_cl".to_owned(),
            Response::TrimFeasible => "trim_feasible".to_owned(),
        }
    }

    /// Parses a name (see [`Response::name`]).
    pub fn parse(name: &str) -> Option<Response> {
        Self::all().into_iter().find(|r| r.name() == name)
    }
}

/// Everything a case evaluation produces.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HoverResponses {
    /// Cycle-mean C_L per term (order of [`Term::ALL`]) and, last, the total.
    pub cl_mean: [f64; 5],
    /// Cycle-mean C_D per term and total.
    pub cd_mean: [f64; 5],
    /// Vertical force, N.
    pub vertical_force_n: f64,
    /// Weight, N.
    pub weight_n: f64,
    /// Aerodynamic power, W.
    pub aero_power_w: f64,
    /// Mean pitch moment about the CoM, N m.
    pub mean_pitch_moment_nm: f64,
    /// Peak wake-capture C_L of eq 23.
    pub wake_capture_peak_cl: f64,
    /// The paper's Re of the wings.
    pub reynolds: f64,
    /// True when the wake-capture inputs were clamped to the fitted range.
    pub wake_capture_clamped: bool,
    /// Whether a hover trim exists (`None`: not computed).
    pub trim_feasible: Option<bool>,
}

impl HoverResponses {
    /// The value of one response.
    pub fn get(&self, r: &Response) -> f64 {
        let idx = |t: &Option<Term>| t.map_or(4, |t| t as usize);
        match r {
            Response::ClMean(t) => self.cl_mean[idx(t)],
            Response::CdMean(t) => self.cd_mean[idx(t)],
            Response::LiftOverWeight => self.vertical_force_n / self.weight_n,
            Response::AeroPowerW => self.aero_power_w,
            Response::LiftPerPowerNPerW => self.vertical_force_n / self.aero_power_w,
            Response::MeanPitchMomentNm => self.mean_pitch_moment_nm,
            Response::WakeCapturePeakCl => self.wake_capture_peak_cl,
            Response::TrimFeasible => match self.trim_feasible {
                Some(true) => 1.0,
                Some(false) => 0.0,
                None => f64::NAN,
            },
        }
    }
}

/// Evaluates a vehicle tethered at its hover attitude over one wingbeat of `steps` samples
/// (an actuated vehicle: over one period of its wings' periodic motion, at the simulation's
/// step; see [`flapsim::actuated::periodic`]).
pub fn hover_responses(vehicle: &Vehicle, steps: usize) -> flapsim::Result<HoverResponses> {
    // The per-wing coefficient means and the wake-capture inputs are those of one pair.
    vehicle.require_one_pair("flapstudy's hover responses")?;
    let still = BodyMotion::default();
    let state = FrozenState {
        world_from_body: vehicle.initial_attitude,
        velocity_body_m_s: Vector3::zeros(),
        angular_velocity_body_rad_s: Vector3::zeros(),
    };
    // The wings whose wake-capture inputs count: an actuated wing's are measured on its
    // periodic motion.
    let (loads, samples, wings) = if vehicle.actuation.is_some() {
        let p = flapsim::actuated::periodic::settle(vehicle, &still)?;
        (p.mean, p.samples, p.wings.to_vec())
    } else {
        let samples = (0..steps)
            .map(|k| {
                let phase = k as f64 / steps as f64;
                [0, 1].map(|i| vehicle.wings[i].evaluate(phase, &still))
            })
            .collect::<Vec<_>>();
        (
            mean_loads(vehicle, &state, steps)?,
            samples,
            vehicle.wings.clone(),
        )
    };
    let mut means = [CycleMean::default(); 2];
    let w = 1.0 / samples.len() as f64;
    for forces in &samples {
        for (mean, f) in means.iter_mut().zip(forces) {
            mean.accumulate(f, w);
        }
    }
    let power = flapsim::flight::cycle_power(&vehicle.wings, samples.iter()).aero_w;
    let mut cl_mean = [0.0; 5];
    let mut cd_mean = [0.0; 5];
    for m in &means {
        for (i, t) in m.terms.iter().chain([&m.total]).enumerate() {
            cl_mean[i] += 0.5 * t.c_l;
            cd_mean[i] += 0.5 * t.c_d;
        }
    }
    let mut peak = 0.0;
    let mut clamped = false;
    for wing in &wings {
        if let Some(p) = wing.wake_capture() {
            peak += 0.5 * p.coefficients(p.mu_star).0;
            clamped |= p.flags.any();
        }
    }
    Ok(HoverResponses {
        cl_mean,
        cd_mean,
        vertical_force_n: loads.force_world_n(&vehicle.initial_attitude).z,
        weight_n: vehicle.weight_n(),
        aero_power_w: power,
        mean_pitch_moment_nm: loads.total.moment_nm.y,
        wake_capture_peak_cl: peak,
        // An actuated wing's Re is that of its measured motion (its stroke reference).
        reynolds: wings[0].reynolds(),
        wake_capture_clamped: clamped,
        trim_feasible: None,
    })
}
