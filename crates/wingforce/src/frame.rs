//! A wing's orientation and rigid-body rates in its stroke-plane frame (MODEL.md section 1):
//! the stroke angle phi about the stroke-plane normal, then the deviation eta, then the pitch
//! theta about the span.

use nalgebra::Vector3;

use crate::kinematics::WingAngles;
use crate::mount::Side;
use crate::terms::TermForce;

/// The wing's unit vectors and rigid-body rates in its stroke-plane frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WingFrame {
    /// Span axis (root to tip).
    pub e_span: Vector3<f64>,
    /// Forward stroke tangent (horizontal; direction of increasing phi).
    pub t: Vector3<f64>,
    /// Leading-edge chord direction.
    pub e_le: Vector3<f64>,
    /// Wing normal, n = d e_le / d theta; (e_span, e_le, n) is right-handed for the right
    /// wing and left-handed for the left (mirror images), so use explicit cross products.
    pub n: Vector3<f64>,
    /// Angular velocity of the wing relative to the stroke frame, rad/s.
    pub omega: Vector3<f64>,
    /// Angular acceleration relative to the stroke frame, rad/s^2.
    pub alpha: Vector3<f64>,
}

impl WingFrame {
    /// The frame for given angles. The wing orientation is a rotation by phi about the
    /// stroke-plane normal, then eta about the stroke tangent, then theta about the span.
    pub fn new(a: &WingAngles, side: Side) -> Self {
        Self::new_with(a, side, f64::sin_cos)
    }

    /// [`Self::new`] with the angles' sines and cosines from `sin_cos` (bit for bit `new`
    /// where `sin_cos` is `f64::sin_cos`'s values: a caller that meets the same angles again
    /// may keep them).
    #[inline(always)]
    pub fn new_with(a: &WingAngles, side: Side, sin_cos: impl Fn(f64) -> (f64, f64)) -> Self {
        let s = side.sign();
        let (sf, cf) = sin_cos(a.phi);
        let (se, ce) = if a.eta == 0.0 {
            (0.0, 1.0)
        } else {
            sin_cos(a.eta)
        };
        let (st, ct) = sin_cos(a.theta);
        let z = Vector3::z();
        let h = Vector3::new(sf, s * cf, 0.0);
        let t = Vector3::new(cf, -s * sf, 0.0);
        let e_span = ce * h + se * z;
        let zp = -se * h + ce * z;
        let e_le = ct * t + st * zp;
        let n = -st * t + ct * zp;
        let k_phi = Vector3::new(0.0, 0.0, -s); // h x t
        let k_eta = e_span.cross(&zp);
        let k_theta = t.cross(&zp);
        let w_phi = a.phi_dot * k_phi;
        let w12 = w_phi + a.eta_dot * k_eta;
        let omega = w12 + a.theta_dot * k_theta;
        let alpha = a.phi_ddot * k_phi
            + a.eta_ddot * k_eta
            + a.theta_ddot * k_theta
            + a.eta_dot * w_phi.cross(&k_eta)
            + a.theta_dot * w12.cross(&k_theta);
        Self {
            e_span,
            t,
            e_le,
            n,
            omega,
            alpha,
        }
    }

    /// The mirror image in the body's x-z plane (left wing to right wing with the same
    /// angles): polar vectors flip y, the angular velocity and acceleration (pseudovectors)
    /// flip x and z.
    pub fn mirrored(&self) -> Self {
        let m = |v: &Vector3<f64>| Vector3::new(v.x, -v.y, v.z);
        let p = |v: &Vector3<f64>| Vector3::new(-v.x, v.y, -v.z);
        Self {
            e_span: m(&self.e_span),
            t: m(&self.t),
            e_le: m(&self.e_le),
            n: m(&self.n),
            omega: p(&self.omega),
            alpha: p(&self.alpha),
        }
    }

    /// Normal acceleration n . a of the wing point at span `r_m` and chordwise `x_m` (from
    /// the pitch axis towards the leading edge) from the rigid-wing kinematics alone.
    pub fn normal_acceleration(&self, r_m: f64, x_m: f64) -> f64 {
        let p = r_m * self.e_span + x_m * self.e_le;
        self.n
            .dot(&(self.alpha.cross(&p) + self.omega.cross(&self.omega.cross(&p))))
    }

    /// A term's force and moment (stroke frame) with its lift and drag coefficients.
    pub(crate) fn term(
        &self,
        f: Vector3<f64>,
        m: Vector3<f64>,
        q_ref_s: f64,
        downstroke: bool,
    ) -> TermForce {
        let dir = if downstroke { 1.0 } else { -1.0 };
        TermForce {
            force_n: f,
            moment_hinge_nm: m,
            c_l: f.z / q_ref_s,
            c_d: -f.dot(&(dir * self.t)) / q_ref_s,
        }
    }
}
