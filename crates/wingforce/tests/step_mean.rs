//! The kinematic loads that represent a step (`Wing::kinematic_loads_over_step`, issue 37).
//!
//! A host that holds a load over [t_k, t_k + dt] needs the load's mean over the step. For the
//! impulse-form added mass that mean is exact: the force is -dP/dt of the fluid's impulse P,
//! so its mean is -(P_end - P_start)/dt, and the moment about the hinge is dW/dt of an angular
//! impulse W plus a remainder without accelerations (MODEL.md 4.3's strip impulse
//! m' v_n n at the mid-chord point p: p x (-dP/dt) = -d(p x P)/dt + (dp/dt) x P). So:
//! * over a wingbeat of N steps the step means of the added-mass force sum to zero whatever N
//!   (P repeats), where one sample per step does not (the pitch flip's pulse aliases);
//! * a step's mean moment equals a fine quadrature of the instantaneous moment over the step,
//!   also for a step that holds a stroke reversal and the steepest part of the flip;
//! * the wake-capture term restarts at each reversal; the step means are taken on each side
//!   of it, so the cycle mean of the step means equals the fine cycle mean at an odd step
//!   count (a reversal inside a step) as at an even one.

use wingforce::{Term, Wing, WingModelSpec};

/// A fruit-fly-like wing (the fly's planform and trapezoidal kinematics with a pitch flip of
/// 0.12 of the wingbeat) with all four terms.
fn fly_wing() -> Wing {
    let text = "name = \"t\"\n\
        [wing.planform]\nshape = \"ellington_beta\"\nspan_m = 2.39e-3\narea_m2 = 2.0e-6\n\
        r1_hat = 0.49\nroot_offset_m = 0.3e-3\npitch_axis_from_le_frac = 0.25\n\
        [kinematics]\nfamily = \"trapezoidal\"\nfreq_hz = 218.0\namplitude_deg = 140.0\n\
        mid_stroke_aoa_deg = 45.0\ndtau_a = 0.12\ndtau_d = 0.12\n";
    WingModelSpec::from_toml(text, "test.toml")
        .unwrap()
        .build("test.toml")
        .unwrap()
}

/// The fine mean of a term's (force, moment) over phases [a, b], midpoint rule on `n` points.
fn fine_mean(w: &Wing, term: Term, a: f64, b: f64, n: usize) -> ([f64; 3], [f64; 3]) {
    let (mut f, mut m) = ([0.0; 3], [0.0; 3]);
    for j in 0..n {
        let k = w.kinematic_loads(a + (j as f64 + 0.5) / n as f64 * (b - a));
        let t = &k.terms[term as usize];
        for i in 0..3 {
            f[i] += t.force_n[i] / n as f64;
            m[i] += t.moment_hinge_nm[i] / n as f64;
        }
    }
    (f, m)
}

/// A term's peak force and moment over the wingbeat.
fn peaks(w: &Wing, term: Term) -> (f64, f64) {
    (0..2000).fold((0.0f64, 0.0f64), |(pf, pm), j| {
        let k = w.kinematic_loads(j as f64 / 2000.0);
        let t = &k.terms[term as usize];
        (pf.max(t.force_n.norm()), pm.max(t.moment_hinge_nm.norm()))
    })
}

