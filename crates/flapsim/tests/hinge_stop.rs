//! Hinge stops as a stiff unilateral contact (`flapsim::actuated::stop`).
//!
//! Physics checked, without aerodynamics so that nothing but the stop acts on the pitch:
//!
//! - Restitution. A wing swinging freely (no hinge spring or damper) at a known speed into
//!   a stop leaves it with e times that speed and e^2 of its energy, e the coefficient of
//!   restitution stated in the model (Newton's impact law; with the stroke free, for the
//!   pitch rate, the contact coordinate, whose effective inertia is 1 / (M^-1)_tt). The
//!   contact law is the clamped linear spring-dashpot whose damping ratio follows from e
//!   by the exact clamped-contact relation (module doc of `flapsim::actuated::stop`; the
//!   same as Schwager and Poeschel 2007, Granular Matter 9:465).
//! - e = 0 is a constraint, not a contact law: the Purdue robot's stops are enforced by its
//!   reference simulator (flappy, purdue-biorobotics/flappy 80399e1, fwmav.py: DART joint
//!   position limits) as an inelastic velocity-level constraint. The strike's impulse acts
//!   on the pitch alone, so it stops the pitch dead and keeps the stroke's generalised
//!   momentum p_phi = M_pp phi_dot + M_pt theta_dot (Lagrange's equation for phi has no
//!   impulsive term); the wing then rests exactly on the stop while a load presses it
//!   there, at any step.
//! - No chatter. A wing pressed into a stop by a steady moment L (here the centrifugal
//!   "propeller" moment B sin(theta) cos(theta) phi_dot^2 of a freely spinning stroke)
//!   settles at the penetration L / k_c and stays in contact without oscillating.
//! - Step-size independence of a strike, and of the hummingbird's flapping with its stops.
//! - The hummingbird's frequency response has a steady response at every default point,
//!   its pitch amplitude held by the stops at +-45 deg (flappy config `left_rotate_lower/
//!   upper` = -+0.7854 rad).

use std::f64::consts::PI;

use flapsim::Vehicle;
use flapsim::actuated::{
    Actuator, Drive, DynamicWing, Hinge, Piezo, ResponseOptions, StopContact, Stroke, WingDynamics,
    WingInertia, WingState, frequency_response,
};
use wingforce::{BodyMotion, Wing};

const B: f64 = 1.5e-12;
const STOP: f64 = 0.5;
const CONTACT_TIME: f64 = 2e-5;

fn wing() -> Wing {
    Vehicle::from_toml(flapsim::ROBOBEE_KINEMATIC_TOML, "robobee")
        .unwrap()
        .wings[0]
        .clone()
}

/// A RoboBee-sized wing (J 51.1 mg mm^2, B 1.5 mg mm^2) with a free stroke (a massive
/// piezo without stiffness, no drive), no hinge spring or damper, stops at +-0.5 rad from
/// the vertical with restitution `e`, no aerodynamics.
fn free_wing(e: f64, com_chord_m: f64) -> DynamicWing {
    let model = WingDynamics {
        inertia: WingInertia {
            mass_kg: 0.5e-6,
            stroke_inertia_kg_m2: 51.1e-12,
            pitch_inertia_kg_m2: B,
            com_span_m: 6e-3,
            com_chord_m,
        },
        hinge: Hinge {
            stiffness_nm_rad: 0.0,
            damping_nm_s_rad: 0.0,
            rest_rad: 0.5 * PI,
            break_rad: f64::INFINITY,
            contact: Some(StopContact::new(
                STOP,
                e,
                StopContact::stiffness_for_contact_time(B, CONTACT_TIME),
            )),
        },
        stroke: Stroke::Driven {
            actuator: Actuator::Piezo(Piezo {
                mass_kg: 25e-6,
                stiffness_n_m: 0.0,
                damping_n_s_m: 0.0,
                force_per_volt_n_v: 3e-4,
                transmission_rad_m: 2666.0,
                voltage_limit_v: 300.0,
            }),
            flexure_nm_rad: 0.0,
            damping_nm_s_rad: 0.0,
            rest_rad: 0.0,
        },
        substeps: 1,
        aero: false,
    };
    DynamicWing::new(model, Drive::sine(100.0, 0.0)).unwrap()
}

/// What a strike did.
#[derive(Debug, Clone, Copy)]
struct Strike {
    /// Pitch rate when the contact ended over the rate it came in with (both at the step
    /// ends around the contact).
    rate_ratio: f64,
    /// Energy after the strike over the energy before.
    energy_ratio: f64,
    /// When the wing came back to where it started, s (interpolated).
    return_s: f64,
}

