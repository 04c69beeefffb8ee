//! The dynamic inflow of a flapping pair (`wingforce::inflow::dynamic`, issue #38) against
//! momentum theory's closed forms and Pitt-Peters' published constants.
//!
//! Physics: Rankine-Froude momentum theory over the disc the pair sweeps gives the hover
//! balance T = 2 rho A w^2; Glauert's extension to a disc moving through the air gives, in an
//! axial climb at V, w = -V/2 + sqrt(V^2/4 + w_h^2), and in fast edgewise flight
//! w -> w_h^2 / V (Johnson 1980, *Helicopter Theory*, section 4.1). Pitt & Peters (1981)
//! give the states' dynamics: the mean's apparent mass (8/3) rho R^3, so a small step of
//! thrust in hover is followed with the time constant 2 R / (3 pi w_h); and the steady
//! skewed-wake gradient -(15 pi / 32) tan(chi / 2) w0 (more downwash behind the centre). A
//! linearly loaded disc in hover has the gradient of its local momentum balance,
//! M / (rho A R w_h).

use nalgebra::{Vector2, Vector3};
use wingforce::inflow::{DynamicInflow, InflowDisc, InflowError, InflowForcing};

const RHO: f64 = 1.204;

/// A bumblebee-sized pair: amplitude 116 deg, tip radius 13.2 mm (Dudley & Ellington 1990).
fn disc() -> InflowDisc {
    InflowDisc::swept(RHO, 116f64.to_radians(), 13.2e-3, 2)
}

const WEIGHT_N: f64 = 1.717e-3;

fn settled(forcing: InflowForcing) -> DynamicInflow {
    let mut i = DynamicInflow::hover(disc(), WEIGHT_N);
    i.settle(&forcing).unwrap();
    i
}

fn hover_forcing() -> InflowForcing {
    InflowForcing {
        thrust_n: WEIGHT_N,
        ..Default::default()
    }
}

#[test]
fn hover_thrust_is_twice_rho_a_w_squared() {
    let w = settled(hover_forcing()).state.mean_m_s;
    let a = disc().area_m2;
    assert!(
        (2.0 * RHO * a * w * w / WEIGHT_N - 1.0).abs() < 1e-12,
        "T = 2 rho A w^2: {} against {WEIGHT_N}",
        2.0 * RHO * a * w * w
    );
}

#[test]
fn axial_climb_follows_momentum_theory() {
    let w_h = disc().hover_m_s(WEIGHT_N);
    for climb_m_s in [0.1, 0.5, 1.0, 3.0] {
        let i = settled(InflowForcing {
            disc_velocity_m_s: Vector3::new(0.0, 0.0, climb_m_s),
            ..hover_forcing()
        });
        let exact = -0.5 * climb_m_s + (0.25 * climb_m_s * climb_m_s + w_h * w_h).sqrt();
        assert!(
            (i.state.mean_m_s - exact).abs() < 1e-12 * w_h,
            "climb {climb_m_s}: {} against {exact}",
            i.state.mean_m_s
        );
        assert!(
            i.state.gradient_m_s.norm() < 1e-15,
            "axial flow has no skew"
        );
    }
}

#[test]
fn fast_forward_flight_tends_to_w_h_squared_over_v() {
    let w_h = disc().hover_m_s(WEIGHT_N);
    let mut last = f64::INFINITY;
    for v in [5.0, 20.0, 100.0] {
        let i = settled(InflowForcing {
            disc_velocity_m_s: Vector3::new(v, 0.0, 0.0),
            ..hover_forcing()
        });
        let ratio = i.state.mean_m_s * v / (w_h * w_h);
        // Glauert: w sqrt(V^2 + w^2) = w_h^2, so w V / w_h^2 = 1 / sqrt(1 + (w/V)^2).
        let exact = 1.0 / (1.0 + (i.state.mean_m_s / v).powi(2)).sqrt();
        assert!(
            (ratio - exact).abs() < 1e-10,
            "V {v}: {ratio} against {exact}"
        );
        assert!((ratio - 1.0).abs() < last, "w V / w_h^2 tends to 1");
        last = (ratio - 1.0).abs();
        // Pitt-Peters' steady skewed wake: more downwash behind (x < 0), by
        // (15 pi / 32) tan(chi / 2) w0 at the rear edge; tan(chi/2) -> 1 in edgewise flight.
        let chi = (v / i.state.mean_m_s).atan();
        let k = 15.0 * std::f64::consts::PI / 32.0 * (0.5 * chi).tan();
        let g = i.state.gradient_m_s;
        assert!(
            (g.x + k * i.state.mean_m_s).abs() < 1e-12 * w_h && g.y.abs() < 1e-15,
            "V {v}: gradient {g:?} against ({}, 0)",
            -k * i.state.mean_m_s
        );
    }
    assert!(last < 2e-4, "at 100 m/s w V / w_h^2 = 1 within {last}");
}

