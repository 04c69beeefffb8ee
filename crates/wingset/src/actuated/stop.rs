//! Hinge stops as a stiff unilateral contact with damping.
//!
//! A wing that pitches passively between mechanical stops (the Purdue hummingbird robot's
//! wing swings freely between stops at +-45 deg from the vertical and strikes them every
//! half stroke) meets a contact, not a spring: no moment while the wing is between the
//! stops, a large one once it presses into a stop, and energy lost at every strike.
//!
//! # The contact law
//! With the pitch measured from the hinge's rest angle, d = theta - theta_r, and the stops
//! at d = +-d_s, the penetration into the stop the wing is nearer to is
//! delta = |d| - d_s (in contact when delta > 0) and its rate delta_dot = sgn(d) theta_dot.
//! The stop's moment on the wing about the pitch axis is
//!
//!   M_stop = -sgn(d) max(0, k_c delta + c delta_dot)   for delta > 0, else 0,
//!
//! a linear spring-dashpot (Kelvin-Voigt) whose total force is clamped at zero: the
//! *clamped Kelvin-Voigt* form (not Hunt-Crossley, whose restitution depends on the impact
//! speed; the reference simulator's stop and a stated restitution do not). The clamp makes
//! the contact unilateral: a stop pushes the wing out and never pulls it in (the unclamped
//! dashpot would, while the wing leaves: the "sticky" artefact).
//!
//! # Restitution and damping
//! Over a strike the contact is far shorter than anything else the wing feels, so the wing
//! is a single inertia m (its effective pitch inertia: the pitch diagonal of the mass matrix
//! with the aerodynamic added inertia, less the part the free stroke takes,
//! m = M_tt - M_tp^2 / M_pp; with a prescribed stroke m = M_tt) striking the spring-dashpot
//! at speed v: m delta_dd = -max(0, k_c delta + c delta_dot), delta(0) = 0,
//! delta_dot(0) = v. With w0 = sqrt(k_c / m) and the damping ratio zeta = c / (2 sqrt(k_c m)),
//! the unclamped solution (zeta < 1, w_d = w0 sqrt(1 - zeta^2)) is
//! delta = (v / w_d) e^(-zeta w0 t) sin(w_d t), and the contact force
//! k_c delta + c delta_dot = m v e^(-zeta w0 t) [w0^2 (1 - 2 zeta^2) / w_d sin(w_d t) +
//! 2 zeta w0 cos(w_d t)] first returns to zero at w_d t* = pi - 2 asin(zeta), where
//! delta_dot = -v e^(-zeta w0 t*) exactly (cos - zeta/sqrt(1 - zeta^2) sin equals -1 there).
//! From then on the clamped force stays zero (delta falls at a constant rate, so
//! k_c delta + c delta_dot < 0): the wing leaves with the speed it had at t*. So the
//! coefficient of restitution of the clamped contact is
//!
//!   e(zeta) = exp(-zeta (pi - 2 asin zeta) / sqrt(1 - zeta^2))     (zeta < 1),
//!   e(1)    = exp(-2),
//!   e(zeta) = exp(-2 zeta acosh(zeta) / sqrt(zeta^2 - 1))          (zeta > 1),
//!
//! independent of v and of k_c (the same result as Schwager and Poeschel 2007, "Coefficient
//! of restitution and linear-dashpot model revisited", Granular Matter 9:465, who end the
//! contact where the force vanishes). It falls monotonically from 1 (zeta = 0) to 0
//! (zeta -> infinity). The textbook relation e = exp(-zeta pi / sqrt(1 - zeta^2)), with
//! e = 0 at zeta >= 1, ends the contact where delta returns to zero and so needs the
//! dashpot to pull; it does not hold for a unilateral contact. [`damping_ratio_for`]
//! inverts e(zeta) by bisection, and c = 2 zeta sqrt(k_c m) is taken with the current m,
//! so a strike returns the stated restitution whatever the wing's effective inertia.
//!
//! A unilateral force law without memory cannot stop a wing dead. While the wing moves out
//! of a stop the force on it points out too, so it leaves with the speed it has when the
//! force first vanishes; e(zeta) ~ 1 / (4 zeta^2) reaches 0 only as zeta -> infinity. A
//! restitution between 0 and [`RESTITUTION_FLOOR`] = 0.01 is therefore realised as 0.01
//! (zeta = 4.81): the wing keeps 1e-4 of its strike energy.
//!
//! # Restitution 0 as a constraint
//! Restitution 0 exactly is the rigid, perfectly inelastic stop that a velocity-level
//! joint-limit constraint imposes (DART's, which the Purdue robot's reference simulator
//! uses), and it is modelled as one, with no contact law at all:
//! - the strike is an impulse at the touch (found within the step as below) that takes the
//!   pitch rate to zero; with the stroke free the same impulse moves the stroke rate by
//!   theta_dot M_pt / M_pp (the first row of M dq_dot = (0, Lambda)), with a prescribed
//!   stroke it does not;
//! - the wing then rests on the stop: its pitch is held there (theta_ddot = 0, the stroke
//!   by its own equation with theta fixed), the stop supplying the moment
//!   M_s = M_tp phi_ddot - Q_theta that holds it, for as long as that moment pushes the wing
//!   out (s M_s <= 0); where it would have to pull, the wing leaves, found within the step
//!   by regula falsi on M_s along the held path and split there.
//! The contact's stiffness and contact steps do not exist for it: a wing on an inelastic
//! stop costs about what a wing without stops does.
//!
//! # Stiffness: a numerical parameter
//! k_c is not a measured property of any robot: a real stop is stiff enough that its
//! penetration is negligible, and k_c only has to make it so. A model file gives it as a
//! contact time t_c, the half period of the undamped contact oscillation of the wing's own
//! pitch inertia B: k_c = B (pi / t_c)^2 (or as a stiffness directly). t_c much shorter
//! than the wingbeat keeps the penetration under a steady moment L, delta = L / k_c,
//! small: for the hummingbird (B = 8.35e-9 kg m^2, t_c = 0.2 ms, k_c = 2.1 N m/rad) a
//! 1e-3 N m aerodynamic moment presses the wing 0.03 deg into its stop.
//!
//! # Integration
//! The contact is stiff: its fastest rate is |lambda| = w0 for zeta <= 1 and
//! w0 (zeta + sqrt(zeta^2 - 1)) for zeta > 1. A sub-step during which the wing is in (or
//! can reach) a stop is cut into n equal contact steps with h |lambda| <= 1/4
//! ([`StopContact::max_step_s`]; the fourth-order Runge-Kutta step then loses < 4e-6 of
//! an undamped contact oscillation's energy per step and resolves an overdamped one), at
//! most [`MAX_CONTACT_STEPS`] per sub-step, else the run stops with an error saying to
//! lengthen the contact time. The contact force is not smooth at two instants, and a
//! Runge-Kutta step across either would lose its order there (measured before these
//! splits: rebound errors of 1-5% of the strike speed, varying with where the steps fell):
//! - at the touch it jumps (the dashpot's c delta_dot): a contact step that starts clear of
//!   the stops is first taken as if there were none; if it ends in a stop, the touch is
//!   found on that contact-free path (a guess on the step's cubic Hermite interpolant,
//!   refined by Newton on the contact-free part's own Runge-Kutta step to round-off), the
//!   wing is put exactly on the stop and the step finished with the contact on;
//! - where the clamp takes over (k_c delta + c delta_dot falls through zero) its slope
//!   jumps: a contact step across that instant is split there (regula falsi, Illinois).
//!
//! So a strike is resolved to the fourth order of the contact step whatever the sub-step:
//! measured, the rebound speed ratio is within 4e-5 of e and changes by < 1e-5 between
//! sub-steps of 1e-4 s and 3e-6 s. Away from the stops a sub-step is one Runge-Kutta step,
//! as without stops.
//!
//! # What the tests check (`tests/hinge_stop.rs`)
//! A wing without aerodynamics thrown at a stop rebounds with the stated e (speed) and e^2
//! (energy), for several e including 0 (realised as the floor); a wing pressed against a
//! stop by a steady load rests there without oscillating; halving the step changes a
//! strike's outcome by less than a stated bound. With restitution 0 (the constraint): the
//! strike leaves the pitch rate 0 and the pitch on the stop to the last bit and keeps the
//! stroke's generalised momentum, at any step; a wing pressed onto the stop rests there
//! with the hinge moment equal to the load.

