//! The induced inflow of a hovering vehicle (`wingforce::inflow`).
//!
//! Physics: momentum theory puts the air coming down through the stroke plane at
//! w_i = sqrt(T / (2 rho A)) with A = Phi R^2 for a pair of wings (Ellington 1984c). A wing in
//! air that comes down at w_i moves, relative to that air, exactly as a wing in still air on
//! a body that climbs at w_i along the stroke-plane normal: Galilean invariance, so the two
//! evaluations must agree to round-off, term by term and on both sides, at any stroke-plane
//! tilt. The downwash then lowers each strip's angle of attack, so hover lift falls.

/// The dynamic inflow against momentum theory and Pitt-Peters (one test binary with this one).
mod dynamic_inflow;

use nalgebra::Vector3;
use wingforce::cycle::cycle_mean;
use wingforce::{BodyMotion, InducedInflow, Mount, Side, Term, Wing, WingModelSpec};

fn robofly() -> Wing {
    let text = include_str!("../../../models/robofly.toml");
    WingModelSpec::from_toml(text, "robofly")
        .unwrap()
        .build("robofly")
        .unwrap()
}

/// The robofly wing on a tilted mount off the origin, with or without inflow.
fn mounted(side: Side, thrust_n: Option<f64>) -> Wing {
    let base = robofly();
    let mut options = base.options().clone();
    options.induced_inflow = thrust_n.map(InducedInflow::hover);
    Wing::builder(base.geometry().clone(), base.kinematics().clone())
        .fluid(*base.fluid())
        .options(options)
        .mount(Mount {
            side,
            hinge_in_body_m: Vector3::new(0.02, 0.03 * side.sign(), 0.05),
            stroke_plane_tilt_rad: 0.6,
        })
        .build()
}

#[test]
fn inflow_is_a_climb_through_the_stroke_plane() {
    let thrust_n = 0.3; // about a third of the robofly's mean lift in oil
    for side in [Side::Left, Side::Right] {
        let with = mounted(side, Some(thrust_n));
        let w = with.induced_downwash_m_s();
        // Analytic: sqrt(T / (2 rho Phi R^2 / 2)).
        let g = with.geometry();
        let area = 0.5 * with.kinematics().amplitude_rad * g.r_tip_m * g.r_tip_m;
        let expected = (thrust_n / (2.0 * with.fluid().density_kg_m3 * area)).sqrt();
        assert!((w - expected).abs() < 1e-14 * expected, "{w} vs {expected}");
        assert!(w > 0.01 * with.v_ref_m_s(), "a downwash that matters: {w}");

        let still = mounted(side, None);
        let climb = BodyMotion {
            velocity_m_s: with.body_from_stroke() * Vector3::new(0.0, 0.0, w),
            angular_velocity_rad_s: Vector3::new(0.3, -0.2, 0.1),
        };
        let spin = BodyMotion {
            velocity_m_s: Vector3::zeros(),
            ..climb
        };
        for k in 0..40 {
            let phase = (k as f64 + 0.37) / 40.0;
            let a = with.evaluate(phase, &spin);
            let b = still.evaluate(phase, &climb);
            for term in Term::ALL {
                let (fa, fb) = (a.term(term).force_n, b.term(term).force_n);
                let tol = 1e-12 * (1.0 + fb.norm());
                assert!(
                    (fa - fb).norm() < tol,
                    "{side:?} {term:?} {phase}: {fa} vs {fb}"
                );
                let (ma, mb) = (a.term(term).moment_hinge_nm, b.term(term).moment_hinge_nm);
                assert!((ma - mb).norm() < 1e-12 * (1.0 + mb.norm()));
            }
        }
    }
}

#[test]
fn downwash_lowers_hover_lift_and_only_the_translational_term() {
    let still = mounted(Side::Left, None);
    let with = mounted(Side::Left, Some(0.3));
    let body = BodyMotion::default();
    let lift = |w: &Wing, term: Term| {
        let m = cycle_mean(w, &body, 0.0, 2000);
        (w.body_from_stroke().transpose() * m.terms[term as usize].force_n).z
    };
    assert!(lift(&with, Term::Translational) < lift(&still, Term::Translational));
    // The other three terms are functions of the kinematics alone (MODEL.md 4.2-4.4).
    for term in [Term::Rotational, Term::AddedMass, Term::WakeCapture] {
        let (a, b) = (lift(&with, term), lift(&still, term));
        assert!(
            (a - b).abs() <= 1e-12 * (1.0 + b.abs()),
            "{term:?}: {a} vs {b}"
        );
    }
}

#[test]
fn a_wing_model_cannot_switch_inflow_on() {
    // The seed paper's robofly is a wing in still fluid (MODEL.md 4.5): no model of the
    // induced flow, frozen or dynamic, in either spelling.
    for line in [
        "induced_inflow = true",
        "inflow = \"frozen\"",
        "inflow = \"dynamic\"",
    ] {
        let text = include_str!("../../../models/robofly.toml")
            .replace("[aero]", &format!("[aero]\n{line}"));
        let err = WingModelSpec::from_toml(&text, "robofly.toml")
            .unwrap()
            .build("robofly.toml")
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("robofly.toml") && err.contains("aero.inflow") && err.contains("still"),
            "{line}: {err}"
        );
    }
}
