//! What the dragonfly wings' spanwise twist does to the published flights' forces.
//!
//! Azuma & Watanabe 1988's Table 3 gives the feathering series at 0.25R, 0.5R and 0.75R:
//! the wing twists (the forewing's first harmonic grows from 14-25 deg at 0.25R to 46-54 deg
//! at 0.75R). The model files take 0.75R's as their pitch and the other stations as their
//! twist (`[kinematics.twist]`). This flies each experiment with rigid wings feathering as at
//! each station (`DragonflyFlight::at_rigid_stations`: the variants
//! `scripts/dragonfly-cases/generate.py --stations` wrote into
//! `crates/flapsim/src/vehicle_validation/dragonfly_stations`, which `flapwing validate`'s
//! causes read too) and with the file's twisted wings, and prints the cycle-mean forces over
//! the weight, in still air and under the dynamic wake, as `validate` measures the files.
//!
//! ```text
//! cargo run --release -p flapsim --example dragonfly_stations
//! ```

use flapsim::vehicle_validation::dragonfly::DRAGONFLY_FLIGHTS;
use wingforce::InflowModel;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    println!(
        "| experiment | wings | vertical / weight | horizontal / weight | dynamic wake: vertical (horizontal) | paper's n |"
    );
    println!("|---|---|---|---|---|---|");
    for (k, flight) in DRAGONFLY_FLIGHTS.iter().enumerate() {
        let (Some([s25, s50, s75]), Some([d25, d50, d75])) = (
            flight.at_rigid_stations(InflowModel::Off)?,
            flight.at_rigid_stations(InflowModel::Dynamic)?,
        ) else {
            continue;
        };
        let file = flight.vehicle()?;
        let file_dynamic = file.with_inflow_model(InflowModel::Dynamic)?;
        let rows = [
            ("rigid, as at 0.25R", &s25, &d25),
            ("rigid, as at 0.5R", &s50, &d50),
            ("rigid, as at 0.75R", &s75, &d75),
            ("twisted (the file)", &file, &file_dynamic),
        ];
        for (wings, s, d) in rows {
            let (s, d) = (flight.forces(s)?, flight.forces(d)?);
            println!(
                "| {k} | {wings} | {:.3} | {:+.3} | {:.3} ({:+.3}) | {} |",
                s.vertical, s.horizontal, d.vertical, d.horizontal, flight.paper_load_factor
            );
        }
    }
    Ok(())
}
