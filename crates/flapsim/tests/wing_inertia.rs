//! The wing's own inertial coupling (`flapsim::actuated::dynamics`), checked against
//! analytic results.
//!
//! A thin rigid wing on a hinge at the stroke axis, stroke phi about the stroke-plane
//! normal, pitch theta about the span: with J = int r^2 dm, B = int x^2 dm and the product
//! C = int r x dm = m r_c x_c (x towards the leading edge), its kinetic energy is
//!
//!   T = 1/2 B theta_dot^2 + 1/2 (J + B cos^2 theta) phi_dot^2 - C sin(theta) phi_dot theta_dot
//!
//! (derived in the module doc of `dynamics/mod.rs` from omega^T I omega with
//! omega = phi_dot k_phi + theta_dot k_theta and the plate's inertia tensor). Three checks:
//!
//! 1. Energy. Without drive, damping and aerodynamics the two-degree-of-freedom system
//!    (stroke spring, hinge spring, centre of mass behind the pitch axis, large motions)
//!    keeps T + V to 1e-9 of itself.
//! 2. A cyclic coordinate. With no stroke spring the stroke angle does not appear in the
//!    Lagrangian, so its momentum p_phi = (J + J_a + B cos^2 theta) phi_dot -
//!    C sin(theta) theta_dot is conserved (to 1e-9), while phi_dot itself swings as the
//!    wing pitches: this checks the B cos^2 theta and C sin theta terms and their sign
//!    against each other.
//! 3. The linearised forced response. With the stroke prescribed as a small sinusoid
//!    (1 deg) and theta = pi/2 + psi, the pitch equation
//!    B theta_dd - C sin(theta) phi_dd + B sin(theta) cos(theta) phi_d^2
//!    = -k_h psi - c_h psi_d becomes B psi_dd + c_h psi_d + k_h psi = C phi_dd (the
//!    parametric term B phi_d^2 psi is 1e-4 of k_h psi here), so the steady pitch is
//!    psi = Re[C Phi_dd e^(i w t) / (k_h - B w^2 + i c_h w)]: matched to 1e-3 in amplitude
//!    and 0.1 deg in phase, for the centre of mass behind the axis and in front of it (the
//!    sign: behind the axis, the wing's trailing edge lags the stroke's acceleration).

use std::f64::consts::PI;

use flapsim::Vehicle;
use flapsim::actuated::{
    Actuator, Drive, DynamicWing, Hinge, Piezo, Stroke, WingDynamics, WingInertia, WingState,
};
use wingforce::{BodyMotion, KinematicsSpec, Validator, Wing};

fn wing() -> Wing {
    Vehicle::from_toml(flapsim::ROBOBEE_KINEMATIC_TOML, "robobee")
        .unwrap()
        .wings[0]
        .clone()
}

const B: f64 = 1.5e-12;
const K_H: f64 = 2.5e-6;

fn inertia(com_chord_m: f64) -> WingInertia {
    WingInertia {
        mass_kg: 0.5e-6,
        stroke_inertia_kg_m2: 51.1e-12,
        pitch_inertia_kg_m2: B,
        // A large product: C = -5e-12 kg m^2, C^2 / (B J) = 0.33.
        com_span_m: 10e-3,
        com_chord_m,
    }
}

fn free(com_chord_m: f64, stroke_spring: f64) -> DynamicWing {
    let model = WingDynamics {
        inertia: inertia(com_chord_m),
        hinge: Hinge {
            stiffness_nm_rad: K_H,
            damping_nm_s_rad: 0.0,
            rest_rad: 0.5 * PI,
            break_rad: f64::INFINITY,
            contact: None,
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
            flexure_nm_rad: stroke_spring,
            damping_nm_s_rad: 0.0,
            rest_rad: 0.0,
        },
        substeps: 1,
        aero: false,
    };
    DynamicWing::new(model, Drive::sine(100.0, 0.0)).unwrap()
}

/// p_phi = (J + J_a + B cos^2 theta) phi_dot - C sin(theta) theta_dot.
fn stroke_momentum(w: &DynamicWing) -> f64 {
    let m = w.model();
    let s = w.state();
    (m.stroke_inertia_kg_m2() + B * s.theta_rad.cos().powi(2)) * s.phi_dot_rad_s
        - m.inertia.product_kg_m2() * s.theta_rad.sin() * s.theta_dot_rad_s
}

#[test]
fn the_free_two_degree_of_freedom_wing_keeps_its_energy() {
    for com_chord in [-1e-3, 1e-3] {
        let mut w = free(com_chord, 28.2e-6);
        w.set_state(WingState {
            phi_rad: 0.8,
            theta_rad: 0.5 * PI + 1.0,
            phi_dot_rad_s: -300.0,
            theta_dot_rad_s: 500.0,
        });
        let e0 = w.energy_j();
        let mut wing = wing();
        let body = BodyMotion::default();
        // The pitch mode is near 200 Hz: 2e-6 s steps, 40 ms.
        let mut worst = 0.0f64;
        for _ in 0..20_000 {
            w.step(&mut wing, &body, 2e-6).unwrap();
            worst = worst.max((w.energy_j() / e0 - 1.0).abs());
        }
        assert!(worst < 1e-9, "x_c {com_chord}: energy drift {worst:e}");
        eprintln!("x_c {com_chord}: largest relative energy change {worst:.2e}");
    }
}

