//! A wake that answers: dynamic inflow of a flapping pair (issue #38, MODEL.md 4.5).
//!
//! The frozen wake of the parent module holds the induced velocity at a trim value. Here it
//! follows what makes it: the pair's **current** aerodynamic loads and the body's velocity
//! through the air, with dynamics of its own. The model is Pitt & Peters' dynamic inflow
//! (Pitt & Peters 1981, Vertica 5:21-34; in the form of Peters & HaQuang 1988, J Am Helicopter
//! Soc 33(4):64-68), adapted to the partial actuator disc of a flapping pair (Ellington 1984c,
//! Phil Trans R Soc B 305:115-144): the pair sweeps A = Phi R^2 (stroke amplitude Phi, tip
//! radius R), taken as a disc of the same area, radius R_e = sqrt(A / pi). That adaptation is
//! this project's (an estimate): a flapping pair loads its sector in pulses, twice a wingbeat,
//! where a rotor loads its disc steadily.
//!
//! Three states per pair: the mean induced velocity w0 and its first-harmonic gradients over
//! the disc, so that the air comes down through the stroke plane at
//!
//! ```text
//! w(x, y) = w0 + w_x x / R_e + w_y y / R_e
//! ```
//!
//! with (x, y) a point of the stroke plane relative to the disc's centre (x forward, y to
//! the left, stroke frame). Positive w_x: more downwash at the front.
//!
//! **Steady state (Pitt-Peters' L matrix, dimensional).** With T the pair's thrust (its
//! aerodynamic force along the stroke-plane normal), M_t and M_n the first moments of that
//! load along and across the free stream's direction in the plane (M_t = integral of
//! (e_t . r) dT, forward of the centre positive), V_t the free stream along the disc and V_n
//! through it (in the sense of the induced flow, positive in a climb), the wake skew angle
//! chi = atan(V_t / (V_n + w0)), X = tan(chi / 2), the total flow V_T = sqrt(V_t^2 +
//! (V_n + w0)^2) and the mass-flow parameter V = (V_t^2 + (V_n + w0)(V_n + 2 w0)) / V_T:
//!
//! ```text
//! w0  = T / (2 rho A V_T) - (15 pi / 64) X M_t / (rho A R_e V)
//! w_t = -(15 pi / 64) X T / (rho A V_T) + 4 cos chi / (1 + cos chi) M_t / (rho A R_e V)
//! w_n = 4 / (1 + cos chi) M_n / (rho A R_e V)
//! ```
//!
//! With no moments the first line is Glauert's momentum balance (parent module), and the
//! gradient is Pitt-Peters' steady skewed-wake result, w_t = -(15 pi / 32) tan(chi / 2) w0:
//! more downwash behind the centre in forward flight, which moves lift forward (the pitching
//! moment with forward speed that a uniform frozen inflow cannot make). In hover (chi = 0) a
//! loading moment gives a gradient w_t = M_t / (rho A R_e w_h), the local momentum balance of
//! a linearly loaded disc (the perturbation pressure 4 rho w_h dw over the disc's second
//! moment A R_e^2 / 4).
//!
//! **Dynamics.** Peters & HaQuang's apparent masses: m0 = (8 / 3) rho R_e^3 for the mean
//! (the apparent mass of a disc accelerating normal to itself, 8/(3 pi) rho A R_e) and
//! m1 = (16 / 45) rho R_e^4 for each gradient (16/(45 pi) rho A R_e^2). The mean follows the
//! momentum balance with the disc's inertia,
//!
//! ```text
//! m0 dw0/dt = T - 2 rho A V_T w0 - (15 pi / 32) X (V_T / V) M_t / R_e
//! ```
//!
//! whose small perturbations in hover decay with the time constant
//! tau0 = m0 / (2 rho A V) = 2 R_e / (3 pi w_h) (V = 2 w_h). Each gradient relaxes to its
//! steady value with its own time constant tau = m1 L_ii / (rho A R_e V), L_ii the
//! diagonal entry above (2 in hover: tau = 16 R_e / (45 pi w_h)). This keeps the diagonal of
//! Pitt-Peters' L M and drops its off-diagonal rate coupling (the skew's coupling enters the
//! steady values only): with the full coupling the open-loop inflow dynamics have a growing
//! mode at skew angles where the (w0, w_t) block of L is indefinite (above about 78 deg, an
//! insect in fast forward flight), which a quasi-steady blade-element loading does not damp.
//! So this is a diagonal-lag form of Pitt-Peters, stated as such.
//!
//! **Stepping.** [`DynamicInflow::advance`] holds the loads over a step and integrates the
//! mean by the exponential rule on its linearisation (exact for the linear gradients; stable
//! at any step), so a host can step coarser than the inflow's time constant (a fly's is about
//! a tenth of its wingbeat).
//!
//! **Range.** Momentum theory describes a climb, hover, forward flight and a descent slower
//! than about 2 w_h; in faster axial descent the flow through the disc reverses (the vortex-
//! ring and windmill-brake states, Johnson 1980, *Helicopter Theory*, section 4.1.2), where
//! [`DynamicInflow::advance`] stops with an error instead of extrapolating.

