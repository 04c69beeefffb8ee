//! The right-hand side of the wing's equations of motion (stated in [`super`]): the
//! inertia matrix with the added inertia, the accelerations under loads held over a
//! sub-step, the angles a state stands for, and the mechanical energy.

use wingforce::WingAngles;

use super::memo::{self, SolveKey, Solved};
use super::model::{Hinge, Stroke};
use super::wing::{DynamicWing, WingState};

/// Held over a sub-step: aerodynamic generalized forces without the added mass's
/// acceleration part, and the added inertia.
#[derive(Debug, Clone, Copy, Default)]
pub(in crate::actuated) struct Held {
    pub(in crate::actuated) q: [f64; 2],
    pub(in crate::actuated) added: [[f64; 2]; 2],
    /// Integrate as if the hinge had no stops (the contact-free part of a step that
    /// touches one).
    pub(in crate::actuated) free: bool,
    /// Hold the pitch on the inelastic stop it rests on whatever the holding moment's sign
    /// (the path along which the integrator looks for the wing's release).
    pub(in crate::actuated) locked: bool,
}

impl Held {
    /// The loads a fraction `s` of the way from `self` to `to` (generalized forces and added
    /// inertia linear in `s`; the flags are `self`'s): the loads of a segment whose two ends
    /// were evaluated, at a time within it (`actuated::contact`).
    pub(in crate::actuated) fn lerp(&self, to: &Held, s: f64) -> Held {
        // Exactly `self`'s at s = 0 and `to`'s at s = 1.
        let l = |a: f64, b: f64| (1.0 - s) * a + s * b;
        Held {
            q: [l(self.q[0], to.q[0]), l(self.q[1], to.q[1])],
            added: [
                [
                    l(self.added[0][0], to.added[0][0]),
                    l(self.added[0][1], to.added[0][1]),
                ],
                [
                    l(self.added[1][0], to.added[1][0]),
                    l(self.added[1][1], to.added[1][1]),
                ],
            ],
            ..*self
        }
    }
}

impl DynamicWing {
    /// Mechanical energy (kinetic plus the springs', the stops' contact springs included),
    /// J: conserved without aerodynamics, damping, drive and stop strikes (or with
    /// perfectly elastic ones).
    pub fn energy_j(&self) -> f64 {
        let s = &self.state;
        let m = self.mass_matrix(s.theta_rad, &[[0.0; 2]; 2]);
        let v = [s.phi_dot_rad_s, s.theta_dot_rad_s];
        let ke =
            0.5 * (m[0][0] * v[0] * v[0] + 2.0 * m[0][1] * v[0] * v[1] + m[1][1] * v[1] * v[1]);
        let k = self.model.stroke_stiffness_nm_rad();
        let phi0 = self.stroke_rest();
        let dth = s.theta_rad - self.model.hinge.rest_rad;
        let stop = self.model.hinge.contact.map_or(0.0, |c| c.potential_j(dth));
        ke + 0.5 * k * (s.phi_rad - phi0).powi(2)
            + 0.5 * self.model.hinge.stiffness_nm_rad * dth * dth
            + stop
    }

    fn stroke_rest(&self) -> f64 {
        match &self.model.stroke {
            Stroke::Driven { rest_rad, .. } => *rest_rad,
            Stroke::Prescribed(_) => 0.0,
        }
    }

    /// Inertia matrix about (phi, theta) plus the added inertia.
    pub(in crate::actuated) fn mass_matrix(
        &self,
        theta: f64,
        added: &[[f64; 2]; 2],
    ) -> [[f64; 2]; 2] {
        let i = &self.model.inertia;
        let (st, ct) = memo::sin_cos_pitch(theta);
        let c = i.product_kg_m2();
        let b = i.pitch_inertia_kg_m2;
        [
            [
                self.model.stroke_inertia_kg_m2() + b * ct * ct + added[0][0],
                -c * st + added[0][1],
            ],
            [-c * st + added[1][0], b + added[1][1]],
        ]
    }

