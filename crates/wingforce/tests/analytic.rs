//! Analytic checks of the blade-element model.
//!
//! Each test compares against a closed-form result: planform integrals of a rectangle and a
//! half-ellipse, force terms that must vanish (no stroke motion, symmetric kinematics), signs
//! fixed by physics (pitch-only rotational force reverses with the pitch rate, a climbing
//! body loses lift), and the paper's eq 8 for the added-mass normal acceleration, which our
//! general rigid-body acceleration must reduce to in the planar stroke-and-pitch case.

use std::f64::consts::PI;

use nalgebra::Vector3;
use wingforce::cycle::cycle_mean;
use wingforce::planform::{GeometryOverrides, PlanformSpec};
use wingforce::wing::WingFrame;
use wingforce::{BodyMotion, Side, Term, Validator, WingAngles, WingModelSpec};

fn v() -> Validator<'static> {
    Validator::new("test")
}

#[test]
fn rectangle_derived_quantities() {
    // b = 2, c = 0.5, root offset 0.5, pitch axis at 0.25 c: S = b c, AR = b/c,
    // R_g^2 = (R^3 - r0^3) / (3 b), S_xx = b c^3 (p^3 + (1-p)^3)/3, S_x|x| = b c^3 (p^3 - (1-p)^3)/3.
    let spec = PlanformSpec::Rectangular {
        span_m: 2.0,
        chord_m: 0.5,
        root_offset_m: 0.5,
        pitch_axis_from_le_frac: 0.25,
    };
    let g = spec
        .build(&v(), "p", &GeometryOverrides::default(), 20, 0.25)
        .unwrap();
    let (b, c, r0, p) = (2.0f64, 0.5f64, 0.5f64, 0.25f64);
    assert!((g.area_m2 - b * c).abs() < 1e-12);
    assert!((g.aspect_ratio - b / c).abs() < 1e-12);
    assert!((g.mean_chord_m - c).abs() < 1e-12);
    assert!((g.rossby - (r0 + b) / c).abs() < 1e-12);
    let rg2 = ((r0 + b).powi(3) - r0.powi(3)) / (3.0 * b);
    assert!((g.r_gyration_m - rg2.sqrt()).abs() < 1e-12);
    assert!((g.sxx_m4 - b * c.powi(3) * (p.powi(3) + (1.0 - p).powi(3)) / 3.0).abs() < 1e-12);
    assert!((g.sx_absx_m4 - b * c.powi(3) * (p.powi(3) - (1.0 - p).powi(3)) / 3.0).abs() < 1e-12);
    assert!((g.syy_m4 - b * c * rg2).abs() < 1e-12);
}

#[test]
fn ellipse_derived_quantities() {
    // Half-ellipse chord c0 sqrt(1 - (2r/b - 1)^2) on [0, b]: S = pi c0 b / 4 and
    // int c r^2 dr = 5 pi c0 b^3 / 64, so R_g = b sqrt(5) / 4.
    let spec = PlanformSpec::Elliptic {
        span_m: 1.0,
        max_chord_m: 0.3,
        root_offset_m: 0.0,
        pitch_axis_from_le_frac: 0.5,
    };
    let g = spec
        .build(&v(), "p", &GeometryOverrides::default(), 20, 0.25)
        .unwrap();
    assert!((g.area_m2 - PI * 0.3 / 4.0).abs() < 2e-6, "S {}", g.area_m2);
    assert!(
        (g.r_gyration_m - 5f64.sqrt() / 4.0).abs() < 2e-6,
        "R_g {}",
        g.r_gyration_m
    );
    // Pitch axis at mid-chord: the section is symmetric, so S_x|x| = 0.
    assert!(g.sx_absx_m4.abs() < 1e-12);
}

fn robofly() -> wingforce::Wing {
    let text = include_str!("../../../models/robofly.toml");
    WingModelSpec::from_toml(text, "robofly")
        .unwrap()
        .build("robofly")
        .unwrap()
}

