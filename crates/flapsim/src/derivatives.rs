//! The longitudinal stability derivatives of the averaged model, dimensional and in the
//! non-dimensional form of Sun & Xiong (2005, J. Exp. Biol. 208:447), so that a reader can
//! set them beside published CFD derivatives.
//!
//! From the averaged model's longitudinal matrix (states u = vx, w = vz, the pitch angle and
//! q, world axes at hover: x forward, z up; body y left, so q > 0 pitches the nose down):
//! X_u = m d(u_dot)/du, X_w, X_q likewise; Z_u, Z_w, Z_q from w_dot; M_u = I_yy d(q_dot)/du,
//! M_w, M_q (I_yy alone: the vehicles' inertia couples y to nothing). References: the mean
//! flapping speed at the radius of gyration U = 2 Phi n r_2 (Phi the peak-to-peak stroke
//! amplitude, n the wingbeat frequency, r_2 = R_g), the time 1/n, the force
//! 0.5 rho U^2 S_t (S_t both wings' area) and the moment 0.5 rho U^2 S_t c (c the mean
//! chord). So X_u+ = X_u U / F, X_q+ = X_q n / F, M_u+ = M_u U / (F c), M_q+ = M_q n / (F c).

use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

use crate::model::Vehicle;

/// The reference quantities of the non-dimensional derivatives.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Reference {
    /// Peak-to-peak stroke amplitude Phi, rad.
    pub stroke_amplitude_rad: f64,
    /// Wingbeat frequency n, Hz.
    pub freq_hz: f64,
    /// Radius of gyration r_2 = R_g, m.
    pub r2_m: f64,
    /// U = 2 Phi n r_2, m/s.
    pub speed_m_s: f64,
    /// Reference time 1/n, s.
    pub time_s: f64,
    /// 0.5 rho U^2 S_t, N.
    pub force_n: f64,
    /// Mean chord c, m.
    pub chord_m: f64,
}

/// One derivative.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Derivative {
    /// `X_u`, `Z_w`, `M_q`, ...
    pub name: String,
    /// Its value in SI units.
    pub value: f64,
    /// The unit of `value`.
    pub unit: String,
    /// The non-dimensional value.
    pub nondimensional: f64,
}

/// The reference quantities of `vehicle` flapping with the peak-to-peak stroke amplitude
/// `stroke_amplitude_rad`.
pub fn reference(vehicle: &Vehicle, stroke_amplitude_rad: f64) -> Reference {
    let g = vehicle.wings[0].geometry();
    let n = vehicle.freq_hz();
    let u = 2.0 * stroke_amplitude_rad * n * g.r_gyration_m;
    let rho = vehicle.wings[0].fluid().density_kg_m3;
    let s_t: f64 = vehicle.wings.iter().map(|w| w.geometry().area_m2).sum();
    Reference {
        stroke_amplitude_rad,
        freq_hz: n,
        r2_m: g.r_gyration_m,
        speed_m_s: u,
        time_s: 1.0 / n,
        force_n: 0.5 * rho * u * u * s_t,
        chord_m: g.mean_chord_m,
    }
}

/// The nine longitudinal derivatives: (name, row and column of the longitudinal matrix
/// (u, w, pitch, q), true for a moment (times I_yy, else the mass), dimensional unit).
pub const LONGITUDINAL: [(&str, usize, usize, bool, &str); 9] = [
    ("X_u", 0, 0, false, "N s/m"),
    ("X_w", 0, 1, false, "N s/m"),
    ("X_q", 0, 3, false, "N s/rad"),
    ("Z_u", 1, 0, false, "N s/m"),
    ("Z_w", 1, 1, false, "N s/m"),
    ("Z_q", 1, 3, false, "N s/rad"),
    ("M_u", 3, 0, true, "N s"),
    ("M_w", 3, 1, true, "N s"),
    ("M_q", 3, 3, true, "N m s/rad"),
];

impl Reference {
    /// The factor that takes a dimensional derivative (SI) to its non-dimensional value:
    /// U / F for a force per velocity, n / F per pitch rate, and a further 1 / c for a
    /// moment.
    pub fn scale(&self, column: usize, moment: bool) -> f64 {
        let per_state = if column == 3 {
            self.freq_hz
        } else {
            self.speed_m_s
        };
        let per_load = if moment {
            self.force_n * self.chord_m
        } else {
            self.force_n
        };
        per_state / per_load
    }
}

/// The longitudinal derivatives of `vehicle` (at trim, stroke amplitude `stroke_amplitude_rad`
/// as it flaps there) from the averaged longitudinal matrix `a_lon` (u, w, pitch, q).
pub fn longitudinal(
    vehicle: &Vehicle,
    a_lon: &DMatrix<f64>,
    stroke_amplitude_rad: f64,
) -> (Reference, Vec<Derivative>) {
    let reference = reference(vehicle, stroke_amplitude_rad);
    let derivatives = LONGITUDINAL
        .iter()
        .map(|&(name, i, j, moment, unit)| {
            let k = if moment {
                vehicle.inertia_kg_m2[(1, 1)]
            } else {
                vehicle.mass_kg
            };
            let value = k * a_lon[(i, j)];
            Derivative {
                name: name.to_owned(),
                value,
                unit: unit.to_owned(),
                nondimensional: value * reference.scale(j, moment),
            }
        })
        .collect();
    (reference, derivatives)
}