#[test]
fn the_stroke_momentum_is_conserved_when_the_stroke_is_cyclic() {
    for com_chord in [-1e-3, 1e-3] {
        let mut w = free(com_chord, 0.0);
        w.set_state(WingState {
            phi_rad: 0.0,
            theta_rad: 0.5 * PI + 0.9,
            phi_dot_rad_s: 200.0,
            theta_dot_rad_s: -400.0,
        });
        let (p0, e0) = (stroke_momentum(&w), w.energy_j());
        let mut wing = wing();
        let body = BodyMotion::default();
        let (mut worst_p, mut worst_e) = (0.0f64, 0.0f64);
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for _ in 0..20_000 {
            w.step(&mut wing, &body, 2e-6).unwrap();
            worst_p = worst_p.max((stroke_momentum(&w) / p0 - 1.0).abs());
            worst_e = worst_e.max((w.energy_j() / e0 - 1.0).abs());
            lo = lo.min(w.state().phi_dot_rad_s);
            hi = hi.max(w.state().phi_dot_rad_s);
        }
        assert!(worst_p < 1e-9, "x_c {com_chord}: p_phi drift {worst_p:e}");
        assert!(worst_e < 1e-9, "x_c {com_chord}: energy drift {worst_e:e}");
        // Not trivially conserved: the stroke rate itself swings by several percent.
        assert!(hi - lo > 0.02 * hi.abs(), "phi_dot {lo}..{hi}");
        eprintln!(
            "x_c {com_chord}: p_phi drift {worst_p:.2e}, energy drift {worst_e:.2e}, phi_dot {lo:.2}..{hi:.2} rad/s"
        );
    }
}

#[test]
fn a_small_prescribed_stroke_drives_the_pitch_as_the_linearised_equation_says() {
    let f = 100.0;
    let w_rad = 2.0 * PI * f;
    let spec: KinematicsSpec = toml::from_str(&format!(
        "family = \"harmonic\"\nfreq_hz = {f:?}\namplitude_deg = 2.0\nmid_stroke_aoa_deg = 45.0"
    ))
    .unwrap();
    let wg = wing();
    let kin = spec
        .build(&Validator::new("test"), "k", wg.geometry().r_gyration_m)
        .unwrap();
    // Pitch mode at sqrt(k_h / B) / 2 pi = 205 Hz, 5% damped.
    let c_h = 2.0 * 0.05 * (K_H * B).sqrt();
    for com_chord in [-1e-3, 1e-3] {
        let model = WingDynamics {
            inertia: inertia(com_chord),
            hinge: Hinge {
                stiffness_nm_rad: K_H,
                damping_nm_s_rad: c_h,
                rest_rad: 0.5 * PI,
                break_rad: f64::INFINITY,
                contact: None,
            },
            stroke: Stroke::Prescribed(kin.clone()),
            substeps: 1,
            aero: false,
        };
        let c = model.inertia.product_kg_m2();
        let mut w = DynamicWing::new(model, Drive::sine(f, 0.0)).unwrap();
        let mut wing = wg.clone();
        let body = BodyMotion::default();
        let n = 1000;
        let dt = 1.0 / (f * n as f64);
        // Fourier coefficients at w of phi_dd and psi over 5 periods after 40.
        let (mut a_re, mut a_im, mut p_re, mut p_im) = (0.0, 0.0, 0.0, 0.0);
        for k in 0..45 * n {
            let s = w.step(&mut wing, &body, dt).unwrap();
            if k >= 40 * n {
                let t = k as f64 * dt;
                let (sn, cs) = (w_rad * t).sin_cos();
                let psi = s.angles.theta - 0.5 * PI;
                let acc = kin.angles(t * f).phi_ddot;
                a_re += acc * cs;
                a_im -= acc * sn;
                p_re += psi * cs;
                p_im -= psi * sn;
            }
        }
        // Expected: psi_hat = C phi_dd_hat / (k_h - B w^2 + i c_h w).
        let (d_re, d_im) = (K_H - B * w_rad * w_rad, c_h * w_rad);
        let den = d_re * d_re + d_im * d_im;
        let e_re = c * (a_re * d_re + a_im * d_im) / den;
        let e_im = c * (a_im * d_re - a_re * d_im) / den;
        let amp = (p_re * p_re + p_im * p_im).sqrt();
        let amp_e = (e_re * e_re + e_im * e_im).sqrt();
        let dphase = (p_im.atan2(p_re) - e_im.atan2(e_re)).to_degrees();
        let dphase = (dphase + 180.0).rem_euclid(360.0) - 180.0;
        assert!(
            (amp / amp_e - 1.0).abs() < 1e-3,
            "x_c {com_chord}: amplitude {amp:e} vs {amp_e:e}"
        );
        assert!(
            dphase.abs() < 0.1,
            "x_c {com_chord}: phase off by {dphase} deg"
        );
        // The sign: with the centre of mass behind the axis (C < 0) and the drive below the
        // pitch mode, the pitch is opposite to the stroke acceleration.
        let in_phase_with_acc = (p_re * a_re + p_im * a_im) > 0.0;
        assert_eq!(in_phase_with_acc, c > 0.0, "x_c {com_chord}");
        eprintln!(
            "x_c {com_chord}: pitch amplitude {:.6e} rad (linear theory {:.6e}), phase off {dphase:.4} deg",
            amp * 2.0 / 5000.0,
            amp_e * 2.0 / 5000.0
        );
    }
}
