//! The wing set's step on its own (no host) for 2, 4 and 8 wings: pairs of the fruit fly's
//! wings at hinges 1 mm apart along the body, the body moving and turning (so every step
//! evaluates the translational term; the kinematic loads come from the wingbeat's table after
//! the first wingbeat, as in a run). Its cost should grow linearly with the number of wings.
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use flapsim::{State, Vehicle, WingSet};
use nalgebra::{UnitQuaternion, Vector3};
use std::hint::black_box;
use wingforce::{Mount, Wing};

fn set_of(vehicle: &Vehicle, pairs: usize) -> WingSet {
    let dt_s = 1.0 / (vehicle.freq_hz() * vehicle.sim.steps_per_wingbeat as f64);
    let mut b = WingSet::builder(dt_s);
    for p in 0..pairs {
        for w in &vehicle.wings {
            let mut mount: Mount = *w.mount();
            mount.hinge_in_body_m.x -= 1e-3 * p as f64;
            b = b.wing(
                Wing::builder(w.geometry().clone(), w.kinematics().clone())
                    .mount(mount)
                    .fluid(*w.fluid())
                    .options(w.options().clone())
                    .build(),
            );
        }
    }
    b.build().expect("a valid set")
}

fn bench(c: &mut Criterion) {
    let vehicle =
        Vehicle::from_toml(flapsim::DROSOPHILA_TOML, "drosophila").expect("built-in model");
    let body = State {
        position_m: Vector3::zeros(),
        world_from_body: UnitQuaternion::from_euler_angles(0.1, 0.6, 0.0),
        velocity_m_s: Vector3::new(0.2, 0.05, -0.1),
        angular_velocity_body_rad_s: Vector3::new(3.0, -5.0, 1.0),
    };
    let mut group = c.benchmark_group("wing_set_step");
    for wings in [2usize, 4, 8] {
        group.bench_with_input(BenchmarkId::from_parameter(wings), &wings, |b, &n| {
            let mut set = set_of(&vehicle, n / 2);
            b.iter(|| black_box(set.step(black_box(&body)).map(|o| o.total.force_n.z).ok()))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
