//! A measured wing's spanwise twist (`[kinematics.twist]`, `wingforce::kinematics` `twist`).
//!
//! The physics: a blade element meets the air at its own feathering angle. A twisted wing's
//! strip at radius r is the reference chord turned about the span by the twist offset d(r),
//! so its angle of attack is the reference's plus d(r) wherever the air comes from, and its
//! lift and drag, turned back into the reference chord's axes, are the force the strip puts
//! on the wing. Two consequences need no numbers from elsewhere:
//! - a twist whose stations all feather as the reference does is the rigid wing (to
//!   round-off: the same strip forces, summed in another order);
//! - the translational force of a twisted wing cannot depend on which station the table
//!   calls its reference: the same wing described from 0.75R (its table the feathering
//!   there, 0.25R a station) and from 0.25R (the reverse) meets the air the same way at every
//!   strip, though the two descriptions' reference chords differ by the twist. A sign error
//!   in turning the strips' velocities into their own axes or their forces back breaks this.

use std::f64::consts::PI;

use wingforce::{BodyMotion, KinematicsSpec, TwistSpec, Validator, Wing, WingModelSpec};

const N: usize = 64;
const PERIOD_S: f64 = 0.2;

/// One period of a sampled harmonic wingbeat (phi = -60 cos, theta = 90 - 45 sin, deg) and
/// its pitch plus `extra_deg(i)` at sample i.
fn pitch_plus(extra_deg: impl Fn(usize) -> f64) -> Vec<f64> {
    let w = |i: usize| 2.0 * PI * i as f64 / N as f64;
    (0..=N)
        .map(|i| 90.0 - 45.0 * w(i).sin() + extra_deg(i % N))
        .collect()
}

/// A twist offset that varies over the wingbeat, deg.
fn wave(i: usize) -> f64 {
    20.0 * (2.0 * PI * i as f64 / N as f64 + 0.3).sin() + 5.0
}

/// The robofly wing with tabulated kinematics: `pitch_deg` the feathering at its reference
/// station, and `twist`.
fn wing(pitch_deg: Vec<f64>, twist: Option<TwistSpec>, dickinson: bool) -> Wing {
    let text = include_str!("../../../models/robofly.toml");
    let robofly = WingModelSpec::from_toml(text, "robofly")
        .unwrap()
        .build("robofly")
        .unwrap();
    let w = |i: usize| 2.0 * PI * i as f64 / N as f64;
    let kinematics = KinematicsSpec::Tabulated {
        t_s: (0..=N).map(|i| PERIOD_S * i as f64 / N as f64).collect(),
        stroke_deg: (0..=N).map(|i| -60.0 * w(i).cos()).collect(),
        pitch_deg,
        deviation_deg: None,
        twist,
    }
    .build(&Validator::new("twist test"), "kinematics", 0.2)
    .unwrap();
    let mut options = robofly.options().clone();
    if dickinson {
        options.translational = wingforce::coefficients::TranslationalModel::Dickinson1999;
    }
    Wing::builder(robofly.geometry().clone(), kinematics)
        .fluid(*robofly.fluid())
        .mount(*robofly.mount())
        .options(options)
        .build()
}

/// The robofly wing described from 0.75R, twisted at 0.25R by [`wave`].
fn waved_at_quarter(dickinson: bool) -> Wing {
    wing(
        pitch_plus(|_| 0.0),
        Some(TwistSpec {
            reference_r_frac: 0.75,
            stations_r_frac: vec![0.25],
            pitch_deg: vec![pitch_plus(wave)],
        }),
        dickinson,
    )
}

/// The body moving through the air (so the strips meet it at many angles).
fn moving() -> BodyMotion {
    BodyMotion {
        velocity_m_s: nalgebra::Vector3::new(0.05, 0.01, -0.03),
        angular_velocity_rad_s: nalgebra::Vector3::new(0.1, -0.2, 0.05),
    }
}

/// The translational term's force and moment of `a` and `b` agree to `tol` of their size at
/// 40 phases.
fn same_translational(a: &Wing, b: &Wing, tol: f64) {
    for k in 0..40 {
        let p = (k as f64 + 0.37) / 40.0;
        let (ta, tb) = (
            a.evaluate(p, &moving()).terms[0],
            b.evaluate(p, &moving()).terms[0],
        );
        for (x, y) in [
            (ta.force_n, tb.force_n),
            (ta.moment_hinge_nm, tb.moment_hinge_nm),
        ] {
            let scale = x.norm().max(1e-300);
            assert!(
                (x - y).norm() <= tol * scale,
                "phase {p}: {x:?} against {y:?}"
            );
        }
    }
}

#[test]
fn a_twist_whose_stations_feather_as_the_reference_is_the_rigid_wing() {
    for dickinson in [false, true] {
        let rigid = wing(pitch_plus(|_| 0.0), None, dickinson);
        let untwisted = wing(
            pitch_plus(|_| 0.0),
            Some(TwistSpec {
                reference_r_frac: 0.75,
                stations_r_frac: vec![0.25, 0.5],
                pitch_deg: vec![pitch_plus(|_| 0.0), pitch_plus(|_| 0.0)],
            }),
            dickinson,
        );
        same_translational(&rigid, &untwisted, 1e-12);
        // A real twist moves the force (the check above can fail).
        let twisted = waved_at_quarter(dickinson);
        let (r, t) = (
            rigid.evaluate(0.3, &moving()).terms[0].force_n,
            twisted.evaluate(0.3, &moving()).terms[0].force_n,
        );
        assert!((r - t).norm() > 1e-3 * r.norm(), "{r:?} {t:?}");
    }
}

