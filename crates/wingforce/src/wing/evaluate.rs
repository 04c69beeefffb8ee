//! Evaluating a wing: the four terms at a wingbeat phase for a body motion, the part the
//! kinematics alone decide ([`Wing::kinematic_loads`]) and its completion with the body's
//! motion ([`Wing::evaluate_with`]), a left and right wing side by side, and the added mass
//! over a step.

use nalgebra::Vector3;

use crate::added_mass::{self, AddedMassForm};
use crate::coefficients::TranslationalModel;
use crate::forces::{KinematicLoads, WingForces};
use crate::frame::WingFrame;
use crate::kinematics::{StrokePhase, WingAngles};
use crate::mount::{BodyMotion, Side};
use crate::strips::{
    StripSums, StripVelocity, dickinson1999_sums, lee2016_sums, lee2016_sums_pair, twisted_sums,
    twisted_sums_pair,
};
use crate::terms::TermForce;
use crate::wing::Wing;

impl Wing {
    /// Forces at time `t_s` for a wing whose phase is `t_s * f` (constant frequency).
    pub fn evaluate_at_time(&self, t_s: f64, body: &BodyMotion) -> WingForces {
        self.evaluate(t_s * self.kinematics.freq_hz, body)
    }

    /// Forces and moments of all four terms at wingbeat `phase` with the body moving as given.
    pub fn evaluate(&self, phase: f64, body: &BodyMotion) -> WingForces {
        self.evaluate_with(&self.kinematic_loads(phase), body)
    }

    /// Both wings of a mirror-symmetric pair (left, right) whose kinematics are identical:
    /// the angles are computed once and the right wing's frame is the mirror image of the
    /// left's. The caller guarantees identical kinematics (checked in debug builds).
    pub fn evaluate_mirrored_pair(
        left: &Wing,
        right: &Wing,
        phase: f64,
        body: &BodyMotion,
    ) -> [WingForces; 2] {
        Wing::evaluate_pair_with(
            left,
            right,
            &Wing::mirrored_kinematic_loads(left, right, phase),
            body,
        )
    }

    /// The evaluation proper, for given angles, stroke phase and frame (see [`Wing::evaluate`]).
    pub fn evaluate_in(
        &self,
        a: &WingAngles,
        sp: &StrokePhase,
        frame: &WingFrame,
        body: &BodyMotion,
    ) -> WingForces {
        self.evaluate_with(&self.kinematic_loads_in(a, sp, frame), body)
    }

    /// `forces` with its rotational, added-mass and wake-capture terms replaced by those of
    /// `k` and the total summed again (the translational term does not depend on the
    /// angular accelerations, so a dynamic wing that learns its accelerations after the
    /// strip loop keeps it).
    pub fn with_kinematic_terms(forces: &WingForces, k: &KinematicLoads) -> WingForces {
        Self::with_translational(&forces.terms[0], k)
    }

    /// [`Self::with_kinematic_terms`] given only the translational term (the one term the
    /// kinematics alone do not decide): the same loads, bit for bit.
    pub fn with_translational(translational: &TermForce, k: &KinematicLoads) -> WingForces {
        let mut terms = k.terms;
        terms[0] = *translational;
        let mut total = TermForce::default();
        for t in &terms {
            total.add(t);
        }
        WingForces {
            terms,
            total,
            angles: k.angles,
            phase: k.phase,
        }
    }

    /// The part of the loads at wingbeat `phase` that the kinematics alone decide (see
    /// [`KinematicLoads`]).
    pub fn kinematic_loads(&self, phase: f64) -> KinematicLoads {
        let a = self.kinematics.angles(phase);
        let sp = self.kinematics.stroke_phase(phase);
        let frame = WingFrame::new(&a, self.mount.side);
        let mut k = self.kinematic_loads_in(&a, &sp, &frame);
        k.twist = self.kinematics.twist_at(phase);
        k
    }

