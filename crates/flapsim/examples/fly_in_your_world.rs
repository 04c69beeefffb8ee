//! A fruit fly in your own rapier world: it sits on the ground, takes off, hovers under the
//! LQR and lands. The world is yours (a ground collider here; add anything); flapwing's part
//! is one [`RapierWings`] on the fly's body, applied before every pipeline step.
//!
//! Run: `cargo run --release -p flapsim --example fly_in_your_world`. It prints the flight and
//! exits non-zero if the fly did not reach its hover height or did not land.

use std::process::ExitCode;

use flapsim::control::{HoverController, LqrWeights};
use flapsim::host::{RapierWings, body_state, vehicle_body};
use flapsim::{FromVehicle, Vehicle, WingSet};
use nalgebra::Vector3;
use rapier3d_f64::prelude::*;

mod common;
use common::World;

/// Hover height above the ground, m (ten body lengths of the 2.5 mm fly).
const HOVER_HEIGHT_M: f64 = 0.025;
/// Climb and descent, s each; hover in between, s.
const RAMP_S: f64 = 0.15;
const HOLD_S: f64 = 0.2;
/// Time on the ground after landing, s.
const SETTLE_S: f64 = 0.05;

fn main() -> ExitCode {
    match fly() {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The reference height at time t: up a smooth ramp, hold, down a smooth ramp.
fn reference_height_m(t_s: f64, ground_m: f64) -> f64 {
    let smooth = |x: f64| {
        let x = x.clamp(0.0, 1.0);
        x * x * (3.0 - 2.0 * x)
    };
    let up = smooth(t_s / RAMP_S);
    let down = smooth((t_s - RAMP_S - HOLD_S) / RAMP_S);
    ground_m + (HOVER_HEIGHT_M - ground_m) * (up - down)
}

fn fly() -> flapsim::Result<bool> {
    let text = flapsim::builtin_model("drosophila").expect("a built-in model");
    let vehicle = Vehicle::from_toml(text, "drosophila")?;
    // The hover trim and an LQR designed about it (flapsim's analyses, host-independent).
    let trim = flapsim::trim::trim(&vehicle)?;
    let mut trimmed = flapsim::trim::trimmed_vehicle(&vehicle, &trim)?;
    let radius_m = 0.5 * trimmed.length_m;
    // Resting on the ground: the centre of mass one collider radius up.
    trimmed.initial_position_m = Vector3::new(0.0, 0.0, radius_m);
    let mut controller = HoverController::design(&trimmed, &trim, &LqrWeights::default(), 0)?;
    let wings = WingSet::from_vehicle_sized(&trimmed)?;

    // Your world: gravity, a ground plane, the fly's body with a massless collider.
    let mut world = World::new(
        wings.dt_s(),
        trimmed.gravity_m_s2,
        trimmed.sim.solver_iterations,
    );
    let up = rapier3d_f64::na::Unit::new_unchecked(Vector::Z); // z is a unit vector
    world
        .colliders
        .insert(ColliderBuilder::halfspace(up).friction(0.8));
    let fly = world.bodies.insert(vehicle_body(&trimmed));
    world.colliders.insert_with_parent(
        ColliderBuilder::ball(radius_m)
            .density(0.0)
            .restitution(0.0),
        fly,
        &mut world.bodies,
    );
    let dt_s = world.params.dt;

    // flapwing's part: the wings on the fly's body.
    let mut host = RapierWings::attach(&world.bodies, fly, wings)?;
    let duration_s = 2.0 * RAMP_S + HOLD_S + SETTLE_S;
    let n = (duration_s / dt_s).round() as u64;
    let mut last_cycle = -1i64;
    let (mut max_height_m, mut max_hold_error_m) = (0.0f64, 0.0f64);
    let mut landed = false;
    println!("   t (s)   height (mm)   reference (mm)   attitude error (deg)");
    for k in 0..n {
        let t_s = k as f64 * dt_s;
        let state = body_state(&world.bodies[fly]);
        let z_ref = reference_height_m(t_s, radius_m);
        // Once a wingbeat: the LQR's controls towards the reference.
        let cycle = host.wings().phase().floor() as i64;
        if cycle != last_cycle {
            last_cycle = cycle;
            controller.set_reference(Vector3::new(0.0, 0.0, z_ref));
            host.wings_mut().set_controls(controller.update(&state))?;
        }
        // Back on the ground after the descent: the wings stop.
        if t_s > 2.0 * RAMP_S + HOLD_S && state.position_m.z < 2.0 * radius_m && !landed {
            landed = true;
            host.wings_mut().set_still(true);
        }
        host.apply(&mut world.bodies)?;
        world.step();
        // The step-mean sampling's pose (second order), as flapsim's own Simulation takes it.
        host.after_step(&mut world.bodies, &world.params)?;
        max_height_m = max_height_m.max(state.position_m.z);
        if t_s > RAMP_S + 0.05 && t_s < RAMP_S + HOLD_S {
            max_hold_error_m = max_hold_error_m
                .max((state.position_m - Vector3::new(0.0, 0.0, HOVER_HEIGHT_M)).norm());
        }
        if k % (n / 16).max(1) == 0 {
            let err = (trim.attitude().inverse() * state.world_from_body)
                .angle()
                .to_degrees();
            println!(
                "{t_s:8.3}   {:11.2}   {:14.2}   {err:20.2}",
                1e3 * state.position_m.z,
                1e3 * z_ref
            );
        }
    }
    let end = body_state(&world.bodies[fly]);
    println!(
        "took off to {:.2} mm (hover height {:.1} mm); hover position error <= {:.2} mm; landed: {} at {:.2} mm, {:.1} mm/s",
        1e3 * max_height_m,
        1e3 * HOVER_HEIGHT_M,
        1e3 * max_hold_error_m,
        landed,
        1e3 * end.position_m.z,
        1e3 * end.velocity_m_s.norm()
    );
    Ok(max_height_m > 0.8 * HOVER_HEIGHT_M && landed && end.position_m.z < 2.0 * radius_m)
}
