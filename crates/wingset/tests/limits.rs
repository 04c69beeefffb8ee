//! What a host may hand the wing set, and the body drag a host may ask it to apply: the step's
//! bound relative to the wingbeat, body states and winds whose loads overflow, and the drag
//! 0.5 rho |V| V C_D S (flapsim::flight's formula) checked against its closed form.

mod common;

use nalgebra::Vector3;
use wingforce::Side;
use wingset::{Error, MIN_STEPS_PER_WINGBEAT, State, WingSet, max_dt_s};

use common::wing;

fn pair(dt_s: f64) -> wingset::Result<WingSet> {
    WingSet::builder(dt_s)
        .wing(wing(Side::Left))
        .wing(wing(Side::Right))
        .build()
}

fn input_message(e: Error) -> String {
    match e {
        Error::Input(m) => m,
        e => panic!("expected Error::Input, got {e:?}"),
    }
}

/// A step refused for overflowing loads: a divergence that `is_load_overflow` recognises.
fn overflow_message(e: Error) -> String {
    assert!(e.is_load_overflow(), "{e:?}");
    e.reason()
}

#[test]
fn the_step_is_at_most_a_tenth_of_the_wingbeat() {
    let f = wing(Side::Left).kinematics().freq_hz;
    assert_eq!(MIN_STEPS_PER_WINGBEAT, 10.0);
    // 1 / (10 f) itself is accepted, and so is every finer step.
    assert!(pair(max_dt_s(f)).is_ok());
    assert!(pair(1.0 / (100.0 * f)).is_ok());
    // A step of 9 per wingbeat, a whole wingbeat, 218 of them and 1e300 s are refused, naming
    // the step and the bound.
    for dt in [1.0 / (9.0 * f), 1.0 / f, 218.0 / f, 1e300] {
        let m = input_message(pair(dt).unwrap_err());
        assert!(
            m.contains(&format!("dt_s = {dt:?}")) && m.contains("at most 1/10 of the wingbeat"),
            "{m}"
        );
    }
    for dt in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let m = input_message(pair(dt).unwrap_err());
        assert!(
            m.contains("dt_s = ") && m.contains("finite step > 0 s"),
            "{m}"
        );
    }
    // New kinematics whose wingbeat the step no longer resolves are refused, the old stay.
    let mut set = WingSet::builder(1.0 / (12.0 * f))
        .wing(wing(Side::Left))
        .build()
        .unwrap();
    let mut k = set.wings()[0].kinematics().clone();
    k.freq_hz = 1.5 * f;
    let m = input_message(set.set_kinematics(0, k).unwrap_err());
    assert!(m.contains("steps per wingbeat"), "{m}");
    assert_eq!(set.freq_hz(), f);
}

#[test]
fn a_state_or_wind_whose_loads_overflow_is_refused_and_changes_nothing() {
    let f = wing(Side::Left).kinematics().freq_hz;
    let mut set = pair(1.0 / (50.0 * f)).unwrap();
    set.step(&State::at_rest()).unwrap();
    let before = set.output().clone();
    let mut fast = State::at_rest();
    fast.velocity_m_s.x = 1e300;
    let m = overflow_message(set.step(&fast).unwrap_err());
    assert!(
        m.contains("the loads overflow") && m.contains("1e300") && m.contains("allowed"),
        "{m}"
    );
    let mut spin = State::at_rest();
    spin.angular_velocity_body_rad_s.y = 1e300;
    let m = overflow_message(set.step(&spin).unwrap_err());
    assert!(m.contains("angular velocity") && m.contains("1e300"), "{m}");
    set.set_wind(Vector3::new(0.0, -1e300, 0.0));
    let m = overflow_message(set.step(&State::at_rest()).unwrap_err());
    assert!(m.contains("wind") && m.contains("-1e300"), "{m}");
    set.set_wind(Vector3::new(f64::NAN, 0.0, 0.0));
    let m = input_message(set.step(&State::at_rest()).unwrap_err());
    assert!(m.contains("wind") && m.contains("not finite"), "{m}");
    // No step was taken: the set goes on where it was.
    assert_eq!(set.steps(), 1);
    set.set_wind(Vector3::zeros());
    let mut again = pair(1.0 / (50.0 * f)).unwrap();
    again.step(&State::at_rest()).unwrap();
    assert_eq!(again.output(), &before);
    assert_eq!(
        set.step(&State::at_rest()).unwrap(),
        again.step(&State::at_rest()).unwrap()
    );
}

#[test]
fn body_drag_is_half_rho_v_squared_cd_s_against_the_air_and_in_the_total() {
    let f = wing(Side::Left).kinematics().freq_hz;
    let rho = wing(Side::Left).fluid().density_kg_m3;
    let mut set = pair(1.0 / (50.0 * f)).unwrap();
    assert_eq!(set.body_drag_area_m2(), 0.0);
    for bad in [-1e-6, f64::NAN, f64::INFINITY] {
        let m = input_message(set.set_body_drag_area_m2(bad).unwrap_err());
        assert!(m.contains("body drag area") && m.contains("allowed"), "{m}");
    }
    let area = 3.85e-5;
    set.set_body_drag_area_m2(area).unwrap();
    // Still wings: the body's drag is all the set applies. The body moves at 2 m/s along
    // world x, yawed 90 deg (its x axis along world y, its y axis along world -x), in a wind
    // of 0.5 m/s along world -x: through the air at 2.5 m/s along world x, so the drag,
    // 0.5 rho C_D S (2.5 m/s)^2, points along world -x, the body's +y.
    set.set_still(true);
    set.set_wind(Vector3::new(-0.5, 0.0, 0.0));
    let body = State {
        velocity_m_s: Vector3::new(2.0, 0.0, 0.0),
        world_from_body: nalgebra::UnitQuaternion::from_euler_angles(
            0.0,
            0.0,
            std::f64::consts::FRAC_PI_2,
        ),
        ..State::at_rest()
    };
    let out = set.step(&body).unwrap();
    let d = 0.5 * rho * area * 2.5 * 2.5;
    let expect = Vector3::new(0.0, d, 0.0);
    assert!(
        (out.body_drag.force_n - expect).norm() <= 1e-12 * d,
        "{:?} vs {expect:?}",
        out.body_drag.force_n
    );
    assert_eq!(out.body_drag.moment_nm, Vector3::zeros());
    assert_eq!(out.total, out.body_drag);
}
