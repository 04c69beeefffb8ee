//! The actuated RoboBee and hummingbird on their drive controls: the same trim, stability and hover LQR as a
//! vehicle with prescribed kinematics, with the wings' motion coming out of the dynamics.
//!
//! Physics: a hovering flapper is balanced when the cycle-mean aerodynamic force equals the
//! weight and the mean pitching moment vanishes; on the RoboBee that is the drive amplitude
//! (lift) and the drive bias (which shifts the mean stroke angle and so the centre of lift
//! fore and aft). Its hover, like an insect's (Sun & Xiong 2005; Taha et al. 2014), has one
//! unstable longitudinal oscillation and two stable subsidences; the averaged model (wings
//! in their periodic motion at each frozen body state) and the Floquet analysis of the full
//! time-periodic system (body and wing states over one wingbeat) must agree on that
//! structure, and on the numbers as far as the wings' own modes are faster than the body's:
//! the averaged model assumes the wings settle at once (see the bounds in the test).

use flapsim::Vehicle;
use flapsim::control::{Disturbance, HoverController, LqrWeights, run_hover};
use flapsim::stability::{ModeKind, analyze};
use flapsim::trim::{trim, trimmed_vehicle};

fn robobee() -> Vehicle {
    Vehicle::from_toml(flapsim::ROBOBEE_TOML, "robobee").unwrap()
}

/// The built-in RoboBee with the other published hinge: the softer of the two wings that
/// robobee3d's system identification measured (PR #93: 2.4e-6 N m/rad), in place of the lab
/// hinge model's 7.5e-6 that `models/robobee.toml` takes with the rest of its parameter set.
/// The built-in one lifts 0.96 W at its 100 V limit and has no hover; this one trims inside
/// it, so the piezo-driven trim, stability and hover are tested on it.
pub fn robobee_identified_hinge() -> Vehicle {
    let text =
        flapsim::ROBOBEE_TOML.replace("stiffness_nm_rad = 7.5e-6", "stiffness_nm_rad = 2.4e-6");
    assert_ne!(text, flapsim::ROBOBEE_TOML);
    Vehicle::from_toml(&text, "robobee, identified hinge").unwrap()
}

/// The built-in RoboBee with its actuator's voltage limit lifted from 100 V (the lab note's
/// 200 V peak-to-peak, an estimate) to 1000 V: not a vehicle, a measurement of what the
/// limit alone withholds.
fn robobee_limit_lifted() -> Vehicle {
    let text = flapsim::ROBOBEE_TOML.replace("voltage_limit_v = 100.0", "voltage_limit_v = 1000.0");
    assert_ne!(text, flapsim::ROBOBEE_TOML);
    Vehicle::from_toml(&text, "robobee, limit lifted").unwrap()
}

fn vehicle(name: &str) -> Vehicle {
    match name {
        "robobee, identified hinge" => robobee_identified_hinge(),
        "robobee, limit lifted" => robobee_limit_lifted(),
        _ => Vehicle::from_toml(flapsim::builtin_model(name).unwrap(), name).unwrap(),
    }
}

#[test]
fn the_built_in_robobee_has_no_hover_and_says_why() {
    // Rebuilt from its published parameter set (issue #24), the RoboBee makes less than its
    // weight at its drive's 100 V limit: the trim stops with an error naming the limit.
    let e = trim(&robobee()).unwrap_err().to_string();
    assert!(e.contains("no hover trim") && e.contains("100 V"), "{e}");
    // The error says what the balance needs and what the limit gives. The need: the trim of
    // the same file with the limit lifted, whose drive peaks where the message says. The
    // lift at the limit: the tethered wings' cycle-mean lift at 100 V and 120 Hz
    // (`frequency-response`: the full wing dynamics, not the averaged model the trim uses),
    // within 2%.
    let number_after = |key: &str| -> f64 {
        let rest = &e[e.find(key).unwrap_or_else(|| panic!("{key:?} in {e}")) + key.len()..];
        let end = rest
            .find(|c: char| !(c.is_ascii_digit() || c == '.'))
            .unwrap();
        rest[..end].parse().unwrap()
    };
    let needs_v = number_after("needs a drive peaking at ");
    let lift_at_limit = number_after("the wings lift ");
    let raised = robobee_limit_lifted();
    let t = trim(&raised).unwrap();
    let peak_v = trimmed_vehicle(&raised, &t)
        .unwrap()
        .actuation
        .unwrap()
        .drives[0]
        .peak_bound_v();
    assert!(
        needs_v > 100.0 && (needs_v - peak_v).abs() < 0.05,
        "{needs_v} against {peak_v}: {e}"
    );
    let v = robobee();
    let run = flapsim::actuated::run_tethered(&v, &Default::default(), 120.0, 100.0).unwrap();
    let tethered = run.mean_lift_n / v.weight_n();
    assert!(
        (lift_at_limit / tethered - 1.0).abs() < 0.02,
        "{lift_at_limit} against the tethered {tethered}: {e}"
    );
}

