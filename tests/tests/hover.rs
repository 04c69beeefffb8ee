//! Hover: trim, stability and control, end to end across wingforce and flapsim.
//!
//! Physics: a hovering flapping flyer is a time-periodic system. Averaging the wing forces
//! over a wingbeat gives a time-invariant model whose linearisation about the trim yields the
//! classic longitudinal hover modes; Sun & Xiong (2005, J Exp Biol 208:447) found, for a
//! bumblebee, an unstable oscillatory mode (period about 0.32 s, amplitude doubling in about
//! 0.1 s), a stable fast subsidence (half time about 0.024 s) and a stable slow subsidence
//! (half time about 0.37 s). Floquet theory on the full periodic system must agree with the
//! averaged model when the wingbeat is much faster than the body modes (here ~60x).

use flapsim::Vehicle;
use flapsim::control::{Disturbance, HoverController, LqrWeights, run_hover};
use flapsim::stability::{ModeKind, analyze};
use flapsim::trim::{trim, trimmed_vehicle};

fn builtin(name: &str) -> Vehicle {
    Vehicle::from_toml(flapsim::builtin_model(name).unwrap(), name).unwrap()
}

#[test]
fn trim_residuals_are_below_one_millionth() {
    // Issue 5: forces below 1e-6 of the weight, moments below 1e-6 of weight x wing length.
    // (The RoboBee has no hover at its published parameter set: flapsim's actuated_hover
    // tests say why and trim its identified-hinge variant.)
    for name in ["drosophila", "bumblebee", "hummingbird"] {
        let t = trim(&builtin(name)).unwrap();
        assert!(t.residual_fx_over_weight.abs() < 1e-6, "{name}: {t:?}");
        assert!(t.residual_fz_over_weight.abs() < 1e-6, "{name}: {t:?}");
        assert!(
            t.residual_my_over_weight_length.abs() < 1e-6,
            "{name}: {t:?}"
        );
    }
}

#[test]
fn bumblebee_longitudinal_modes_match_sun_and_xiong() {
    let r = analyze(&builtin("bumblebee"), true).unwrap();
    let modes = &r.longitudinal_modes;
    let osc: Vec<_> = modes
        .iter()
        .filter(|m| m.kind == ModeKind::Oscillatory)
        .collect();
    let real: Vec<_> = modes.iter().filter(|m| m.kind == ModeKind::Real).collect();
    // Structure (Sun & Xiong 2005): one unstable oscillatory pair, two stable real modes.
    assert_eq!(osc.len(), 1, "{modes:#?}");
    assert!(!osc[0].stable);
    assert_eq!(real.len(), 2, "{modes:#?}");
    assert!(real.iter().all(|m| m.stable));
    // Magnitudes: same order as theirs (period 0.32 s, doubling 0.1 s, half times 0.024 s
    // and 0.37 s). Our figures are in the README; here a factor-of-two band guards them.
    let period = osc[0].period_s.unwrap();
    assert!((0.16..0.64).contains(&period), "period {period}");
    assert!((0.05..0.2).contains(&osc[0].time_to_half_or_double_s.unwrap()));
    let mut halves: Vec<f64> = real
        .iter()
        .map(|m| m.time_to_half_or_double_s.unwrap())
        .collect();
    halves.sort_by(f64::total_cmp);
    assert!(
        (0.012..0.048).contains(&halves[0]),
        "fast subsidence {}",
        halves[0]
    );
    assert!(
        (0.185..0.74).contains(&halves[1]),
        "slow subsidence {}",
        halves[1]
    );
    // Floquet exponents of the full periodic system agree with the averaged unstable pair
    // to 1% (measured: about 0.2%).
    let f = &r.floquet_longitudinal[0];
    let rel_re = (f.exponent.0 - osc[0].re_per_s).abs() / osc[0].re_per_s.abs();
    let rel_im = (f.exponent.1.abs() - osc[0].im_rad_s.abs()).abs() / osc[0].im_rad_s.abs();
    assert!(
        rel_re < 0.01 && rel_im < 0.01,
        "Floquet {:?} vs averaged {} {}",
        f.exponent,
        osc[0].re_per_s,
        osc[0].im_rad_s
    );
}