/// Throws the wing from 0.1 rad short of the upper stop at `v` rad/s, steps of `dt` s;
/// `back`: run until the wing is back where it started (else stop when the contact ends).
fn strike(e: f64, com_chord_m: f64, v: f64, dt: f64, back: bool) -> Strike {
    let mut w = free_wing(e, com_chord_m);
    let start = 0.5 * PI + STOP - 0.1;
    w.set_state(WingState {
        phi_rad: 0.0,
        theta_rad: start,
        phi_dot_rad_s: 0.0,
        theta_dot_rad_s: v,
    });
    let e0 = w.energy_j();
    let mut wing = wing();
    let body = BodyMotion::default();
    let mut touched = false;
    let mut approach = v;
    let mut out_rate = None;
    let mut prev = w.state();
    for _ in 0..1_000_000 {
        w.step(&mut wing, &body, dt).unwrap();
        let s = w.state();
        let delta = s.theta_rad - 0.5 * PI - STOP;
        // A contact shorter than the step shows only as the reversed pitch rate.
        if !touched && (delta > 0.0 || s.theta_dot_rad_s < 0.0) {
            touched = true;
            approach = prev.theta_dot_rad_s;
        }
        if touched && delta <= 0.0 && out_rate.is_none() {
            out_rate = Some(s.theta_dot_rad_s);
            if !back {
                return Strike {
                    rate_ratio: -s.theta_dot_rad_s / approach,
                    energy_ratio: w.energy_j() / e0,
                    return_s: f64::NAN,
                };
            }
        }
        if touched && s.theta_rad <= start {
            let f = (prev.theta_rad - start) / (prev.theta_rad - s.theta_rad);
            return Strike {
                rate_ratio: -out_rate.unwrap() / approach,
                energy_ratio: w.energy_j() / e0,
                return_s: w.t_s() - dt + f * dt,
            };
        }
        prev = s;
    }
    panic!("e {e}: the wing did not come back (state {:?})", w.state());
}

#[test]
fn a_strike_returns_the_stated_restitution_in_speed_and_its_square_in_energy() {
    // Aligned wing (centre of mass on the pitch axis): the pitch is decoupled from the
    // stroke, so after the strike the wing swings back at constant speed. Measured: the
    // speed ratio is within 4e-5 of e and the energy ratio within 4e-5 of e^2 (the contact
    // steps' fourth-order error); bounds 1e-4.
    for e in [0.005, 0.1, 0.3, 0.5, 0.8, 1.0] {
        let realised = free_wing(e, 0.0)
            .model()
            .hinge
            .contact
            .unwrap()
            .realised_restitution();
        if e >= 0.01 {
            assert!((realised - e).abs() < 1e-12, "e {e}: realised {realised}");
        } else {
            assert!(
                (realised - 0.01).abs() < 1e-12,
                "e {e}: realised {realised}"
            );
        }
        let s = strike(e, 0.0, 50.0, 1e-4, true);
        eprintln!(
            "e {e}: speed ratio {:.6} (stated {realised:.6}), energy ratio {:.6} (stated {:.6})",
            s.rate_ratio,
            s.energy_ratio,
            realised * realised
        );
        assert!(
            (s.rate_ratio - realised).abs() < 1e-4,
            "e {e}: rebound speed ratio {} vs {realised}",
            s.rate_ratio
        );
        assert!(
            (s.energy_ratio - realised * realised).abs() < 1e-4,
            "e {e}: energy ratio {} vs {}",
            s.energy_ratio,
            realised * realised
        );
    }
}

#[test]
fn a_strike_of_a_coupled_wing_restitutes_its_pitch_rate() {
    // Centre of mass 1 mm behind the pitch axis (C / sqrt(B J) = -0.29): the stop's impulse
    // also moves the free stroke, and the contact's damping takes the effective inertia
    // 1 / (M^-1)_tt. The pitch rate after the contact is -e times the rate before it, up to
    // the coupling's velocity terms over the 20 us contact; bound 1e-3.
    for e in [0.005, 0.5, 1.0] {
        let s = strike(e, -1e-3, 50.0, 2e-6, false);
        let realised = e.max(0.01);
        eprintln!("coupled e {e}: pitch rate ratio {:.6}", s.rate_ratio);
        assert!(
            (s.rate_ratio - realised).abs() < 1e-3,
            "e {e}: pitch rate ratio {} vs {realised}",
            s.rate_ratio
        );
    }
}

