//! Induced inflow: the mean downwash a hovering insect draws through its own stroke plane.
//!
//! A hovering animal pushes air down to carry its weight. Rankine-Froude momentum theory over
//! the area the wings sweep (the partial actuator disc of Ellington 1984c, Phil Trans R Soc
//! B 305:115-144: a pair of wings of tip radius R and stroke amplitude Phi sweeps A = Phi R^2)
//! gives the mean induced velocity through that disc:
//!
//! ```text
//! w_i = sqrt(T / (2 rho A))
//! ```
//!
//! for a thrust T (the weight in hover). Blade-element models of hovering insects that
//! account for it (blade-element momentum theory; e.g. Sane 2006, J Exp Biol 209:32, for
//! the rotor-theory induced flow of flapping wings) feed it to each strip as a flow through
//! the stroke plane: the strip sees the air coming down at w_i, which lowers its effective
//! angle of attack and tilts its lift backwards. Without it a quasi-steady model treats every
//! wingbeat as the first one, in still air.
//!
//! MODEL.md section 1 defines the strip velocity relative to "the air" and leaves the air's
//! own motion open; this module is the documented decision for hovering vehicles. It is off
//! by default (the seed paper's robofly is a wing on a fixed mount, and MODEL.md's numbers are
//! for still fluid) and a vehicle switches it on with `[aero] induced_inflow = true`.
//!
//! Per wing: a wing carrying its share T of the thrust sweeps a sector of area Phi R^2 / 2,
//! which gives the same w_i as the pair. The inflow is uniform over the span (the classical
//! actuator disc) and held at its hover value while the body moves (a frozen wake): body
//! motion changes each strip's velocity relative to that wake, not the wake itself.

use serde::{Deserialize, Serialize};

/// The induced inflow of one wing: the thrust it carries, from which the downwash through the
/// area it sweeps follows at its current amplitude ([`downwash_m_s`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct InducedInflow {
    /// This wing's share of the thrust, N (half the weight for a hovering pair).
    pub thrust_n: f64,
}

impl InducedInflow {
    /// The downwash of a wing carrying `self.thrust_n` with stroke amplitude `amplitude_rad`
    /// and tip radius `tip_radius_m` (from the stroke axis) in a fluid of density
    /// `density_kg_m3`, m/s.
    pub fn downwash_m_s(&self, density_kg_m3: f64, amplitude_rad: f64, tip_radius_m: f64) -> f64 {
        downwash_m_s(
            self.thrust_n,
            density_kg_m3,
            0.5 * amplitude_rad * tip_radius_m * tip_radius_m,
        )
    }
}

/// Rankine-Froude momentum theory: the induced velocity through an actuator disc of area
/// `disc_area_m2` carrying `thrust_n` in a fluid of density `density_kg_m3`,
/// sqrt(T / (2 rho A)), m/s. Zero for zero thrust; callers validate the inputs.
pub fn downwash_m_s(thrust_n: f64, density_kg_m3: f64, disc_area_m2: f64) -> f64 {
    (thrust_n / (2.0 * density_kg_m3 * disc_area_m2)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The actuator-disc momentum balance: the mass flow rho A w through the disc, sped up
    /// to 2 w in the far wake, carries the thrust, T = rho A w (2 w).
    #[test]
    fn momentum_balance_holds() {
        let (t, rho, a) = (1.717e-3, 1.204, 3.5e-4);
        let w = downwash_m_s(t, rho, a);
        assert!((rho * a * w * 2.0 * w - t).abs() < 1e-15);
    }

    /// One wing over its sector with half the thrust has the pair's downwash over Phi R^2.
    #[test]
    fn one_wing_equals_the_pair() {
        let (weight, rho, phi, r) = (1.0e-5, 1.204, 2.44, 2.69e-3);
        let pair = downwash_m_s(weight, rho, phi * r * r);
        let one = InducedInflow {
            thrust_n: 0.5 * weight,
        }
        .downwash_m_s(rho, phi, r);
        assert!((pair - one).abs() < 1e-14 * pair);
    }
}
