//! The native side of `scripts/host-step-cost`: a built-in vehicle's wing set, built as the C
//! ABI builds it for `flapwing_wings_from_builtin(MODEL, 0)` (its own step, the body drag on),
//! stepped `N` times with the body at rest at the origin, level: what `step_cost abi` does
//! through the C ABI and `step_cost fmu` through the FMU (crates/fmu/bench/step_cost.c).
//! Callgrind's instruction counts of the three, less a shorter run's, are the per-step costs.
//!
//! `cargo run --release -p flapwing-ffi --example native_steps -- MODEL N [DT_S]` (DT_S: a
//! host's step in place of the model's own, as `flapwing_wings_from_builtin(MODEL, DT_S)`)

use flapsim::wings::{FromVehicle, WingSet};
use flapsim::{State, Vehicle};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let (Some(model), Some(n)) = (args.get(1), args.get(2)) else {
        return Err("usage: native_steps MODEL N [DT_S]".into());
    };
    let n: u64 = n.parse()?;
    let text = flapsim::builtin_model(model).ok_or_else(|| format!("no built-in `{model}`"))?;
    let vehicle = Vehicle::from_toml(text, model)?;
    let mut set = match args.get(3) {
        Some(dt) => WingSet::from_vehicle(&vehicle, dt.parse()?)?,
        None => WingSet::from_vehicle_sized(&vehicle)?,
    };
    set.set_body_drag_area_m2(vehicle.body_drag_area_m2)?;
    let body = State::at_rest();
    let mut fz = 0.0;
    for _ in 0..n {
        fz = set.step(&body)?.total.force_n.z;
    }
    println!("fz {fz:?} dt_s {:?}", set.dt_s());
    Ok(())
}