#[test]
fn a_thrust_step_is_followed_with_pitt_peters_time_constant() {
    let d = disc();
    let w_h = d.hover_m_s(WEIGHT_N);
    let tau = d.hover_time_constant_s(WEIGHT_N);
    // Published form: m0 / (2 rho A V) with m0 = (8/3) rho R^3 and V = 2 w_h.
    let r = (d.area_m2 / std::f64::consts::PI).sqrt();
    let expected = (8.0 / 3.0) * RHO * r.powi(3) / (2.0 * RHO * d.area_m2 * 2.0 * w_h);
    assert!((tau - expected).abs() < 1e-15, "{tau} against {expected}");
    // A small step of thrust (0.1 %): after one time constant the mean has gone 1 - 1/e of
    // the way to its new steady value (to the linearisation's accuracy, 1e-3 of the step).
    let mut i = settled(hover_forcing());
    let w0 = i.state.mean_m_s;
    let stepped = InflowForcing {
        thrust_n: 1.001 * WEIGHT_N,
        ..Default::default()
    };
    let w_end = settled(stepped).state.mean_m_s;
    let n = 1000;
    for _ in 0..n {
        i.advance(&stepped, tau / n as f64).unwrap();
    }
    let fraction = (i.state.mean_m_s - w0) / (w_end - w0);
    let e = 1.0 - (-1.0f64).exp();
    assert!(
        (fraction - e).abs() < 1e-3,
        "{fraction} against 1 - 1/e = {e}"
    );
    // The exponential rule is stable at any step: one step of 100 time constants lands on
    // the steady value.
    let mut j = settled(hover_forcing());
    j.advance(&stepped, 100.0 * tau).unwrap();
    assert!((j.state.mean_m_s - w_end).abs() < 1e-6 * w_h);
}

#[test]
fn a_loading_moment_in_hover_gives_the_local_momentum_gradient() {
    let d = disc();
    let w_h = d.hover_m_s(WEIGHT_N);
    let r = d.radius_m();
    let m = Vector2::new(2e-6, -1e-6);
    let i = settled(InflowForcing {
        load_moment_nm: m,
        ..hover_forcing()
    });
    let expected = m / (RHO * d.area_m2 * r * w_h);
    assert!(
        (i.state.gradient_m_s - expected).norm() < 1e-12 * expected.norm(),
        "{:?} against {expected:?}",
        i.state.gradient_m_s
    );
}

#[test]
fn descent_through_the_own_wake_is_refused() {
    let w_h = disc().hover_m_s(WEIGHT_N);
    let mut i = settled(hover_forcing());
    let before = i.state;
    let err = i
        .advance(
            &InflowForcing {
                disc_velocity_m_s: Vector3::new(0.0, 0.0, -2.5 * w_h),
                ..hover_forcing()
            },
            1e-4,
        )
        .unwrap_err();
    assert!(matches!(err, InflowError::VortexRing { .. }));
    assert!(err.to_string().contains("vortex-ring"), "{err}");
    assert_eq!(i.state, before, "a refused step changes nothing");
    let bad = i.advance(
        &InflowForcing {
            thrust_n: f64::NAN,
            ..Default::default()
        },
        1e-4,
    );
    assert_eq!(bad, Err(InflowError::NotFinite));
}
