//! Two vehicles in one rapier world: a fruit fly and a bumblebee, each with its own wing set
//! and LQR, recovering from a pitch disturbance side by side. The world steps at the fly's
//! step; the bumblebee's wing set takes that step too (its phase then advances by f dt).
//!
//! Run: `cargo run --release -p flapsim --example two_vehicles`. Exits non-zero unless both
//! end within one body length and 2 deg of their hover.

use std::process::ExitCode;

use flapsim::control::{HoverController, LqrWeights};
use flapsim::host::{RapierWings, body_state, vehicle_body};
use flapsim::{FromVehicle, Vehicle, WingSet};
use nalgebra::{UnitQuaternion, Vector3};

mod common;
use common::World;

const DURATION_S: f64 = 0.4;
const PITCH_DISTURBANCE_DEG: f64 = 5.0;

struct Flier {
    name: &'static str,
    host: RapierWings,
    controller: HoverController,
    q_trim: UnitQuaternion<f64>,
    hover_m: Vector3<f64>,
    length_m: f64,
    last_cycle: i64,
}

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

fn fly() -> flapsim::Result<bool> {
    let load = |name: &str| {
        Vehicle::from_toml(
            flapsim::builtin_model(name).expect("a built-in model"),
            name,
        )
    };
    let fly = load("drosophila")?;
    let dt_s = WingSet::from_vehicle_sized(&fly)?.dt_s();
    let mut world = World::new(dt_s, fly.gravity_m_s2, fly.sim.solver_iterations);
    let mut fliers = Vec::new();
    for (name, x_m) in [("drosophila", -0.02), ("bumblebee", 0.02)] {
        let vehicle = load(name)?;
        let trim = flapsim::trim::trim(&vehicle)?;
        let mut v = flapsim::trim::trimmed_vehicle(&vehicle, &trim)?;
        let hover_m = Vector3::new(x_m, 0.0, 0.1);
        v.initial_position_m = hover_m;
        // Disturbed: pitched nose up from the trim.
        v.initial_attitude = trim.attitude()
            * UnitQuaternion::from_scaled_axis(Vector3::new(
                0.0,
                -PITCH_DISTURBANCE_DEG.to_radians(),
                0.0,
            ));
        let mut controller = HoverController::design(&v, &trim, &LqrWeights::default(), 0)?;
        controller.set_reference(hover_m);
        let body = world.bodies.insert(vehicle_body(&v));
        let wings = WingSet::from_vehicle(&v, dt_s)?;
        fliers.push(Flier {
            name: if name == "drosophila" {
                "fruit fly"
            } else {
                "bumblebee"
            },
            host: RapierWings::attach(&world.bodies, body, wings)?,
            controller,
            q_trim: trim.attitude(),
            hover_m,
            length_m: v.length_m,
            last_cycle: -1,
        });
    }
    let n = (DURATION_S / dt_s).round() as u64;
    for _ in 0..n {
        for f in &mut fliers {
            let cycle = f.host.wings().phase().floor() as i64;
            if cycle != f.last_cycle {
                f.last_cycle = cycle;
                let state = body_state(&world.bodies[f.host.body()]);
                let u = f.controller.update(&state);
                f.host.wings_mut().set_controls(u)?;
            }
            f.host.apply(&mut world.bodies)?;
        }
        world.step();
        for f in &mut fliers {
            f.host.after_step(&mut world.bodies, &world.params)?;
        }
    }
    let mut ok = true;
    for f in &fliers {
        let s = body_state(&world.bodies[f.host.body()]);
        let p_err = (s.position_m - f.hover_m).norm();
        let a_err = (f.q_trim.inverse() * s.world_from_body)
            .angle()
            .to_degrees();
        let good = p_err < f.length_m && a_err < 2.0;
        ok &= good;
        println!(
            "{:10} after {DURATION_S} s: position error {:.2} mm ({:.2} body lengths), attitude error {a_err:.2} deg{}",
            f.name,
            1e3 * p_err,
            p_err / f.length_m,
            if good { "" } else { "  NOT RECOVERED" }
        );
    }
    Ok(ok)
}
