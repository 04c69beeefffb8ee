//! Physics invariants of actuated wings (`flapsim::actuated`).
//!
//! The wing is a two-degree-of-freedom system (stroke phi, pitch theta). Without
//! aerodynamics and damping it is conservative: its mechanical energy (kinetic plus the
//! springs') is constant, and near rest its two modes are those of linear oscillators, the
//! stroke at f_n = (1/2 pi) sqrt((k_a + T^2 k_t)/(m_a + T^2 J)) (Steinmeyer et al. 2019's
//! lumped RoboBee model, after Jafferis et al. 2016) and the pitch at sqrt(k_h / I_pitch).
//! With damping and a harmonic drive the stroke is a driven damped oscillator whose steady
//! amplitude and lag follow the second-order transfer function
//! H(w) = g / (k - J w^2 + i c w). A hinge far stiffer than the aerodynamic pitching moment
//! holds the wing at its rest angle, so the forces equal those of the same wing on
//! prescribed kinematics with that pitch (today's path). A DC motor's stall torque and
//! no-load speed are K_t V / R and V / K_e.

use std::f64::consts::PI;

use flapsim::Vehicle;
use flapsim::actuated::{
    Actuator, DcMotor, Drive, DynamicWing, Hinge, Piezo, ResponseOptions, Stroke, WingDynamics,
    WingInertia, WingState, frequency_response,
};
use wingforce::{BodyMotion, KinematicsSpec, Validator, Wing};

/// Steinmeyer et al. (2019) lumped RoboBee stroke parameters (after Jafferis et al. 2016):
/// m_a = 25 mg, k_a = 300 N/m, T = 2666 rad/m, k_t = 28.2 uN m/rad, J = 51.1 mg mm^2.
fn robobee_piezo() -> Piezo {
    Piezo {
        mass_kg: 25e-6,
        stiffness_n_m: 300.0,
        damping_n_s_m: 0.0,
        force_per_volt_n_v: 3e-4,
        transmission_rad_m: 2666.0,
        voltage_limit_v: 300.0,
    }
}

const J_STROKE: f64 = 51.1e-12;
const K_FLEXURE: f64 = 28.2e-6;

fn structural(com_chord_m: f64, stroke_damping: f64) -> WingDynamics {
    WingDynamics {
        inertia: WingInertia {
            mass_kg: 0.5e-6,
            stroke_inertia_kg_m2: J_STROKE,
            pitch_inertia_kg_m2: 1.5e-12,
            com_span_m: 6e-3,
            com_chord_m,
        },
        hinge: Hinge {
            stiffness_nm_rad: 2.5e-6,
            damping_nm_s_rad: 0.0,
            rest_rad: 0.5 * PI,
            break_rad: 1.5,
            contact: None,
        },
        stroke: Stroke::Driven {
            actuator: Actuator::Piezo(robobee_piezo()),
            flexure_nm_rad: K_FLEXURE,
            damping_nm_s_rad: stroke_damping,
            rest_rad: 0.0,
        },
        substeps: 1,
        aero: false,
    }
}

/// A wing for the aerodynamic loads (the RoboBee-class built-in's left wing).
fn robobee_wing() -> Wing {
    Vehicle::from_toml(flapsim::ROBOBEE_KINEMATIC_TOML, "robobee")
        .unwrap()
        .wings[0]
        .clone()
}

/// Upward zero crossings of a sampled signal, interpolated linearly.
fn upward_crossings(t: &[f64], x: &[f64]) -> Vec<f64> {
    (1..x.len())
        .filter(|&i| x[i - 1] < 0.0 && x[i] >= 0.0)
        .map(|i| t[i - 1] + (t[i] - t[i - 1]) * x[i - 1] / (x[i - 1] - x[i]))
        .collect()
}

/// Runs `periods` periods of `f_hz` at 100 steps each; returns (times, phi, theta, energy).
fn free_run(
    model: WingDynamics,
    start: WingState,
    f_hz: f64,
    periods: usize,
) -> (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut w = DynamicWing::new(model, Drive::sine(f_hz, 0.0)).unwrap();
    w.set_state(start);
    let mut wing = robobee_wing();
    let dt = 1.0 / (100.0 * f_hz);
    let (mut t, mut phi, mut th, mut e) = (vec![], vec![], vec![], vec![]);
    for _ in 0..100 * periods {
        t.push(w.t_s());
        phi.push(w.state().phi_rad);
        th.push(w.state().theta_rad - 0.5 * PI);
        e.push(w.energy_j());
        w.step(&mut wing, &BodyMotion::default(), dt).unwrap();
    }
    (t, phi, th, e)
}