#[test]
fn the_actuated_robobee_trims_on_its_drive() {
    let v = robobee_identified_hinge();
    let t = trim(&v).unwrap();
    assert!(t.max_residual() < 1e-6, "{t:?}");
    // The drive at trim stays within the piezo's limit, and only the drive channels moved.
    let tv = trimmed_vehicle(&v, &t).unwrap();
    let a = tv.actuation.as_ref().unwrap();
    assert!(a.drives.iter().all(|d| d.peak_bound_v() <= 100.0));
    assert_eq!(t.controls.amplitude_rad, 0.0);
}

#[test]
fn averaged_and_floquet_modes_of_the_actuated_vehicles_agree() {
    // The RoboBee (identified hinge): the averaged model's unstable oscillation and the
    // Floquet analysis's leading pair agree within a factor 1.6 in growth rate and frequency
    // (its wing modes sit close to its body modes, so the averaged model's assumption that
    // the wings settle at once holds only roughly).
    let name = "robobee, identified hinge";
    let r = analyze(&vehicle(name), true).unwrap();
    let osc = insect_like_averaged_modes(name, &r);
    let f = &r.floquet_longitudinal;
    assert_eq!(f.len(), 8);
    assert!(
        f[0].exponent.0 > 0.0 && f[0].exponent.1.abs() > 0.0,
        "{f:?}"
    );
    assert!(f[2..].iter().all(|m| m.exponent.0 < 0.0), "{f:?}");
    let ratio = |a: f64, b: f64| (a / b).abs().max((b / a).abs());
    assert!(
        ratio(f[0].exponent.0, osc.0) < 1.6 && ratio(f[0].exponent.1, osc.1) < 1.6,
        "{name}: Floquet {:?} vs averaged {osc:?}",
        f[0].exponent,
    );

    // The hummingbird, its wing free between inelastic stops (flappy's: a constraint),
    // striking one every half stroke. Both analyses converge in the step and find the
    // insect structure, one unstable oscillation: the averaged model at +0.97 +- 3.60i 1/s
    // (+0.97 to +0.99 +- 3.60i to 3.65i over 200 to 1600 steps per wingbeat), the Floquet
    // analysis at +0.561 +- 3.117i (+0.559 to +0.562 +- 3.111i to 3.119i). They differ by
    // 1.16x in frequency and 1.73x in growth (bounds 1.3 and 2): the full periodic system's
    // body rocks within the wingbeat, the averaged model's does not (the test below takes
    // the rocking away and the two meet); docs/commands.md, "Averaged against Floquet".
    let name = "hummingbird";
    let r = analyze(&vehicle(name), true).unwrap();
    let osc = insect_like_averaged_modes(name, &r);
    let f = &r.floquet_longitudinal;
    assert_eq!(f.len(), 8);
    // Its one-wingbeat map is smooth at its own step count (one-sided differences within
    // 1.3e-3 of a perturbation; at 3200 steps per wingbeat they part by 1.84 and the
    // analysis warns: `stability::SMOOTH_GAP`).
    assert!(r.floquet_warnings.is_empty(), "{:?}", r.floquet_warnings);
    let unstable: Vec<_> = f.iter().filter(|m| m.exponent.0 > 0.0).collect();
    assert_eq!(unstable.len(), 2, "{f:?}");
    assert!(
        unstable[0].exponent.1.abs() > 0.0 && unstable[0].exponent.1 == -unstable[1].exponent.1,
        "{name}: the unstable Floquet exponents are not a complex pair: {f:?}"
    );
    assert!(
        ratio(unstable[0].exponent.1, osc.1) < 1.3 && ratio(unstable[0].exponent.0, osc.0) < 2.0,
        "{name}: Floquet {f:?} vs averaged {osc:?}"
    );
}