#[test]
fn halving_the_step_changes_a_strike_by_less_than_the_stated_bound() {
    // The touch and the clamp's onset are located within the step, so the strike does not
    // depend on where the step boundaries fall: halving (and halving again) the step
    // changes the rebound speed ratio by < 2e-5 and the time the wing comes back by < 5e-8 s,
    // a quarter of a percent of the 20 us contact (measured: at most 1.2e-6 and 2.4e-8 s;
    // the swing back lasts 4 ms to 0.2 s).
    for e in [0.005, 0.5, 1.0] {
        let a = strike(e, 0.0, 50.0, 1e-4, true);
        let b = strike(e, 0.0, 50.0, 5e-5, true);
        let c = strike(e, 0.0, 50.0, 2.5e-5, true);
        eprintln!(
            "e {e}: rebound ratio {:.8} / {:.8} / {:.8}, back at {:.9} / {:.9} / {:.9} s",
            a.rate_ratio, b.rate_ratio, c.rate_ratio, a.return_s, b.return_s, c.return_s
        );
        for (x, y) in [(a, b), (b, c)] {
            assert!(
                (x.rate_ratio - y.rate_ratio).abs() < 2e-5,
                "e {e}: {x:?} vs {y:?}"
            );
            assert!(
                (x.return_s - y.return_s).abs() < 5e-8,
                "e {e}: {x:?} vs {y:?}"
            );
        }
    }
}

/// The aligned free wing (restitution `e`) on its lower stop with its stroke spinning
/// freely at 200 rad/s, whose propeller moment presses it onto the stop; and the stop's
/// pitch.
fn on_lower_stop_spinning(e: f64) -> (DynamicWing, f64) {
    let mut w = free_wing(e, 0.0);
    let theta_s = 0.5 * PI - STOP;
    w.set_state(WingState {
        phi_rad: 0.0,
        theta_rad: theta_s,
        phi_dot_rad_s: 200.0,
        theta_dot_rad_s: 0.0,
    });
    (w, theta_s)
}

#[test]
fn a_wing_pressed_into_a_stop_rests_there_without_chatter() {
    // The stroke spins freely at 200 rad/s; the wing rests against the lower stop
    // (theta = 90 - 28.6 deg), where the propeller moment B sin cos phi_dot^2 presses it in
    // with L = 2.5e-8 N m: it settles at delta = L / k_c (0.68 urad) and, after 50 contact
    // times, stays in contact with the pitch varying by less than 1e-3 of that penetration.
    for e in [0.005, 0.3, 0.8] {
        let (mut w, theta_s) = on_lower_stop_spinning(e);
        let stop = w.model().hinge.contact.unwrap();
        let mut wing = wing();
        let body = BodyMotion::default();
        let dt = 1e-5;
        let settle = (50.0 * CONTACT_TIME / dt) as usize;
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let mut left = 0;
        let mut pd = 0.0;
        for k in 0..settle + 1000 {
            w.step(&mut wing, &body, dt).unwrap();
            let s = w.state();
            let delta = theta_s - s.theta_rad;
            if k >= settle {
                lo = lo.min(delta);
                hi = hi.max(delta);
                if delta <= 0.0 {
                    left += 1;
                }
                pd = s.phi_dot_rad_s;
            }
        }
        let load = B * theta_s.sin() * theta_s.cos() * pd * pd;
        let expected = load / stop.stiffness_nm_rad;
        assert_eq!(left, 0, "e {e}: the wing left the stop");
        assert!(
            (0.5 * (lo + hi) / expected - 1.0).abs() < 1e-3,
            "e {e}: penetration {lo:e}..{hi:e} rad, L / k_c = {expected:e}"
        );
        assert!(
            hi - lo < 1e-3 * expected,
            "e {e}: pitch varies by {:e} rad at rest (penetration {expected:e})",
            hi - lo
        );
        eprintln!(
            "e {e}: penetration {:.6e} rad (L / k_c {expected:.6e}), variation {:.3e} rad",
            0.5 * (lo + hi),
            hi - lo
        );
    }
}