fn measured_freq(t: &[f64], x: &[f64]) -> f64 {
    let c = upward_crossings(t, x);
    (c.len() - 1) as f64 / (c[c.len() - 1] - c[0])
}

#[test]
fn stroke_free_oscillation_matches_the_analytic_natural_frequency() {
    let model = structural(0.0, 0.0);
    let p = robobee_piezo();
    let t2 = p.transmission_rad_m.powi(2);
    let f_n =
        ((p.stiffness_n_m + t2 * K_FLEXURE) / (p.mass_kg + t2 * J_STROKE)).sqrt() / (2.0 * PI);
    // The issue quotes "about 181 Hz" for this set.
    assert!((f_n - 181.0).abs() < 1.0, "f_n = {f_n}");
    assert!((model.stroke_natural_freq_hz() / f_n - 1.0).abs() < 1e-12);
    let start = WingState {
        phi_rad: 0.4,
        theta_rad: 0.5 * PI,
        ..Default::default()
    };
    let (t, phi, _, e) = free_run(model, start, f_n, 100);
    let f = measured_freq(&t, &phi);
    assert!(
        (f / f_n - 1.0).abs() < 5e-3,
        "measured {f} Hz, analytic {f_n} Hz"
    );
    // RK4 at 100 steps per period: amplitude error per step ~ (w h)^6 / 144, so about 1e-5 in
    // energy over 100 periods; bound stated in the dynamics module doc.
    let drift = e.iter().map(|x| (x / e[0] - 1.0).abs()).fold(0.0, f64::max);
    assert!(drift < 1e-5, "energy drift {drift:e} over 100 periods");
}

#[test]
fn pitch_mode_matches_sqrt_kh_over_i_pitch() {
    let model = structural(0.0, 0.0);
    let f_p =
        (model.hinge.stiffness_nm_rad / model.inertia.pitch_inertia_kg_m2).sqrt() / (2.0 * PI);
    assert!((model.pitch_natural_freq_hz() / f_p - 1.0).abs() < 1e-12);
    let start = WingState {
        theta_rad: 0.5 * PI + 0.2,
        ..Default::default()
    };
    let (t, _, th, e) = free_run(model, start, f_p, 100);
    let f = measured_freq(&t, &th);
    assert!(
        (f / f_p - 1.0).abs() < 5e-3,
        "measured {f} Hz, analytic {f_p} Hz"
    );
    let drift = e.iter().map(|x| (x / e[0] - 1.0).abs()).fold(0.0, f64::max);
    assert!(drift < 1e-5, "energy drift {drift:e}");
}

#[test]
fn coupled_stroke_and_pitch_conserve_energy() {
    // The centre of mass 0.3 mm behind the pitch axis couples the two degrees of freedom
    // through the product of inertia and the Coriolis and centrifugal terms; a sign slip in
    // any of them would pump or drain energy. Large amplitudes, 100 stroke periods.
    let mut model = structural(-0.3e-3, 0.0);
    // No stops in the way: this is about the equations, not the hinge's travel.
    model.hinge.break_rad = 3.0;
    let f = model.stroke_natural_freq_hz();
    let start = WingState {
        phi_rad: 0.5,
        theta_rad: 0.5 * PI + 0.2,
        ..Default::default()
    };
    let (_, _, th, e) = free_run(model, start, f, 100);
    let drift = e.iter().map(|x| (x / e[0] - 1.0).abs()).fold(0.0, f64::max);
    assert!(drift < 1e-4, "energy drift {drift:e}");
    // and the pitch really moved (the coupling is exercised).
    let span = th.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
        - th.iter().cloned().fold(f64::INFINITY, f64::min);
    assert!(span > 0.1, "pitch span {span}");
}

/// A vehicle built from the RoboBee-class built-in with an actuation section whose
/// aerodynamics are switched off (structural frequency response).
fn vehicle_with(actuation: &str) -> Vehicle {
    let text = format!("{}\n{actuation}", flapsim::ROBOBEE_KINEMATIC_TOML);
    Vehicle::from_toml(&text, "test").unwrap()
}

