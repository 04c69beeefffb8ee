//! Actuated vehicles end to end: passive pitch with aerodynamics, the Simulation's tethered
//! loads and free flight, trim, stability and hover on drive controls, and bad models.
//!
//! Physics: while the stroke turns at a constant rate, a passively pitching wing comes to
//! rest at the angle where the hinge spring balances the aerodynamic pitching moment and
//! the wing's own centrifugal ("propeller") moment, B sin(theta) cos(theta) phi_dot^2; the
//! dynamics must find the same angle as a static root-finder on the prescribed-kinematics
//! loads. A stiffer hinge lets the wing rotate less (smaller pitch amplitude) and earlier
//! (pitch advanced towards symmetric rotation), the trend that passive-pitch studies report
//! (Ishihara et al. 2009, J. Exp. Biol. 212:1, Fig. 6: the rotation phase advances and its
//! amplitude falls as the hinge stiffness parameter grows; compared qualitatively, no figure
//! digitized).

use flapsim::actuated::{
    DynamicWing, Hinge, ResponseOptions, Stroke, WingDynamics, WingInertia, frequency_response,
};
use flapsim::{Mode, Simulation, Vehicle};
use wingforce::{BodyMotion, StrokePhase, Validator, WingAngles, WingFrame};

fn robobee() -> Vehicle {
    Vehicle::from_toml(flapsim::ROBOBEE_TOML, "robobee").unwrap()
}

#[test]
fn pitch_on_a_constant_rate_stroke_settles_where_the_hinge_balances_the_air() {
    // A light wing (pitch inertia B = 1e-13 kg m^2, no chordwise mass offset) on the RoboBee
    // planform, stroke prescribed as the paper's trapezoid at 20 Hz with 160 deg amplitude
    // and short ramps, so each half stroke holds a constant rate for 38% of the period. The
    // pitch mode is sqrt(k_h / (B + A)) with A the air's added inertia about the pitch axis
    // ([`wingforce::Wing::added_inertia`]); with k_h = 1.6e-7 N m/rad (rest 90 deg) the air
    // deflects the wing by a few degrees and the hinge damping, set critical for B + A,
    // settles the pitch within the plateau. A static equilibrium does not depend on the
    // damping.
    let v = robobee();
    let mut wing = v.wings[0].clone();
    let mut o = wing.options().clone();
    o.wake_capture = None;
    wing.set_options(o);
    let spec: wingforce::KinematicsSpec = toml::from_str(
        "family = \"trapezoidal\"\nfreq_hz = 20.0\namplitude_deg = 160.0\nmid_stroke_aoa_deg = 45.0\ndtau_a = 0.06\ndtau_d = 0.06",
    )
    .unwrap();
    let kin = spec
        .build(&Validator::new("test"), "k", wing.geometry().r_gyration_m)
        .unwrap();
    let b = 1e-13;
    let k_h = 1.6e-7;
    let vertical = WingAngles {
        theta: 90f64.to_radians(),
        ..WingAngles::default()
    };
    let added = wing.added_inertia(&WingFrame::new(&vertical, wing.mount().side))[1][1];
    let model = WingDynamics {
        inertia: WingInertia {
            mass_kg: 0.1e-6,
            stroke_inertia_kg_m2: 10e-12,
            pitch_inertia_kg_m2: b,
            com_span_m: 6e-3,
            com_chord_m: 0.0,
        },
        hinge: Hinge {
            stiffness_nm_rad: k_h,
            damping_nm_s_rad: 2.0 * (k_h * (b + added)).sqrt(),
            rest_rad: 90f64.to_radians(),
            break_rad: 85f64.to_radians(),
            contact: None,
        },
        stroke: Stroke::Prescribed(kin.clone()),
        substeps: 4,
        aero: true,
    };
    let mut w = DynamicWing::new(model.clone(), flapsim::actuated::Drive::sine(20.0, 0.0)).unwrap();
    let n = 2000;
    let dt = 1.0 / (20.0 * n as f64);
    let body = BodyMotion::default();
    // Run two wingbeats, then read the state late in the third downstroke's plateau (the
    // ramps end at phase 0.06 and the deceleration starts at 0.44).
    let mut mid = None;
    for k in 0..3 * n {
        let s = w.step(&mut wing, &body, dt).unwrap();
        let phase = k as f64 / n as f64;
        if (phase - 2.38).abs() < 0.5 / n as f64 {
            mid = Some(s);
        }
    }
    let s = mid.expect("mid-plateau sample");
    let a = s.angles;
    // Settled: the hinge damping is critical for k_h alone, but the impulse-form added mass
    // (MODEL.md 4.3) adds the Munk moment of a plate translating at an angle of attack, a
    // pitch stiffness that damping does not include, so the pitch still rings slightly
    // (0.19 rad/s measured here; 0.1 held with eq 7-8). The static check below is the test.
    assert!(
        a.theta_dot.abs() < 0.25,
        "settled: theta_dot {} rad/s",
        a.theta_dot
    );
    assert!(a.phi_ddot.abs() < 1e-6 * a.phi_dot.powi(2), "constant rate");
    // The static balance: -k_h (theta - theta_r) + Q_aero(theta) - B sin cos phi_dot^2 = 0,
    // solved by bisection with the prescribed-kinematics loads (pitch held, no rates).
    let residual = |theta: f64| {
        let angles = WingAngles {
            phi: a.phi,
            theta,
            phi_dot: a.phi_dot,
            ..WingAngles::default()
        };
        let frame = WingFrame::new(&angles, wing.mount().side);
        let phase = StrokePhase {
            half_stroke: 4,
            t_star: 0.25,
            downstroke: a.phi_dot > 0.0,
        };
        let k = wing.kinematic_loads_in(&angles, &phase, &frame);
        let f = wing.evaluate_with(&k, &body);
        let q = wing.axis_moments(&frame, &f.total).pitch_nm;
        -k_h * (theta - model.hinge.rest_rad) + q
            - b * theta.sin() * theta.cos() * a.phi_dot.powi(2)
    };
    let (mut lo, mut hi) = (5f64.to_radians(), 175f64.to_radians());
    assert!(residual(lo).signum() != residual(hi).signum());
    for _ in 0..100 {
        let m = 0.5 * (lo + hi);
        if residual(m).signum() == residual(lo).signum() {
            lo = m;
        } else {
            hi = m;
        }
    }
    let theta_static = 0.5 * (lo + hi);
    let deflection = (a.theta - model.hinge.rest_rad).to_degrees();
    assert!(deflection.abs() > 2.0, "deflected {deflection} deg");
    assert!(
        (a.theta - theta_static).abs().to_degrees() < 0.02,
        "dynamics {:.3} deg, static balance {:.3} deg",
        a.theta.to_degrees(),
        theta_static.to_degrees()
    );
}