#[test]
fn an_inelastic_stop_stops_the_pitch_and_keeps_the_stroke_momentum_at_any_step() {
    // e = 0 (the constraint). A coupled wing (centre of mass 1 mm behind the pitch axis)
    // thrown at the upper stop at 50 rad/s with its stroke at rest: after the strike the
    // pitch rate is exactly 0 and the wing sits exactly on the stop; the stroke moves with
    // the momentum the pitch carried, p_phi = M_pp phi_dot + M_pt theta_dot kept to 1e-12
    // (relative); nothing presses or pulls (no loads), so it stays there. The touch is
    // found within the step: the stroke's position when the wing has come to rest does not
    // depend on the step (1e-4, 5e-5, 2.5e-5 s) beyond 1e-9 rad.
    let mut ends = Vec::new();
    for dt in [1e-4, 5e-5, 2.5e-5] {
        let mut w = free_wing(0.0, -1e-3);
        assert!(w.model().hinge.contact.unwrap().is_inelastic());
        let start = 0.5 * PI + STOP - 0.1;
        w.set_state(WingState {
            phi_rad: 0.0,
            theta_rad: start,
            phi_dot_rad_s: 0.0,
            theta_dot_rad_s: 50.0,
        });
        let p_phi = |w: &DynamicWing| {
            let s = w.state();
            let i = &w.model().inertia;
            let m_pp = w.model().stroke_inertia_kg_m2()
                + i.pitch_inertia_kg_m2 * s.theta_rad.cos().powi(2);
            let m_pt = -i.product_kg_m2() * s.theta_rad.sin();
            m_pp * s.phi_dot_rad_s + m_pt * s.theta_dot_rad_s
        };
        let p0 = p_phi(&w);
        let mut wing = wing();
        let body = BodyMotion::default();
        // 0.1 rad at 50 rad/s: the strike comes after 2 ms; run 10 ms.
        for _ in 0..(0.01 / dt) as usize {
            w.step(&mut wing, &body, dt).unwrap();
        }
        let s = w.state();
        assert_eq!(s.theta_dot_rad_s, 0.0, "dt {dt}: {s:?}");
        assert_eq!(s.theta_rad, 0.5 * PI + STOP, "dt {dt}: {s:?}");
        assert!(s.phi_dot_rad_s != 0.0);
        assert!(
            (p_phi(&w) / p0 - 1.0).abs() < 1e-12,
            "dt {dt}: p_phi {} against {p0}",
            p_phi(&w)
        );
        ends.push(s.phi_rad - s.phi_dot_rad_s * w.t_s());
    }
    for pair in ends.windows(2) {
        assert!((pair[0] - pair[1]).abs() < 1e-9, "{ends:?}");
    }
}

#[test]
fn a_wing_pressed_onto_an_inelastic_stop_rests_exactly_there() {
    // e = 0: the propeller moment of a freely spinning stroke presses the wing onto the
    // lower stop (as in the compliant case above): it stays exactly at the stop angle with
    // no pitch rate, step after step, and the stop holds it with the moment the pitch
    // equation asks (reported as the hinge moment, equal and opposite to the propeller
    // moment B sin cos phi_dot^2, to 1e-9).
    let (mut w, theta_s) = on_lower_stop_spinning(0.0);
    let mut wing = wing();
    let body = BodyMotion::default();
    for _ in 0..2000 {
        let out = w.step(&mut wing, &body, 1e-5).unwrap();
        let s = w.state();
        assert_eq!(s.theta_rad, theta_s);
        assert_eq!(s.theta_dot_rad_s, 0.0);
        let pd = s.phi_dot_rad_s;
        let load = B * theta_s.sin() * theta_s.cos() * pd * pd;
        assert!(
            (out.hinge_moment_nm - load).abs() < 1e-9 * load.abs(),
            "hinge {} against {load}",
            out.hinge_moment_nm
        );
    }
}

fn hummingbird() -> Vehicle {
    Vehicle::from_toml(flapsim::HUMMINGBIRD_TOML, "hummingbird").unwrap()
}

#[test]
fn the_hummingbird_wing_strikes_each_stop_once_per_half_stroke() {
    // At the hover drive (34 Hz, 9.3 V, flappy pid hover_voltage_) the flapping wing meets
    // each stop once per wingbeat and does not bounce off it: 2 touches per period, counted
    // at 1000 steps per period after 30 periods of settling.
    let v = hummingbird();
    let act = v.actuation.clone().unwrap();
    let mut w = DynamicWing::new(act.dynamics.clone(), act.drives[0]).unwrap();
    let mut wing = v.wings[0].clone();
    let stop = act.dynamics.hinge.contact.unwrap();
    let rest = act.dynamics.hinge.rest_rad;
    let n = 1000;
    let dt = 1.0 / (34.0 * n as f64);
    let body = BodyMotion::default();
    let mut touches = 0;
    let mut was_in = false;
    let mut deepest = 0.0f64;
    for k in 0..40 * n {
        w.step(&mut wing, &body, dt).unwrap();
        let d = stop.beyond_rad(rest, w.state().theta_rad).1;
        let now_in = d >= 0.0;
        if k >= 30 * n {
            if now_in && !was_in {
                touches += 1;
            }
            deepest = deepest.max(d);
        }
        was_in = now_in;
    }
    assert_eq!(touches, 20, "touches in 10 periods");
    // Inelastic: the wing never passes its stops.
    assert_eq!(deepest, 0.0, "{} deg", deepest.to_degrees());
    eprintln!("deepest penetration {:.3} deg", deepest.to_degrees());
}