#[test]
fn zero_stroke_rate_gives_no_translational_force_and_only_pitch_rotation() {
    // At stroke reversal phi_dot = 0: no strip moves through the fluid, so the translational
    // force vanishes, and of the rotational force only the pitch-only part
    // -C_rot rho S_x|x| theta_dot |theta_dot| remains.
    let wing = robofly();
    let f = wing.evaluate(0.5, &BodyMotion::default());
    assert_eq!(f.angles.phi_dot, 0.0);
    let g = wing.geometry();
    let rot = f.term(Term::Rotational).force_n.norm();
    // Round-off only (the pitch rate's axis is the span, so omega x e_span is ~1e-17).
    assert!(f.term(Term::Translational).force_n.norm() < 1e-12 * rot);
    let td = f.angles.theta_dot;
    let expected = 2.08 * 1229.0 * (-g.sx_absx_m4) * td * td.abs();
    let got = f.term(Term::Rotational).force_n.norm();
    assert!(
        (got - expected.abs()).abs() < 1e-12 * expected.abs(),
        "{got} vs {expected}"
    );
}

#[test]
fn pitch_only_rotational_force_reverses_with_pitch_rate() {
    // MODEL.md 4.2: the paper's theta_dot^2 cannot be right; theta_dot |theta_dot| is. At the
    // two reversals the pitch rates are opposite and equal (dtau_A = dtau_D), so the force is.
    let wing = robofly();
    let a = wing.evaluate(0.5, &BodyMotion::default());
    let b = wing.evaluate(1.0, &BodyMotion::default());
    assert!(a.angles.theta_dot > 0.0 && b.angles.theta_dot < 0.0);
    assert!((a.angles.theta_dot + b.angles.theta_dot).abs() < 1e-12);
    let (fa, fb) = (
        a.term(Term::Rotational).force_n,
        b.term(Term::Rotational).force_n,
    );
    // Same wing orientation up to the reversal mirror: the normal components have opposite sign
    // along the wing normal at each instant.
    let na = WingFrame::new(&a.angles, Side::Left).n;
    let nb = WingFrame::new(&b.angles, Side::Left).n;
    assert!(fa.dot(&na) > 0.0 && fb.dot(&nb) < 0.0, "{fa} {fb}");
    assert!((fa.norm() - fb.norm()).abs() < 1e-12 * fa.norm());
    // Trailing edge (x < 0) velocity is x theta_dot n: opposite to the force.
    assert!((-1.0 * a.angles.theta_dot * na).dot(&fa) < 0.0);
}

#[test]
fn stroke_pitch_rotational_force_is_on_the_lift_side_when_alpha_rises() {
    // MODEL.md 4.2: rotating to raise the angle of attack while translating adds lift-side
    // normal force. Late in the downstroke the flip has begun: theta rises from 40 deg
    // towards 140 deg while the wing still moves forward, so alpha = theta rises.
    let wing = robofly();
    let f = wing.evaluate(0.45, &BodyMotion::default());
    assert!(f.angles.phi_dot > 0.0 && f.angles.theta_dot > 0.0);
    let g = wing.geometry();
    let fr = f.term(Term::Rotational).force_n;
    let n = WingFrame::new(&f.angles, Side::Left).n;
    let sp = 2.08 * 1229.0 * g.sqrt_sxx_syy_m4 * f.angles.phi_dot * f.angles.theta_dot;
    let po = -2.08 * 1229.0 * g.sx_absx_m4 * f.angles.theta_dot.powi(2);
    assert!((fr.dot(&n) - (sp + po)).abs() < 1e-12 * (sp + po));
    // Lift side in a downstroke is the side opposite the motion: n . (+t) < 0.
    assert!(n.dot(&WingFrame::new(&f.angles, Side::Left).t) < 0.0);
}