const ACTUATION: &str = r#"
[actuation]
substeps = 1
[actuation.wing_inertia]
mass_kg = 0.5e-6
stroke_inertia_kg_m2 = 51.1e-12
pitch_inertia_kg_m2 = 1.5e-12
com_span_m = 6.0e-3
com_chord_m = 0.0
[actuation.hinge]
stiffness_nm_rad = 2.5e-6
[actuation.stroke]
flexure_nm_rad = 28.2e-6
damping_nm_s_rad = 2.0e-8
[actuation.piezo]
mass_kg = 25e-6
stiffness_n_m = 300.0
force_per_volt_n_v = 3e-4
transmission_rad_m = 2666.0
voltage_limit_v = 300.0
[actuation.drive]
freq_hz = 120.0
amplitude_v = 50.0
"#;

#[test]
fn forced_response_matches_the_second_order_transfer_function() {
    let mut v = vehicle_with(ACTUATION);
    let act = v.actuation.as_mut().unwrap();
    act.dynamics.aero = false;
    let d = act.dynamics.clone();
    let Stroke::Driven {
        actuator,
        damping_nm_s_rad,
        flexure_nm_rad,
        ..
    } = &d.stroke
    else {
        panic!()
    };
    let r = actuator.reflected();
    let j = d.stroke_inertia_kg_m2();
    let k = r.stiffness_nm_rad + flexure_nm_rad;
    let c = r.damping_nm_s_rad + damping_nm_s_rad;
    let opts = ResponseOptions {
        freqs_hz: vec![100.0, 150.0, 175.0, 181.0, 190.0, 220.0, 300.0],
        amplitudes_v: vec![50.0],
        settle_cycles: 60,
        measure_cycles: 4,
        steps_per_cycle: 200,
    };
    let resp = frequency_response(&v, &opts, &|| {}).unwrap();
    for p in &resp.points {
        let w = 2.0 * PI * p.freq_hz;
        let re = k - j * w * w;
        let im = c * w;
        let amp = r.torque_per_volt_nm_v * p.amplitude_v / (re * re + im * im).sqrt();
        let lag = im.atan2(re).to_degrees();
        let got = p.stroke_amplitude_deg.to_radians();
        assert!(
            (got / amp - 1.0).abs() < 0.01,
            "{} Hz: amplitude {got} rad, analytic {amp} rad",
            p.freq_hz
        );
        assert!(
            (p.stroke_lag_deg - lag).abs() < 0.01 * 180.0,
            "{} Hz: lag {} deg, analytic {lag} deg",
            p.freq_hz,
            p.stroke_lag_deg
        );
    }
}

#[test]
fn dc_motor_stall_torque_and_no_load_speed_are_analytic() {
    // Motor of the Purdue hummingbird robot (flappy simulator configuration, nominal):
    // R = 12.4 ohm, K_t = 1.75e-3 N m/A, gear ratio 10, efficiency 0.85, rotor 7.03e-10 kg m^2.
    let m = DcMotor {
        resistance_ohm: 12.4,
        torque_constant_nm_a: 1.75e-3,
        back_emf_v_s_rad: 1.75e-3,
        rotor_inertia_kg_m2: 7.03e-10,
        shaft_damping_nm_s_rad: 0.0,
        gear_ratio: 10.0,
        gear_efficiency: 0.85,
        voltage_limit_v: 20.0,
    };
    let v = 6.0;
    assert!((m.stall_torque_nm(v) - 1.75e-3 * 6.0 / 12.4).abs() < 1e-15);
    assert!((m.shaft_torque_nm(v, 0.0) - m.stall_torque_nm(v)).abs() < 1e-15);
    assert!(m.shaft_torque_nm(v, m.no_load_speed_rad_s(v)).abs() < 1e-15);
    // Integrated: with no spring, no aerodynamics and a constant voltage the stroke runs up
    // to the no-load speed V / (K_e G) and starts with the stall torque's acceleration.
    let model = WingDynamics {
        inertia: WingInertia {
            mass_kg: 35e-6,
            stroke_inertia_kg_m2: 59.5e-9,
            pitch_inertia_kg_m2: 4.7e-9,
            com_span_m: 37.4e-3,
            com_chord_m: 0.0,
        },
        hinge: Hinge {
            stiffness_nm_rad: 1e-3,
            damping_nm_s_rad: 0.0,
            rest_rad: 0.5 * PI,
            break_rad: 1.0,
            contact: None,
        },
        stroke: Stroke::Driven {
            actuator: Actuator::DcMotor(m),
            flexure_nm_rad: 0.0,
            damping_nm_s_rad: 0.0,
            rest_rad: 0.0,
        },
        substeps: 1,
        aero: false,
    };
    let j = model.stroke_inertia_kg_m2();
    let mut w = DynamicWing::new(
        model,
        Drive {
            freq_hz: 34.0,
            bias_v: v,
            amplitude_v: 0.0,
            second_harmonic: 0.0,
            second_harmonic_phase_rad: 0.0,
        },
    )
    .unwrap();
    let mut wing = robobee_wing();
    let first = w.step(&mut wing, &BodyMotion::default(), 1e-5).unwrap();
    let stall_acc = 0.85 * 10.0 * m.stall_torque_nm(v) / j;
    assert!(
        (first.angles.phi_ddot / stall_acc - 1.0).abs() < 1e-9,
        "{} vs {stall_acc}",
        first.angles.phi_ddot
    );
    assert!((first.actuator.current_a - v / 12.4).abs() < 1e-12);
    for _ in 0..200_000 {
        w.step(&mut wing, &BodyMotion::default(), 1e-5).unwrap();
    }
    let shaft = 10.0 * w.state().phi_dot_rad_s;
    assert!(
        (shaft / m.no_load_speed_rad_s(v) - 1.0).abs() < 1e-6,
        "shaft {shaft} rad/s"
    );
}

