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
//! actuator disc) and held at its trim value while the body moves (a frozen wake): body
//! motion changes each strip's velocity relative to that wake, not the wake itself.
//!
//! In forward flight and climb the disc moves through the air. Glauert's momentum theory
//! (Glauert 1926, ARC R&M 1111; the form rotorcraft texts use, e.g. Johnson, *Helicopter
//! Theory*, 1980, section 4.1, and the one Ellington 1984c and Dudley & Ellington 1990b, J Exp
//! Biol 148:53, apply to insects in forward flight) puts the mass flow through the disc at
//! rho A U' with U' the resultant of the free stream and the induced velocity:
//!
//! ```text
//! w_i = w_h^2 / sqrt(V_t^2 + (V_n + w_i)^2),    w_h = sqrt(T / (2 rho A))
//! ```
//!
//! with V_t the free stream along the disc and V_n its component through the disc in the
//! sense of the induced flow (positive in a climb along the stroke-plane normal). Hover
//! (V_t = V_n = 0) gives w_i = w_h; an axial climb gives w_i = -V_n/2 + sqrt(V_n^2/4 + w_h^2);
//! fast forward flight gives w_i -> w_h^2 / V_t. The induced velocity stays along the
//! stroke-plane normal. [`InducedInflow::flight_velocity_body_m_s`] holds the body's
//! velocity through the air at the flight condition (body frame); like the hover downwash,
//! it is frozen there while the body moves about it. Descent faster than about 2 w_h (the
//! vortex-ring and windmill states) is outside momentum theory; [`glauert_downwash_m_s`]
//! returns the root its bisection finds there and callers refuse such conditions.

pub mod dynamic;
pub mod interference;

use serde::{Deserialize, Serialize};

pub use dynamic::{DynamicInflow, InflowDisc, InflowError, InflowForcing, InflowState};
pub use interference::{PlacedDisc, WakeShare, wake_share};

/// Which induced flow a vehicle's wings meet (`[aero] inflow` in a model file; MODEL.md 4.5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum InflowModel {
    /// Still air: no induced flow (the robofly reproduction, and the wings' own default).
    #[default]
    Off,
    /// The frozen wake: momentum theory's downwash for the weight, held at the flight
    /// condition while the body moves (this module).
    Frozen,
    /// The wake that answers: each pair's induced flow follows its own current loads and the
    /// body's velocity, with Pitt-Peters dynamics ([`dynamic`]).
    Dynamic,
}

impl InflowModel {
    /// The model of a wing's induced inflow option (`AeroOptions::induced_inflow`): none is
    /// `Off`, a dynamic one `Dynamic`, else `Frozen`.
    pub fn of(induced_inflow: Option<&InducedInflow>) -> Self {
        match induced_inflow {
            None => Self::Off,
            Some(i) if i.dynamic => Self::Dynamic,
            Some(_) => Self::Frozen,
        }
    }

    /// The name a model file and every report use.
    pub fn name(self) -> &'static str {
        match self {
            Self::Off => "off",
            Self::Frozen => "frozen",
            Self::Dynamic => "dynamic",
        }
    }

    /// What the model is, in words for reports.
    pub fn describe(self) -> &'static str {
        match self {
            Self::Off => "off (still air)",
            Self::Frozen => {
                "frozen (the hover downwash of the weight, held at the flight condition)"
            }
            Self::Dynamic => {
                "dynamic (each pair's wake follows its loads and the body: Pitt-Peters, wingforce::inflow::dynamic)"
            }
        }
    }

    /// The model named `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.name() == name)
    }

    /// Every model, for error messages.
    pub const ALL: [Self; 3] = [Self::Off, Self::Frozen, Self::Dynamic];
}

impl std::fmt::Display for InflowModel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The induced inflow of one wing: the thrust it carries, from which the downwash through the
/// area it sweeps follows at its current amplitude ([`downwash_m_s`]), and the flight
/// condition the wake was shed at ([`glauert_downwash_m_s`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct InducedInflow {
    /// This wing's share of the thrust, N (half the weight for a hovering pair).
    pub thrust_n: f64,
    /// The body's velocity through the far air at the flight condition, body frame, m/s
    /// (zero in hover).
    #[serde(default)]
    pub flight_velocity_body_m_s: [f64; 3],
    /// The wake answers ([`InflowModel::Dynamic`]): the wing set that holds this wing runs
    /// its pair's [`DynamicInflow`], and this inflow is its start (and the added mass's
    /// reference air); otherwise it is frozen.
    #[serde(default)]
    pub dynamic: bool,
}

impl InducedInflow {
    /// The inflow of a hovering wing carrying `thrust_n`.
    pub fn hover(thrust_n: f64) -> Self {
        Self {
            thrust_n,
            flight_velocity_body_m_s: [0.0; 3],
            dynamic: false,
        }
    }