fn response_at(v: &Vehicle, f: f64, steps: usize) -> flapsim::actuated::ResponsePoint {
    let o = ResponseOptions {
        freqs_hz: vec![f],
        steps_per_cycle: steps,
        ..ResponseOptions::default()
    };
    frequency_response(v, &o, &|| {}).unwrap().points[0].clone()
}

#[test]
fn the_hummingbird_flapping_does_not_depend_on_the_step() {
    // Halving the step (100 -> 200 per period, the frequency response's default and twice
    // it) at the hover drive changes the stroke and pitch amplitudes by < 0.1 deg, the
    // pitch-stroke phase by < 0.5 deg and the mean lift by < 1%.
    let v = hummingbird();
    let a = response_at(&v, 34.0, 100);
    let b = response_at(&v, 34.0, 200);
    assert!(a.failed.is_none() && b.failed.is_none(), "{a:?} {b:?}");
    eprintln!("100 steps: {a:?}\n200 steps: {b:?}");
    assert!((a.stroke_amplitude_deg - b.stroke_amplitude_deg).abs() < 0.1);
    assert!((a.pitch_amplitude_deg - b.pitch_amplitude_deg).abs() < 0.1);
    assert!((a.pitch_phase_deg - b.pitch_phase_deg).abs() < 0.5);
    assert!((a.mean_lift_n / b.mean_lift_n - 1.0).abs() < 0.01);
}

#[test]
fn every_point_of_the_hummingbird_frequency_response_is_steady() {
    // `flapwing frequency-response --model hummingbird` sweeps 21 frequencies from 0.5 to
    // 1.5 times the stroke's natural frequency. With the invented 1e-3 N m/rad hinge spring
    // and the 85 deg failure limit 5 of the 21 ended with "no steady response" (issue 24,
    // with eq 7-8's added mass; with the impulse form all 21 were steady but the pitch swung
    // 26-79 deg, past the robot's 45 deg stops). With the stops every point is steady and
    // the pitch amplitude is the stops' 45 deg (the inelastic stop holds the wing exactly
    // there; bound 1e-9 deg).
    let v = hummingbird();
    let act = v.actuation.as_ref().unwrap();
    let fn_hz = act.dynamics.stroke_natural_freq_hz();
    let freqs: Vec<f64> = (0..21).map(|i| fn_hz * (0.5 + i as f64 / 20.0)).collect();
    let o = ResponseOptions {
        freqs_hz: freqs,
        ..ResponseOptions::default()
    };
    let r = frequency_response(&v, &o, &|| {}).unwrap();
    for p in &r.points {
        assert!(p.failed.is_none(), "{} Hz: {:?}", p.freq_hz, p.failed);
        assert!(
            (p.pitch_amplitude_deg - 45.0).abs() < 1e-9,
            "{} Hz: pitch amplitude {}",
            p.freq_hz,
            p.pitch_amplitude_deg
        );
    }
}

fn load_err(text: &str) -> String {
    Vehicle::from_toml(text, "m.toml").unwrap_err().to_string()
}

