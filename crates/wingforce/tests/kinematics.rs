//! Kinematics: derivatives are the derivatives, reversals and t* are where they should be,
//! and the half-peak rule recovers a trapezoid's own dtau_A and dtau_D.

use wingforce::{KinematicsSpec, Validator};

fn trapezoid(da: f64, dd: f64) -> wingforce::Kinematics {
    KinematicsSpec::Trapezoidal {
        freq_hz: Some(2.0),
        peak_rg_speed_m_s: None,
        amplitude_deg: 155.0,
        mid_stroke_aoa_deg: 40.0,
        dtau_a: da,
        dtau_d: dd,
        mean_stroke_deg: 5.0,
        pitch_bias_deg: 3.0,
    }
    .build(&Validator::new("t"), "kinematics", 0.2)
    .unwrap()
}

fn harmonic() -> wingforce::Kinematics {
    KinematicsSpec::Harmonic {
        freq_hz: 3.0,
        amplitude_deg: 140.0,
        mid_stroke_aoa_deg: 45.0,
        pitch_phase_deg: 10.0,
        deviation_amplitude_deg: 8.0,
        mean_stroke_deg: 0.0,
        pitch_bias_deg: 0.0,
    }
    .build(&Validator::new("t"), "kinematics", 0.2)
    .unwrap()
}

fn flip(offset: f64) -> wingforce::Kinematics {
    KinematicsSpec::HarmonicFlip {
        freq_hz: 155.0,
        amplitude_deg: 116.0,
        downstroke_aoa_deg: 40.0,
        upstroke_aoa_deg: 32.0,
        flip_duration: 0.25,
        flip_offset: offset,
        mean_stroke_deg: 2.0,
        pitch_bias_deg: 0.0,
    }
    .build(&Validator::new("t"), "kinematics", 0.2)
    .unwrap()
}

fn tabulated() -> wingforce::Kinematics {
    // One period of a sampled harmonic wingbeat at 5 Hz (phi = -60 cos, theta = 90 - 45 sin).
    let n = 64;
    let t: Vec<f64> = (0..=n).map(|i| 0.2 * i as f64 / n as f64).collect();
    let w = |i: usize| 2.0 * std::f64::consts::PI * i as f64 / n as f64;
    let stroke: Vec<f64> = (0..=n).map(|i| -60.0 * w(i).cos()).collect();
    let pitch: Vec<f64> = (0..=n).map(|i| 90.0 - 45.0 * w(i).sin()).collect();
    KinematicsSpec::Tabulated {
        t_s: t,
        stroke_deg: stroke,
        pitch_deg: pitch,
        deviation_deg: None,
        twist: None,
    }
    .build(&Validator::new("t"), "kinematics", 0.2)
    .unwrap()
}

/// Central differences of the angles against the analytic derivatives.
fn check_derivatives(k: &wingforce::Kinematics, tol: f64) {
    let f = k.freq_hz;
    let h = 1e-6; // in phase units
    for i in 0..400 {
        let p = (i as f64 + 0.37) / 400.0;
        let (a, lo, hi) = (k.angles(p), k.angles(p - h), k.angles(p + h));
        let dt = h / f;
        let fd = |x: f64, y: f64| (y - x) / (2.0 * dt);
        let scale = |x: f64| tol * (1.0 + x.abs());
        assert!(
            (fd(lo.phi, hi.phi) - a.phi_dot).abs() < scale(a.phi_dot),
            "phi_dot at {p}"
        );
        assert!(
            (fd(lo.theta, hi.theta) - a.theta_dot).abs() < scale(a.theta_dot),
            "theta_dot at {p}"
        );
        assert!(
            (fd(lo.eta, hi.eta) - a.eta_dot).abs() < scale(a.eta_dot),
            "eta_dot at {p}"
        );
        assert!(
            (fd(lo.phi_dot, hi.phi_dot) - a.phi_ddot).abs() < scale(a.phi_ddot),
            "phi_ddot at {p}"
        );
        assert!(
            (fd(lo.theta_dot, hi.theta_dot) - a.theta_ddot).abs() < scale(a.theta_ddot),
            "theta_ddot at {p}"
        );
        assert!(
            (fd(lo.eta_dot, hi.eta_dot) - a.eta_ddot).abs() < scale(a.eta_ddot),
            "eta_ddot at {p}"
        );
    }
}

#[test]
fn analytic_derivatives_match_finite_differences() {
    check_derivatives(&trapezoid(0.12, 0.08), 1e-5);
    check_derivatives(&harmonic(), 1e-5);
    check_derivatives(&tabulated(), 1e-5);
    check_derivatives(&flip(0.0), 1e-5);
    check_derivatives(&flip(-0.04), 1e-5);
}