#[test]
fn a_stiffer_hinge_rotates_less_and_earlier() {
    let mut prev: Option<(f64, f64)> = None;
    for scale in [0.8, 1.0, 1.5] {
        let mut v = robobee();
        let act = v.actuation.as_mut().unwrap();
        act.dynamics.hinge.stiffness_nm_rad *= scale;
        let opts = ResponseOptions {
            freqs_hz: vec![act.drives[0].freq_hz],
            settle_cycles: 20,
            measure_cycles: 2,
            ..Default::default()
        };
        let p = frequency_response(&v, &opts, &|| {}).unwrap().points[0].clone();
        assert!(p.failed.is_none(), "{:?}", p.failed);
        if let Some((amp, phase)) = prev {
            assert!(
                p.pitch_amplitude_deg < amp,
                "x{scale}: pitch {} deg after {amp}",
                p.pitch_amplitude_deg
            );
            assert!(
                p.pitch_phase_deg > phase,
                "x{scale}: phase {} deg after {phase}",
                p.pitch_phase_deg
            );
        }
        prev = Some((p.pitch_amplitude_deg, p.pitch_phase_deg));
    }
}

#[test]
fn tethered_loads_report_wing_inertia_apart_from_aerodynamics() {
    let v = robobee();
    let mut sim = Simulation::new(v, Mode::Tethered);
    let mut inertia_peak = 0.0f64;
    for _ in 0..2000 {
        let o = *sim.step().unwrap();
        let a = o.actuated.expect("actuated output");
        assert!(a[0].actuator.voltage_v.abs() <= 250.0);
        let aero: nalgebra::Vector3<f64> = o.terms.iter().map(|t| t.force_n).sum();
        let sum = aero + o.wing_inertia.force_n;
        assert!((sum - o.total.force_n).norm() <= 1e-12 * (1.0 + o.total.force_n.norm()));
        inertia_peak = inertia_peak.max(o.wing_inertia.force_n.norm());
    }
    assert!(inertia_peak > 0.0);
}

#[test]
fn free_flight_runs_from_rest() {
    // From rest the wings take a few wingbeats to build up their stroke; the vehicle falls
    // meanwhile, but the run stays finite and the pitch within its stops.
    let mut sim = Simulation::new(robobee(), Mode::Free);
    sim.run_for(0.05, |_| {}).unwrap();
    assert!(sim.state().position_m.iter().all(|x| x.is_finite()));
}

#[test]
fn bad_actuation_values_are_named() {
    let over = flapsim::ROBOBEE_TOML.replace("amplitude_v = 90.0", "amplitude_v = 400.0");
    assert_ne!(
        over,
        flapsim::ROBOBEE_TOML,
        "the robobee's drive amplitude moved"
    );
    let e = Vehicle::from_toml(&over, "m.toml").unwrap_err().to_string();
    assert!(
        e.contains("m.toml") && e.contains("actuation.drive") && e.contains("100"),
        "{e}"
    );
    let neg =
        flapsim::ROBOBEE_TOML.replace("stiffness_nm_rad = 7.5e-6", "stiffness_nm_rad = -5.0e-6");
    let e = Vehicle::from_toml(&neg, "m.toml").unwrap_err().to_string();
    assert!(
        e.contains("actuation.hinge.stiffness_nm_rad") && e.contains("-0.000005"),
        "{e}"
    );
    // A hinge so soft the wing flips past its stops ends the run with an error that says so.
    let soft =
        flapsim::ROBOBEE_TOML.replace("stiffness_nm_rad = 7.5e-6", "stiffness_nm_rad = 1.0e-8");
    let mut sim = Simulation::new(Vehicle::from_toml(&soft, "soft").unwrap(), Mode::Tethered);
    let e = sim.run_for(0.1, |_| {}).unwrap_err().to_string();
    assert!(e.contains("stops") && e.contains("too soft"), "{e}");
}