#[test]
fn symmetric_kinematics_give_no_mean_horizontal_force() {
    // Downstroke and upstroke mirror each other: the mean force along the stroke direction
    // (x at phi = 0) cancels over a cycle, for every term.
    let wing = robofly();
    let m = cycle_mean(&wing, &BodyMotion::default(), 0.0, 4000);
    let lift = m.total.force_n.z;
    assert!(lift > 0.0);
    for t in m.terms.iter().chain([&m.total]) {
        assert!(
            t.force_n.x.abs() < 1e-9 * lift.abs().max(1e-30) + 1e-12,
            "{}",
            t.force_n
        );
    }
}

#[test]
fn added_mass_normal_acceleration_reduces_to_eq8() {
    // Planar case (no deviation): our rigid-body normal acceleration of the point (r, x),
    // n . (alpha x p + omega x (omega x p)), equals minus the paper's eq 8
    // a_n = x_m theta_ddot + r psi_ddot sin(theta) + x_m psi_dot^2 cos(theta) sin(theta)
    // with x_m = -x (the paper measures towards the trailing edge and uses the opposite normal).
    for side in [Side::Left, Side::Right] {
        for k in 0..50 {
            let s = k as f64 * 0.37;
            let a = WingAngles {
                phi: s.sin(),
                theta: 0.3 + 2.0 * (1.3 * s).cos().abs(),
                eta: 0.0,
                phi_dot: 3.0 * (0.7 * s).cos(),
                theta_dot: 5.0 * (1.1 * s).sin(),
                eta_dot: 0.0,
                phi_ddot: 40.0 * (0.9 * s).sin(),
                theta_ddot: -60.0 * (0.5 * s).cos(),
                eta_ddot: 0.0,
            };
            let fr = WingFrame::new(&a, side);
            let (r, x) = (0.2 + 0.01 * k as f64, -0.03 + 0.001 * k as f64);
            let ours = fr.normal_acceleration(r, x);
            let xm = -x;
            let eq8 = xm * a.theta_ddot
                + r * a.phi_ddot * a.theta.sin()
                + xm * a.phi_dot.powi(2) * a.theta.cos() * a.theta.sin();
            assert!(
                (ours + eq8).abs() < 1e-10 * (1.0 + eq8.abs()),
                "{side:?} k={k}: {ours} vs {eq8}"
            );
        }
    }
}

#[test]
fn climbing_body_loses_lift() {
    // A body moving up at w sees the wings' relative flow from above: the angle of attack
    // drops and the cycle-mean lift falls (the damping that makes hover analysable).
    let wing = robofly();
    let still = cycle_mean(&wing, &BodyMotion::default(), 0.0, 1000)
        .total
        .force_n
        .z;
    let climb = BodyMotion {
        velocity_m_s: Vector3::new(0.0, 0.0, 0.1 * wing.v_ref_m_s()),
        ..Default::default()
    };
    let up = cycle_mean(&wing, &climb, 0.0, 1000).total.force_n.z;
    let sink = BodyMotion {
        velocity_m_s: Vector3::new(0.0, 0.0, -0.1 * wing.v_ref_m_s()),
        ..Default::default()
    };
    let down = cycle_mean(&wing, &sink, 0.0, 1000).total.force_n.z;
    assert!(up < still && still < down, "{up} {still} {down}");
}

