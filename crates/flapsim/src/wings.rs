//! The wing set, the force element of crate `wingset` (re-exported here; no engine, no I/O:
//! it depends on wingforce and nalgebra only), and what ties it to flapsim's vehicle model:
//! [`Vehicle`] maps controls onto the wings (a [`ControlMap`]), and [`FromVehicle`] builds a
//! set from a model and gives the model back. flapsim's hosts of the set are its own
//! [`crate::Simulation`] (a private rapier world) and [`crate::host::RapierWings`] (a body in
//! the user's rapier world); the C ABI, the MuJoCo plugin, the FMU and the Python module host
//! it too (crates `flapwing-ffi`, `flapwing-mujoco`, `flapwing-fmu`, `flapwing-python`).

use wingforce::Wing;
pub use wingset::set::{
    BodyLoad, ControlMap, MeanLoads, State, WingSet, WingSetBuilder, WingSetOutput, zero_forces,
};

use crate::error::Result;
use crate::model::{Controls, Vehicle};
use wingset::actuated::{Drive, DynamicWing};

/// A vehicle model maps controls onto its wings ([`Vehicle::apply_controls`]).
impl ControlMap for Vehicle {
    fn apply(&mut self, controls: &Controls) -> wingset::Result<()> {
        Ok(self.apply_controls(controls)?)
    }
    fn wings(&self) -> &[Wing] {
        &self.wings
    }
    fn drives(&self) -> Option<&[Drive]> {
        self.actuation.as_ref().map(|a| &a.drives[..])
    }
    fn clone_box(&self) -> Box<dyn ControlMap> {
        Box::new(self.clone())
    }
}

/// A [`WingSet`] from a vehicle model, and the model back (`use flapsim::wings::FromVehicle`
/// to call these on `WingSet`).
pub trait FromVehicle: Sized {
    /// The wings of a vehicle model with its controls, stepped by `dt_s` (flapsim's own host
    /// uses `1 / (f steps_per_wingbeat)`; [`FromVehicle::from_vehicle_sized`] does that). An
    /// actuated vehicle's wings start at rest at their springs' rest angles.
    fn from_vehicle(vehicle: &Vehicle, dt_s: f64) -> Result<Self>;
    /// [`FromVehicle::from_vehicle`] with the step the model asks for:
    /// `sim.steps_per_wingbeat` steps per wingbeat.
    fn from_vehicle_sized(vehicle: &Vehicle) -> Result<Self>;
    /// The vehicle model the set was built from, with the controls in force.
    fn vehicle(&self) -> Option<&Vehicle>;
}

impl FromVehicle for WingSet {
    fn from_vehicle(vehicle: &Vehicle, dt_s: f64) -> Result<Self> {
        let dynamic = match &vehicle.actuation {
            Some(a) => Some(
                a.drives
                    .iter()
                    .map(|d| {
                        let mut w = DynamicWing::new(a.dynamics.clone(), *d)?;
                        // Hosts of their own (the C ABI, MuJoCo, Python) move the body
                        // semi-implicitly unless a replay says otherwise; flapsim's set
                        // theirs (`Vehicle::strike_share`).
                        w.set_strike_share(vehicle.sim.strike_share.unwrap_or_default());
                        w.set_stage_loads(vehicle.sim.actuated_stage_loads);
                        Ok(w)
                    })
                    .collect::<wingset::Result<Vec<_>>>()?,
            ),
            None => None,
        };
        let mut set = WingSet::with_control_map(
            Box::new(vehicle.clone()),
            dynamic,
            vehicle.sim.wing_mass_kg,
            dt_s,
            vehicle.controls,
        )?;
        set.set_load_sampling(vehicle.load_sampling());
        if vehicle.load_sampling().is_second_order() {
            set.set_body_inertia_kg_m2(Some(vehicle.inertia_kg_m2));
        }
        Ok(set)
    }

    fn from_vehicle_sized(vehicle: &Vehicle) -> Result<Self> {
        let dt_s = 1.0 / (vehicle.freq_hz() * vehicle.sim.steps_per_wingbeat as f64);
        Self::from_vehicle(vehicle, dt_s)
    }

    fn vehicle(&self) -> Option<&Vehicle> {
        let map: &dyn std::any::Any = self.control_map()?;
        map.downcast_ref::<Vehicle>()
    }
}