    /// The effective pitch inertia a stop strike meets, kg m^2: M_tt - M_tp^2 / M_pp with
    /// the stroke free (driven), M_tt with the stroke prescribed.
    pub(in crate::actuated) fn pitch_inertia_effective(&self, m: &[[f64; 2]; 2]) -> f64 {
        match &self.model.stroke {
            Stroke::Driven { .. } => m[1][1] - m[0][1] * m[1][0] / m[0][0],
            Stroke::Prescribed(_) => m[1][1],
        }
    }

    /// The side s = +-1 of the inelastic stop (restitution 0, [`crate::actuated::stop`])
    /// that the state rests on: exactly at the stop angle or past it, with no pitch rate.
    /// `None` without such a stop, away from it, moving, or integrating `free`.
    pub(in crate::actuated) fn on_inelastic_stop(&self, y: &[f64; 4], held: &Held) -> Option<f64> {
        let c = self.model.hinge.contact?;
        if !c.is_inelastic() || held.free || y[3] != 0.0 {
            return None;
        }
        let (s, beyond) = c.beyond_rad(self.model.hinge.rest_rad, y[1]);
        (beyond >= 0.0).then_some(s)
    }

    /// How hard an inelastic stop holds a wing resting on it: -s M_s, N m (positive: the
    /// stop pushes the wing out, so it stays), with M_s the moment that keeps
    /// theta_ddot = 0; `None` when the wing does not rest on one ([`Self::on_inelastic_stop`]).
    pub(in crate::actuated) fn stop_hold_nm(
        &self,
        t: f64,
        y: &[f64; 4],
        held: &Held,
    ) -> Option<f64> {
        let s = self.on_inelastic_stop(y, held)?;
        Some(-s * self.solve_memo(t, y, held).2)
    }

    /// Accelerations at time t for y = (phi, theta, phi_dot, theta_dot), from the memo of
    /// the states a step comes back to (module `memo`).
    pub(in crate::actuated) fn accelerations(&self, t: f64, y: &[f64; 4], held: &Held) -> [f64; 2] {
        self.accelerations_from(self.solve_memo(t, y, held), y, held)
    }

    /// [`Self::accelerations`] without the memo: a Runge-Kutta step's later stages, at
    /// states no other call asks for.
    pub(in crate::actuated) fn stage_accelerations(
        &self,
        t: f64,
        y: &[f64; 4],
        held: &Held,
    ) -> [f64; 2] {
        self.accelerations_from(self.solve(t, y, held), y, held)
    }

    fn accelerations_from(&self, solved: Solved, y: &[f64; 4], held: &Held) -> [f64; 2] {
        let (free, phi_ddot_held, m_s) = solved;
        match self.on_inelastic_stop(y, held) {
            Some(s) if held.locked || s * m_s <= 0.0 => [phi_ddot_held, 0.0],
            _ => free,
        }
    }

    /// [`Self::solve`] through the memo: the last two distinct arguments and their results.
    fn solve_memo(&self, t: f64, y: &[f64; 4], held: &Held) -> Solved {
        let free_matters = self.model.hinge.contact.is_some_and(|c| !c.is_inelastic());
        let key = SolveKey::new(
            self.memo,
            t,
            y,
            (held.q, held.added),
            held.free && free_matters,
        );
        memo::solved(key, || self.solve(t, y, held))
    }

    /// The drive's voltage at `t_s`, V: the sub-step's (`volts`, one sine each for its
    /// start, middle and end, where the equations are solved over and over), else computed.
    pub(in crate::actuated) fn voltage_v(&self, t_s: f64) -> f64 {
        let key = t_s.to_bits();
        match self.volts.iter().find(|(t, _)| *t == key) {
            Some((_, v)) => *v,
            None => self.drive.voltage_v(t_s),
        }
    }