    /// [`Wing::kinematic_loads`] of a mirror-symmetric pair (left, right) with identical
    /// kinematics: the angles once, the right frame as the mirror image of the left (checked
    /// in debug builds).
    pub fn mirrored_kinematic_loads(left: &Wing, right: &Wing, phase: f64) -> [KinematicLoads; 2] {
        debug_assert!(
            left.kinematics == right.kinematics
                && left.mount.side == Side::Left
                && right.mount.side == Side::Right
        );
        let a = left.kinematics.angles(phase);
        let sp = left.kinematics.stroke_phase(phase);
        let fl = WingFrame::new(&a, Side::Left);
        let fr = fl.mirrored();
        let twist = left.kinematics.twist_at(phase);
        let (mut kl, mut kr) = (
            left.kinematic_loads_in(&a, &sp, &fl),
            right.kinematic_loads_in(&a, &sp, &fr),
        );
        (kl.twist, kr.twist) = (twist, twist);
        [kl, kr]
    }

    /// The rotational, added-mass and wake-capture terms for given angles, stroke phase and
    /// frame, for a rigid wing (`twist` `None`: a dynamic wing's angles are its own).
    #[inline(always)]
    pub fn kinematic_loads_in(
        &self,
        a: &WingAngles,
        sp: &StrokePhase,
        frame: &WingFrame,
    ) -> KinematicLoads {
        let c = &self.cache;
        let mut terms = [TermForce::default(); 4];

        // 2. Rotational (Van Veen et al., MODEL.md 4.2), normal to the wing, at R_g on the
        //    pitch axis. Stroke-pitch: lift side when the angle of attack rises; pitch-only:
        //    against the motion of the area farther from the pitch axis.
        if self.options.rotational {
            let g = &self.geometry;
            let rho = self.fluid.density_kg_m3;
            let td = a.theta_dot;
            let mag = self.options.c_rot
                * rho
                * (g.sqrt_sxx_syy_m4 * a.phi_dot.abs() * td - g.sx_absx_m4 * td * td.abs());
            let f = mag * frame.n;
            // The pitch-only part is a sum of strip forces C_rot rho x|x| theta_dot|theta_dot|
            // dS at their own chordwise stations x; applied on the pitch axis the force keeps
            // its lift and stroke-axis moment, and its moment about the pitch axis is added
            // from the same integrand: -C_rot rho S_|x|^3 theta_dot|theta_dot|, opposing the
            // rotation (the rotational damping that a passive-pitch hinge relies on, as in
            // Whitney & Wood 2010, J. Fluid Mech. 660:197). Prescribed kinematics only
            // report it; a dynamic pitch feels it.
            let damping = -self.options.c_rot * rho * g.s_absx3_m5 * td * td.abs();
            let m = (g.r_gyration_m * frame.e_span).cross(&f)
                + damping * frame.pitch_axis(self.mount.side);
            terms[1] = frame.term(f, m, c.q_ref_s_n, sp.downstroke);
        }

        // 3. Added mass in the chosen form (crate::added_mass); the span integrals are cached.
        let am = match self.options.added_mass {
            AddedMassForm::Impulse => Some(added_mass::impulse(
                frame,
                &self.geometry.added_mass,
                c.am_k,
                &c.inflow_s,
            )),
            AddedMassForm::Paper => {
                Some(added_mass::paper(frame, &self.geometry.added_mass, c.am_k))
            }
            AddedMassForm::Off => None,
        };
        if let Some(am) = am {
            terms[2] = frame.term(am.force_n, am.moment_nm, c.q_ref_s_n, sp.downstroke);
        }

        // 4. Wake capture (eq 23-24) on the reference scale, at R_g: lift along the stroke-plane
        //    normal, drag against the new half stroke's motion.
        if let Some(w) = &c.wake {
            let (cl, cd) = w.coefficients(sp.t_star);
            let dir = if sp.downstroke { 1.0 } else { -1.0 };
            let f = c.q_ref_s_n * (cl * Vector3::z() - cd * dir * frame.t);
            let m = (self.geometry.r_gyration_m * frame.e_span).cross(&f);
            terms[3] = frame.term(f, m, c.q_ref_s_n, sp.downstroke);
        }

        for t in &mut terms[1..] {
            c.to_body(t);
        }
        KinematicLoads {
            angles: *a,
            phase: *sp,
            frame: *frame,
            terms,
            twist: None,
        }
    }