fn norm(v: [f64; 3]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn diff(a: [f64; 3], b: [f64; 3]) -> f64 {
    norm([a[0] - b[0], a[1] - b[1], a[2] - b[2]])
}

/// The step means' cycle mean at `n` steps per wingbeat.
fn step_cycle_mean(w: &Wing, term: Term, n: usize) -> ([f64; 3], [f64; 3]) {
    let dt = 1.0 / (w.kinematics().freq_hz * n as f64);
    let (mut f, mut m) = ([0.0; 3], [0.0; 3]);
    for j in 0..n {
        let s = w.kinematic_loads_over_step(j as f64 / n as f64, (j + 1) as f64 / n as f64, dt);
        let t = &s.mean.terms[term as usize];
        for i in 0..3 {
            f[i] += t.force_n[i] / n as f64;
            m[i] += t.moment_hinge_nm[i] / n as f64;
        }
    }
    (f, m)
}

#[test]
fn added_mass_step_means_carry_no_cycle_mean_force_at_any_step_count() {
    let w = fly_wing();
    // The scale: the term's peak force over the wingbeat.
    let peak = peaks(&w, Term::AddedMass).0;
    for n in [20, 25, 40] {
        let (f, _) = step_cycle_mean(&w, Term::AddedMass, n);
        assert!(
            norm(f) < 1e-12 * peak,
            "N = {n}: cycle mean {f:?} against peak {peak:e}"
        );
        // One sample per step (at each step's midpoint) aliases the flip's pulse.
        let (sampled, _) = fine_mean(&w, Term::AddedMass, 0.0, 1.0, n);
        if n == 25 {
            assert!(norm(sampled) > 1e-3 * peak, "N = 25 sampled {sampled:?}");
        }
    }
}

#[test]
fn a_step_mean_is_the_steps_fine_mean_across_a_reversal() {
    let w = fly_wing();
    let f_hz = w.kinematics().freq_hz;
    // Steps of 1/25 of the wingbeat: one centred on the reversal at phase 0.5 (inside the
    // flip), one starting at it, one in mid-stroke.
    for (a, b) in [(0.48, 0.52), (0.5, 0.54), (0.2, 0.24)] {
        let s = w.kinematic_loads_over_step(a, b, (b - a) / f_hz);
        for term in [Term::AddedMass, Term::Rotational, Term::WakeCapture] {
            let (f, m) = fine_mean(&w, term, a, b, 20_000);
            let (pf, pm) = peaks(&w, term);
            let t = &s.mean.terms[term as usize];
            let (ef, em) = (diff(t.force_n.into(), f), diff(t.moment_hinge_nm.into(), m));
            // Measured: at most 0.05% of the term's peak (the rotational term inside the
            // flip); the added mass's at round-off.
            assert!(
                ef <= 2e-3 * pf,
                "{term:?} [{a}, {b}]: force {:?} against {f:?}",
                t.force_n
            );
            assert!(
                em <= 2e-3 * pm,
                "{term:?} [{a}, {b}]: moment {:?} against {m:?}",
                t.moment_hinge_nm
            );
            if term == Term::AddedMass {
                // The reference's own error (20,000 midpoint samples across the flip's kinks)
                // is about 1e-5 of the peak.
                assert!(
                    ef <= 1e-9 * pf && em <= 1e-4 * pm,
                    "[{a}, {b}]: {ef:e} {em:e}"
                );
            }
        }
    }
}

#[test]
fn odd_and_even_step_counts_give_the_fine_cycle_mean() {
    let w = fly_wing();
    for term in [Term::AddedMass, Term::Rotational, Term::WakeCapture] {
        let (f, m) = fine_mean(&w, term, 0.0, 1.0, 200_000);
        let (pf, pm) = peaks(&w, term);
        // The scale of a cycle mean: its size, or 1e-6 of the term's peak where it is zero
        // (the added-mass force).
        let (fs, ms) = (norm(f).max(1e-6 * pf), norm(m).max(1e-6 * pm));
        for n in [24, 25] {
            let (sf, sm) = step_cycle_mean(&w, term, n);
            let (ef, em) = (diff(sf, f), diff(sm, m));
            eprintln!(
                "{term:?} N = {n}: force {ef:.3e}, moment {em:.3e} (fine {fs:.3e}, {ms:.3e})"
            );
            // Measured: within 0.4% (force) and 2% (moment) of the fine cycle means, the
            // rotational term's pulse at 25 steps (three steps per flip) the largest.
            assert!(ef <= 5e-3 * fs, "{term:?} N = {n}: force {ef:e} of {fs:e}");
            assert!(em <= 3e-2 * ms, "{term:?} N = {n}: moment {em:e} of {ms:e}");
        }
    }
}
