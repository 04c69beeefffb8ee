//! What a step of a [`DynamicWing`] reports at a point of it: the motion there (angles,
//! actuator, stroke phase) and the loads on the body (aerodynamic terms, hinge and inertial
//! reaction), which `step` weighs into the step's mean.

use nalgebra::Matrix3;
use wingforce::{AxisMoments, Wing, WingForces, WingFrame};

use super::super::actuator::ActuatorState;
use super::equations::Held;
use super::model::Stroke;
use super::points::{Aero, StepStart};
use super::wing::{DynamicWing, WingStep};

impl DynamicWing {
    /// The wing's frame at angles `a` ([`WingFrame::new`], bit for bit), with the sines
    /// and cosines of the angles met last ([`super::memo::frame_trig`]).
    #[inline(always)]
    pub(super) fn frame(&self, a: &wingforce::WingAngles, side: wingforce::Side) -> WingFrame {
        let trig = super::memo::frame_trig(a.phi, a.theta);
        let (p, t) = (a.phi.to_bits(), a.theta.to_bits());
        WingFrame::new_with(a, side, |x| match x.to_bits() {
            b if b == p => (trig[0], trig[1]),
            b if b == t => (trig[2], trig[3]),
            _ => x.sin_cos(),
        })
    }

    /// The motion at `at` with the accelerations `acc` (angles, actuator and stroke phase)
    /// and no loads: what [`Self::report`] gives there with every load zero.
    pub(super) fn motion(&self, acc: [f64; 2], at: &StepStart) -> WingStep {
        let a = self.angles_at(&at.state, at.t_s, acc);
        WingStep {
            forces: WingForces {
                terms: Default::default(),
                total: Default::default(),
                angles: a,
                phase: at.phase,
            },
            aero_axis: AxisMoments::default(),
            hinge_moment_nm: 0.0,
            inertial_force_n: Default::default(),
            inertial_moment_hinge_nm: Default::default(),
            actuator: self.actuator_state(&a, at.t_s),
            angles: a,
        }
    }

    /// The actuator's state at angles `a` and time `t_s` (none with a prescribed stroke).
    fn actuator_state(&self, a: &wingforce::WingAngles, t_s: f64) -> ActuatorState {
        match &self.model.stroke {
            Stroke::Driven {
                actuator, rest_rad, ..
            } => actuator.state(a.phi - rest_rad, a.phi_dot, self.voltage_v(t_s)),
            Stroke::Prescribed(_) => ActuatorState::default(),
        }
    }

    /// The loads at the step's start `at`, with the accelerations `acc`.
    pub(super) fn report(
        &self,
        wing: &Wing,
        held: &Held,
        aero: Option<Aero>,
        acc: [f64; 2],
        at: &StepStart,
    ) -> WingStep {
        self.report_framed(wing, held, aero, acc, at).0
    }

    /// [`Self::report`] and the wing's frame at `at` (with the accelerations: its axes and
    /// angular velocity are those of the frame without them, bit for bit).
    #[inline(always)]
    pub(super) fn report_framed(
        &self,
        wing: &Wing,
        held: &Held,
        aero: Option<Aero>,
        acc: [f64; 2],
        at: &StepStart,
    ) -> (WingStep, WingFrame) {
        let a = self.angles_at(&at.state, at.t_s, acc);
        let side = wing.mount().side;
        let frame = self.frame(&a, side);
        let (forces, aero_axis) = match aero {
            Some((f, _)) => {
                let k = wing.kinematic_loads_in(&a, &at.phase, &frame);
                let f = Wing::with_translational(&f, &k);
                (f, wing.axis_moments(&frame, &f.total))
            }
            None => (
                WingForces {
                    terms: Default::default(),
                    total: Default::default(),
                    angles: a,
                    phase: at.phase,
                },
                AxisMoments::default(),
            ),
        };
        let m_eff = self.pitch_inertia_effective(&self.mass_matrix(a.theta, &held.added));
        let y = [a.phi, a.theta, a.phi_dot, a.theta_dot];
        // A wing resting on an inelastic stop: the moment that holds it there.
        let held_on_stop = match (
            self.on_inelastic_stop(&y, held),
            self.stop_hold_nm(at.t_s, &y, held),
        ) {
            (Some(s), Some(hold)) if hold >= 0.0 => -s * hold,
            _ => 0.0,
        };
        let hinge_moment = self.model.hinge.moment_nm(a.theta, a.theta_dot, m_eff) + held_on_stop;
        // Inertial reaction: -m a_c and -(I_h alpha + omega x I_h omega) about the hinge,
        // plus the actuator's reflected inertia about the stroke axis.
        let i = &self.model.inertia;
        let p_c = i.com_span_m * frame.e_span + i.com_chord_m * frame.e_le;
        let a_c = frame.alpha.cross(&p_c) + frame.omega.cross(&frame.omega.cross(&p_c));
        let (j, b, c) = (
            i.stroke_inertia_kg_m2,
            i.pitch_inertia_kg_m2,
            i.product_kg_m2(),
        );
        let (es, el) = (frame.e_span, frame.e_le);
        let i_h = Matrix3::identity() * (j + b)
            - (j * es * es.transpose()
                + b * el * el.transpose()
                + c * (es * el.transpose() + el * es.transpose()));
        let ja = self.model.stroke_inertia_kg_m2() - j;
        let k_phi = WingFrame::stroke_axis(side);
        let dh =
            i_h * frame.alpha + frame.omega.cross(&(i_h * frame.omega)) + ja * a.phi_ddot * k_phi;
        let r = wing.body_from_stroke();
        let actuator = self.actuator_state(&a, at.t_s);
        let step = WingStep {
            forces,
            aero_axis,
            hinge_moment_nm: hinge_moment,
            inertial_force_n: r * (-i.mass_kg * a_c),
            inertial_moment_hinge_nm: r * (-dh),
            actuator,
            angles: a,
        };
        (step, frame)
    }
}
