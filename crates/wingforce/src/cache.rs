//! A wing's precomputed numbers: everything the per-step evaluation needs that depends only
//! on Re, the planform, the kinematics parameters, the mount or the fluid, laid out for the
//! hot loop (filled by the wing when it is built or changed).

use nalgebra::{Matrix3, Vector3};

use crate::coefficients::WakeCaptureParams;
use crate::terms::TermForce;

/// Strip data laid out for the hot loop.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct StripK {
    pub(crate) r_m: f64,
    pub(crate) half_rho_area: f64,
    pub(crate) x_cp_m: f64,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Cache {
    pub(crate) strips: Vec<StripK>,
    pub(crate) reynolds: f64,
    pub(crate) v_ref_m_s: f64,
    /// 0.5 rho V_ref^2 S, N.
    pub(crate) q_ref_s_n: f64,
    /// Lee: 2 K_l f, C_d0 f, 2 K_d f (f = f_AR f_Ro or 1).
    pub(crate) kl2: f64,
    pub(crate) cd0: f64,
    pub(crate) kd2: f64,
    pub(crate) wake: Option<WakeCaptureParams>,
    pub(crate) body_from_stroke: Matrix3<f64>,
    pub(crate) stroke_from_body: Matrix3<f64>,
    /// The hinge position in the stroke frame, m.
    pub(crate) hinge_s: Vector3<f64>,
    /// -(pi/4) rho.
    pub(crate) am_k: f64,
    /// The wing's velocity relative to the induced inflow's air, stroke frame, m/s: the air
    /// comes down through the stroke plane at w_i, so the wing moves up through it.
    pub(crate) inflow_s: Vector3<f64>,
    /// The air the translational term's strips meet at the hinge: `inflow_s`, or the dynamic
    /// inflow's field there ([`crate::Wing::set_inflow_field`]), stroke frame, m/s.
    pub(crate) translational_inflow_s: Vector3<f64>,
    /// The dynamic inflow's gradient over the stroke plane, (d w / d x, d w / d y) in the
    /// stroke frame, 1/s (zero for a frozen or no inflow).
    pub(crate) inflow_gradient_per_s: nalgebra::Vector2<f64>,
}

impl Cache {
    /// Rotates a term from the stroke frame into the body frame.
    #[inline]
    pub(crate) fn to_body(&self, t: &mut TermForce) {
        t.force_n = self.body_from_stroke * t.force_n;
        t.moment_hinge_nm = self.body_from_stroke * t.moment_hinge_nm;
    }
}

impl Cache {
    pub(crate) fn empty() -> Self {
        Self {
            strips: Vec::new(),
            reynolds: 0.0,
            v_ref_m_s: 0.0,
            q_ref_s_n: 0.0,
            kl2: 0.0,
            cd0: 0.0,
            kd2: 0.0,
            wake: None,
            body_from_stroke: Matrix3::identity(),
            stroke_from_body: Matrix3::identity(),
            hinge_s: Vector3::zeros(),
            am_k: 0.0,
            inflow_s: Vector3::zeros(),
            translational_inflow_s: Vector3::zeros(),
            inflow_gradient_per_s: nalgebra::Vector2::zeros(),
        }
    }
}
