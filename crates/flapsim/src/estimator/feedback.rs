//! [`EstimatedFeedback`]: a vehicle's sensors feeding the [`Estimator`], for flying the
//! controller on the estimate.

use crate::error::Result;
use crate::model::Vehicle;
use crate::sensor_run::{Reading, SensorRun, SensorSummary};
use crate::sim::State;

use super::filter::{Estimator, Prior};

/// A vehicle's sensors feeding the estimator, for flying on the estimate: shown the body
/// each step, it samples the model's `[sensors]` and hands every delivered reading to the
/// filter.
#[derive(Debug, Clone)]
pub struct EstimatedFeedback {
    sensors: SensorRun,
    filter: Estimator,
    readings: Vec<Reading>,
}

impl EstimatedFeedback {
    /// The sensors of `vehicle` (every random draw from `seed`) and a filter from `prior`;
    /// an error names the model and what its `[sensors]` lacks.
    pub fn new(vehicle: &Vehicle, seed: u64, prior: &Prior) -> Result<Self> {
        let mut filter = Estimator::for_vehicle(vehicle, prior)?;
        // Room for the controller's look-back (see EstimatedFeedback::controller_input):
        // the IMU latency plus a wingbeat and two IMU periods.
        if let Some(p) = &vehicle.sensors {
            filter.keep_history_s(
                p.imu.latency_s + 1.0 / vehicle.freq_hz() + 2.0 * filter.imu_period_s(),
            );
        }
        Ok(Self {
            sensors: SensorRun::new(vehicle, seed)?,
            filter,
            readings: Vec::new(),
        })
    }

    /// Shows the sensors the body `state` at `t_s` (once per step, in time order) and
    /// applies what they deliver to the filter.
    pub fn observe(&mut self, t_s: f64, state: &State) {
        self.readings.clear();
        let (readings, filter) = (&mut self.readings, &mut self.filter);
        self.sensors.observe(t_s, state, |r| {
            filter.reading(&r);
            readings.push(r);
        });
    }

    /// The readings delivered at the last [`EstimatedFeedback::observe`].
    pub fn readings(&self) -> &[Reading] {
        &self.readings
    }

    /// The estimated state at `t_s` (see [`Estimator::state_at`]).
    pub fn estimate(&self, t_s: f64) -> State {
        self.filter.state_at(t_s)
    }

    /// What a controller acting once per wingbeat of `period_s` at `t_s` should fly on:
    /// the estimate and how many whole wingbeats before `t_s` it is. A filter within one
    /// IMU period of `t_s` (no IMU latency) gives its state carried to `t_s` (0 wingbeats;
    /// [`Estimator::state_at`]). A filter behind by more (the IMU's latency) gives its state
    /// at t_s - d period, the same wingbeat phase d wingbeats ago, for the smallest d that
    /// reaches into its history: the controller predicts it forward with the controls it
    /// applied since ([`crate::control::HoverController::update_from_past`]). Carrying the
    /// newest state across a latency of a wingbeat at constant rates instead would hold an
    /// instant of the in-wingbeat oscillation for the whole latency: measured, the fruit
    /// fly's loop with its 5 ms IMU latency then diverges within 7 wingbeats.
    pub fn controller_input(&self, t_s: f64, period_s: f64) -> (State, usize) {
        let f = &self.filter;
        let Some(t_filter) = f.time_s() else {
            return (f.state_at(t_s), 0);
        };
        let lag = t_s - t_filter;
        if lag <= f.imu_period_s() * (1.0 + 1e-6) {
            return (f.state_at(t_s), 0);
        }
        let d = ((lag / period_s) - 1e-9).ceil().max(1.0) as usize;
        match f.state_in_history(t_s - d as f64 * period_s) {
            Some(s) => (s, d),
            None => (f.state_at(t_s), 0),
        }
    }

    /// The filter.
    pub fn filter(&self) -> &Estimator {
        &self.filter
    }

    /// What the sensors sampled.
    pub fn summary(&self) -> &SensorSummary {
        self.sensors.summary()
    }
}