use serde::{Deserialize, Serialize};

/// Restitutions below this are realised as this (see the module doc: a unilateral force
/// law without memory cannot make e = 0).
pub const RESTITUTION_FLOOR: f64 = 0.01;

/// Most contact steps in one sub-step; a contact that needs more is an error.
pub const MAX_CONTACT_STEPS: usize = 100_000;

/// h |lambda| of a contact step (see the module doc).
pub const CONTACT_STEP_FACTOR: f64 = 0.25;

/// Hinge stops as a clamped spring-dashpot contact, symmetric about the hinge's rest angle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct StopContact {
    /// Angle from the hinge's rest angle where the wing touches a stop, both ways, rad.
    pub angle_rad: f64,
    /// Coefficient of restitution e asked for, in [0, 1].
    pub restitution: f64,
    /// Contact stiffness k_c, N m/rad (a numerical parameter, see the module doc).
    pub stiffness_nm_rad: f64,
    /// Damping ratio zeta realising `restitution` (at least the floor's).
    pub damping_ratio: f64,
}

impl StopContact {
    /// A stop at `angle_rad` from rest with restitution `e` and stiffness `k_c`; restitution
    /// 0 is the perfectly inelastic constraint ([`Self::inelastic`]: `k_c` unused).
    pub fn new(angle_rad: f64, restitution: f64, stiffness_nm_rad: f64) -> Self {
        if restitution == 0.0 {
            return Self::inelastic(angle_rad);
        }
        Self {
            angle_rad,
            restitution,
            stiffness_nm_rad,
            damping_ratio: damping_ratio_for(restitution),
        }
    }

