//! Which way the dragonfly wings' spanwise twist pushes the published flights' forces.
//!
//! Azuma & Watanabe 1988's Table 3 gives the feathering series at 0.25R, 0.5R and 0.75R:
//! the wing twists (the first harmonic grows from 14-25 deg at 0.25R to 46-54 deg at 0.75R
//! on the forewing). flapwing's wings are rigid, and the model files feather the whole wing
//! as at 0.75R. This flies each experiment with the whole wing feathering as at each station
//! (`DragonflyFlight::at_inner_stations`: the variants `scripts/dragonfly-cases/generate.py
//! --stations` wrote into `crates/flapsim/src/vehicle_validation/dragonfly_stations`, which
//! `flapwing validate`'s causes read too) and prints the cycle-mean forces over the weight,
//! in still air and under the dynamic wake, as `validate` measures the files.
//!
//! ```text
//! cargo run --release -p flapsim --example dragonfly_stations
//! ```

use flapsim::vehicle_validation::dragonfly::{DRAGONFLY_FLIGHTS, FlightForces};
use wingforce::InflowModel;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    println!(
        "| experiment | feathering as at | vertical / weight | horizontal / weight | dynamic wake: vertical (horizontal) | paper's n |"
    );
    println!("|---|---|---|---|---|---|");
    for (k, flight) in DRAGONFLY_FLIGHTS.iter().enumerate() {
        let (Some(still), Some(dynamic)) = (
            flight.at_inner_stations(InflowModel::Off)?,
            flight.at_inner_stations(InflowModel::Dynamic)?,
        ) else {
            continue;
        };
        let file = flight.vehicle()?;
        let rows = [
            ("0.25R", &still[0], &dynamic[0]),
            ("0.5R", &still[1], &dynamic[1]),
            (
                "0.75R (the file)",
                &file,
                &file.with_inflow_model(InflowModel::Dynamic)?,
            ),
        ];
        for (station, s, d) in rows {
            let (s, d): (FlightForces, FlightForces) = (flight.forces(s)?, flight.forces(d)?);
            println!(
                "| {k} | {station} | {:.3} | {:+.3} | {:.3} ({:+.3}) | {} |",
                s.vertical, s.horizontal, d.vertical, d.horizontal, flight.paper_load_factor
            );
        }
    }
    Ok(())
}
