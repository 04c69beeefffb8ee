//! The added-mass term's forms (MODEL.md 4.3, revised).
//!
//! A thin flat plate's strip in 2-D ideal flow carries the fluid impulse P = m' v_n n,
//! m' = (pi/4) rho c^2 dr, with v_n the normal velocity of its mid-chord point. The impulse
//! form's force is -dP/dt, so:
//! * over a periodic motion P repeats and the force's cycle mean is zero in every direction
//!   (added mass carries no weight), whatever the kinematics: a property test on random
//!   harmonic kinematics with deviation, pitch phase and bias, on random planforms;
//! * it is the time derivative of the impulse computed from nothing but the wing points'
//!   positions (finite differences of positions and of P, on a rectangle whose span
//!   integrals Gauss-Legendre quadrature takes exactly);
//! * in the planar case (no deviation), with this crate's conventions (t the direction of
//!   increasing stroke angle phi, n = d e_le / d theta, x from the pitch axis towards the
//!   leading edge) v_n = x theta_dot - r phi_dot sin(theta), so per strip the normal part is
//!   m' (r phi_ddot sin theta + r phi_dot theta_dot cos theta - x theta_ddot), the chordwise
//!   part m' v_n theta_dot and the spanwise part -m' v_n phi_dot sin theta: the issue's
//!   -m' (r psi_ddot sin theta + r psi_dot theta_dot cos theta + x_m theta_ddot) and
//!   m' v_n theta_dot with its stroke angle psi = -phi;
//! * a plate pitching about an axis at x from its mid-chord feels the non-circulatory pitch
//!   moment -(pi rho c^4 / 128 + m' x^2) theta_ddot per unit span (Theodorsen 1935, NACA
//!   Report 496, the apparent-mass moment of inertia pi rho b^4 (1/8 + a^2) with b = c/2,
//!   a = x / b);
//! * the added inertia the actuated wing moves to its inertia side is exactly the
//!   acceleration-proportional part of the term's generalized moments, in both forms.
//!
//! The paper's form (eq 7-8) fails the first property: its cycle mean is shown non-zero on
//! the paper's own robofly kinematics, where the impulse form's is zero.

use std::f64::consts::PI;

use nalgebra::Vector3;
use proptest::prelude::*;
use wingforce::wing::WingFrame;
use wingforce::{AddedMassForm, Wing, WingAngles, WingModelSpec};

/// A wing with only the added-mass term, in `form`, on a fixed mount (body = stroke frame).
fn wing(planform: &str, kinematics: &str, form: &str) -> Wing {
    let text = format!(
        "name = \"t\"\n[fluid]\ndensity_kg_m3 = 1000.0\nkinematic_viscosity_m2_s = 1e-6\n\
         [wing.planform]\n{planform}\n[kinematics]\n{kinematics}\n\
         [aero]\nrotational = false\nwake_capture = false\nadded_mass = \"{form}\"\n"
    );
    WingModelSpec::from_toml(&text, "test.toml")
        .unwrap()
        .build("test.toml")
        .unwrap()
}

fn harmonic(amp_deg: f64, aoa_deg: f64, phase_deg: f64, dev_deg: f64, bias_deg: f64) -> String {
    format!(
        "family = \"harmonic\"\nfreq_hz = 20.0\namplitude_deg = {amp_deg}\n\
         mid_stroke_aoa_deg = {aoa_deg}\npitch_phase_deg = {phase_deg}\n\
         deviation_amplitude_deg = {dev_deg}\nmean_stroke_deg = 10.0\npitch_bias_deg = {bias_deg}"
    )
}

fn rectangle(span: f64, chord: f64, root: f64, axis: f64) -> String {
    format!(
        "shape = \"rectangular\"\nspan_m = {span}\nchord_m = {chord}\nroot_offset_m = {root}\n\
         pitch_axis_from_le_frac = {axis}"
    )
}