    /// A perfectly inelastic stop at `angle_rad` from rest: a velocity-level constraint,
    /// no contact stiffness (module doc, "Restitution 0 as a constraint"). Its stiffness and
    /// damping ratio read 0 and are not used.
    pub fn inelastic(angle_rad: f64) -> Self {
        Self {
            angle_rad,
            restitution: 0.0,
            stiffness_nm_rad: 0.0,
            damping_ratio: 0.0,
        }
    }

    /// True for the perfectly inelastic constraint (restitution 0).
    pub fn is_inelastic(&self) -> bool {
        self.restitution == 0.0
    }

    /// The stiffness whose undamped contact with pitch inertia `b` lasts `t_c`:
    /// k_c = b (pi / t_c)^2, N m/rad.
    pub fn stiffness_for_contact_time(pitch_inertia_kg_m2: f64, contact_time_s: f64) -> f64 {
        pitch_inertia_kg_m2 * (std::f64::consts::PI / contact_time_s).powi(2)
    }

    /// The restitution a strike actually has: `restitution`, the floor for a compliant
    /// contact below it, 0 for the inelastic constraint.
    pub fn realised_restitution(&self) -> f64 {
        if self.is_inelastic() {
            return 0.0;
        }
        clamped_restitution(self.damping_ratio)
    }

    /// The pitch where the wing touches the stop on side `s` (+1 or -1), rad. The inelastic
    /// stop puts a striking wing exactly here, and [`Self::beyond_rad`] compares with the
    /// same sum, so a wing put there is at the stop to the last bit.
    pub fn stop_theta_rad(&self, rest_rad: f64, s: f64) -> f64 {
        rest_rad + s * self.angle_rad
    }

    /// The side s of the stop the pitch `theta_rad` is nearer to, and how far past that stop
    /// it is, s (theta - stop), rad (0: at it, positive: past it).
    pub fn beyond_rad(&self, rest_rad: f64, theta_rad: f64) -> (f64, f64) {
        let s = (theta_rad - rest_rad).signum();
        (s, s * (theta_rad - self.stop_theta_rad(rest_rad, s)))
    }

    /// Penetration delta = |d| - d_s (positive in contact) and the sign of d, for the
    /// pitch from rest d.
    pub fn penetration(&self, dev_rad: f64) -> (f64, f64) {
        (dev_rad.abs() - self.angle_rad, dev_rad.signum())
    }

