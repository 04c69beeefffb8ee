//! What going back costs (`WingSet::save_state`, module `wingset::set::rewind`): a host that
//! can set its body back a step (MuJoCo's `mjd_transitionFD`, the plugin's `rewind`
//! attribute) saves the wings before every step. Per built-in vehicle, interleaved rounds
//! (this VM's speed changes by up to 2x from minute to minute, so only ratios measured side
//! by side mean anything) of the wing set's step alone, the step with a save before it, and a
//! whole copy (`Clone`, what a save per step would cost without leaving out the kinematic
//! loads' table); prints the medians and the ratios to the step.
use std::hint::black_box;
use std::time::Instant;

use criterion::{Criterion, criterion_group, criterion_main};
use flapsim::{FromVehicle, State, Vehicle, WingSet};
use nalgebra::{UnitQuaternion, Vector3};

fn body() -> State {
    State {
        position_m: Vector3::zeros(),
        world_from_body: UnitQuaternion::from_euler_angles(0.02, 0.1, 0.0),
        velocity_m_s: Vector3::new(0.05, 0.0, -0.02),
        angular_velocity_body_rad_s: Vector3::new(0.3, -0.5, 0.1),
    }
}

fn set_of(name: &str) -> WingSet {
    let text = flapsim::builtin_model(name).expect("a built-in model");
    let v = Vehicle::from_toml(text, name).expect("a built-in model");
    WingSet::from_vehicle_sized(&v).expect("its wing set")
}

fn bench(c: &mut Criterion) {
    let body = body();
    let set = set_of("drosophila");
    let mut saved = set.clone();
    c.bench_function("drosophila_save_state", |b| {
        b.iter(|| black_box(set.save_state(black_box(&mut saved)).is_ok()))
    });
    for name in flapsim::BUILTIN_MODELS {
        rounds(name, &body);
    }
}

/// 15 interleaved rounds of 2000 steps of each kind (a fresh set every round: the same steps).
fn rounds(name: &str, body: &State) {
    let n = 2000;
    let fresh = set_of(name);
    let time = |kind: u8| {
        let mut set = fresh.clone();
        let mut saved = fresh.clone();
        let t0 = Instant::now();
        for _ in 0..n {
            match kind {
                0 => {}
                1 => set.save_state(&mut saved).expect("a copy of the set"),
                _ => saved = black_box(set.clone()),
            }
            black_box(set.step(body).expect("a short flight runs").total.force_n.z);
        }
        t0.elapsed().as_secs_f64() / n as f64
    };
    let (mut step, mut save, mut copy) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..15 {
        let t = time(0);
        step.push(t);
        save.push(time(1) / t);
        copy.push(time(2) / t);
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    println!(
        "{name}: step {:.3} us; with a save before it {:.3}x; with a clone before it {:.3}x (15 interleaved rounds of {n} steps, medians)",
        1e6 * median(&mut step),
        median(&mut save),
        median(&mut copy)
    );
}

criterion_group!(benches, bench);
criterion_main!(benches);
