//! The cycle-averaged vehicle as a nonlinear ODE and its linearisation about a state.
//!
//! State (12): world position (3), world velocity (3), attitude error delta (3, a rotation
//! vector in the body frame: world_from_body = q_ref * exp(delta)), body angular velocity (3).
//! Controls (4), as offsets on a reference: for prescribed kinematics the mean stroke angle
//! (pitch), amplitude (height), left-minus-right amplitude (roll) and left-minus-right pitch
//! bias (yaw), in radians; for an actuated vehicle the drive's bias (pitch), amplitude
//! (height) and left-minus-right amplitude (roll), in volts, and the left-minus-right second
//! harmonic (yaw) ([`Vehicle::control_channels`]). Loads are cycle averages at the frozen
//! state (the averaged model of Sun and Xiong 2005) plus the body's parasite drag
//! ([`crate::flight`]); an actuated vehicle's wings are run into their periodic motion at
//! that state ([`crate::actuated::periodic`]). The velocity is through still air, so a
//! flight condition's trim state has its velocity in `x[3..6]`.

use nalgebra::{DMatrix, DVector, UnitQuaternion, Vector3};

use std::sync::OnceLock;

use crate::averaged::{FrozenState, StepTable, mean_loads, mean_loads_tabled};
use crate::error::Result;
use crate::model::{Controls, Vehicle};

/// Number of states.
pub const N_STATES: usize = 12;
/// Number of control inputs.
pub const N_CONTROLS: usize = 4;
/// State names (with units).
pub const STATE_NAMES: [&str; N_STATES] = [
    "x_m",
    "y_m",
    "z_m",
    "vx_m_s",
    "vy_m_s",
    "vz_m_s",
    "roll_err_rad",
    "pitch_err_rad",
    "yaw_err_rad",
    "p_rad_s",
    "q_rad_s",
    "r_rad_s",
];
/// Control names of a vehicle with prescribed kinematics (an actuated vehicle's are
/// [`crate::model::DRIVE_CHANNELS`]; [`Vehicle::control_channels`] picks).
pub const CONTROL_NAMES: [&str; N_CONTROLS] = crate::model::KINEMATIC_CHANNELS;

/// Indices of the longitudinal states: vx, vz, pitch error, pitch rate.
pub const LONGITUDINAL: [usize; 4] = [3, 5, 7, 10];
/// Indices of the lateral states: vy, roll error, yaw error, roll rate, yaw rate.
pub const LATERAL: [usize; 5] = [4, 6, 8, 9, 11];

/// The averaged model about a reference attitude and controls.
#[derive(Debug, Clone)]
pub struct AveragedModel {
    vehicle: Vehicle,
    q_ref: UnitQuaternion<f64>,
    base_controls: Controls,
    samples: usize,
    /// The vehicle's kinematic step loads, shared by every state at the base controls (the
    /// Jacobian's 24 state columns), tabled when first needed.
    table: OnceLock<Option<StepTable>>,
}

impl AveragedModel {
    /// A model of `vehicle` about attitude `q_ref` and `controls`, averaging `samples` phases.
    pub fn new(
        vehicle: &Vehicle,
        q_ref: UnitQuaternion<f64>,
        controls: Controls,
        samples: usize,
    ) -> Self {
        Self {
            vehicle: vehicle.clone(),
            q_ref,
            base_controls: controls,
            samples,
            table: OnceLock::new(),
        }
    }

    /// The reference attitude.
    pub fn q_ref(&self) -> UnitQuaternion<f64> {
        self.q_ref
    }

    /// dx/dt for state `x` and control offsets `u` (on [`Vehicle::control_channels`]).
    pub fn rhs(&self, x: &DVector<f64>, u: &[f64]) -> Result<DVector<f64>> {
        let mut v = self.vehicle.clone();
        let moved = u.iter().any(|&x| x != 0.0) || v.controls != self.base_controls;
        if moved {
            let c = v.controls_with(&self.base_controls, u);
            v.apply_controls(&c)?;
        }
        let delta = Vector3::new(x[6], x[7], x[8]);
        let q = self.q_ref * UnitQuaternion::from_scaled_axis(delta);
        let vel_w = Vector3::new(x[3], x[4], x[5]);
        let w_b = Vector3::new(x[9], x[10], x[11]);
        let state = FrozenState {
            world_from_body: q,
            velocity_body_m_s: q.inverse() * vel_w,
            angular_velocity_body_rad_s: w_b,
        };
        let table = match moved {
            false => self
                .table
                .get_or_init(|| StepTable::of(&self.vehicle, self.samples))
                .as_ref(),
            true => None,
        };
        let loads = match table {
            Some(t) => mean_loads_tabled(&v, &state, t)?,
            None => mean_loads(&v, &state, self.samples)?,
        };
        let acc = (q * loads.total.force_n + v.body_drag_world_n(&vel_w)) / v.mass_kg
            - Vector3::new(0.0, 0.0, v.gravity_m_s2);
        let i = &v.inertia_kg_m2;
        let i_inv = i.try_inverse().unwrap_or_else(nalgebra::Matrix3::zeros);
        let wdot = i_inv * (loads.total.moment_nm - w_b.cross(&(i * w_b)));
        // Attitude error rate: d/dt exp(delta) = exp(delta) [omega] to first order in delta.
        let ddot = w_b + 0.5 * delta.cross(&w_b);
        Ok(DVector::from_iterator(
            N_STATES,
            vel_w
                .iter()
                .chain(acc.iter())
                .chain(ddot.iter())
                .chain(wdot.iter())
                .copied(),
        ))
    }

    /// Jacobians (A, B) at state `x0` and zero control offset by central differences
    /// (control steps 1e-5 of each channel's scale, [`Vehicle::control_scales`]).
    pub fn linearize(&self, x0: &DVector<f64>) -> Result<(DMatrix<f64>, DMatrix<f64>)> {
        let v = &self.vehicle;
        let l = v.length_m;
        let speed = v.wings[0].v_ref_m_s();
        // Perturbation sizes scaled to the vehicle (small, but well above round-off).
        let hx = [
            l * 1e-3,
            l * 1e-3,
            l * 1e-3,
            speed * 1e-4,
            speed * 1e-4,
            speed * 1e-4,
            1e-5,
            1e-5,
            1e-5,
            1e-3,
            1e-3,
            1e-3,
        ];
        // Each column is an independent pair of averaged loads: in parallel, bit for bit.
        let a_cols = crate::cancel::par_in_order(N_STATES, |j| {
            let mut xp = x0.clone();
            let mut xm = x0.clone();
            xp[j] += hx[j];
            xm[j] -= hx[j];
            Ok((self.rhs(&xp, &[0.0; 4])? - self.rhs(&xm, &[0.0; 4])?) / (2.0 * hx[j]))
        })?;
        let scales = v.control_scales();
        let b_cols = crate::cancel::par_in_order(N_CONTROLS, |j| {
            let h = 1e-5 * scales[j];
            let mut up = [0.0; 4];
            let mut um = [0.0; 4];
            up[j] = h;
            um[j] = -h;
            Ok((self.rhs(x0, &up)? - self.rhs(x0, &um)?) / (2.0 * h))
        })?;
        let a = DMatrix::from_columns(&a_cols);
        let b = DMatrix::from_columns(&b_cols);
        Ok((a, b))
    }
}

/// A sub-matrix of `a` on the given state indices.
pub fn submatrix(a: &DMatrix<f64>, idx: &[usize]) -> DMatrix<f64> {
    DMatrix::from_fn(idx.len(), idx.len(), |i, j| a[(idx[i], idx[j])])
}