    /// The stop's moment on the wing about the pitch axis, N m, for the pitch from rest d,
    /// its rate and the wing's effective pitch inertia m.
    pub fn moment_nm(&self, dev_rad: f64, dev_rate_rad_s: f64, m_eff_kg_m2: f64) -> f64 {
        let (delta, s) = self.penetration(dev_rad);
        // In contact from delta = 0 on: a wing exactly on the stop and moving in meets the
        // dashpot at once (the integrator puts a touching wing there). The inelastic stop
        // is a constraint the integrator keeps, not a force law.
        if delta < 0.0 || self.is_inelastic() {
            return 0.0;
        }
        let c = 2.0 * self.damping_ratio * (self.stiffness_nm_rad * m_eff_kg_m2).sqrt();
        -s * (self.stiffness_nm_rad * delta + c * s * dev_rate_rad_s).max(0.0)
    }

    /// Energy stored in the contact spring, J.
    pub fn potential_j(&self, dev_rad: f64) -> f64 {
        if self.is_inelastic() {
            return 0.0;
        }
        let delta = self.penetration(dev_rad).0.max(0.0);
        0.5 * self.stiffness_nm_rad * delta * delta
    }

    /// The contact's fastest rate |lambda| with effective inertia m, 1/s.
    pub fn fastest_rate_s(&self, m_eff_kg_m2: f64) -> f64 {
        let w0 = (self.stiffness_nm_rad / m_eff_kg_m2).sqrt();
        let z = self.damping_ratio;
        if z <= 1.0 {
            w0
        } else {
            w0 * (z + (z * z - 1.0).sqrt())
        }
    }

    /// The longest contact step, [`CONTACT_STEP_FACTOR`] / |lambda|, s.
    pub fn max_step_s(&self, m_eff_kg_m2: f64) -> f64 {
        CONTACT_STEP_FACTOR / self.fastest_rate_s(m_eff_kg_m2)
    }
}

/// The coefficient of restitution of the clamped linear spring-dashpot with damping ratio
/// `zeta` (module doc).
pub fn clamped_restitution(zeta: f64) -> f64 {
    if zeta <= 0.0 {
        1.0
    } else if (zeta - 1.0).abs() < 1e-9 {
        (-2.0f64).exp()
    } else if zeta < 1.0 {
        (-zeta * (std::f64::consts::PI - 2.0 * zeta.asin()) / (1.0 - zeta * zeta).sqrt()).exp()
    } else {
        (-2.0 * zeta * zeta.acosh() / (zeta * zeta - 1.0).sqrt()).exp()
    }
}

