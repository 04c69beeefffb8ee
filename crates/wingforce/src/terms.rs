//! The four aerodynamic terms and one term's force and moment (with its lift and drag
//! coefficients), the unit every evaluation reports in.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// The four aerodynamic terms.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Term {
    /// Quasi-steady translational lift and drag (delayed stall).
    Translational,
    /// Rotational circulation and pitch drag (Van Veen et al.).
    Rotational,
    /// Added mass (fluid accelerated with the wing).
    AddedMass,
    /// The seed paper's wake capture.
    WakeCapture,
}

impl Term {
    /// All terms, in the order of [`crate::WingForces::terms`].
    pub const ALL: [Term; 4] = [
        Term::Translational,
        Term::Rotational,
        Term::AddedMass,
        Term::WakeCapture,
    ];

    /// Snake-case name used in CSV headers, JSON and logs.
    pub fn name(self) -> &'static str {
        match self {
            Term::Translational => "translational",
            Term::Rotational => "rotational",
            Term::AddedMass => "added_mass",
            Term::WakeCapture => "wake_capture",
        }
    }
}

/// Force and moment of one term, body frame.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct TermForce {
    /// Force on the wing, body frame, N.
    pub force_n: Vector3<f64>,
    /// Moment about the hinge, body frame, N m.
    pub moment_hinge_nm: Vector3<f64>,
    /// Lift coefficient on the reference scale (eq 11): force along the stroke-plane normal
    /// over 0.5 rho V_ref^2 S.
    pub c_l: f64,
    /// Drag coefficient on the reference scale (eq 12): force in the stroke plane against the
    /// wing's current stroke direction over 0.5 rho V_ref^2 S.
    pub c_d: f64,
}

impl TermForce {
    /// Moment about the centre of mass given the hinge position (body frame, from the CoM):
    /// `M_com = M_hinge + r_hinge x F`.
    pub fn moment_about_com_nm(&self, hinge_in_body_m: &Vector3<f64>) -> Vector3<f64> {
        self.moment_hinge_nm + hinge_in_body_m.cross(&self.force_n)
    }

    pub(crate) fn add(&mut self, other: &TermForce) {
        self.force_n += other.force_n;
        self.moment_hinge_nm += other.moment_hinge_nm;
        self.c_l += other.c_l;
        self.c_d += other.c_d;
    }
}