    /// The fluid impulse P of the wing's strips (MODEL.md 4.3), stroke frame, N s, at the
    /// wing's angles and rates in `frame` (the air moving steadily relative to the stroke
    /// frame, as the impulse form takes it): `Some` when the added mass is in the impulse
    /// form, whose force is -dP/dt.
    pub fn fluid_impulse_n_s(&self, frame: &WingFrame) -> Option<Vector3<f64>> {
        (self.options.added_mass == AddedMassForm::Impulse).then(|| {
            added_mass::fluid_impulse(
                frame,
                &self.geometry.added_mass,
                self.cache.am_k,
                &self.cache.inflow_s,
            )
        })
    }

    /// The impulse-form added mass's moment about the hinge as (W, R), stroke frame, with
    /// the moment dW/dt + R (`added_mass::impulse_moment_parts`): `Some` when the added mass
    /// is in the impulse form.
    pub(crate) fn added_mass_moment_parts(
        &self,
        frame: &WingFrame,
    ) -> Option<(Vector3<f64>, Vector3<f64>)> {
        (self.options.added_mass == AddedMassForm::Impulse).then(|| {
            added_mass::impulse_moment_parts(
                frame,
                &self.geometry.added_mass,
                self.cache.am_k,
                &self.cache.inflow_s,
            )
        })
    }

    /// The impulse-form added-mass term over a step from `start` to `end` (the wing's
    /// frames there) of `dt_s`: the force -(P_end - P_start) / dt, so that a host which holds
    /// it over the step hands the body exactly the fluid's change of impulse, with the moment
    /// of `at_start` (the term evaluated at the step's start, body frame). `None` unless the
    /// added mass is in the impulse form.
    pub fn added_mass_over_step(
        &self,
        start: &WingFrame,
        end: &WingFrame,
        dt_s: f64,
        at_start: &TermForce,
        downstroke: bool,
    ) -> Option<TermForce> {
        let p0 = self.fluid_impulse_n_s(start)?;
        let p1 = self.fluid_impulse_n_s(end)?;
        let c = &self.cache;
        let moment_s = c.body_from_stroke.transpose() * at_start.moment_hinge_nm;
        let mut t = start.term(-(p1 - p0) / dt_s, moment_s, c.q_ref_s_n, downstroke);
        c.to_body(&mut t);
        Some(t)
    }

    /// All four terms: the translational one from the body's motion, the others from `k`
    /// (computed by [`Wing::kinematic_loads`] for this wing).
    #[inline]
    pub fn evaluate_with(&self, k: &KinematicLoads, body: &BodyMotion) -> WingForces {
        let u = self.strip_velocity(&k.frame, body);
        let sums = match (&k.twist, self.options.translational) {
            (Some(t), model) => twisted_sums(&self.cache, &u, model, self.geometry.r_tip_m, t),
            (None, TranslationalModel::Lee2016) => lee2016_sums(&self.cache, &u),
            (None, TranslationalModel::Dickinson1999) => dickinson1999_sums(&self.cache.strips, u),
        };
        self.finish(k, &sums)
    }

    /// Two wings at once, each at its own kinematic loads, for the same body motion. Wings
    /// with the same number of strips and the Lee et al. model (every vehicle's pair), both
    /// rigid or both twisted, have their strips evaluated side by side, two lanes at a time;
    /// the results are bit for bit those of [`Wing::evaluate_with`].
    pub fn evaluate_pair_with(
        left: &Wing,
        right: &Wing,
        k: &[KinematicLoads; 2],
        body: &BodyMotion,
    ) -> [WingForces; 2] {
        Self::evaluate_pair_each(left, right, k, [body, body])
    }