/// The added-mass force's cycle mean and its peak magnitude, over `n` phases.
fn mean_and_peak(w: &Wing, n: usize) -> (Vector3<f64>, f64) {
    let mut mean = Vector3::zeros();
    let mut peak: f64 = 0.0;
    for k in 0..n {
        let f = w.kinematic_loads(k as f64 / n as f64).terms[2].force_n;
        mean += f / n as f64;
        peak = peak.max(f.norm());
    }
    (mean, peak)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn impulse_form_carries_no_mean_force(
        amp in 60.0f64..170.0,
        aoa in 15.0f64..70.0,
        phase in -40.0f64..40.0,
        dev in 0.0f64..20.0,
        bias in -10.0f64..10.0,
        span in 0.01f64..0.3,
        aspect in 2.0f64..6.0,
        root_frac in 0.0f64..0.5,
        axis in 0.0f64..1.0,
        elliptic in any::<bool>(),
    ) {
        let chord = span / aspect;
        let planform = if elliptic {
            format!(
                "shape = \"elliptic\"\nspan_m = {span}\nmax_chord_m = {chord}\n\
                 root_offset_m = {}\npitch_axis_from_le_frac = {axis}",
                root_frac * span
            )
        } else {
            rectangle(span, chord, root_frac * span, axis)
        };
        let w = wing(&planform, &harmonic(amp, aoa, phase, dev, bias), "impulse");
        // The force is smooth and periodic: the mean of equally spaced samples converges
        // faster than any power of their number.
        let (mean, peak) = mean_and_peak(&w, 4096);
        prop_assert!(peak > 0.0);
        prop_assert!(mean.norm() <= 1e-9 * peak, "mean {mean:?}, peak {peak:e}");
    }
}

#[test]
fn the_papers_form_carries_a_mean_force_the_impulse_form_does_not() {
    let text = include_str!("../../../models/robofly.toml");
    let mut spec = WingModelSpec::from_toml(text, "robofly").unwrap();
    spec.aero.rotational = false;
    spec.aero.wake_capture = false;
    let mut means = Vec::new();
    for form in [AddedMassForm::Paper, AddedMassForm::Impulse] {
        spec.aero.added_mass = form;
        let w = spec.build("robofly").unwrap();
        // Trapezoidal kinematics have kinks in their accelerations: many samples.
        let (mean, peak) = mean_and_peak(&w, 200_000);
        means.push(mean.z / peak);
    }
    // The paper's form lifts by a few per cent of its peak on the paper's own wing; the
    // impulse form's mean is zero to the sampling of the kinks.
    assert!(means[0] > 0.01, "paper form mean lift / peak {}", means[0]);
    assert!(
        means[1].abs() < 1e-6,
        "impulse form mean lift / peak {}",
        means[1]
    );
}

/// Gauss-Legendre nodes and weights on [-1, 1], three points (exact to degree 5).
const GL3: [(f64, f64); 3] = [
    (-0.774_596_669_241_483_4, 5.0 / 9.0),
    (0.0, 8.0 / 9.0),
    (0.774_596_669_241_483_4, 5.0 / 9.0),
];

#[test]
fn impulse_form_is_minus_the_rate_of_the_fluid_impulse() {
    let (span, chord, root, axis) = (0.2, 0.06, 0.05, 0.2);
    let rho = 1000.0;
    let kin = harmonic(140.0, 35.0, 15.0, 12.0, 5.0);
    let w = wing(&rectangle(span, chord, root, axis), &kin, "impulse");
    let side = w.mount().side;
    let freq = w.kinematics().freq_hz;
    // Mid-chord offset from the pitch axis, towards the leading edge.
    let x_mid = (axis - 0.5) * chord;
    let m_per_m = 0.25 * PI * rho * chord * chord;
    let frame_at = |t: f64| WingFrame::new(&w.kinematics().angles(t * freq), side);
    let point = |fr: &WingFrame, r: f64| r * fr.e_span + x_mid * fr.e_le;
    // The impulse at time t from positions alone: v by a central difference.
    let d = 1e-7;
    let impulse = |t: f64| {
        let (a, b, c) = (frame_at(t - d), frame_at(t), frame_at(t + d));
        let mut p = Vector3::zeros();
        for (u, wt) in GL3 {
            let r = root + 0.5 * span * (1.0 + u);
            let v = (point(&c, r) - point(&a, r)) / (2.0 * d);
            p += 0.5 * span * wt * m_per_m * b.n.dot(&v) * b.n;
        }
        p
    };
    let h = 1e-5;
    let mut worst: f64 = 0.0;
    let mut peak: f64 = 0.0;
    for k in 0..40 {
        let t = k as f64 / (40.0 * freq);
        let fd = -(impulse(t + h) - impulse(t - h)) / (2.0 * h);
        let ours = w.kinematic_loads(t * freq).terms[2].force_n;
        worst = worst.max((ours - fd).norm());
        peak = peak.max(ours.norm());
    }
    assert!(worst < 1e-5 * peak, "worst {worst:e} of peak {peak:e}");
}