#[test]
fn open_loop_diverges_and_closed_loop_recovers_from_5_deg_pitch() {
    let v = builtin("drosophila");
    let t = trim(&v).unwrap();
    let tv = trimmed_vehicle(&v, &t).unwrap();
    let d = Disturbance {
        pitch_deg: 5.0,
        ..Default::default()
    };
    let open = run_hover(&tv, &t, None, &d, 1.0, |_| true).unwrap();
    assert!(
        open.diverged.is_some() || open.max_attitude_error_deg > 45.0,
        "{open:?}"
    );
    // Closed loop: back within 1 body length and 2 deg within 0.3 s and staying there for 2 s
    // (the bar; flies recover from 40 deg in about 30 ms, Whitehead et al. 2015).
    let c = HoverController::design(&tv, &t, &LqrWeights::default(), 0).unwrap();
    let closed = run_hover(&tv, &t, Some(c), &d, 2.3, |_| true).unwrap();
    assert!(closed.diverged.is_none(), "{closed:?}");
    let rec = closed.recovery_time_s.expect("recovered");
    assert!(rec <= 0.3, "recovery after {rec} s");
    assert!(
        closed.final_attitude_error_deg < 2.0 && closed.final_position_error_m < v.length_m,
        "{closed:?}"
    );
}

#[test]
fn nondimensional_derivatives_follow_sun_and_xiong_references() {
    // Sun & Xiong 2005 (J. Exp. Biol. 208:447): U = 2 Phi n r_2, t = 1/n, F = 0.5 rho U^2 S_t,
    // moments with the mean chord. The dimensional derivatives are the averaged matrix's
    // entries times the mass (forces) or I_yy (pitch moment).
    let v = builtin("bumblebee");
    let r = flapsim::stability::analyze(&v, false).unwrap();
    let rf = &r.nondimensional_reference;
    let g = v.wings[0].geometry();
    let phi = rf.stroke_amplitude_rad;
    let u = 2.0 * phi * rf.freq_hz * g.r_gyration_m;
    assert!((rf.speed_m_s - u).abs() < 1e-12 * u);
    let f = 0.5 * v.wings[0].fluid().density_kg_m3 * u * u * 2.0 * g.area_m2;
    assert!((rf.force_n - f).abs() < 1e-12 * f);
    let get = |n: &str| r.nondimensional.iter().find(|d| d.name == n).unwrap();
    let a = &r.a_longitudinal;
    let xu = get("X_u");
    assert!((xu.value - v.mass_kg * a[0][0]).abs() < 1e-12 * xu.value.abs());
    assert!((xu.nondimensional - xu.value * u / f).abs() < 1e-12 * xu.nondimensional.abs());
    let mq = get("M_q");
    let iyy = v.inertia_kg_m2[(1, 1)];
    assert!((mq.value - iyy * a[3][3]).abs() < 1e-12 * mq.value.abs());
    let c = g.mean_chord_m;
    assert!(
        (mq.nondimensional - mq.value * rf.freq_hz / (f * c)).abs()
            < 1e-12 * mq.nondimensional.abs()
    );
    // Hover damping: a horizontal speed is resisted, and so is a pitch rate.
    assert!(xu.value < 0.0 && mq.value < 0.0);
}

#[test]
fn trim_on_the_angle_of_attack_or_the_frequency_keeps_the_amplitude() {
    // Sun & Xiong (2005) trimmed their bumblebee's angle of attack at its measured stroke
    // amplitude and frequency. Trimming the angle of attack or the frequency must balance the
    // weight with the amplitude untouched. For the frequency, quasi-steady scaling gives a
    // check: every force term goes as the square of the wing speed, so at fixed kinematic
    // shape the lift grows as f^2, and the trimmed frequency is about f0 sqrt(W / L0); the
    // Reynolds-number dependence of the coefficients (Lee et al. 2016's C_l falls about 1.6%
    // for a 10% lower Re at the fly's Re of about 120) and the re-trimmed mean stroke angle
    // and body pitch keep it within 5%.
    use flapsim::trim::{LiftVariable, trim_on};
    let v = builtin("drosophila");
    let r0 = flapstudy::hover_responses(&v, 200).unwrap();
    let lw0 = r0.vertical_force_n / r0.weight_n;
    let t = trim_on(&v, LiftVariable::Frequency).unwrap();
    assert!(t.max_residual() < 1e-6, "{t:?}");
    assert_eq!(t.controls.amplitude_rad, 0.0);
    assert_eq!(t.lift_variable, LiftVariable::Frequency);
    let f0 = v.freq_hz();
    let expect = f0 / lw0.sqrt();
    let got = f0 + t.controls.freq_hz;
    assert!((got / expect - 1.0).abs() < 0.05, "{got} Hz vs {expect} Hz");
    // The fly flaps at 45 deg mid-stroke angle of attack, the top of C_l's sin 2 alpha, and
    // makes less than its weight there (0.88 W with the impulse-form added mass, which
    // carries none of it): no angle of attack carries the weight, and the trim says it
    // failed instead of returning a point that does not balance.
    assert!(lw0 < 1.0, "{lw0}");
    let e = trim_on(&v, LiftVariable::AngleOfAttack).unwrap_err();
    assert!(e.to_string().contains("no hover trim"), "{e}");
    // The bumblebee makes more than its weight at its published kinematics: its angle of
    // attack trims below the 40 deg it starts from, amplitude untouched.
    let bee = builtin("bumblebee");
    let t = trim_on(&bee, LiftVariable::AngleOfAttack).unwrap();
    assert!(t.max_residual() < 1e-6, "{t:?}");
    assert_eq!(t.controls.amplitude_rad, 0.0);
    assert_eq!(t.lift_variable, LiftVariable::AngleOfAttack);
    assert!(t.controls.aoa_rad < -1e-3, "{t:?}");
    // An actuated vehicle trims its drive amplitude only, and says so.
    let e = trim_on(&builtin("robobee"), LiftVariable::AngleOfAttack).unwrap_err();
    assert!(e.to_string().contains("drive amplitude"), "{e}");
    let bad = format!(
        "{}\n[trim]\nlift_variable = \"angle_of_attack\"\n",
        flapsim::ROBOBEE_TOML
    );
    let e = Vehicle::from_toml(&bad, "rb.toml").unwrap_err().to_string();
    assert!(
        e.contains("rb.toml") && e.contains("trim.lift_variable"),
        "{e}"
    );
}