    /// As [`Wing::evaluate_pair_with`], each wing with its own body motion relative to its
    /// air (e.g. each in the wind at its own hinge); bit for bit [`Wing::evaluate_with`] of
    /// each.
    pub fn evaluate_pair_each(
        left: &Wing,
        right: &Wing,
        k: &[KinematicLoads; 2],
        body: [&BodyMotion; 2],
    ) -> [WingForces; 2] {
        let lee = TranslationalModel::Lee2016;
        if left.options.translational == lee
            && right.options.translational == lee
            && left.cache.strips.len() == right.cache.strips.len()
        {
            let u = [
                left.strip_velocity(&k[0].frame, body[0]),
                right.strip_velocity(&k[1].frame, body[1]),
            ];
            let c = [&left.cache, &right.cache];
            let [sl, sr] = match (&k[0].twist, &k[1].twist) {
                (None, None) => lee2016_sums_pair(c, [&u[0], &u[1]]),
                (Some(tl), Some(tr)) => twisted_sums_pair(
                    c,
                    [&u[0], &u[1]],
                    [left.geometry.r_tip_m, right.geometry.r_tip_m],
                    [tl, tr],
                ),
                _ => {
                    return [
                        left.evaluate_with(&k[0], body[0]),
                        right.evaluate_with(&k[1], body[1]),
                    ];
                }
            };
            [left.finish(&k[0], &sl), right.finish(&k[1], &sr)]
        } else {
            [
                left.evaluate_with(&k[0], body[0]),
                right.evaluate_with(&k[1], body[1]),
            ]
        }
    }

    /// The pitch-axis velocity relative to the air at radius r is linear in r:
    /// u(r) = v_hinge + r (omega_wing + omega_body) x e_span, plus the induced flow (uniform,
    /// or with a dynamic inflow's gradient, also linear in r). Its (e_le, n) components as
    /// `StripVelocity`.
    #[inline(always)]
    fn strip_velocity(&self, frame: &WingFrame, body: &BodyMotion) -> StripVelocity {
        let c = &self.cache;
        let v_body_s = c.stroke_from_body * body.velocity_m_s;
        let w_body_s = c.stroke_from_body * body.angular_velocity_rad_s;
        let v_hinge_s = v_body_s + w_body_s.cross(&c.hinge_s) + c.translational_inflow_s;
        let mut b = (frame.omega + w_body_s).cross(&frame.e_span);
        // A dynamic inflow's gradient over the plane: linear in r along the span too.
        b.z +=
            c.inflow_gradient_per_s.x * frame.e_span.x + c.inflow_gradient_per_s.y * frame.e_span.y;
        StripVelocity {
            a_le: v_hinge_s.dot(&frame.e_le),
            b_le: b.dot(&frame.e_le),
            a_n: v_hinge_s.dot(&frame.n),
            b_n: b.dot(&frame.n),
        }
    }

    /// The translational term from the strip sums, then the total.
    #[inline(always)]
    fn finish(&self, k: &KinematicLoads, sums: &StripSums) -> WingForces {
        let c = &self.cache;
        let frame = &k.frame;
        let f_tr = sums.f_le * frame.e_le + sums.f_n * frame.n;
        let m_tr = frame
            .e_span
            .cross(&(sums.rf_le * frame.e_le + sums.rf_n * frame.n))
            + frame.e_le.cross(&(sums.xf_n * frame.n));
        let mut terms = k.terms;
        terms[0] = frame.term(f_tr, m_tr, c.q_ref_s_n, k.phase.downstroke);
        c.to_body(&mut terms[0]);
        if k.terms[0] != TermForce::default() {
            terms[0].add(&k.terms[0]);
        }
        let mut total = TermForce::default();
        for t in &terms {
            total.add(t);
        }
        WingForces {
            terms,
            total,
            angles: k.angles,
            phase: k.phase,
        }
    }
}