use nalgebra::{Vector2, Vector3};

/// Pitt-Peters' skew coupling coefficient 15 pi / 64.
const SKEW_COUPLING: f64 = 15.0 * std::f64::consts::PI / 64.0;

/// The disc a flapping pair sweeps, and the fluid it pushes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InflowDisc {
    /// Fluid density, kg/m^3.
    pub density_kg_m3: f64,
    /// Swept area A = Phi R^2 of the pair (half that for a lone wing), m^2.
    pub area_m2: f64,
}

impl InflowDisc {
    /// The disc of a pair of wings of tip radius `tip_radius_m` sweeping `amplitude_rad`
    /// peak to peak (`wings` = 2; 1 for a wing alone, its sector).
    pub fn swept(density_kg_m3: f64, amplitude_rad: f64, tip_radius_m: f64, wings: usize) -> Self {
        Self {
            density_kg_m3,
            area_m2: 0.5 * wings as f64 * amplitude_rad * tip_radius_m * tip_radius_m,
        }
    }

    /// The radius of the circular disc of the same area, m.
    pub fn radius_m(&self) -> f64 {
        (self.area_m2 / std::f64::consts::PI).sqrt()
    }

    /// The apparent mass of the mean state, (8/3) rho R_e^3, kg (Peters & HaQuang 1988).
    pub fn mean_apparent_mass_kg(&self) -> f64 {
        8.0 / 3.0 * self.density_kg_m3 * self.radius_m().powi(3)
    }

    /// The apparent mass of each gradient state, (16/45) rho R_e^4, kg m.
    pub fn gradient_apparent_mass_kg_m(&self) -> f64 {
        16.0 / 45.0 * self.density_kg_m3 * self.radius_m().powi(4)
    }

    /// Hover induced velocity for `thrust_n`, sqrt(T / (2 rho A)), m/s.
    pub fn hover_m_s(&self, thrust_n: f64) -> f64 {
        (thrust_n.max(0.0) / (2.0 * self.density_kg_m3 * self.area_m2)).sqrt()
    }

    /// The mean state's time constant for small perturbations about hover at `thrust_n`,
    /// m0 / (2 rho A V) with V = 2 w_h: 2 R_e / (3 pi w_h), s.
    pub fn hover_time_constant_s(&self, thrust_n: f64) -> f64 {
        2.0 * self.radius_m() / (3.0 * std::f64::consts::PI * self.hover_m_s(thrust_n))
    }
}

/// What drives the inflow over a step: the pair's loads and the disc's motion through the
/// air, in the disc's stroke frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct InflowForcing {
    /// The pair's aerodynamic force along the stroke-plane normal, N.
    pub thrust_n: f64,
    /// The first moments of that force over the plane about the disc's centre, (x, y),
    /// N m: the integral of x dT and of y dT (x forward, y left).
    pub load_moment_nm: Vector2<f64>,
    /// The free stream through the disc: the air's velocity relative to the disc, negated
    /// (the disc's velocity through the air), stroke frame, m/s. Its z component along the
    /// normal is V_n with the induced flow's sign: a climb (the disc moving up) is positive.
    pub disc_velocity_m_s: Vector3<f64>,
}

