//! The wingbeat clock and the per-step table of kinematic loads.
//!
//! The step is sized so that a wingbeat at the model's frequency takes exactly
//! `steps_per_wingbeat` (N) steps. While that frequency holds, step k of a run is step
//! j = k mod N of wingbeat m = k div N, the kinematics are those of phase j/N (after the last
//! control change), and everything the kinematics alone decide (angles, wing frames, the
//! rotational, added-mass and wake-capture terms) repeats bit for bit every wingbeat. The
//! simulation computes those once per step of the wingbeat and reuses them; only the
//! translational term depends on the body's motion and is evaluated every step. These tests
//! check that the reuse changes nothing: every step's wing loads equal a direct wingforce
//! evaluation at the step's phase and body motion, bit for bit, and a frequency change (the
//! kinematics no longer repeat on the step grid) falls back to the plain clock.

use flapsim::{Controls, Mode, Simulation, StepOutput, Vehicle};
use wingforce::{BodyMotion, WingForces};

/// The fly with its loads taken at each step's start, where a step's loads are wingforce's
/// at the step's phase (the midpoint sampling's step means are checked against wingforce in
/// wingforce's `tests/step_mean.rs`).
fn drosophila() -> Vehicle {
    let mut v = Vehicle::from_toml(flapsim::DROSOPHILA_TOML, "models/drosophila.toml").unwrap();
    v.sim.load_sampling = Some(flapsim::LoadSampling::StepStart);
    v
}

/// The body's motion relative to still air, body frame, at the step's state.
fn motion(o: &StepOutput) -> BodyMotion {
    let s = &o.state;
    BodyMotion {
        velocity_m_s: s.world_from_body.inverse() * s.velocity_m_s,
        angular_velocity_rad_s: s.angular_velocity_body_rad_s,
    }
}

/// Wingforce's own evaluation of wing `i` at `phase`, with the half-stroke count of `cycles`
/// wingbeats later.
fn direct(sim: &Simulation, i: usize, phase: f64, cycles: i64, o: &StepOutput) -> WingForces {
    let mut f = sim.vehicle().wings[i].evaluate(phase, &motion(o));
    f.phase.half_stroke += 2 * cycles;
    f
}

#[test]
fn kinematics_repeat_bit_for_bit_every_wingbeat() {
    let v = drosophila();
    let n = v.sim.steps_per_wingbeat;
    let mut sim = Simulation::new(v, Mode::Tethered);
    let outs: Vec<StepOutput> = (0..3 * n).map(|_| *sim.step().unwrap()).collect();
    for k in n..3 * n {
        let (a, b) = (&outs[k - n], &outs[k]);
        for w in 0..2 {
            assert_eq!(a.wings[w].angles, b.wings[w].angles, "step {k}");
            assert_eq!(a.wings[w].terms[1..], b.wings[w].terms[1..], "step {k}");
            assert_eq!(a.wings[w].phase.t_star, b.wings[w].phase.t_star);
            assert_eq!(
                a.wings[w].phase.half_stroke + 2,
                b.wings[w].phase.half_stroke
            );
        }
        // Tethered: the body never moves, so the whole load repeats too.
        assert_eq!(a.total, b.total, "step {k}");
        assert!((b.phase - a.phase - 1.0).abs() < 1e-12, "step {k}");
    }
    // The clock: phase k/N exactly within the first wingbeat.
    for (k, o) in outs.iter().take(n).enumerate() {
        assert_eq!(o.phase, k as f64 * (1.0 / n as f64));
    }
}

#[test]
fn free_flight_loads_equal_direct_evaluation() {
    // Asymmetric controls (a roll command) so that each wing is evaluated on its own, in
    // free flight so that the translational term sees a moving body.
    let mut v = drosophila();
    v.controls = Controls {
        diff_amplitude_rad: 0.05,
        ..Default::default()
    };
    let n = v.sim.steps_per_wingbeat;
    let mut sim = Simulation::new(v, Mode::Free);
    for k in 0..3 * n {
        let o = *sim.step().unwrap();
        let (m, j) = ((k / n) as i64, k % n);
        let phase = j as f64 * (1.0 / n as f64);
        for w in 0..2 {
            assert_eq!(o.wings[w], direct(&sim, w, phase, m, &o), "step {k}");
        }
        if k > n {
            assert!(motion(&o).velocity_m_s.norm() > 0.0);
        }
    }
    // New controls at the same frequency from wingbeat 4 on: the table starts afresh (a
    // stale one would keep the old amplitude's rotational and added-mass terms).
    sim.set_controls(Controls {
        amplitude_rad: 0.1,
        diff_amplitude_rad: 0.05,
        ..Default::default()
    });
    for k in 3 * n..5 * n {
        let o = *sim.step().unwrap();
        for w in 0..2 {
            let d = direct(&sim, w, o.phase, 0, &o);
            for t in 0..4 {
                let (a, b) = (o.wings[w].terms[t].force_n, d.terms[t].force_n);
                assert!((a - b).norm() <= 1e-9 * b.norm().max(1e-12), "step {k}");
            }
        }
    }
}

#[test]
fn a_frequency_change_leaves_the_periodic_clock() {
    let v = drosophila();
    let n = v.sim.steps_per_wingbeat;
    let f0 = v.freq_hz();
    let mut sim = Simulation::new(v, Mode::Tethered);
    let dt = sim.dt_s();
    for _ in 0..n / 2 {
        sim.step().unwrap();
    }
    sim.set_controls(Controls {
        freq_hz: 5.0,
        ..Default::default()
    });
    // The change takes effect at the start of the next wingbeat, phase 1.
    let mut prev = 0.0;
    for k in n / 2..3 * n {
        let o = *sim.step().unwrap();
        if k > n {
            // (f0 + 5 Hz) dt per step from phase 1, the kinematics at that phase.
            let expected = 1.0 + (k - n) as f64 * ((f0 + 5.0) * dt);
            assert!((o.phase - expected).abs() < 1e-12, "step {k}");
            assert!((o.phase - prev - (f0 + 5.0) * dt).abs() < 1e-12);
            for w in 0..2 {
                assert_eq!(o.wings[w], direct(&sim, w, o.phase, 0, &o), "step {k}");
            }
        }
        prev = o.phase;
    }
}