#[test]
fn pitch_flip_family_is_sun_and_lans_motion() {
    // Sun & Lan 2004 (J. Exp. Biol. 207:1887, eq. 1-2): a simple-harmonic stroke (its rate
    // peaks at pi f Phi mid-stroke), the angles of attack held in mid half strokes, and a
    // flip whose rate 0.5 w0 (1 - cos) is zero at its ends and peaks at twice its mean.
    let k = flip(0.0);
    let (a0, mid_down, a_half, mid_up) =
        (k.angles(0.0), k.angles(0.25), k.angles(0.5), k.angles(0.75));
    let amp = 116f64.to_radians();
    let mean = 2f64.to_radians();
    assert!((a0.phi - (mean - 0.5 * amp)).abs() < 1e-12);
    assert!((a_half.phi - (mean + 0.5 * amp)).abs() < 1e-12);
    let peak = std::f64::consts::PI * 155.0 * amp;
    assert!((mid_down.phi_dot - peak).abs() < 1e-9 * peak);
    assert!((k.peak_stroke_rate_rad_s() - peak).abs() < 1e-9 * peak);
    assert!((mid_down.theta - 40f64.to_radians()).abs() < 1e-12);
    assert!((mid_up.theta - (std::f64::consts::PI - 32f64.to_radians())).abs() < 1e-12);
    assert_eq!(mid_down.theta_dot, 0.0);
    // Symmetric rotation: the flip's rate peaks at the reversal, at twice the mean rate
    // (the swept angle over the flip's 0.25 T).
    let swept = std::f64::consts::PI - 32f64.to_radians() - 40f64.to_radians();
    let mean_rate = swept / (0.25 / 155.0);
    assert!((a_half.theta_dot - 2.0 * mean_rate).abs() < 1e-9 * mean_rate);
    // The flip's ends (0.125 T from the reversal) hold the mid-stroke angle again.
    assert!((k.angles(0.375).theta - 40f64.to_radians()).abs() < 1e-12);
    assert!(k.angles(0.375).theta_dot.abs() < 1e-9 * mean_rate);
    // A harmonic stroke's half-peak point is T/12 from a reversal.
    assert_eq!(k.acceleration_fractions(), (1.0 / 6.0, 1.0 / 6.0));
    // The angle-of-attack control moves both half strokes alike.
    let moved = k.with_aoa_offset(-5f64.to_radians()).unwrap();
    assert!((moved.angles(0.25).theta - 35f64.to_radians()).abs() < 1e-12);
    assert!((moved.angles(0.75).theta - (std::f64::consts::PI - 27f64.to_radians())).abs() < 1e-12);
    assert!(tabulated().with_aoa_offset(0.1).is_none());
}

#[test]
fn trapezoid_sweeps_its_amplitude_and_holds_alpha() {
    let k = trapezoid(0.1, 0.15);
    let (a0, a_half, a1) = (k.angles(0.0), k.angles(0.5), k.angles(1.0));
    let amp = 155f64.to_radians();
    let mean = 5f64.to_radians();
    assert!((a0.phi - (mean - 0.5 * amp)).abs() < 1e-12);
    assert!((a_half.phi - (mean + 0.5 * amp)).abs() < 1e-12);
    assert!((a1.phi - a0.phi).abs() < 1e-12);
    assert_eq!(a0.phi_dot, 0.0);
    // Hold phase: alpha_m + bias in the downstroke, pi - alpha_m + bias in the upstroke.
    let bias = 3f64.to_radians();
    assert!((k.angles(0.2).theta - (40f64.to_radians() + bias)).abs() < 1e-12);
    assert!(
        (k.angles(0.7).theta - (std::f64::consts::PI - 40f64.to_radians() + bias)).abs() < 1e-12
    );
    // Peak stroke rate: f A / (0.5 - (dA + dD)/2).
    let peak = (0..10_000)
        .map(|i| k.angles(i as f64 / 10_000.0).phi_dot.abs())
        .fold(0.0, f64::max);
    assert!((peak - k.peak_stroke_rate_rad_s()).abs() < 1e-9 * peak);
}

#[test]
fn half_stroke_index_and_t_star() {
    let k = trapezoid(0.12, 0.12);
    let p = k.stroke_phase(1.3);
    assert_eq!(p.half_stroke, 2);
    assert!(p.downstroke);
    assert!((p.t_star - 0.3).abs() < 1e-12);
    let q = k.stroke_phase(1.75);
    assert_eq!(q.half_stroke, 3);
    assert!(!q.downstroke);
    assert!((q.t_star - 0.25).abs() < 1e-12);
}

