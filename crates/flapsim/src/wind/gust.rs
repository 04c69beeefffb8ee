//! The discrete "1 - cosine" gust.
//!
//! v(tau) = (A / 2) (1 - cos(2 pi tau / T)) along a fixed world direction for
//! 0 <= tau <= T, zero otherwise: it rises from zero to its peak A at tau = T/2 and returns
//! to zero at T, with continuous velocity and acceleration-free ends. This is the full
//! 1 - cosine of the certification gust (CS-25.341 / 14 CFR 25.341: U = (U_ds/2)
//! (1 - cos(pi s / H)) for 0 <= s <= 2H, gust gradient H = half the length); MIL-F-8785C
//! section 3.7.4.2 uses its first half, v = (v_m/2)(1 - cos(pi x / d_m)), which then holds
//! v_m (a ramp to a new steady wind, which this module does not model).
//! The same single bump, U = (u_de/2)(1 - cos(2 pi x / S)) over a gust length S, is SHARPy's
//! `one_minus_cos` gust (<https://ic-sharpy.readthedocs.io/en/latest/includes/generators/gustvelocityfield/one_minus_cos.html>).
//!
//! A gust given by its length d (m) is frozen in the air and convected past the vehicle at
//! the wind's convection speed U_c, so it lasts T = d / U_c; tau counts from the time its
//! front reaches the reference point (the vehicle's start) and a point displaced by dx along
//! the convection direction sees it dx / U_c later (see [`super`]).

use nalgebra::Vector3;

/// A 1 - cosine gust (validated: see [`super::WindSpec`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gust {
    /// Peak speed A, m/s (>= 0).
    pub amplitude_m_s: f64,
    /// Direction the air moves, world, unit vector.
    pub direction_world: Vector3<f64>,
    /// When the gust's front reaches the reference point, s.
    pub start_s: f64,
    /// Duration T at the reference point, s (> 0).
    pub duration_s: f64,
}

impl Gust {
    /// The gust's speed tau seconds after its front passed (zero outside [0, T]).
    pub fn speed_m_s(&self, tau_s: f64) -> f64 {
        if !(0.0..=self.duration_s).contains(&tau_s) {
            return 0.0;
        }
        0.5 * self.amplitude_m_s * (1.0 - (std::f64::consts::TAU * tau_s / self.duration_s).cos())
    }

    /// The gust's velocity, world, tau seconds after its front passed.
    pub fn velocity_world_m_s(&self, tau_s: f64) -> Vector3<f64> {
        self.speed_m_s(tau_s) * self.direction_world
    }

    /// When the gust has passed the reference point, s.
    pub fn end_s(&self) -> f64 {
        self.start_s + self.duration_s
    }
}
