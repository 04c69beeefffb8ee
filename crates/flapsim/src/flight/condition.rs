//! The flight condition and what it does to a vehicle: the body's parasite drag and the
//! induced inflow frozen at the condition (see the module above). Plain and below the trim,
//! which takes a condition.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::model::Vehicle;

/// A steady flight condition: see the module documentation.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct FlightCondition {
    /// Forward speed through the air along world x, m/s (>= 0).
    pub forward_speed_m_s: f64,
    /// Climb rate along world z (up), m/s (negative: descent).
    pub climb_rate_m_s: f64,
}

impl FlightCondition {
    /// Hover.
    pub const HOVER: FlightCondition = FlightCondition {
        forward_speed_m_s: 0.0,
        climb_rate_m_s: 0.0,
    };

    /// A condition, or an error naming the value and what is allowed (a forward speed finite
    /// and >= 0, at most 100 m/s; a finite climb rate within +-100 m/s).
    pub fn new(forward_speed_m_s: f64, climb_rate_m_s: f64) -> Result<Self> {
        if !(forward_speed_m_s.is_finite() && (0.0..=100.0).contains(&forward_speed_m_s)) {
            return Err(Error::Input(format!(
                "forward speed {forward_speed_m_s} m/s; allowed: a finite speed in [0, 100] m/s (the vehicle flies nose first along world x)"
            )));
        }
        if !(climb_rate_m_s.is_finite() && climb_rate_m_s.abs() <= 100.0) {
            return Err(Error::Input(format!(
                "climb rate {climb_rate_m_s} m/s; allowed: a finite rate in [-100, 100] m/s (negative descends)"
            )));
        }
        Ok(Self {
            forward_speed_m_s,
            climb_rate_m_s,
        })
    }

    /// Hover (both velocities zero).
    pub fn is_hover(&self) -> bool {
        self.forward_speed_m_s == 0.0 && self.climb_rate_m_s == 0.0
    }

    /// The body's velocity through the air, world frame, m/s.
    pub fn velocity_world_m_s(&self) -> Vector3<f64> {
        Vector3::new(self.forward_speed_m_s, 0.0, self.climb_rate_m_s)
    }

    /// "hover" or "3.00 m/s forward, 0.50 m/s climb" for messages.
    pub fn describe(&self) -> String {
        if self.is_hover() {
            "hover".into()
        } else {
            format!(
                "{:.2} m/s forward, {:.2} m/s climb",
                self.forward_speed_m_s, self.climb_rate_m_s
            )
        }
    }
}

impl Vehicle {
    /// The body's parasite drag for a velocity `velocity_world_m_s` through the air, world
    /// frame, N (zero without `[body] drag_area_m2`).
    pub fn body_drag_world_n(&self, velocity_world_m_s: &Vector3<f64>) -> Vector3<f64> {
        if self.body_drag_area_m2 == 0.0 {
            return Vector3::zeros();
        }
        let rho = self.wings[0].fluid().density_kg_m3;
        -0.5 * rho * self.body_drag_area_m2 * velocity_world_m_s.norm() * velocity_world_m_s
    }

    /// Whether the wings carry an induced inflow (`[aero] induced_inflow`).
    pub fn has_induced_inflow(&self) -> bool {
        self.wings
            .iter()
            .any(|w| w.options().induced_inflow.is_some())
    }

    /// Freezes the wings' induced inflow at `condition` for a body at `world_from_body`: the
    /// wings, moving with the body through the air, carry the weight and the body's drag
    /// (shared equally). Hover keeps the model's own hover inflow untouched.
    pub fn freeze_inflow_at(
        &mut self,
        condition: &FlightCondition,
        world_from_body: &nalgebra::UnitQuaternion<f64>,
    ) {
        if condition.is_hover() {
            return;
        }
        let vel_w = condition.velocity_world_m_s();
        let required = Vector3::new(0.0, 0.0, self.weight_n()) - self.body_drag_world_n(&vel_w);
        let velocity_body_m_s: [f64; 3] = (world_from_body.inverse() * vel_w).into();
        let thrust_n = required.norm() / self.wings.len() as f64;
        for w in self.wings.iter_mut() {
            let Some(mut inflow) = w.options().induced_inflow else {
                continue;
            };
            inflow.thrust_n = thrust_n;
            inflow.flight_velocity_body_m_s = velocity_body_m_s;
            let mut options = w.options().clone();
            options.induced_inflow = Some(inflow);
            w.set_options(options);
        }
    }

    /// Refuses conditions outside momentum theory: an axial descent faster than half the
    /// hover downwash w_h enters the vortex-ring state (Johnson 1980, *Helicopter Theory*,
    /// section 4.2: momentum theory has no valid solution for -2 w_h < V_c < 0 and is unreliable
    /// from about -0.5 w_h), unless the forward speed exceeds w_h and carries the wake away.
    pub fn check_flight_condition(&self, condition: &FlightCondition) -> Result<()> {
        if !self.has_induced_inflow() || condition.climb_rate_m_s >= 0.0 {
            return Ok(());
        }
        let w_h = self.wings[0].induced_downwash_m_s();
        if -condition.climb_rate_m_s > 0.5 * w_h && condition.forward_speed_m_s < w_h {
            return Err(Error::Input(format!(
                "`{}` at {}: a descent faster than half the hover downwash ({:.3} m/s) at a forward speed below it ({w_h:.3} m/s) is the vortex-ring state, outside the momentum theory of the induced inflow; allowed: climb rate >= {:.3} m/s here, or a forward speed >= {w_h:.3} m/s",
                self.name,
                condition.describe(),
                0.5 * w_h,
                -0.5 * w_h,
            )));
        }
        Ok(())
    }
}
