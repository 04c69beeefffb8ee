//! The wing set hosted by a rapier world of the user's, and the wing set on its own.
//!
//! Physics: a host only integrates the body; the wings' loads depend on the body's state and
//! the wings' own state alone. So the fly in a user's world with no other bodies, stepped by
//! the same pipeline with the same step, follows flapsim's own `Simulation` (which hosts the
//! same element in a private world) to round-off. A set of wings is a sum: wings at rest in
//! still air feel no body motion, so a second pair at another hinge adds the same force and
//! that force's moment about the CoM shifted by the hinge offset (statics).

use flapsim::host::{RapierWings, body_state, vehicle_body};
use flapsim::{FromVehicle, Mode, Simulation, State, Vehicle, WingSet};
use nalgebra::{UnitQuaternion, Vector3};
use rapier3d_f64::prelude::*;
use wingforce::{Mount, Side, Wing};

/// The fly with its loads taken at each step's start. Under a second-order sampling
/// (wingset::sampling) `Simulation` moves the pose to the trapezoidal rule after each step,
/// and the user's world does the same with `RapierWings::after_step`; the fly is checked
/// under the step-start sampling, the actuated vehicles under their files' (the hummingbird
/// step-start, the RoboBee the step mean).
fn fly() -> Vehicle {
    let mut v =
        Vehicle::from_toml(flapsim::builtin_model("drosophila").unwrap(), "drosophila").unwrap();
    v.sim.load_sampling = Some(flapsim::LoadSampling::StepStart);
    v
}

// The user's world of the examples (the same rapier sets, pipeline and parameters).
#[path = "../examples/common/mod.rs"]
mod common;
use common::World as UserWorld;

fn disturbed(mut v: Vehicle) -> Vehicle {
    v.initial_position_m = Vector3::new(0.0, 0.0, 0.1);
    v.initial_attitude = UnitQuaternion::from_euler_angles(0.05, 0.3, 0.02);
    v.initial_velocity_m_s = Vector3::new(0.05, -0.02, 0.03);
    v.initial_angular_velocity_rad_s = Vector3::new(1.0, -2.0, 0.5);
    v
}

fn max_state_difference(a: &State, b: &State) -> f64 {
    let d = [
        (a.position_m - b.position_m).norm() / 1e-3,
        (a.velocity_m_s - b.velocity_m_s).norm(),
        a.world_from_body.angle_to(&b.world_from_body),
        (a.angular_velocity_body_rad_s - b.angular_velocity_body_rad_s).norm() / 100.0,
    ];
    d.into_iter().fold(0.0, f64::max)
}

fn compare_with_simulation(v: Vehicle, wingbeats: u64) {
    let mut sim = Simulation::new(v.clone(), Mode::Free);
    let wings = WingSet::from_vehicle_sized(&v).unwrap();
    let mut world = UserWorld::new(wings.dt_s(), v.gravity_m_s2, v.sim.solver_iterations);
    let body = world.bodies.insert(vehicle_body(&v));
    let mut host = RapierWings::attach(&world.bodies, body, wings).unwrap();
    let n = wingbeats * v.sim.steps_per_wingbeat as u64;
    let mut worst = 0.0f64;
    for k in 0..n {
        let mine = host.apply(&mut world.bodies).unwrap().clone();
        let theirs = *sim.step().unwrap();
        let dl = (mine.total.force_n - theirs.total.force_n).norm()
            / theirs.total.force_n.norm().max(1e-300);
        assert!(dl <= 1e-12, "step {k}: loads differ by {dl:e} relative");
        world.step();
        host.after_step(&mut world.bodies, &world.params).unwrap();
        worst = worst.max(max_state_difference(
            &body_state(&world.bodies[body]),
            &sim.state(),
        ));
    }
    // Position in mm, velocity in m/s, attitude in rad, rate in 100 rad/s: all to 1e-12.
    assert!(
        worst <= 1e-12,
        "{}: states differ by up to {worst:e}",
        v.name
    );
}

#[test]
fn the_fly_in_a_users_world_follows_the_simulation() {
    compare_with_simulation(disturbed(fly()), 10);
    // Its file's step mean: the user's world calls `after_step` (the trapezoidal pose), and
    // the midpoint rule's torque takes the model's inertia from the first step on (rapier
    // computes the body's mass properties only in its first pipeline step). Before either,
    // the two parted at the second step.
    let v =
        Vehicle::from_toml(flapsim::builtin_model("drosophila").unwrap(), "drosophila").unwrap();
    assert!(v.load_sampling().is_second_order());
    compare_with_simulation(disturbed(v), 10);
}

