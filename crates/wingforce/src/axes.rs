//! Loads about the wing's own joint axes, for wings whose angles are dynamic states (a
//! passive pitch hinge, an actuated stroke) rather than prescribed functions of time.
//!
//! A wing with stroke angle phi and pitch angle theta (deviation prescribed) is a
//! two-degree-of-freedom system. The generalized force conjugate to each angle is the moment
//! about the hinge projected on that angle's rotation axis: Q_phi = M . k_phi and
//! Q_theta = M . k_theta, where the wing's angular velocity relative to the stroke frame is
//! omega = phi_dot k_phi + eta_dot k_eta + theta_dot k_theta ([`WingFrame::new`]). Both axes
//! pass through the hinge, so the moment about the hinge is the right one to project.
//!
//! The added-mass term (eq 7) is linear in the angular accelerations. Written as
//! Q_am = Q_am(phi_ddot = theta_ddot = 0) - A [phi_ddot, theta_ddot], the matrix A is the
//! fluid's added inertia about the two axes. A dynamics integrator must move A to the
//! inertia side of its equations (treating the added mass as a force from the previous
//! step's acceleration is unstable once A is comparable to the wing's own inertia, the
//! classic added-mass instability of partitioned fluid-structure coupling), so
//! [`Wing::added_inertia`] gives it in closed form from the cached span integrals.

use nalgebra::Vector3;

use crate::added_mass::AddedMassForm;
use crate::frame::WingFrame;
use crate::mount::Side;
use crate::terms::TermForce;
use crate::wing::Wing;

/// Generalized moments about the stroke and pitch axes, N m.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct AxisMoments {
    /// Conjugate to the stroke angle phi (drives phi up when positive), N m.
    pub stroke_nm: f64,
    /// Conjugate to the pitch angle theta (drives theta up when positive), N m.
    pub pitch_nm: f64,
}

impl WingFrame {
    /// The stroke axis k_phi (stroke frame): the wing turns about it by +phi.
    pub fn stroke_axis(side: Side) -> Vector3<f64> {
        Vector3::new(0.0, 0.0, -side.sign())
    }

    /// The pitch axis k_theta (stroke frame): the wing turns about it by +theta, which
    /// carries the leading edge from the stroke tangent towards the stroke-plane normal.
    /// From [`WingFrame::new`], k_theta = t x z' with z' = s (t x e_span) (s = +1 left,
    /// -1 right), and t is normal to the span, so k_theta = -s e_span for any deviation.
    pub fn pitch_axis(&self, side: Side) -> Vector3<f64> {
        -side.sign() * self.e_span
    }
}

impl Wing {
    /// A term's moment about the hinge projected on the stroke and pitch axes.
    pub fn axis_moments(&self, frame: &WingFrame, term: &TermForce) -> AxisMoments {
        let m_s = self.body_from_stroke().transpose() * term.moment_hinge_nm;
        AxisMoments {
            stroke_nm: m_s.dot(&WingFrame::stroke_axis(self.mount().side)),
            pitch_nm: m_s.dot(&frame.pitch_axis(self.mount().side)),
        }
    }

    /// The added-mass inertia A about (stroke, pitch), kg m^2, symmetric and positive
    /// semi-definite: the added-mass term's generalized moments fall by A [phi_ddot,
    /// theta_ddot] (see the module doc). Depends on the wing's orientation only.
    ///
    /// Both forms' normal parts hold the strip's mid-chord term n . (alpha x p), alpha's
    /// part from q_ddot_j being q_ddot_j k_j: with a1_j = n . (k_j x e_span) and
    /// a2_j = n . (k_j x e_le), dQ_i / dq_ddot_j = -(pi/4) rho [a1_i a1_j int c^2 r^2 dr +
    /// (a1_i a2_j + a2_i a1_j) int c^2 r x dr + a2_i a2_j int c^2 x^2 dr]. The impulse
    /// form adds the strips' rotational added inertia about the span axis,
    /// (pi/128) rho int c^4 dr (k_i . e_span)(k_j . e_span); its chordwise part holds no
    /// acceleration. Zero with the term off.
    pub fn added_inertia(&self, frame: &WingFrame) -> [[f64; 2]; 2] {
        let am = &self.geometry().added_mass;
        let side = self.mount().side;
        let k = [WingFrame::stroke_axis(side), frame.pitch_axis(side)];
        let a1 = |j: usize| frame.n.dot(&k[j].cross(&frame.e_span));
        let a2 = |j: usize| frame.n.dot(&k[j].cross(&frame.e_le));
        let s = |j: usize| k[j].dot(&frame.e_span);
        let form = self.options().added_mass;
        let scale = if form.is_on() {
            0.25 * std::f64::consts::PI * self.fluid().density_kg_m3
        } else {
            0.0
        };
        let spin = if form == AddedMassForm::Impulse {
            scale / 32.0 * am.c4
        } else {
            0.0
        };
        let mut a = [[0.0; 2]; 2];
        for (i, row) in a.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = scale
                    * (a1(i) * a1(j) * am.c2_r2
                        + (a1(i) * a2(j) + a2(i) * a1(j)) * am.c2_rx
                        + a2(i) * a2(j) * am.c2_x2)
                    + spin * s(i) * s(j);
            }
        }
        a
    }
}