/// The three inflow states of a pair (see the module documentation), m/s.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct InflowState {
    /// Mean induced velocity w0 through the disc (down), m/s.
    pub mean_m_s: f64,
    /// The gradients (w_x, w_y): the extra downwash at the disc's front and left edge
    /// (x = R_e, y = R_e), m/s.
    pub gradient_m_s: Vector2<f64>,
}

impl InflowState {
    /// The state as an array (w0, w_x, w_y), m/s.
    pub fn to_array(&self) -> [f64; 3] {
        [self.mean_m_s, self.gradient_m_s.x, self.gradient_m_s.y]
    }

    /// The state from (w0, w_x, w_y), m/s.
    pub fn from_array(a: [f64; 3]) -> Self {
        Self {
            mean_m_s: a[0],
            gradient_m_s: Vector2::new(a[1], a[2]),
        }
    }

    /// The downwash at a point `xy_m` of the plane relative to the disc's centre, m/s.
    pub fn at(&self, xy_m: &Vector2<f64>, radius_m: f64) -> f64 {
        self.mean_m_s + self.gradient_m_s.dot(xy_m) / radius_m
    }
}

/// Why an inflow step was refused.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum InflowError {
    /// The flow through the disc reversed: an axial descent faster than momentum theory
    /// describes (the vortex-ring state). Holds V_n and w0, m/s.
    VortexRing {
        /// The disc's velocity along the normal (climb positive), m/s.
        through_m_s: f64,
        /// The mean induced velocity, m/s.
        mean_m_s: f64,
    },
    /// A load or velocity that is not finite.
    NotFinite,
}

impl std::fmt::Display for InflowError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::VortexRing {
                through_m_s,
                mean_m_s,
            } => write!(
                f,
                "the disc descends through its own wake (climb rate {through_m_s:.3} m/s along the stroke-plane normal against a mean induced velocity of {mean_m_s:.3} m/s): the vortex-ring state, outside the momentum theory of the dynamic inflow (allowed: a descent slower than the induced velocity, or a forward speed above it)"
            ),
            Self::NotFinite => write!(
                f,
                "the inflow's loads or the disc's velocity are not finite"
            ),
        }
    }
}

impl std::error::Error for InflowError {}

/// The flow quantities of Pitt-Peters at a mean inflow: (V_T, V, tan(chi/2), cos chi).
fn flow(state_mean_m_s: f64, forcing: &InflowForcing) -> (f64, f64, f64, f64) {
    let v = forcing.disc_velocity_m_s;
    let vt = (v.x * v.x + v.y * v.y).sqrt();
    let through = v.z + state_mean_m_s;
    let vtot = (vt * vt + through * through).sqrt();
    let mass_flow = if vtot > 0.0 {
        (vt * vt + through * (v.z + 2.0 * state_mean_m_s)) / vtot
    } else {
        0.0
    };
    // chi = atan(V_t / through): tan(chi/2) = V_t / (V_T + through), cos chi = through / V_T.
    let (x, cos_chi) = if vtot > 0.0 {
        (vt / (vtot + through), through / vtot)
    } else {
        (0.0, 1.0)
    };
    (vtot, mass_flow, x, cos_chi)
}

/// A pair's dynamic inflow: its disc and states (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DynamicInflow {
    /// The disc the pair sweeps.
    pub disc: InflowDisc,
    /// The states.
    pub state: InflowState,
}

/// The steady values the states relax to, with the gradients' time constants, at a mean
/// inflow `w0` (the gradients' forcing; the mean's own balance is [`DynamicInflow::advance`]'s).
struct Targets {
    /// (15 pi / 32) X (V_T / V) M_t / R_e: the skew's coupling of the moment into the mean
    /// state's balance, N.
    mean_coupling_n: f64,
    /// The free stream's direction in the plane, e_t, and the one across it, e_n.
    axes: [Vector2<f64>; 2],
    /// The steady gradients along e_t and e_n, m/s.
    gradient_m_s: [f64; 2],
    /// Their time constants, s.
    time_constant_s: [f64; 2],
}