#[test]
fn planar_impulse_form_matches_the_strip_formulas() {
    let (span, chord, root, axis) = (0.25, 0.08, 0.1, 0.3);
    let rho = 1000.0;
    let w = wing(
        &rectangle(span, chord, root, axis),
        &harmonic(150.0, 40.0, 20.0, 0.0, 0.0),
        "impulse",
    );
    let x = (axis - 0.5) * chord;
    let c2 = chord * chord;
    let k = 0.25 * PI * rho;
    // Span integrals of c^2 and c^2 r over the rectangle.
    let (i0, i1) = (c2 * span, c2 * ((root + span).powi(2) - root * root) / 2.0);
    for j in 0..64 {
        let phase = j as f64 / 64.0;
        let a = w.kinematics().angles(phase);
        let loads = w.kinematic_loads(phase);
        let (fr, f) = (loads.frame, loads.terms[2].force_n);
        let (st, ct) = a.theta.sin_cos();
        // The strips' m' v_n and m' dv_n/dt summed: v_n = x theta_dot - r phi_dot sin theta.
        let mv = k * (x * a.theta_dot * i0 - a.phi_dot * st * i1);
        let normal =
            k * ((a.phi_ddot * st + a.phi_dot * a.theta_dot * ct) * i1 - x * a.theta_ddot * i0);
        let scale = f.norm().max(1e-12);
        let check = |got: f64, want: f64, what: &str| {
            assert!(
                (got - want).abs() < 1e-10 * scale,
                "phase {phase}: {what} {got:e} vs {want:e}"
            );
        };
        check(f.dot(&fr.n), normal, "normal");
        check(f.dot(&fr.e_le), mv * a.theta_dot, "chordwise");
        check(f.dot(&fr.e_span), -mv * a.phi_dot * st, "spanwise");
    }
}

#[test]
fn pitching_plate_feels_theodorsens_apparent_inertia() {
    let (span, chord, root, axis) = (0.2, 0.05, 0.0, 0.15);
    let rho = 1000.0;
    let w = wing(
        &rectangle(span, chord, root, axis),
        &harmonic(120.0, 40.0, 0.0, 0.0, 0.0),
        "impulse",
    );
    let side = w.mount().side;
    let x = (axis - 0.5) * chord;
    // Per unit span pi rho c^4 / 128 + m' x^2, times the span.
    let inertia =
        (PI * rho * chord.powi(4) / 128.0 + 0.25 * PI * rho * chord * chord * x * x) * span;
    for (theta, theta_ddot) in [(0.3, 500.0), (1.2, -800.0), (-0.7, 40.0)] {
        // Pure pitch from rest: no stroke, no pitch rate.
        let a = WingAngles {
            theta,
            theta_ddot,
            ..WingAngles::default()
        };
        let frame = WingFrame::new(&a, side);
        let loads = w.kinematic_loads_in(&a, &w.kinematics().stroke_phase(0.0), &frame);
        let m = w.axis_moments(&frame, &loads.terms[2]).pitch_nm;
        let alpha_about_axis = frame.alpha.dot(&frame.pitch_axis(side));
        let want = -inertia * alpha_about_axis;
        assert!(
            (m - want).abs() < 1e-12 * want.abs(),
            "theta {theta}: pitch moment {m:e} vs {want:e}"
        );
        // And the actuated wing's added inertia about the pitch axis is the same number.
        let a11 = w.added_inertia(&frame)[1][1];
        assert!(
            (a11 - inertia).abs() < 1e-12 * inertia,
            "{a11:e} vs {inertia:e}"
        );
    }
}

