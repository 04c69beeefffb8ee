//! Loads about the joint axes (`wingforce::axes`).
//!
//! Physics: for a rigid wing turning about its hinge, the power the air takes from the wing
//! is M_hinge . omega, and with omega = phi_dot k_phi + theta_dot k_theta that is
//! Q_phi phi_dot + Q_theta theta_dot: the generalized moments are the projections of the
//! hinge moment on the joint axes. The added-mass term (eq 7) is linear in the angular
//! accelerations, so its generalized moments fall by exactly A q_ddot with A the closed-form
//! added inertia, which is symmetric and positive semi-definite (a kinetic energy).

use wingforce::{BodyMotion, Side, StrokePhase, Term, Wing, WingAngles, WingFrame, WingModelSpec};

fn robofly(side: Side) -> Wing {
    let text = include_str!("../../../models/robofly.toml");
    let mut w = WingModelSpec::from_toml(text, "robofly")
        .unwrap()
        .build("robofly")
        .unwrap();
    if side == Side::Right {
        let mut b = Wing::builder(w.geometry().clone(), w.kinematics().clone())
            .fluid(*w.fluid())
            .options(w.options().clone());
        let mut m = *w.mount();
        m.side = Side::Right;
        b = b.mount(m);
        w = b.build();
    }
    w
}

fn angles(k: usize) -> WingAngles {
    let x = k as f64;
    WingAngles {
        phi: 0.9 * (0.7 * x).sin(),
        theta: 1.57 + 0.8 * (1.3 * x).cos(),
        phi_dot: 2.0 * (0.4 * x).cos(),
        theta_dot: -3.0 * (0.9 * x).sin(),
        phi_ddot: 20.0 * (0.3 * x).sin(),
        theta_ddot: 35.0 * (1.1 * x).cos(),
        ..Default::default()
    }
}

const PHASE: StrokePhase = StrokePhase {
    half_stroke: 0,
    t_star: 0.2,
    downstroke: true,
};

#[test]
fn axis_moments_carry_the_aerodynamic_power() {
    for side in [Side::Left, Side::Right] {
        let wing = robofly(side);
        for k in 0..12 {
            let a = angles(k);
            let frame = WingFrame::new(&a, side);
            let f = wing.evaluate_with(
                &wing.kinematic_loads_in(&a, &PHASE, &frame),
                &BodyMotion::default(),
            );
            for t in Term::ALL.iter().map(|t| f.term(*t)).chain([&f.total]) {
                let q = wing.axis_moments(&frame, t);
                let m_s = wing.body_from_stroke().transpose() * t.moment_hinge_nm;
                let power = m_s.dot(&frame.omega);
                let via_axes = q.stroke_nm * a.phi_dot + q.pitch_nm * a.theta_dot;
                assert!(
                    (power - via_axes).abs() <= 1e-12 * (1.0 + power.abs()),
                    "{side:?} case {k}: M.omega {power:e}, Q.qdot {via_axes:e}"
                );
            }
        }
    }
}

#[test]
fn added_inertia_is_the_added_mass_terms_acceleration_part() {
    for side in [Side::Left, Side::Right] {
        let wing = robofly(side);
        for k in 0..12 {
            let a = angles(k);
            let still = WingAngles {
                phi_ddot: 0.0,
                theta_ddot: 0.0,
                ..a
            };
            let am = |x: &WingAngles| {
                let frame = WingFrame::new(x, side);
                let l = wing.kinematic_loads_in(x, &PHASE, &frame);
                wing.axis_moments(&frame, &l.terms[Term::AddedMass as usize])
            };
            let (q, q0) = (am(&a), am(&still));
            let m = wing.added_inertia(&WingFrame::new(&a, side));
            let pred = [
                q0.stroke_nm - (m[0][0] * a.phi_ddot + m[0][1] * a.theta_ddot),
                q0.pitch_nm - (m[1][0] * a.phi_ddot + m[1][1] * a.theta_ddot),
            ];
            let scale = q.stroke_nm.abs() + q.pitch_nm.abs() + 1e-30;
            assert!(
                ((q.stroke_nm - pred[0]).abs() + (q.pitch_nm - pred[1]).abs()) < 1e-10 * scale,
                "{side:?} case {k}: {q:?} vs {pred:?}"
            );
            assert!((m[0][1] - m[1][0]).abs() <= 1e-15 * (m[0][0] + m[1][1]));
            assert!(m[0][0] >= 0.0 && m[1][1] >= 0.0);
            assert!(m[0][0] * m[1][1] - m[0][1] * m[1][0] >= -1e-12 * (m[0][0] * m[1][1]));
        }
    }
}