impl DynamicInflow {
    /// A pair's inflow starting from the steady hover inflow of `thrust_n`.
    pub fn hover(disc: InflowDisc, thrust_n: f64) -> Self {
        Self {
            disc,
            state: InflowState {
                mean_m_s: disc.hover_m_s(thrust_n),
                gradient_m_s: Vector2::zeros(),
            },
        }
    }

    fn targets(&self, forcing: &InflowForcing, mean_m_s: f64) -> Targets {
        let d = &self.disc;
        let (rho, a, r) = (d.density_kg_m3, d.area_m2, d.radius_m());
        let (vtot, mass_flow, x, cos_chi) = flow(mean_m_s, forcing);
        let v = forcing.disc_velocity_m_s;
        let vt = (v.x * v.x + v.y * v.y).sqrt();
        // The free stream's direction in the plane (any in hover: the gradients' diagonal
        // entries are equal there and the skew terms vanish).
        let e_t = if vt > 0.0 {
            Vector2::new(v.x / vt, v.y / vt)
        } else {
            Vector2::x()
        };
        let e_n = Vector2::new(-e_t.y, e_t.x);
        let m_t = forcing.load_moment_nm.dot(&e_t);
        let m_n = forcing.load_moment_nm.dot(&e_n);
        let l_tt = 4.0 * cos_chi / (1.0 + cos_chi);
        let l_nn = 4.0 / (1.0 + cos_chi);
        let k = rho * a * r * mass_flow;
        let (g_t, g_n) = if k > 0.0 {
            (
                -SKEW_COUPLING * x * forcing.thrust_n / (rho * a * vtot) + l_tt * m_t / k,
                l_nn * m_n / k,
            )
        } else {
            (0.0, 0.0)
        };
        let m1 = d.gradient_apparent_mass_kg_m();
        let tau = |l: f64| if k > 0.0 { m1 * l / k } else { 0.0 };
        let mean_coupling_n = if mass_flow > 0.0 {
            2.0 * SKEW_COUPLING * x * (vtot / mass_flow) * m_t / r
        } else {
            0.0
        };
        Targets {
            mean_coupling_n,
            axes: [e_t, e_n],
            gradient_m_s: [g_t, g_n],
            time_constant_s: [tau(l_tt), tau(l_nn)],
        }
    }

    /// Advances the states by `dt_s` with `forcing` held over the step (see the module
    /// documentation). An error leaves the states as they were.
    pub fn advance(&mut self, forcing: &InflowForcing, dt_s: f64) -> Result<(), InflowError> {
        let finite = forcing.thrust_n.is_finite()
            && forcing.load_moment_nm.iter().all(|x| x.is_finite())
            && forcing.disc_velocity_m_s.iter().all(|x| x.is_finite());
        if !finite {
            return Err(InflowError::NotFinite);
        }
        if self.disc.area_m2.is_nan() || self.disc.area_m2 <= 0.0 {
            // A pair that sweeps nothing (no stroke) moves no air.
            self.state = InflowState::default();
            return Ok(());
        }
        let w0 = self.state.mean_m_s;
        let v = forcing.disc_velocity_m_s;
        // The flow through the disc against the induced velocity (a descent into the own
        // wake; a negative thrust's upwash is the mirror image and allowed).
        if (v.z + w0) * w0 < 0.0 && (v.x * v.x + v.y * v.y) < w0 * w0 {
            return Err(InflowError::VortexRing {
                through_m_s: v.z,
                mean_m_s: w0,
            });
        }
        let d = &self.disc;
        let rho_a = d.density_kg_m3 * d.area_m2;
        let (vtot, mass_flow, _, _) = flow(w0, forcing);
        let m0 = d.mean_apparent_mass_kg();
        // m0 dw0/dt = f(w0); linearised about w0, f' = -2 rho A V, and stepped exactly (the
        // exponential Rosenbrock-Euler rule: second order). The steady values the gradients
        // relax to, and the skew's coupling into the mean, depend on w0: taken at the step's
        // midpoint, w0 + dw0 / 2, from a first pass at w0 (so the step stays second order).
        let rate = 2.0 * rho_a * mass_flow / m0;
        let mean_step = |coupling_n: f64| {
            let f = forcing.thrust_n - coupling_n - 2.0 * rho_a * vtot * w0;
            if rate * dt_s > 1e-12 {
                f / m0 * (1.0 - (-rate * dt_s).exp()) / rate
            } else {
                f / m0 * dt_s
            }
        };
        let predicted = mean_step(self.targets(forcing, w0).mean_coupling_n);
        let targets = self.targets(forcing, w0 + 0.5 * predicted);
        let dw0 = mean_step(targets.mean_coupling_n);
        let g = self.state.gradient_m_s;
        let relax = |x: f64, target: f64, tau: f64| {
            if tau > 0.0 {
                target + (x - target) * (-dt_s / tau).exp()
            } else {
                target
            }
        };
        // Each gradient along its own axis (along and across the free stream).
        let mut gradient_m_s = Vector2::zeros();
        for k in 0..2 {
            let e = targets.axes[k];
            gradient_m_s += e * relax(
                g.dot(&e),
                targets.gradient_m_s[k],
                targets.time_constant_s[k],
            );
        }
        self.state = InflowState {
            mean_m_s: w0 + dw0,
            gradient_m_s,
        };
        Ok(())
    }