#[test]
fn added_inertia_is_the_acceleration_part_of_the_generalized_moments() {
    for form in ["impulse", "paper"] {
        let w = wing(
            &rectangle(0.2, 0.06, 0.03, 0.25),
            &harmonic(140.0, 40.0, 10.0, 8.0, 0.0),
            form,
        );
        let side = w.mount().side;
        for j in 0..16 {
            let base = w.kinematics().angles(j as f64 / 16.0);
            let q = |phi_ddot: f64, theta_ddot: f64| {
                let a = WingAngles {
                    phi_ddot,
                    theta_ddot,
                    ..base
                };
                let frame = WingFrame::new(&a, side);
                let loads = w.kinematic_loads_in(&a, &w.kinematics().stroke_phase(0.0), &frame);
                let m = w.axis_moments(&frame, &loads.terms[2]);
                [m.stroke_nm, m.pitch_nm]
            };
            let frame = WingFrame::new(&base, side);
            let added = w.added_inertia(&frame);
            let q0 = q(0.0, 0.0);
            for (col, acc) in [(0usize, [300.0, 0.0]), (1, [0.0, -700.0])] {
                let qa = q(acc[0], acc[1]);
                let s = acc[col];
                for row in 0..2 {
                    // Q(q_ddot) - Q(0) = -A q_ddot.
                    let got = -(qa[row] - q0[row]) / s;
                    let want = added[row][col];
                    let tol = 1e-9 * (added[0][0].abs() + added[1][1].abs());
                    assert!(
                        (got - want).abs() < tol,
                        "{form} phase {j}/16 A[{row}][{col}]: {got:e} vs {want:e}"
                    );
                }
            }
        }
    }
}

#[test]
fn forms_are_named_and_checked() {
    for f in AddedMassForm::ALL {
        assert_eq!(AddedMassForm::from_name(f.name()), Some(f));
    }
    let bad = "name = \"t\"\n[wing.planform]\nshape = \"rectangular\"\nspan_m = 0.1\nchord_m = 0.03\n\
               [kinematics]\nfamily = \"harmonic\"\nfreq_hz = 20.0\namplitude_deg = 120.0\n\
               mid_stroke_aoa_deg = 40.0\n[aero]\nadded_mass = \"virtual\"\n";
    let e = WingModelSpec::from_toml(bad, "bad.toml")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("bad.toml") && e.contains("virtual") && e.contains("impulse"),
        "{e}"
    );
    // The switch of before still reads: true is the paper's form, false is off.
    for (written, form) in [
        ("true", AddedMassForm::Paper),
        ("false", AddedMassForm::Off),
    ] {
        let text = bad.replace("\"virtual\"", written);
        let spec = WingModelSpec::from_toml(&text, "ok.toml").unwrap();
        assert_eq!(spec.aero.added_mass, form);
    }
}

/// The impulse form's force is -dP/dt of the impulse `Wing::fluid_impulse_n_s` reports:
/// central differences of P along the motion against the force (fixed mount: body = stroke
/// frame), and the term over a step, `Wing::added_mass_over_step`, is -(P_end - P_start)/dt.
#[test]
fn the_reported_impulse_is_what_the_force_differentiates() {
    let w = wing(
        &rectangle(0.2, 0.06, 0.02, 0.3),
        &harmonic(140.0, 40.0, 10.0, 8.0, 3.0),
        "impulse",
    );
    let side = w.mount().side;
    let frame_at = |u: f64| WingFrame::new(&w.kinematics().angles(u), side);
    let freq = w.kinematics().freq_hz;
    let du = 1e-5;
    let dt = du / freq;
    for k in 0..16 {
        let u = 0.03 + k as f64 / 16.0;
        let p = |u: f64| w.fluid_impulse_n_s(&frame_at(u)).unwrap();
        let dp_dt = (p(u + du) - p(u - du)) / (2.0 * dt);
        let f = w.kinematic_loads(u).terms[2].force_n;
        assert!(
            (f + dp_dt).norm() <= 1e-6 * f.norm().max(1e-12),
            "phase {u}: force {f:?}, -dP/dt {:?}",
            -dp_dt
        );
        let at_start = w.kinematic_loads(u).terms[2];
        let step = w
            .added_mass_over_step(&frame_at(u), &frame_at(u + du), dt, &at_start, true)
            .unwrap();
        let expect = -(p(u + du) - p(u)) / dt;
        assert!((step.force_n - expect).norm() <= 1e-12 * expect.norm());
        assert_eq!(step.moment_hinge_nm, at_start.moment_hinge_nm);
    }
    let paper = wing(
        &rectangle(0.2, 0.06, 0.02, 0.3),
        &harmonic(140.0, 40.0, 10.0, 8.0, 3.0),
        "paper",
    );
    assert!(paper.fluid_impulse_n_s(&frame_at(0.1)).is_none());
}
