//! The hover's setup (trim and LQR design) under the second-order load samplings (issue 37).
//!
//! A trim is an equilibrium: the loads averaged over a wingbeat at the trim state balance the
//! weight (force) and have no pitching moment. The simulation steps with the step means of
//! its own step count (`[sim] steps_per_wingbeat`), a quadrature of the wingbeat whose
//! result differs from a finer one by the quadrature's error, so the trim balances those
//! loads: held tethered at the trim, the simulated vehicle's wingbeat-mean force is the
//! weight to round-off (measured: 2e-15; a trim on 200 phases of the wingbeat, as before,
//! left the fly stepped at its 20 with 2.5e-5 of its weight unbalanced, and its stroke
//! amplitude 0.0015 deg off). And the analyses' finite-difference columns, computed in parallel,
//! are the same numbers bit for bit on one thread.

use super::builtin;
use flapsim::linear::{AveragedModel, N_STATES};
use flapsim::{Mode, Simulation};
use nalgebra::{DVector, Vector3};

#[test]
fn a_step_mean_trim_balances_the_steps_the_simulation_takes() {
    for name in ["drosophila", "bumblebee"] {
        let v = builtin(name);
        assert_eq!(v.load_sampling(), flapsim::LoadSampling::StepMean, "{name}");
        let t = flapsim::trim::trim(&v).unwrap();
        let tv = flapsim::trim::trimmed_vehicle(&v, &t).unwrap();
        let steps = tv.sim.steps_per_wingbeat;
        let (w, r_m) = (tv.weight_n(), tv.wings[0].geometry().r_tip_m);
        let q = tv.initial_attitude;
        let mut sim = Simulation::new(tv, Mode::Tethered);
        let (mut force_w, mut moment_b) = (Vector3::zeros(), Vector3::zeros());
        for _ in 0..steps {
            let out = sim.step().unwrap();
            force_w += q * out.total.force_n / steps as f64;
            moment_b += out.total.moment_nm / steps as f64;
        }
        // Equilibrium in hover: F = (0, 0, W) in the world, no pitching moment. Round-off of
        // the sums is ~1e-15 of the weight; the trim's own tolerance is 1e-10.
        let residual = [force_w.x / w, force_w.z / w - 1.0, moment_b.y / (w * r_m)];
        assert!(
            residual.iter().all(|r| r.abs() < 1e-9),
            "{name} at {steps} steps per wingbeat: residual {residual:?}"
        );
    }
}

#[test]
fn the_parallel_trim_and_jacobians_match_one_thread_bit_for_bit() {
    let v = builtin("drosophila");
    let setup = || {
        let t = flapsim::trim::trim(&v).unwrap();
        let model = AveragedModel::new(&v, t.attitude(), t.controls, 100);
        let (a, b) = model.linearize(&DVector::zeros(N_STATES)).unwrap();
        (t, a, b)
    };
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(setup);
    let many = rayon::ThreadPoolBuilder::new()
        .num_threads(4)
        .build()
        .unwrap()
        .install(setup);
    assert_eq!(one, many);
}