#[test]
fn the_translational_force_does_not_depend_on_which_station_is_the_reference() {
    for dickinson in [false, true] {
        let from_outer = waved_at_quarter(dickinson);
        let from_inner = wing(
            pitch_plus(wave),
            Some(TwistSpec {
                reference_r_frac: 0.25,
                stations_r_frac: vec![0.75],
                pitch_deg: vec![pitch_plus(|_| 0.0)],
            }),
            dickinson,
        );
        same_translational(&from_outer, &from_inner, 1e-9);
        // Three stations, the middle one on the line through the other two: the same wing
        // as two.
        let three = wing(
            pitch_plus(|_| 0.0),
            Some(TwistSpec {
                reference_r_frac: 0.75,
                stations_r_frac: vec![0.25, 0.5],
                pitch_deg: vec![pitch_plus(wave), pitch_plus(|i| 0.5 * wave(i))],
            }),
            dickinson,
        );
        same_translational(&from_outer, &three, 1e-9);
    }
}

/// `w` mounted on the right.
fn on_the_right(w: &Wing) -> Wing {
    let mut mount = *w.mount();
    mount.side = wingforce::Side::Right;
    Wing::builder(w.geometry().clone(), w.kinematics().clone())
        .fluid(*w.fluid())
        .options(w.options().clone())
        .mount(mount)
        .build()
}

#[test]
fn a_pair_of_twisted_wings_evaluates_as_each_alone() {
    let left = waved_at_quarter(false);
    let right = on_the_right(&left);
    for k in 0..20 {
        let p = k as f64 / 20.0 + 0.01;
        let [l, r] = Wing::evaluate_mirrored_pair(&left, &right, p, &moving());
        assert_eq!(l, left.evaluate(p, &moving()));
        assert_eq!(r, right.evaluate(p, &moving()));
    }
}

#[test]
fn a_pair_of_differently_twisted_wings_evaluates_as_each_alone() {
    // Side by side in SIMD lanes, each wing with its own twist (no sine or cosine shared),
    // and a rigid wing beside a twisted one: bit for bit each wing alone.
    let left = waved_at_quarter(false);
    let twisted_right = wing(
        pitch_plus(|_| 0.0),
        Some(TwistSpec {
            reference_r_frac: 0.75,
            stations_r_frac: vec![0.25, 0.5],
            pitch_deg: vec![pitch_plus(|i| 0.5 * wave(i)), pitch_plus(|i| -wave(i))],
        }),
        false,
    );
    let rigid_right = wing(pitch_plus(|_| 0.0), None, false);
    for right in [twisted_right, rigid_right] {
        let right = on_the_right(&right);
        for k in 0..20 {
            let p = k as f64 / 20.0 + 0.01;
            let loads = [left.kinematic_loads(p), right.kinematic_loads(p)];
            let [l, r] = Wing::evaluate_pair_with(&left, &right, &loads, &moving());
            assert_eq!(l, left.evaluate(p, &moving()));
            assert_eq!(r, right.evaluate(p, &moving()));
        }
    }
}

#[test]
fn bad_twists_are_refused_with_the_field_and_what_is_allowed() {
    let build = |twist: TwistSpec| {
        let w = |i: usize| 2.0 * PI * i as f64 / N as f64;
        KinematicsSpec::Tabulated {
            t_s: (0..=N).map(|i| PERIOD_S * i as f64 / N as f64).collect(),
            stroke_deg: (0..=N).map(|i| -60.0 * w(i).cos()).collect(),
            pitch_deg: pitch_plus(|_| 0.0),
            deviation_deg: None,
            twist: Some(twist),
        }
        .build(&Validator::new("bee.toml"), "kinematics", 0.2)
        .unwrap_err()
        .to_string()
    };
    let ok = || TwistSpec {
        reference_r_frac: 0.75,
        stations_r_frac: vec![0.25],
        pitch_deg: vec![pitch_plus(wave)],
    };
    let cases: [(TwistSpec, &str); 6] = [
        (
            TwistSpec {
                reference_r_frac: 1.5,
                ..ok()
            },
            "kinematics.twist.reference_r_frac",
        ),
        (
            TwistSpec {
                stations_r_frac: vec![0.75],
                ..ok()
            },
            "kinematics.twist.stations_r_frac[0]",
        ),
        (
            TwistSpec {
                stations_r_frac: vec![],
                pitch_deg: vec![],
                ..ok()
            },
            "kinematics.twist.stations_r_frac",
        ),
        (
            TwistSpec {
                stations_r_frac: vec![0.25, 0.5],
                ..ok()
            },
            "kinematics.twist.pitch_deg",
        ),
        (
            TwistSpec {
                pitch_deg: vec![pitch_plus(wave)[..N].to_vec()],
                ..ok()
            },
            "kinematics.twist.pitch_deg[0]",
        ),
        (
            TwistSpec {
                pitch_deg: vec![{
                    let mut p = pitch_plus(wave);
                    p[N] += 3.0;
                    p
                }],
                ..ok()
            },
            "kinematics.twist.pitch_deg[0][64]",
        ),
    ];
    for (twist, field) in cases {
        let e = build(twist);
        assert!(e.contains("bee.toml") && e.contains(field), "{field}: {e}");
    }
}
