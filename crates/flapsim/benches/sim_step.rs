//! One bare rapier step of the vehicle's body beside one full flapsim step (two wings, 20
//! strips each, all four terms), and a tethered wingbeat.
use criterion::{Criterion, criterion_group, criterion_main};
use flapsim::{Mode, Simulation, Vehicle};
use rapier3d_f64::prelude::*;
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let vehicle =
        Vehicle::from_toml(flapsim::DROSOPHILA_TOML, "drosophila").expect("built-in model");
    let dt = 1.0 / (vehicle.freq_hz() * 100.0);
    c.bench_function("rapier_bare_step", |b| {
        let mut world = PhysicsWorld::new();
        world.gravity = Vector::new(0.0, 0.0, 0.0);
        world.integration_parameters.dt = dt;
        world.integration_parameters.num_solver_iterations = vehicle.sim.solver_iterations;
        let props = MassProperties::new(
            Vector::ZERO,
            vehicle.mass_kg,
            Vector::new(8.1e-14, 3.53e-13, 3.53e-13),
        );
        let h = world.insert_body(
            RigidBodyBuilder::dynamic()
                .additional_mass_properties(props)
                .can_sleep(false),
        );
        b.iter(|| {
            let rb = &mut world.bodies[h];
            rb.reset_forces(false);
            rb.reset_torques(false);
            rb.add_force(Vector::new(0.0, 0.0, 1e-9), true);
            rb.add_torque(Vector::new(0.0, 1e-15, 0.0), true);
            world.step();
            black_box(world.bodies[h].translation());
        })
    });
    c.bench_function("flapsim_full_step", |b| {
        let mut sim = Simulation::new(vehicle.clone(), Mode::Free);
        b.iter(|| {
            let ok = sim.step().map(|o| black_box(o.t_s)).is_ok();
            if !ok {
                sim = Simulation::new(vehicle.clone(), Mode::Free);
            }
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