    /// The downwash of a wing carrying `self.thrust_n` through the area it sweeps (stroke
    /// amplitude `amplitude_rad`, tip radius `tip_radius_m`), in a fluid of density
    /// `density_kg_m3`, with the stroke-plane normal `normal_body` (unit, body frame) moving
    /// at [`InducedInflow::flight_velocity_body_m_s`] (Glauert; hover when that is zero), m/s.
    pub fn flight_downwash_m_s(
        &self,
        density_kg_m3: f64,
        amplitude_rad: f64,
        tip_radius_m: f64,
        normal_body: &nalgebra::Vector3<f64>,
    ) -> f64 {
        let hover = self.downwash_m_s(density_kg_m3, amplitude_rad, tip_radius_m);
        let v = nalgebra::Vector3::from(self.flight_velocity_body_m_s);
        if v == nalgebra::Vector3::zeros() {
            return hover;
        }
        let v_n = v.dot(normal_body);
        let v_t = (v - v_n * normal_body).norm();
        glauert_downwash_m_s(hover, v_t, v_n)
    }

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

/// Glauert's induced velocity through a disc whose hover induced velocity is `hover_m_s`
/// (w_h), with the free stream `along_m_s` (V_t) along the disc and `through_m_s` (V_n)
/// through it in the sense of the induced flow: the root of w sqrt(V_t^2 + (V_n + w)^2) = w_h^2
/// (module documentation), by Newton's method safeguarded by bisection on [0, w_h + 2|V_n|].
pub fn glauert_downwash_m_s(hover_m_s: f64, along_m_s: f64, through_m_s: f64) -> f64 {
    let wh2 = hover_m_s * hover_m_s;
    if wh2 == 0.0 {
        return 0.0;
    }
    let vt2 = along_m_s * along_m_s;
    // g(w) = w^2 (V_t^2 + (V_n + w)^2) - w_h^4: negative at 0, and at w_h + 2|V_n| both
    // factors are at least w_h^2, so a root lies between.
    let g = |w: f64| w * w * (vt2 + (through_m_s + w).powi(2)) - wh2 * wh2;
    let dg = |w: f64| 2.0 * w * (vt2 + (through_m_s + w).powi(2)) + 2.0 * w * w * (through_m_s + w);
    let (mut lo, mut hi) = (0.0, hover_m_s + 2.0 * through_m_s.abs());
    let mut w = if through_m_s >= 0.0 {
        // Climb and level flight: the axial-climb or high-speed estimate, whichever is smaller.
        (wh2 / (vt2.sqrt() + 1e-300))
            .min(-0.5 * through_m_s + (0.25 * through_m_s * through_m_s + wh2).sqrt())
    } else {
        hover_m_s
    };
    for _ in 0..100 {
        let gw = g(w);
        if gw == 0.0 {
            return w;
        }
        if gw < 0.0 {
            lo = w;
        } else {
            hi = w;
        }
        let d = dg(w);
        let mut next = if d > 0.0 { w - gw / d } else { f64::NAN };
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        if (next - w).abs() <= 1e-15 * hover_m_s {
            return next;
        }
        w = next;
    }
    w
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
        let one = InducedInflow::hover(0.5 * weight).downwash_m_s(rho, phi, r);
        assert!((pair - one).abs() < 1e-14 * pair);
    }

    /// Glauert's limits (Johnson 1980, section 4.1): hover w_h; axial climb at V_c,
    /// w = -V_c/2 + sqrt(V_c^2/4 + w_h^2); fast edgewise flight w -> w_h^2 / V; and in between
    /// the root satisfies the momentum balance w sqrt(V_t^2 + (V_n + w)^2) = w_h^2.
    #[test]
    fn glauert_limits_and_balance() {
        let wh = 0.9;
        assert!((glauert_downwash_m_s(wh, 0.0, 0.0) - wh).abs() < 1e-14);
        for vc in [0.1, 0.5, 2.0, 10.0] {
            let exact = -0.5 * vc + (0.25 * vc * vc + wh * wh).sqrt();
            let w = glauert_downwash_m_s(wh, 0.0, vc);
            assert!((w - exact).abs() < 1e-12 * wh, "climb {vc}: {w} vs {exact}");
        }
        let fast = glauert_downwash_m_s(wh, 100.0, 0.0);
        assert!((fast * 100.0 / (wh * wh) - 1.0).abs() < 1e-4, "{fast}");
        for (vt, vn) in [(0.3, 0.0), (1.0, 0.2), (2.5, -0.3), (0.5, -1.0)] {
            let w = glauert_downwash_m_s(wh, vt, vn);
            let balance = w * (vt * vt + (vn + w) * (vn + w)).sqrt();
            assert!((balance - wh * wh).abs() < 1e-12, "({vt}, {vn}): {balance}");
        }
    }
}
