//! What a prescribed step needs of the kinematics alone, per wing: the kinematic loads
//! (wingforce's [`KinematicLoads`]) and the inertial reaction of the wing's mass, at the
//! step's start ([`LoadSampling::StepStart`]) or as the step's means with the midpoint's
//! state (the second-order samplings: [`Wing::loads_over_step`] under their
//! [`StepRule`], the step mean's carrying the translational term's still-air correction, and
//! the inertial reaction's exact mean from the wing's motion at the step's ends). Both
//! depend on the wingbeat phase only, so the set tables them once per step of the wingbeat.

use nalgebra::Vector3;
use wingforce::{KinematicLoads, StepRule, Wing, WingFrame};

use super::WingSet;
use super::body::BodyLoad;
use super::held_correction;
use crate::sampling::LoadSampling;

/// One wing's part of a prescribed step that the kinematics decide.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct StepKinematics {
    /// The kinematic loads (at the start, or the step's means with the midpoint's state).
    pub kin: KinematicLoads,
    /// The inertial reaction of the wing's mass on the body, body frame, moment about the
    /// centre of mass (zero for massless wings).
    pub inertia: BodyLoad,
}

/// The reaction of a wing's centre of mass (on the pitch axis at its centroid radius
/// `r_c`) accelerating with the kinematics: -m a, applied at the hinge, body frame.
fn inertia_at(wing: &Wing, frame: &WingFrame, r_c: f64, m_w: f64) -> BodyLoad {
    let p: Vector3<f64> = r_c * frame.e_span;
    let a = frame.alpha.cross(&p) + frame.omega.cross(&frame.omega.cross(&p));
    let f_s = -m_w * a;
    let r = wing.body_from_stroke();
    let f_b = r * f_s;
    let m_b = r * p.cross(&f_s) + wing.mount().hinge_in_body_m.cross(&f_b);
    BodyLoad {
        force_n: f_b,
        moment_nm: m_b,
    }
}

/// [`inertia_at`]'s mean over a step from the frames at its start and end, exactly: the
/// centre of mass at p = r_c e_span moves at v = omega x p, so the mean of -m a is
/// -m (v_end - v_start)/dt, and that of p x (-m a) about the hinge is
/// -m ((p x v)_end - (p x v)_start)/dt (d(p x v)/dt = v x v + p x a).
fn inertia_over_step(
    wing: &Wing,
    start: &WingFrame,
    end: &WingFrame,
    r_c: f64,
    m_w: f64,
    dt_s: f64,
) -> BodyLoad {
    let motion = |f: &WingFrame| {
        let p: Vector3<f64> = r_c * f.e_span;
        let v = f.omega.cross(&p);
        (v, p.cross(&v))
    };
    let ((v0, h0), (v1, h1)) = (motion(start), motion(end));
    let f_s = -m_w * (v1 - v0) / dt_s;
    let m_s = -m_w * (h1 - h0) / dt_s;
    let r = wing.body_from_stroke();
    let f_b = r * f_s;
    BodyLoad {
        force_n: f_b,
        moment_nm: r * m_s + wing.mount().hinge_in_body_m.cross(&f_b),
    }
}

impl WingSet {
    /// Every wing's step kinematics for the step whose loads are sampled at `phase`
    /// (the start's phase, or the midpoint's with a second-order sampling), appended to
    /// `out` in the set's order.
    pub(super) fn step_kinematics_extend(&self, phase: f64, out: &mut Vec<StepKinematics>) {
        let m_w = self.wing_mass_kg;
        match self.sampling {
            LoadSampling::StepStart => {
                let mut kin = Vec::with_capacity(self.wings.len());
                self.kinematic_loads_extend(phase, &mut kin);
                for ((k, w), r_c) in kin.into_iter().zip(&self.wings).zip(&self.centroid_r_m) {
                    let inertia = if m_w > 0.0 {
                        inertia_at(w, &k.frame, *r_c, m_w)
                    } else {
                        BodyLoad::default()
                    };
                    out.push(StepKinematics { kin: k, inertia });
                }
            }
            LoadSampling::Midpoint | LoadSampling::StepMean => {
                let rule = self.sampling.step_rule().unwrap_or(StepRule::Midpoint);
                let half = 0.5 * self.phase_per_step;
                let (p0, p1) = (phase - half, phase + half);
                let map = self.control_map.as_deref().map(|m| m.wings());
                let from_controls =
                    |i: usize, w: &Wing| map.is_some_and(|m| m[i].kinematics() == w.kinematics());
                // The correction's table is built when a wing first takes it: a set whose
                // controls stay the build's never pays for it.
                let held = match (&self.held, self.steps_per_wingbeat) {
                    (Some(h), Some(per))
                        if self.periodic
                            && held_correction::serves(self.sampling)
                            && self
                                .wings
                                .iter()
                                .enumerate()
                                .any(|(i, w)| h.applies(i, w, from_controls(i, w))) =>
                    {
                        h.at(p0, per, self.dt_s).map(|c| (h, c))
                    }
                    _ => None,
                };
                for (i, (w, r_c)) in self.wings.iter().zip(&self.centroid_r_m).enumerate() {
                    let k = match held {
                        Some((h, c)) if h.applies(i, w, from_controls(i, w)) => {
                            held_correction::held_step(w, p0, p1, self.dt_s, &c[i])
                        }
                        _ => w.loads_over_step(p0, p1, self.dt_s, rule),
                    };
                    let inertia = if m_w > 0.0 {
                        inertia_over_step(w, &k.start, &k.end, *r_c, m_w, self.dt_s)
                    } else {
                        BodyLoad::default()
                    };
                    out.push(StepKinematics {
                        kin: k.mean,
                        inertia,
                    });
                }
            }
        }
    }

    /// [`Self::step_kinematics_extend`] into a new vector.
    pub(super) fn step_kinematics(&self, phase: f64) -> Vec<StepKinematics> {
        let mut out = Vec::with_capacity(self.wings.len());
        self.step_kinematics_extend(phase, &mut out);
        out
    }
}