#[test]
fn an_actuated_vehicle_in_a_users_world_follows_the_simulation() {
    for name in ["hummingbird", "robobee"] {
        let v = Vehicle::from_toml(flapsim::builtin_model(name).unwrap(), name).unwrap();
        compare_with_simulation(disturbed(v), 2);
    }
}

/// A vehicle that names how its strikes are shared (a replay of a log written with the
/// semi-implicit hat under a second-order sampling) keeps that rule in a user's world too,
/// and so follows the `Simulation` that replays it. (Before 2026-12-07 `RapierWings::attach`
/// set the trapezoid's shares whatever the vehicle named, and the two parted at the first
/// strike.)
#[test]
fn a_vehicles_own_strike_rule_holds_in_a_users_world() {
    use flapsim::actuated::dynamics::StrikeShare;
    let mut v = Vehicle::from_toml(flapsim::HUMMINGBIRD_TOML, "hummingbird").unwrap();
    assert!(v.load_sampling().is_second_order());
    v.sim.strike_share = Some(StrikeShare::SemiImplicitPose);
    let wings = WingSet::from_vehicle_sized(&v).unwrap();
    let mut world = UserWorld::new(wings.dt_s(), v.gravity_m_s2, v.sim.solver_iterations);
    let body = world.bodies.insert(vehicle_body(&v));
    let host = RapierWings::attach(&world.bodies, body, wings).unwrap();
    for w in host.wings().dynamic_wings().unwrap() {
        assert_eq!(w.strike_share_rule(), StrikeShare::SemiImplicitPose);
    }
    compare_with_simulation(disturbed(v), 1);
}

/// Runs an example binary that `cargo test` built beside this test.
fn run_example(name: &str) -> String {
    let exe = std::env::current_exe().unwrap();
    let dir = exe.parent().unwrap().parent().unwrap().join("examples");
    let out = std::process::Command::new(dir.join(name))
        .output()
        .unwrap_or_else(|e| panic!("example {name} in {} runs: {e}", dir.display()));
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "example {name} failed:\n{text}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    text
}

#[test]
fn the_examples_take_off_hover_land_and_fly_two_vehicles() {
    let text = run_example("fly_in_your_world");
    assert!(text.contains("landed: true"), "{text}");
    let text = run_example("two_vehicles");
    assert_eq!(text.matches("position error").count(), 2, "{text}");
    assert!(!text.contains("NOT RECOVERED"), "{text}");
}

fn pair(hinge_x_m: f64, v: &Vehicle) -> [Wing; 2] {
    [Side::Left, Side::Right].map(|side| {
        let w = &v.wings[side as usize];
        let mut mount: Mount = *w.mount();
        mount.hinge_in_body_m.x += hinge_x_m;
        Wing::builder(w.geometry().clone(), w.kinematics().clone())
            .mount(mount)
            .fluid(*w.fluid())
            .options(w.options().clone())
            .build()
    })
}

#[test]
fn a_second_pair_adds_its_force_and_that_forces_moment() {
    let v = fly();
    let dt_s = 1.0 / (v.freq_hz() * 40.0);
    let [l, r] = pair(0.0, &v);
    let [l2, r2] = pair(-1e-3, &v);
    let mut two = WingSet::builder(dt_s)
        .wing(l.clone())
        .wing(r.clone())
        .build()
        .unwrap();
    let mut four = WingSet::builder(dt_s)
        .wing(l)
        .wing(r)
        .wing(l2.clone())
        .wing(r2)
        .build()
        .unwrap();
    // A lone wing (odd count) is evaluated on its own path.
    let mut three = WingSet::builder(dt_s)
        .wing(pair(0.0, &v)[0].clone())
        .wing(pair(0.0, &v)[1].clone())
        .wing(l2)
        .build()
        .unwrap();
    let rest = State::at_rest();
    let offset = Vector3::new(-1e-3, 0.0, 0.0);
    for k in 0..40 {
        let a = two.step(&rest).unwrap().clone();
        let b = four.step(&rest).unwrap().clone();
        let c = three.step(&rest).unwrap().clone();
        let f = a.total.force_n;
        let scale = f.norm().max(1e-12);
        assert!(
            (b.total.force_n - 2.0 * f).norm() <= 1e-12 * scale,
            "step {k}"
        );
        let m = 2.0 * a.total.moment_nm + offset.cross(&f);
        assert!(
            (b.total.moment_nm - m).norm() <= 1e-12 * scale * 1e-3,
            "step {k}"
        );
        // The third wing is the left wing of the second pair.
        assert_eq!(c.wings[2], b.wings[2], "step {k}");
        assert_eq!(b.wings.len(), 4);
    }
}