/// The damping ratio whose clamped contact restitutes `e` (e below [`RESTITUTION_FLOOR`]
/// as the floor), by bisection on [`clamped_restitution`] (monotonic) to 1e-14.
pub fn damping_ratio_for(restitution: f64) -> f64 {
    let e = restitution.clamp(RESTITUTION_FLOOR, 1.0);
    if e >= 1.0 {
        return 0.0;
    }
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    while clamped_restitution(hi) > e {
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if clamped_restitution(mid) > e {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo < 1e-14 * hi {
            break;
        }
    }
    0.5 * (lo + hi)
}

/// Where a function that is positive at 0 (`f0`) and not at `span` (`f1`, with what its
/// evaluation carried, `at_end`) falls through zero: regula falsi (Illinois) on `eval(tau)`
/// = (value, what goes with it), at most `iterations` steps, stopping once |value| <=
/// `value_tol` or the bracket is narrower than `span_tol`. Returns the last tau tried and
/// what its evaluation carried.
pub(crate) fn illinois_root<T>(
    span: f64,
    (f0, f1): (f64, f64),
    at_end: T,
    (iterations, value_tol, span_tol): (usize, f64, f64),
    eval: impl Fn(f64) -> (f64, T),
) -> (f64, T) {
    let (mut lo, mut hi, mut plo, mut phi) = (0.0, span, f0, f1);
    let (mut tau, mut carried) = (span, at_end);
    // The side the last point replaced: the other end's value is halved only when the same
    // side is replaced twice running (Illinois; halving every time would slow the secant
    // down on a smooth function, where it converges superlinearly).
    let mut last_low = None;
    for _ in 0..iterations {
        tau = lo + (hi - lo) * plo / (plo - phi);
        let (pa, c) = eval(tau);
        carried = c;
        if pa.abs() <= value_tol || hi - lo <= span_tol {
            break;
        }
        let low = pa > 0.0;
        if low {
            lo = tau;
            plo = pa;
            if last_low == Some(true) {
                phi *= 0.5;
            }
        } else {
            hi = tau;
            phi = pa;
            if last_low == Some(false) {
                plo *= 0.5;
            }
        }
        last_low = Some(low);
    }
    (tau, carried)
}

/// The cubic Hermite interpolant's fraction s in (0, 1] of a step where `g` (value and
/// rate at both ends, the step's length `h`) first reaches zero from below; bisection on
/// the interpolant. `g0 <= 0 < g1` is assumed.
pub(crate) fn hermite_root(g0: f64, g0_dot: f64, g1: f64, g1_dot: f64, h: f64) -> f64 {
    let at = |s: f64| {
        let s2 = s * s;
        let s3 = s2 * s;
        (2.0 * s3 - 3.0 * s2 + 1.0) * g0
            + (s3 - 2.0 * s2 + s) * h * g0_dot
            + (-2.0 * s3 + 3.0 * s2) * g1
            + (s3 - s2) * h * g1_dot
    };
    // The interpolant may touch zero before the end's sign change: scan for the first
    // sign change, then bisect.
    let n = 16;
    let mut lo = 0.0;
    let mut hi = 1.0;
    for i in 1..=n {
        let s = i as f64 / n as f64;
        if at(s) > 0.0 {
            hi = s;
            lo = (i - 1) as f64 / n as f64;
            break;
        }
    }
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if at(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn restitution_is_monotonic_and_continuous_at_critical_damping() {
        let mut prev = 1.0;
        for i in 1..4000 {
            let z = i as f64 * 0.005;
            let e = clamped_restitution(z);
            assert!(e < prev, "zeta {z}: {e} >= {prev}");
            prev = e;
        }
        let below = clamped_restitution(1.0 - 1e-6);
        let above = clamped_restitution(1.0 + 1e-6);
        assert!((below - (-2.0f64).exp()).abs() < 1e-5, "{below}");
        assert!((above - (-2.0f64).exp()).abs() < 1e-5, "{above}");
    }

    #[test]
    fn damping_ratio_inverts_restitution() {
        for e in [0.01, 0.05, 0.1, 0.3, 0.5, 0.8, 0.99] {
            let z = damping_ratio_for(e);
            assert!((clamped_restitution(z) - e).abs() < 1e-12, "e {e}");
        }
        assert_eq!(damping_ratio_for(1.0), 0.0);
        assert_eq!(damping_ratio_for(0.0), damping_ratio_for(RESTITUTION_FLOOR));
        assert!((damping_ratio_for(0.0) - 4.807).abs() < 0.001);
    }

    #[test]
    fn the_release_root_converges_like_a_secant_on_a_smooth_function() {
        // A holding moment that falls smoothly through zero within the step, as the wing's
        // does: the Illinois rule keeps regula falsi superlinear (Dowell & Jarratt 1971,
        // BIT 11:168, order about 1.44), so to 1e-12 of the moment it takes a handful of
        // evaluations; halving the far end at every iteration took 15 per release on the
        // hummingbird (docs/speed.md). Roots: exp(-3 tau) = 0.4 and 1 - tau - tau^3 = 0.
        for (f, root) in [
            (
                (|tau: f64| (-3.0 * tau).exp() - 0.4) as fn(f64) -> f64,
                -(0.4f64).ln() / 3.0,
            ),
            (|tau: f64| 1.0 - tau - tau.powi(3), 0.682_327_803_828_019_3),
        ] {
            let calls = std::cell::Cell::new(0);
            let (tau, value) =
                illinois_root(1.0, (f(0.0), f(1.0)), f(1.0), (60, 1e-12, 1e-14), |t| {
                    calls.set(calls.get() + 1);
                    (f(t), f(t))
                });
            assert!(
                value.abs() <= 1e-12 && (tau - root).abs() < 1e-11,
                "{tau} {value}"
            );
            assert!(calls.get() <= 8, "{} evaluations", calls.get());
        }
    }

    #[test]
    fn the_force_never_pulls() {
        let s = StopContact::new(0.5, 0.0, 1.0);
        for &(d, r) in &[
            (0.6, -1e3),
            (-0.6, 1e3),
            (0.6, 1e3),
            (-0.6, -1e3),
            (0.4, 5.0),
        ] {
            let m = s.moment_nm(d, r, 1e-8);
            assert!(m * d <= 0.0, "d {d} rate {r}: {m}");
        }
    }
}
