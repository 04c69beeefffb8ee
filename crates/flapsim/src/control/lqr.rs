//! The LQR design's parts: the weights as largest acceptable excursions (Bryson's rule),
//! the discrete-time algebraic Riccati equation that gives the gain, and the zero-order-hold
//! discretisation of the averaged model over one wingbeat.

use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::linear::N_CONTROLS;
use crate::model::Vehicle;

/// LQR weights as the largest acceptable excursions (Bryson's rule: weight = 1/max^2).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LqrWeights {
    /// Position error, in body lengths.
    pub position_body_lengths: f64,
    /// Velocity error, body lengths per wingbeat.
    pub velocity_body_lengths_per_wingbeat: f64,
    /// Attitude error, rad.
    pub attitude_rad: f64,
    /// Angular rate, rad per wingbeat.
    pub rate_rad_per_wingbeat: f64,
    /// Control excursion, rad (kinematic controls).
    pub control_rad: f64,
    /// Control excursion of a drive voltage channel, V (actuated vehicles).
    #[serde(default = "default_control_v")]
    pub control_v: f64,
    /// Control excursion of the second-harmonic difference (actuated vehicles).
    #[serde(default = "default_control_second_harmonic")]
    pub control_second_harmonic: f64,
    /// Time scale of the position-error integral, s (its weight is 1/(position x this)^2).
    pub integral_time_s: f64,
}

impl Default for LqrWeights {
    fn default() -> Self {
        Self {
            position_body_lengths: 0.1,
            velocity_body_lengths_per_wingbeat: 0.05,
            attitude_rad: 2f64.to_radians(),
            rate_rad_per_wingbeat: 1f64.to_radians(),
            control_rad: 10f64.to_radians(),
            control_v: default_control_v(),
            control_second_harmonic: default_control_second_harmonic(),
            integral_time_s: 0.1,
        }
    }
}

fn default_control_v() -> f64 {
    10.0
}

fn default_control_second_harmonic() -> f64 {
    0.1
}

impl LqrWeights {
    /// The largest acceptable excursion of each of `vehicle`'s control channels.
    pub fn control_max(&self, vehicle: &Vehicle) -> [f64; N_CONTROLS] {
        if vehicle.drive_controlled() {
            [
                self.control_v,
                self.control_v,
                self.control_v,
                self.control_second_harmonic,
            ]
        } else {
            [self.control_rad; N_CONTROLS]
        }
    }
}

/// Discrete-time algebraic Riccati equation by fixed-point iteration; returns the gain K of
/// u = -K x for x+ = A x + B u with costs Q, R.
pub fn dlqr(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    q: &DMatrix<f64>,
    r: &DMatrix<f64>,
) -> Result<DMatrix<f64>> {
    let mut p = q.clone();
    for i in 0..100_000 {
        if i % 64 == 0 {
            crate::cancel::check()?;
        }
        let btp = b.transpose() * &p;
        let s = r + &btp * b;
        let Some(s_inv) = s.try_inverse() else {
            return Err(Error::Analysis("LQR: singular R + B'PB".into()));
        };
        let k = &s_inv * &btp * a;
        let next = q + a.transpose() * &p * a - a.transpose() * &p * b * &k;
        let diff = (&next - &p).amax();
        p = next;
        if diff <= 1e-12 * p.amax() {
            return Ok(k);
        }
    }
    Err(Error::Analysis("LQR: the Riccati iteration did not converge (the hover may not be stabilisable with these controls)".into()))
}

/// Zero-order-hold discretisation over `t_s`: (A_d, B_d) = (exp(A t), int_0^t exp(A s) ds B).
pub fn discretize(a: &DMatrix<f64>, b: &DMatrix<f64>, t_s: f64) -> (DMatrix<f64>, DMatrix<f64>) {
    let (n, m) = (a.nrows(), b.ncols());
    let mut aug = DMatrix::zeros(n + m, n + m);
    aug.view_mut((0, 0), (n, n)).copy_from(&(a * t_s));
    aug.view_mut((0, n), (n, m)).copy_from(&(b * t_s));
    let e = aug.exp();
    (
        e.view((0, 0), (n, n)).into_owned(),
        e.view((0, n), (n, m)).into_owned(),
    )
}