#[test]
fn bad_input_is_named() {
    let v = fly();
    let err = |r: wingset::Result<WingSet>| r.unwrap_err().to_string();
    let e = err(WingSet::builder(1e-4).build());
    assert!(e.contains("no wings"), "{e}");
    let [l, r] = pair(0.0, &v);
    let e = err(WingSet::builder(1e-4)
        .wing(l.clone())
        .wing(l.clone())
        .build());
    assert!(e.contains("wings 0 and 1 are at the same place"), "{e}");
    let e = err(WingSet::builder(-1.0).wing(l.clone()).build());
    assert!(e.contains("dt_s = -1") && e.contains("allowed"), "{e}");
    let mut fast = r.clone();
    let mut k = fast.kinematics().clone();
    k.freq_hz *= 2.0;
    fast.set_kinematics(k);
    let e = err(WingSet::builder(1e-4).wing(l.clone()).wing(fast).build());
    assert!(
        e.contains("wing 1 flaps at") && e.contains("one wingbeat frequency"),
        "{e}"
    );
    // A NaN from the host is refused and changes nothing.
    let mut set = WingSet::builder(1e-4).wing(l).wing(r).build().unwrap();
    let mut bad = State::at_rest();
    bad.velocity_m_s.y = f64::NAN;
    let e = set.step(&bad).unwrap_err().to_string();
    assert!(e.contains("velocity_m_s is not finite"), "{e}");
    assert_eq!(set.steps(), 0);
    // Controls need a vehicle model.
    assert!(set.set_controls(flapsim::Controls::default()).is_err());
    // Handles: removed, or of a body the wings cannot push.
    let mut bodies = RigidBodySet::new();
    let gone = bodies.insert(vehicle_body(&v));
    let fixed = bodies.insert(RigidBodyBuilder::fixed());
    bodies.remove(
        gone,
        &mut IslandManager::new(),
        &mut ColliderSet::new(),
        &mut ImpulseJointSet::new(),
        &mut MultibodyJointSet::new(),
        &mut SoftBodySet::new(),
        true,
    );
    let set = WingSet::from_vehicle_sized(&v).unwrap();
    let e = RapierWings::attach(&bodies, gone, set.clone())
        .unwrap_err()
        .to_string();
    assert!(e.contains("is not in the rigid-body set"), "{e}");
    let e = RapierWings::attach(&bodies, fixed, set)
        .unwrap_err()
        .to_string();
    assert!(e.contains("allowed: a dynamic body"), "{e}");
}

/// Euler's equations from rest: a body at zero angular velocity under a torque tau gains
/// I dw/dt = tau (the gyroscopic term w x I w is zero), so one step of dt gives
/// w = dt I^-1 tau for any inertia tensor. Checked on the hummingbird's tensor (with its Ixz)
/// at Iyy below and above its Ixx, where parry's diagonalization gave the body the pitch
/// inertia of Ixx instead (found by flapwing-identify), and on a diagonal tensor with
/// Ixx > Iyy, its other wrong case. It fails if `vehicle_body` gives rapier a principal frame
/// that does not reproduce the tensor.
#[test]
fn a_torque_from_rest_turns_the_body_by_its_inverse_inertia() {
    let base = Vehicle::from_toml(flapsim::HUMMINGBIRD_TOML, "hummingbird").unwrap();
    let dt_s = 1e-4;
    for (diag, ixz) in [
        ([4238.1285e-9, 3970.1646e-9, 2440.9505e-9], -16.55e-9),
        ([4238.1285e-9, 4764.19752e-9, 2440.9505e-9], -16.55e-9),
        ([4.3e-13, 8.1e-14, 3.53e-13], 0.0),
    ] {
        let mut v = base.clone();
        v.inertia_kg_m2 = nalgebra::Matrix3::new(
            diag[0], 0.0, ixz, //
            0.0, diag[1], 0.0, //
            ixz, 0.0, diag[2],
        );
        v.initial_attitude = UnitQuaternion::identity();
        v.initial_velocity_m_s = Vector3::zeros();
        v.initial_angular_velocity_rad_s = Vector3::zeros();
        let mut world = UserWorld::new(dt_s, 0.0, 4);
        let h = world.bodies.insert(vehicle_body(&v));
        let tau = Vector3::new(0.3, 1.0, -0.2) * diag[1];
        world.bodies[h].add_torque(flapsim::frames::to_glam(&tau), true);
        world.step();
        let w = flapsim::frames::from_glam(world.bodies[h].angvel());
        let expected = v.inertia_kg_m2.try_inverse().unwrap() * tau * dt_s;
        assert!(
            (w - expected).norm() <= 1e-9 * expected.norm(),
            "inertia {diag:?}, Ixz {ixz:e}: w {w:?}, expected {expected:?}"
        );
    }
}