#[test]
fn bad_stop_values_are_named_and_old_files_keep_their_meaning() {
    let h = flapsim::HUMMINGBIRD_TOML;
    // A compliant variant (restitution 0.5, 0.2 ms contact) for the contact's own fields.
    let c = h.replace(
        "restitution = 0.0",
        "restitution = 0.5\ncontact_time_s = 2.0e-4",
    );
    assert_ne!(c, h);
    let cases = [
        (
            h.replace("restitution = 0.0", "restitution = 1.5"),
            "actuation.hinge.stop.restitution",
            "1.5",
            "[0, 1]",
        ),
        (
            h.replace("restitution = 0.0", "restitution = -0.1"),
            "actuation.hinge.stop.restitution",
            "-0.1",
            "[0, 1]",
        ),
        (
            // Below the floor a compliant contact cannot go (no silent 0.01).
            h.replace("restitution = 0.0", "restitution = 0.005"),
            "actuation.hinge.stop.restitution",
            "0.005",
            "or a number in [0.01, 1]",
        ),
        (
            c.replace("contact_time_s = 2.0e-4", "stiffness_nm_rad = -2.0"),
            "actuation.hinge.stop.stiffness_nm_rad",
            "-2",
            "> 0",
        ),
        (
            c.replace("contact_time_s = 2.0e-4", "contact_time_s = -2.0e-4"),
            "actuation.hinge.stop.contact_time_s",
            "-0.0002",
            "(0, 1]",
        ),
        (
            // The inelastic stop is a constraint: a contact time means nothing to it.
            h.replace(
                "restitution = 0.0",
                "restitution = 0.0\ncontact_time_s = 2.0e-4",
            ),
            "actuation.hinge.stop.contact_time_s",
            "0.0002 with restitution = 0",
            "a restitution from 0.01 to 1",
        ),
        (
            h.replace("angle_deg = 45.0", "angle_deg = 200.0"),
            "actuation.hinge.stop.angle_deg",
            "200",
            "(0, 179]",
        ),
        (
            c.replace(
                "contact_time_s = 2.0e-4",
                "contact_time_s = 2.0e-4\nstiffness_nm_rad = 2.0",
            ),
            "actuation.hinge.stop.stiffness_nm_rad",
            "both",
            "one of the two",
        ),
        (
            h.replace("rest_deg = 90.0 ", "break_deg = 30.0\nrest_deg = 90.0 "),
            "actuation.hinge.break_deg",
            "30",
            "past the contact stops at 45",
        ),
        (
            h.replace(
                "rest_deg = 90.0 ",
                "break_deg = 80.0\nstop_deg = 80.0\nrest_deg = 90.0 ",
            ),
            "actuation.hinge.stop_deg",
            "both",
            "older name",
        ),
        (
            flapsim::ROBOBEE_TOML.replace("stiffness_nm_rad = 7.5e-6", "stiffness_nm_rad = 0.0"),
            "actuation.hinge.stiffness_nm_rad",
            "0",
            "contact stops",
        ),
        (
            // Issue #24: a negative wing inertia.
            flapsim::ROBOBEE_TOML.replace(
                "pitch_inertia_kg_m2 = 2.33e-12",
                "pitch_inertia_kg_m2 = -2.33e-12",
            ),
            "actuation.wing_inertia.pitch_inertia_kg_m2",
            "-0.00000000000233",
            "a finite number > 0",
        ),
    ];
    for (text, field, value, allowed) in cases {
        let e = load_err(&text);
        assert!(
            e.contains("m.toml") && e.contains(field) && e.contains(value) && e.contains(allowed),
            "{field}: {e}"
        );
    }
    // An old file with only `stop_deg` (the RoboBee's flexure) loads with the meaning it had:
    // a break limit at 85 deg, no contact stops.
    let rb = Vehicle::from_toml(flapsim::ROBOBEE_TOML, "robobee").unwrap();
    let hinge = rb.actuation.unwrap().dynamics.hinge;
    assert!(flapsim::ROBOBEE_TOML.contains("stop_deg = 85.0"));
    assert!((hinge.break_rad - 85f64.to_radians()).abs() < 1e-15);
    assert!(hinge.contact.is_none());
    // The hummingbird's stops: 45 deg, restitution 0 (the inelastic constraint), no break
    // limit, no spring.
    let hb = hummingbird().actuation.unwrap().dynamics;
    let stop = hb.hinge.contact.unwrap();
    assert_eq!(hb.hinge.stiffness_nm_rad, 0.0);
    assert!(hb.hinge.break_rad.is_infinite());
    assert!((stop.angle_rad - 45f64.to_radians()).abs() < 1e-15);
    assert!(stop.is_inelastic() && stop.realised_restitution() == 0.0);
    // The compliant variant keeps the contact law: 0.2 ms contact time.
    let cv = Vehicle::from_toml(&c, "c.toml")
        .unwrap()
        .actuation
        .unwrap()
        .dynamics;
    let cc = cv.hinge.contact.unwrap();
    let k = StopContact::stiffness_for_contact_time(cv.inertia.pitch_inertia_kg_m2, 2e-4);
    assert!(!cc.is_inelastic() && (cc.stiffness_nm_rad / k - 1.0).abs() < 1e-15);
}
