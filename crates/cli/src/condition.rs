//! The flight-condition options `trim` and `stability` share (`--speed-m-s`,
//! `--climb-m-s`): hover unless given.

use anyhow::Result;
use flapsim::flight::FlightCondition;

use crate::error::InputContext;

/// A flight condition on the command line.
#[derive(Debug, Clone, Copy, clap::Args)]
pub struct ConditionArgs {
    /// Forward speed through the air, m/s (default 0: hover). The body flies nose first
    /// along world x, with its drag (`[body] drag_area_m2`) and Glauert's induced inflow.
    #[arg(
        long = "speed-m-s",
        value_name = "M/S",
        default_value_t = 0.0,
        allow_negative_numbers = true
    )]
    pub speed_m_s: f64,
    /// Climb rate, m/s (negative descends; default 0).
    #[arg(
        long = "climb-m-s",
        value_name = "M/S",
        default_value_t = 0.0,
        allow_negative_numbers = true
    )]
    pub climb_m_s: f64,
}

impl ConditionArgs {
    /// The condition, or an error naming the option, its value and what is allowed.
    pub fn condition(&self) -> Result<FlightCondition> {
        FlightCondition::new(self.speed_m_s, self.climb_m_s)
            .input_context("--speed-m-s / --climb-m-s")
    }

    /// Checks the condition against `vehicle` (momentum theory's range), as bad input.
    pub fn check(&self, vehicle: &flapsim::model::Vehicle) -> Result<FlightCondition> {
        let c = self.condition()?;
        vehicle
            .check_flight_condition(&c)
            .input_context("--speed-m-s / --climb-m-s")?;
        Ok(c)
    }
}