    /// Takes the drive's voltage at the start, middle and end of the sub-step from `t0_s`
    /// of `h_s` (the times as the integrators form them: the middle as t0 + h/2 and, on
    /// inelastic stops, as t0 + (end - t0)/2, `actuated::contact`).
    pub(in crate::actuated) fn take_volts(&mut self, t0_s: f64, h_s: f64) {
        let end = t0_s + h_s;
        let times = [t0_s, t0_s + 0.5 * h_s, t0_s + 0.5 * (end - t0_s), end];
        self.volts = times.map(|t| (t.to_bits(), self.drive.voltage_v(t)));
    }

    /// The accelerations of the free equations, the stroke acceleration with the pitch held
    /// (theta_ddot = 0) and the pitch moment M_s that holding takes, N m.
    fn solve(&self, t: f64, y: &[f64; 4], held: &Held) -> Solved {
        let [phi, theta, mut pd, td] = *y;
        let prescribed = match &self.model.stroke {
            Stroke::Prescribed(k) => {
                let a = k.angles(t * k.freq_hz);
                pd = a.phi_dot;
                Some(a)
            }
            Stroke::Driven { .. } => None,
        };
        let i = &self.model.inertia;
        let (st, ct) = memo::sin_cos_pitch(theta);
        let b = i.pitch_inertia_kg_m2;
        let c = i.product_kg_m2();
        let m = self.mass_matrix(theta, &held.added);
        let m_eff = self.pitch_inertia_effective(&m);
        let hinge = if held.free {
            Hinge {
                contact: None,
                ..self.model.hinge
            }
        } else {
            self.model.hinge
        };
        let q_theta = held.q[1] + hinge.moment_nm(theta, td, m_eff) - b * st * ct * pd * pd;
        match &self.model.stroke {
            Stroke::Driven {
                actuator,
                flexure_nm_rad,
                damping_nm_s_rad,
                rest_rad,
            } => {
                let r = actuator.reflected();
                let q_phi = held.q[0] + r.torque_per_volt_nm_v * self.voltage_v(t)
                    - (r.stiffness_nm_rad + flexure_nm_rad) * (phi - rest_rad)
                    - (r.damping_nm_s_rad + damping_nm_s_rad) * pd
                    + 2.0 * b * st * ct * pd * td
                    + c * ct * td * td;
                let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
                let held_phi = q_phi / m[0][0];
                (
                    [
                        (m[1][1] * q_phi - m[0][1] * q_theta) / det,
                        (m[0][0] * q_theta - m[1][0] * q_phi) / det,
                    ],
                    held_phi,
                    m[1][0] * held_phi - q_theta,
                )
            }
            Stroke::Prescribed(_) => {
                let a = prescribed.unwrap_or_default();
                (
                    [a.phi_ddot, (q_theta - m[1][0] * a.phi_ddot) / m[1][1]],
                    a.phi_ddot,
                    m[1][0] * a.phi_ddot - q_theta,
                )
            }
        }
    }

    /// Angles at the current time with the given accelerations (prescribed stroke: from the
    /// kinematics).
    pub(super) fn angles(&self, acc: [f64; 2]) -> WingAngles {
        self.angles_at(&self.state, self.t_s, acc)
    }

    /// Angles of `state` at time `t` with the given accelerations.
    pub(super) fn angles_at(&self, s: &WingState, t: f64, acc: [f64; 2]) -> WingAngles {
        let mut a = WingAngles {
            phi: s.phi_rad,
            theta: s.theta_rad,
            phi_dot: s.phi_dot_rad_s,
            theta_dot: s.theta_dot_rad_s,
            phi_ddot: acc[0],
            theta_ddot: acc[1],
            ..WingAngles::default()
        };
        if let Stroke::Prescribed(k) = &self.model.stroke {
            let p = k.angles(t * k.freq_hz);
            a.phi = p.phi;
            a.phi_dot = p.phi_dot;
            a.phi_ddot = p.phi_ddot;
        }
        a
    }
}