#[test]
fn a_stiff_hinge_reproduces_the_prescribed_kinematics_forces() {
    // Stroke prescribed (harmonic, 120 Hz, 90 deg), pitch held at 60 deg by a hinge whose
    // natural frequency is 5 kHz, critically damped: its forces must match the same wing on
    // prescribed kinematics with the pitch fixed at 60 deg (harmonic, mid-stroke AoA 90 deg,
    // pitch bias -30 deg) within 1% of the peak force.
    let spec: KinematicsSpec = toml::from_str(
        "family = \"harmonic\"\nfreq_hz = 120.0\namplitude_deg = 90.0\nmid_stroke_aoa_deg = 90.0\npitch_bias_deg = -30.0",
    )
    .unwrap();
    let mut prescribed = robobee_wing();
    let kin = spec
        .build(
            &Validator::new("test"),
            "k",
            prescribed.geometry().r_gyration_m,
        )
        .unwrap();
    prescribed.set_kinematics(kin.clone());
    let b = 1.5e-12;
    let f_p = 5000.0;
    let k_h = b * (2.0 * PI * f_p).powi(2);
    let model = WingDynamics {
        inertia: WingInertia {
            mass_kg: 0.5e-6,
            stroke_inertia_kg_m2: J_STROKE,
            pitch_inertia_kg_m2: b,
            com_span_m: 6e-3,
            com_chord_m: 0.0,
        },
        hinge: Hinge {
            stiffness_nm_rad: k_h,
            damping_nm_s_rad: 2.0 * (k_h * b).sqrt(),
            rest_rad: 60f64.to_radians(),
            break_rad: 1.0,
            contact: None,
        },
        stroke: Stroke::Prescribed(kin),
        substeps: 8,
        aero: true,
    };
    let mut w = DynamicWing::new(model, Drive::sine(120.0, 0.0)).unwrap();
    let mut wing = prescribed.clone();
    let n = 100;
    let dt = 1.0 / (120.0 * n as f64);
    let body = BodyMotion::default();
    let mut worst = 0.0f64;
    let mut peak = 0.0f64;
    for k in 0..4 * n {
        let s = w.step(&mut wing, &body, dt).unwrap();
        if k >= 3 * n {
            // The dynamics apply the impulse-form added mass as the fluid impulse's change
            // over the step (its mean over the step: the value at mid-step to second
            // order); the other terms at the step's start.
            let at = |u: f64| prescribed.evaluate(u, &body);
            let (start, mid) = (at(k as f64 / n as f64), at((k as f64 + 0.5) / n as f64));
            let am = wingforce::Term::AddedMass as usize;
            let f_ref = start.total.force_n - start.terms[am].force_n + mid.terms[am].force_n;
            worst = worst.max((s.forces.total.force_n - f_ref).norm());
            peak = peak.max(f_ref.norm());
        }
    }
    assert!(
        worst < 0.01 * peak,
        "largest difference {worst:e} N, peak force {peak:e} N"
    );
}