    /// The states' time constants for small perturbations at the states now, with the disc
    /// moving as `forcing` says (its loads do not enter), s: the mean's m0 / (2 rho A V) and
    /// the gradients' m1 L_ii / (rho A R_e V) along and across the free stream (module
    /// documentation; V the mass-flow parameter). Infinite where no air flows through the
    /// disc.
    pub fn time_constants_s(&self, forcing: &InflowForcing) -> [f64; 3] {
        let d = &self.disc;
        let w0 = self.state.mean_m_s;
        let (_, mass_flow, _, _) = flow(w0, forcing);
        if !(mass_flow > 0.0 && d.area_m2 > 0.0) {
            return [f64::INFINITY; 3];
        }
        let mean = d.mean_apparent_mass_kg() / (2.0 * d.density_kg_m3 * d.area_m2 * mass_flow);
        let [t, n] = self.targets(forcing, w0).time_constant_s;
        [mean, t, n]
    }

    /// The steady state under `forcing` (the loads held), by stepping to convergence: what
    /// the states settle to. For tests and for starting a run at a flight condition.
    pub fn settle(&mut self, forcing: &InflowForcing) -> Result<(), InflowError> {
        let tau = self
            .disc
            .hover_time_constant_s(forcing.thrust_n.abs().max(1e-30));
        let dt = if tau.is_finite() && tau > 0.0 {
            tau
        } else {
            1e-3
        };
        for _ in 0..10_000 {
            let before = self.state;
            self.advance(forcing, dt)?;
            let change = (self.state.mean_m_s - before.mean_m_s).abs()
                + (self.state.gradient_m_s - before.gradient_m_s).abs().sum();
            if change <= 1e-15 * (1.0 + self.state.mean_m_s.abs()) {
                break;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fly_disc() -> InflowDisc {
        InflowDisc::swept(1.204, 2.44, 2.69e-3, 2)
    }

    /// Steady hover: the mean is Rankine-Froude's sqrt(T / (2 rho A)), so T = 2 rho A w^2.
    #[test]
    fn hover_balances_momentum() {
        let d = fly_disc();
        let t = 9.5e-6;
        let mut i = DynamicInflow::hover(d, 0.5 * t);
        i.settle(&InflowForcing {
            thrust_n: t,
            ..Default::default()
        })
        .unwrap();
        let w = i.state.mean_m_s;
        assert!((2.0 * 1.204 * d.area_m2 * w * w / t - 1.0).abs() < 1e-12);
        assert_eq!(i.state.gradient_m_s, Vector2::zeros());
    }
}
