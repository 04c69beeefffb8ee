//! The impulse-form added mass (MODEL.md 4.3, revised) on the actuated wings' own periodic
//! motion: no cycle-mean force.
//!
//! The force of the fluid a thin plate accelerates is -dP/dt of the fluid impulse P of each
//! strip. P depends on the wing's angles and rates only (the body held still), so over a
//! periodic wing motion P repeats and the force's cycle mean is zero in every direction,
//! whatever the motion. The prescribed kinematics families are checked in
//! `wingforce/tests/added_mass.rs`; here the motion is the one the actuated vehicles' drive
//! and passive hinge produce, which no family describes (the RoboBee's pitch is not a
//! harmonic; the hummingbird's wing meets its stops).
//!
//! Two statements:
//! * On the motion's Fourier series (exact): the stroke and pitch angles of the settled
//!   cycle, transformed (a discrete Fourier transform of its samples), give an exactly
//!   periodic, band-limited motion with the same shape, whose angles, rates and
//!   accelerations follow analytically. The added-mass force on it, sampled at 4096 equally
//!   spaced phases (the rectangle rule is exact for a trigonometric polynomial of lower
//!   degree), must have a cycle mean below 1e-9 of its peak in every axis.
//! * On the simulated cycle itself: the actuated wing applies over each step the change of
//!   the fluid's impulse across it, -(P_end - P_start) / dt (`DynamicWing::step`), so the
//!   steps' forces telescope and their cycle mean is exactly -(P(T) - P(0)) / T: zero to the
//!   motion's periodicity (the settling tolerance,
//!   [`flapsim::actuated::PERIODIC_TOLERANCE_RAD`], bounds it; 1e-10 of the peak and below is
//!   measured). Holding the force at each step's start instead left 0.4% (RoboBee) and 1%
//!   (hummingbird) of the peak, about 1% of the mean lift: hence the telescoping form. The
//!   added-mass share of the vehicles' mean lift must be below 1% (issue #24); it is
//!   1e-10 and below.

use std::f64::consts::PI;

use flapsim::Vehicle;
use flapsim::actuated::periodic::settle_at_rest;
use nalgebra::Vector3;
use wingforce::{AddedMassForm, StrokePhase, Term, WingAngles, WingFrame};

/// Fourier coefficients (a_k cos + b_k sin, k = 0..n/2-1) of n equally spaced samples.
fn dft(x: &[f64]) -> Vec<(f64, f64)> {
    let n = x.len();
    (0..n / 2)
        .map(|k| {
            let (mut a, mut b) = (0.0, 0.0);
            for (j, v) in x.iter().enumerate() {
                let w = 2.0 * PI * (k * j) as f64 / n as f64;
                a += v * w.cos();
                b += v * w.sin();
            }
            let s = if k == 0 { 1.0 } else { 2.0 } / n as f64;
            (a * s, b * s)
        })
        .collect()
}

/// Value, first and second derivative at phase `u` (in periods) of the series, period `t_s`.
fn eval(c: &[(f64, f64)], u: f64, t_s: f64) -> (f64, f64, f64) {
    let (mut x, mut dx, mut ddx) = (0.0, 0.0, 0.0);
    for (k, (a, b)) in c.iter().enumerate() {
        let w = 2.0 * PI * k as f64 / t_s;
        let (s, co) = (2.0 * PI * k as f64 * u).sin_cos();
        x += a * co + b * s;
        dx += w * (-a * s + b * co);
        ddx += -w * w * (a * co + b * s);
    }
    (x, dx, ddx)
}

#[test]
fn the_actuated_wings_periodic_motion_gets_no_mean_added_mass_force() {
    for name in ["robobee", "hummingbird"] {
        let v = Vehicle::from_toml(flapsim::builtin_model(name).unwrap(), name).unwrap();
        assert_eq!(v.wings[0].options().added_mass, AddedMassForm::Impulse);
        let periodic = settle_at_rest(&v).unwrap().expect("an actuated vehicle");
        let m = &periodic.mean;
        let share = m.terms[Term::AddedMass as usize].force_n.z / m.total.force_n.z;
        assert!(
            share.abs() < 0.01,
            "{name}: added-mass share of lift {share:e}"
        );
        let period_s = 1.0 / v.actuation.as_ref().unwrap().drives[0].freq_hz;
        for side in 0..2 {
            let wing = &periodic.wings[side];
            let phi: Vec<f64> = periodic
                .samples
                .iter()
                .map(|s| s[side].angles.phi)
                .collect();
            let theta: Vec<f64> = periodic
                .samples
                .iter()
                .map(|s| s[side].angles.theta)
                .collect();

            // The raw cycle: periodic to the settling tolerance only.
            let mut raw_mean = Vector3::zeros();
            let mut raw_peak: f64 = 0.0;
            for s in &periodic.samples {
                let f = s[side].term(Term::AddedMass).force_n;
                raw_mean += f / periodic.samples.len() as f64;
                raw_peak = raw_peak.max(f.norm());
            }
            assert!(raw_peak > 0.0);
            assert!(
                raw_mean.norm() < 1e-6 * raw_peak,
                "{name} wing {side}: raw cycle mean {raw_mean:?} vs peak {raw_peak:e}"
            );

            // Its Fourier series: exactly periodic.
            let (cp, ct) = (dft(&phi), dft(&theta));
            let n = 4096;
            let mut mean = Vector3::zeros();
            let mut peak: f64 = 0.0;
            for k in 0..n {
                let u = k as f64 / n as f64;
                let (p, pd, pdd) = eval(&cp, u, period_s);
                let (t, td, tdd) = eval(&ct, u, period_s);
                let a = WingAngles {
                    phi: p,
                    theta: t,
                    phi_dot: pd,
                    theta_dot: td,
                    phi_ddot: pdd,
                    theta_ddot: tdd,
                    ..WingAngles::default()
                };
                let sp = StrokePhase {
                    half_stroke: 0,
                    t_star: 0.5,
                    downstroke: pd > 0.0,
                };
                let frame = WingFrame::new(&a, wing.mount().side);
                let f = wing.kinematic_loads_in(&a, &sp, &frame).terms[Term::AddedMass as usize]
                    .force_n;
                mean += f / n as f64;
                peak = peak.max(f.norm());
            }
            assert!(peak > 0.0);
            for axis in 0..3 {
                assert!(
                    mean[axis].abs() <= 1e-9 * peak,
                    "{name} wing {side}, axis {axis}: mean {mean:?} vs peak {peak:e}"
                );
            }
            eprintln!(
                "{name} wing {side}: raw cycle mean / peak {:.2e}, Fourier motion {:.2e}, share of lift {share:.1e}",
                raw_mean.norm() / raw_peak,
                mean.norm() / peak
            );
        }
    }
}