#[test]
fn published_operating_points_agree_or_say_why_not() {
    // Issue 17's bounds: weight support within 15% at the published kinematics (Sun & Xiong
    // 2005's bumblebee hovers at 116 deg and 155 Hz; Fry et al. 2005 found quasi-steady
    // mechanisms account for nearly all the force their hovering flies needed), and Sun &
    // Xiong's four mode times (abstract: period 0.32 s, doubling 0.1 s, half times 0.024 s and
    // 0.37 s) within 30%. A row outside carries a fixed note; no row may miss without one,
    // and no note may stay on a row that agrees.
    use flapsim::operating_points::{
        Verdict, lift_over_weight, operating_points, trimmed_angle_of_attack_deg,
    };
    let rows = operating_points().unwrap();
    assert_eq!(rows.len(), 6);
    for r in &rows {
        assert!(
            matches!(r.verdict(), Verdict::Pass | Verdict::KnownLimitation),
            "{r:?}"
        );
    }
    // The notes' claims. The hover downwash (Ellington 1984c's actuator disc,
    // wingforce::inflow) costs the fly lift: in still air the same fly makes more than its
    // weight (1.12 W), with the downwash 0.88 W.
    let fly = builtin("drosophila");
    assert!(
        rows[1].within() && rows[1].limitation.is_none(),
        "{:?}",
        rows[1]
    );
    let still_air = Vehicle::from_toml(
        &flapsim::DROSOPHILA_TOML.replace("inflow = \"frozen\"", "inflow = \"off\""),
        "drosophila, still air",
    )
    .unwrap();
    let lw_still = lift_over_weight(&still_air).unwrap();
    assert!(lw_still > 1.0, "still-air fly L/W {lw_still}");
    assert!(lift_over_weight(&fly).unwrap() < lw_still);
    // The bumblebee's angle-of-attack trim lands inside the 30-45 deg band of hovering
    // insects (below it while eq 7-8's added mass carried part of the weight).
    let aoa_deg = trimmed_angle_of_attack_deg(&builtin("bumblebee")).unwrap();
    assert!((30.0..45.0).contains(&aoa_deg), "{aoa_deg}");
    // The doubling and slow-subsidence times agree within the rows' 30% (measured: 16% and
    // 23% with the impulse-form added mass; 14% and 16% with eq 7-8). The note on the two
    // pitch-dominated misses gives the times of Sun & Xiong's own derivative table with the
    // model's mass and inertia, which meet the abstract (so the miss is in the derivatives).
    for r in [&rows[3], &rows[5]] {
        assert!(r.within() && r.limitation.is_none(), "{r:?}");
    }
    let note = rows[2].limitation.as_deref().unwrap();
    let c = flapsim::sun_xiong::compare(&builtin("bumblebee")).unwrap();
    let t = c.published_derivative_times_s;
    assert!(
        note.contains(&format!("{:.3} s period, {:.3} s doubling", t[0], t[1])),
        "{note}"
    );
    for (i, published) in flapsim::sun_xiong::MODE_TIMES_S.iter().enumerate() {
        assert!((t[i] / published - 1.0).abs() < 0.30, "{t:?}");
    }
}

#[test]
fn angle_of_attack_control_refuses_angles_past_90_deg() {
    let mut v = builtin("drosophila");
    let c = flapsim::Controls {
        aoa_rad: 50f64.to_radians(),
        ..Default::default()
    };
    let e = v.apply_controls(&c).unwrap_err().to_string();
    assert!(
        e.contains("angle of attack of 95.00 deg") && e.contains("(0, 90]"),
        "{e}"
    );
}
