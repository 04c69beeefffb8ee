//! Drive signals: a periodic voltage per wing.

use std::f64::consts::PI;

use serde::{Deserialize, Serialize};

/// V(t) = bias + amplitude (sin(2 pi f t) + h2 sin(4 pi f t + psi2)): a sine with an
/// optional second harmonic h2 at phase psi2. The second harmonic makes the down- and
/// upstroke unequal in speed (the split-cycle idea of Doman et al. 2010, here as its
/// first Fourier correction), which a controller uses for yaw and drag asymmetry.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Drive {
    /// Drive frequency f, Hz.
    pub freq_hz: f64,
    /// Bias (DC offset), V.
    pub bias_v: f64,
    /// Amplitude of the fundamental, V.
    pub amplitude_v: f64,
    /// Second-harmonic amplitude as a fraction of the fundamental.
    pub second_harmonic: f64,
    /// Phase of the second harmonic, rad.
    pub second_harmonic_phase_rad: f64,
}

impl Drive {
    /// A pure sine.
    pub fn sine(freq_hz: f64, amplitude_v: f64) -> Self {
        Self {
            freq_hz,
            bias_v: 0.0,
            amplitude_v,
            second_harmonic: 0.0,
            second_harmonic_phase_rad: 0.0,
        }
    }

    /// Voltage at time `t_s`, V.
    #[inline]
    pub fn voltage_v(&self, t_s: f64) -> f64 {
        let w = 2.0 * PI * self.freq_hz * t_s;
        let mut v = w.sin();
        if self.second_harmonic != 0.0 {
            v += self.second_harmonic * (2.0 * w + self.second_harmonic_phase_rad).sin();
        }
        self.bias_v + self.amplitude_v * v
    }

    /// An upper bound of |V(t)|: |bias| + |amplitude| (1 + |h2|), V.
    pub fn peak_bound_v(&self) -> f64 {
        self.bias_v.abs() + self.amplitude_v.abs() * (1.0 + self.second_harmonic.abs())
    }
}