#[test]
fn left_and_right_wings_mirror() {
    // Same kinematics on the right wing: forces mirror in y, moments about the hinge mirror as
    // pseudovectors (x and z flip sign, y keeps it).
    let text = include_str!("../../../models/robofly.toml");
    let spec = WingModelSpec::from_toml(text, "robofly").unwrap();
    let left = spec.build("robofly").unwrap();
    let mut right_mount = *left.mount();
    right_mount.side = Side::Right;
    let right = wingforce::Wing::builder(left.geometry().clone(), left.kinematics().clone())
        .fluid(*left.fluid())
        .options(left.options().clone())
        .mount(right_mount)
        .build();
    let body = BodyMotion::default();
    for k in 0..20 {
        let p = k as f64 * 0.05 + 0.01;
        let (l, r) = (
            left.evaluate(p, &body).total,
            right.evaluate(p, &body).total,
        );
        let tol = 1e-12 * l.force_n.norm();
        assert!((l.force_n.x - r.force_n.x).abs() < tol && (l.force_n.y + r.force_n.y).abs() < tol);
        assert!((l.force_n.z - r.force_n.z).abs() < tol);
        let mt = 1e-12 * l.moment_hinge_nm.norm();
        assert!((l.moment_hinge_nm.x + r.moment_hinge_nm.x).abs() < mt);
        assert!((l.moment_hinge_nm.y - r.moment_hinge_nm.y).abs() < mt);
        assert!((l.moment_hinge_nm.z + r.moment_hinge_nm.z).abs() < mt);
    }
}

/// The robofly wing on the left and its mirror image on the right, the right wing's stroke
/// amplitude scaled by `right_amplitude_factor`; a moving body.
fn robofly_pair(right_amplitude_factor: f64) -> (wingforce::Wing, wingforce::Wing, BodyMotion) {
    let text = include_str!("../../../models/robofly.toml");
    let left = WingModelSpec::from_toml(text, "robofly")
        .unwrap()
        .build("robofly")
        .unwrap();
    let mut k_right = left.kinematics().clone();
    k_right.amplitude_rad *= right_amplitude_factor;
    let mut m = *left.mount();
    m.side = Side::Right;
    let right = wingforce::Wing::builder(left.geometry().clone(), k_right)
        .fluid(*left.fluid())
        .options(left.options().clone())
        .mount(m)
        .build();
    let body = BodyMotion {
        velocity_m_s: Vector3::new(0.01, -0.02, 0.005),
        angular_velocity_rad_s: Vector3::new(0.03, 0.02, -0.01),
    };
    (left, right, body)
}

#[test]
fn mirrored_pair_equals_separate_evaluation() {
    // The right wing's frame as the mirror image of the left's (a speed-up for symmetric
    // kinematics) must give the same forces as building it from the angles, with any body motion.
    let (left, right, body) = robofly_pair(1.0);
    for k in 0..40 {
        let p = 0.0137 + k as f64 * 0.025;
        let [l, r] = wingforce::Wing::evaluate_mirrored_pair(&left, &right, p, &body);
        let (l2, r2) = (left.evaluate(p, &body), right.evaluate(p, &body));
        assert_eq!(l.total, l2.total);
        let d = (r.total.force_n - r2.total.force_n).norm()
            + (r.total.moment_hinge_nm - r2.total.moment_hinge_nm).norm();
        assert!(
            d <= 1e-15 * (1.0 + r2.total.force_n.norm()),
            "phase {p}: {d}"
        );
    }
}

#[test]
fn pair_and_cached_kinematic_loads_equal_single_evaluation() {
    // Two wings with different kinematics (a roll command: more amplitude on the left)
    // evaluated side by side in SIMD lanes, and evaluations from kinematic loads computed
    // once and reused, must give exactly the bits of evaluating each wing alone.
    let (left, right, body) = robofly_pair(0.9);
    for k in 0..40 {
        let p = 0.0137 + k as f64 * 0.025;
        let loads = [left.kinematic_loads(p), right.kinematic_loads(p)];
        let [l, r] = wingforce::Wing::evaluate_pair_with(&left, &right, &loads, &body);
        assert_eq!(l, left.evaluate(p, &body), "phase {p}");
        assert_eq!(r, right.evaluate(p, &body), "phase {p}");
        // The translational term is the only one that depends on the body's motion.
        let still = left.evaluate_with(&loads[0], &BodyMotion::default());
        assert_eq!(still.terms[1..], l.terms[1..]);
        assert_ne!(still.terms[0], l.terms[0]);
    }
}