#[test]
fn half_peak_rule_recovers_trapezoid_fractions() {
    // The rule applied to the trapezoid's own stroke-rate profile returns its dtau_A, dtau_D.
    for (da, dd) in [(0.06, 0.06), (0.12, 0.18), (0.18, 0.09)] {
        let k = trapezoid(da, dd);
        let (ma, md) = wingforce::kinematics::measure_acceleration_fractions(
            |p| k.angles(p).phi_dot,
            k.stroke_reversals(),
        );
        assert!(
            (ma - da).abs() < 2e-4 && (md - dd).abs() < 2e-4,
            "({ma}, {md}) vs ({da}, {dd})"
        );
    }
    // Sinusoid: |sin| reaches half its peak at T/12 after reversal, so dtau = 1/6.
    let h = harmonic();
    let (ha, hd) = wingforce::kinematics::measure_acceleration_fractions(
        |p| h.angles(p).phi_dot,
        h.stroke_reversals(),
    );
    assert_eq!(h.acceleration_fractions(), (1.0 / 6.0, 1.0 / 6.0));
    assert!((ha - 1.0 / 6.0).abs() < 2e-4 && (hd - 1.0 / 6.0).abs() < 2e-4);
}

#[test]
fn tabulated_spline_reproduces_a_sampled_harmonic() {
    // A periodic cubic spline through 64 samples of a sinusoid interpolates it to ~1e-5 rad.
    let k = tabulated();
    let f = k.freq_hz;
    assert!((f - 5.0).abs() < 1e-12);
    for i in 0..97 {
        let p = i as f64 / 97.0;
        let w = 2.0 * std::f64::consts::PI * p;
        let phi = -60f64.to_radians() * w.cos();
        let phi_dot = 60f64.to_radians() * 2.0 * std::f64::consts::PI * f * w.sin();
        let a = k.angles(p);
        assert!((a.phi - phi).abs() < 2e-5, "phi at {p}");
        assert!(
            (a.phi_dot - phi_dot).abs()
                < 1e-3 * 60f64.to_radians() * 2.0 * std::f64::consts::PI * f
        );
    }
    let r = k.stroke_reversals();
    assert!(r[0].0.abs() < 1e-6 || (r[0].0 - 1.0).abs() < 1e-6 || (r[1].0).abs() < 1e-6);
}

#[test]
fn sampled_half_peak_rule_matches_the_grid_rule_on_the_same_interpolant() {
    // A stroke rate with unequal half strokes (a sine plus a second harmonic), sampled at 100
    // points per period as a dynamic wing samples its own motion: the rule on the samples and
    // on the function resampled finely (40,000 points per period) see the same
    // piecewise-linear profile, so they must agree to the fine grid's resolution.
    use wingforce::kinematics::{measure_acceleration_fractions, sampled_acceleration_fractions};
    let f = |x: f64| {
        (2.0 * std::f64::consts::PI * x).cos() + 0.3 * (4.0 * std::f64::consts::PI * x).sin()
    };
    let n = 100;
    let phase: Vec<f64> = (0..n).map(|k| k as f64 / n as f64).collect();
    let rate: Vec<f64> = phase.iter().map(|&x| f(x)).collect();
    // Reversals of the interpolant, found on it.
    let mut rev = Vec::new();
    for k in 0..n {
        let (a, b) = (rate[k], rate[(k + 1) % n]);
        if (a > 0.0 && b <= 0.0) || (a < 0.0 && b >= 0.0) {
            rev.push(((k as f64 + a / (a - b)) / n as f64, b > 0.0));
        }
    }
    assert_eq!(rev.len(), 2);
    let interp = |x: f64| {
        let x = x.rem_euclid(1.0) * n as f64;
        let k = x.floor() as usize % n;
        let t = x - x.floor();
        rate[k] + (rate[(k + 1) % n] - rate[k]) * t
    };
    let grid = measure_acceleration_fractions(interp, [rev[0], rev[1]]);
    let exact = sampled_acceleration_fractions(&phase, &rate, [rev[0], rev[1]]);
    assert!((grid.0 - exact.0).abs() < 2e-4, "{grid:?} vs {exact:?}");
    assert!((grid.1 - exact.1).abs() < 2e-4, "{grid:?} vs {exact:?}");
    assert!(exact.0 > 0.05 && exact.1 > 0.05, "{exact:?}");
}