/// The averaged longitudinal modes of an insect's hover (Sun & Xiong 2005): one unstable
/// oscillation and two stable subsidences; returns the oscillation's (growth, frequency).
fn insect_like_averaged_modes(name: &str, r: &flapsim::stability::StabilityReport) -> (f64, f64) {
    let modes = &r.longitudinal_modes;
    let osc: Vec<_> = modes
        .iter()
        .filter(|m| m.kind == ModeKind::Oscillatory)
        .collect();
    let real: Vec<_> = modes.iter().filter(|m| m.kind == ModeKind::Real).collect();
    assert_eq!(osc.len(), 1, "{name}: {modes:#?}");
    assert!(!osc[0].stable);
    assert_eq!(real.len(), 2, "{name}: {modes:#?}");
    assert!(real.iter().all(|m| m.stable));
    (osc[0].re_per_s, osc[0].im_rad_s)
}

#[test]
fn the_actuated_robobee_and_hummingbird_hover_under_lqr_from_a_5_deg_pitch_disturbance() {
    // The built-in RoboBee with its voltage limit lifted hovers too: of its published
    // parameter set, only the drive's limit keeps it from hovering (it needs 101.9 V).
    for name in [
        "robobee, identified hinge",
        "robobee, limit lifted",
        "hummingbird",
    ] {
        let v = vehicle(name);
        let t = trim(&v).unwrap();
        let tv = trimmed_vehicle(&v, &t).unwrap();
        let d = Disturbance {
            pitch_deg: 5.0,
            ..Default::default()
        };
        let open = run_hover(&tv, &t, None, &d, 1.5, |_| true).unwrap();
        assert!(
            open.diverged.is_some() || open.max_attitude_error_deg > 30.0,
            "{name}: {open:?}"
        );
        let c = HoverController::design(&tv, &t, &LqrWeights::default(), 0).unwrap();
        let closed = run_hover(&tv, &t, Some(c), &d, 1.5, |_| true).unwrap();
        assert!(closed.diverged.is_none(), "{name}: {closed:?}");
        // Back at the hover point (within 0.1 body length) and the trim attitude (within
        // 3 deg: the wings' inertial reaction rocks the body by about a degree within each
        // wingbeat, and the averaged trim's attitude differs from the periodic hover's by
        // about as much, so the 2 deg band of the fruit fly's test is too tight here).
        assert!(closed.max_attitude_error_deg < 20.0, "{name}: {closed:?}");
        assert!(
            closed.final_position_error_m < 0.1 * tv.length_m,
            "{name}: {closed:?}"
        );
        assert!(closed.final_attitude_error_deg < 3.0, "{name}: {closed:?}");
    }
}

#[test]
fn the_hummingbird_analyses_meet_as_its_body_stops_rocking_within_the_wingbeat() {
    // The averaged model freezes the body over a wingbeat; the full periodic system lets it
    // rock with the wings' inertial and aerodynamic loads (the hummingbird's 0.77 g of spar
    // and wing per side flap +-72 deg against a 12.4 g body). Averaging is exact in the limit
    // of a body that does not move within the wingbeat (the averaging theorem, e.g. Taha,
    // Hajj & Nayfeh 2014, J. Guid. Control Dyn. 37(3)). Scaling the body's mass and inertia
    // by K while dividing gravity by K keeps the weight, the trim and the wings' motion and
    // shrinks the body's rocking by K: the gap between the two analyses' unstable pairs
    // (measured: 1.73x growth, 1.16x frequency at K = 1) closes, to 6% and 3% at K = 10 and
    // 3% and 2.3% at K = 100 (bound 5% at K = 100).
    let mut v = vehicle("hummingbird");
    let k = 100.0;
    v.mass_kg *= k;
    v.inertia_kg_m2 *= k;
    v.gravity_m_s2 /= k;
    let r = analyze(&v, true).unwrap();
    let osc = r
        .longitudinal_modes
        .iter()
        .find(|m| m.kind == ModeKind::Oscillatory && !m.stable)
        .expect("an unstable oscillation");
    let f = &r.floquet_longitudinal[0];
    let close = |a: f64, b: f64| (a / b - 1.0).abs() < 0.05;
    assert!(
        close(f.exponent.0, osc.re_per_s) && close(f.exponent.1.abs(), osc.im_rad_s.abs()),
        "Floquet {:?} against averaged {} {}",
        f.exponent,
        osc.re_per_s,
        osc.im_rad_s
    );
}
