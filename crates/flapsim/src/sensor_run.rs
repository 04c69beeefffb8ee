//! A vehicle's sensors through a whole run: the model's `[sensors]` sampled from every
//! simulation step, each reading handed on once, in order, when it is delivered (sample time
//! plus latency), and a summary of what was sampled. What `flapwing simulate` and `flapwing
//! hover` log to `/sensors/imu` and `/sensors/mocap`.
//!
//! ```
//! use flapsim::sensor_run::{Reading, SensorRun};
//! let v = flapsim::Vehicle::from_toml(flapsim::DROSOPHILA_TOML, "drosophila.toml")?;
//! let mut run = SensorRun::new(&v, 7)?;
//! let mut sim = flapsim::Simulation::new(v, flapsim::Mode::Tethered);
//! let mut imu = 0;
//! for _ in 0..500 {
//!     let out = sim.step()?;
//!     run.observe(out.t_s, &out.state, |r| if let Reading::Imu { .. } = r { imu += 1 });
//! }
//! assert_eq!(imu, run.summary().imu_samples);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::model::Vehicle;
use crate::sensors::{ImuSample, MocapSample, Sensors};
use crate::sim::State;

/// One delivered reading.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Reading {
    /// An IMU sample, delivered at `t_delivered_s` (its own `t_s` plus the latency).
    Imu {
        /// Delivery time, s.
        t_delivered_s: f64,
        /// The sample.
        sample: ImuSample,
    },
    /// A motion-capture frame, delivered at `t_delivered_s`.
    Mocap {
        /// Delivery time, s.
        t_delivered_s: f64,
        /// The frame.
        sample: MocapSample,
    },
}

/// What a run's sensors sampled (the `sensors` object of the CLI's JSON reports).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SensorSummary {
    /// The seed of every random draw of the sensors (turn-on biases, noise, bias walk).
    pub seed: u64,
    /// IMU output rate, Hz.
    pub imu_rate_hz: f64,
    /// IMU latency, s.
    pub imu_latency_s: f64,
    /// IMU samples delivered during the run.
    pub imu_samples: u64,
    /// The gyroscope's turn-on bias drawn for this run, body frame, rad/s.
    pub gyro_turn_on_bias_rad_s: [f64; 3],
    /// The accelerometer's turn-on bias drawn for this run, body frame, m/s^2.
    pub accel_turn_on_bias_m_s2: [f64; 3],
    /// Per-sample gyroscope white-noise standard deviation, rad/s (density x sqrt(rate)).
    pub gyro_noise_std_rad_s: f64,
    /// Per-sample accelerometer white-noise standard deviation, m/s^2.
    pub accel_noise_std_m_s2: f64,
    /// Motion-capture frame rate, Hz (`None` without motion capture).
    pub mocap_rate_hz: Option<f64>,
    /// Motion-capture latency, s.
    pub mocap_latency_s: Option<f64>,
    /// Motion-capture frames delivered during the run.
    pub mocap_frames: u64,
}

/// The sensors of one run.
#[derive(Debug, Clone)]
pub struct SensorRun {
    sensors: Sensors,
    summary: SensorSummary,
}

fn arr(v: &Vector3<f64>) -> [f64; 3] {
    [v.x, v.y, v.z]
}

impl SensorRun {
    /// The sensors of the vehicle's `[sensors]` table, every random draw from `seed`; an
    /// error names the model when it has no such table.
    pub fn new(vehicle: &Vehicle, seed: u64) -> Result<Self> {
        let p = vehicle.sensors.ok_or_else(|| {
            Error::Analysis(format!(
                "the model `{}` has no [sensors] table to sample (see models/drosophila.toml)",
                vehicle.name
            ))
        })?;
        let sensors = Sensors::new(&p, vehicle.gravity_m_s2, seed);
        let (gb, ab) = sensors.imu.biases();
        let (sg, sa) = sensors.imu.noise_std();
        let summary = SensorSummary {
            seed,
            imu_rate_hz: p.imu.rate_hz,
            imu_latency_s: p.imu.latency_s,
            imu_samples: 0,
            gyro_turn_on_bias_rad_s: arr(&gb),
            accel_turn_on_bias_m_s2: arr(&ab),
            gyro_noise_std_rad_s: sg,
            accel_noise_std_m_s2: sa,
            mocap_rate_hz: p.mocap.map(|m| m.rate_hz),
            mocap_latency_s: p.mocap.map(|m| m.latency_s),
            mocap_frames: 0,
        };
        Ok(Self { sensors, summary })
    }

    /// Shows the sensors the body `state` at time `t_s` (call once per step, in time
    /// order) and hands `sink` every reading delivered by then, oldest first.
    pub fn observe(&mut self, t_s: f64, state: &State, mut sink: impl FnMut(Reading)) {
        self.sensors.observe(t_s, state);
        while let Some((t_delivered_s, sample)) = self.sensors.imu.next_delivered(t_s) {
            self.summary.imu_samples += 1;
            sink(Reading::Imu {
                t_delivered_s,
                sample,
            });
        }
        if let Some(m) = &mut self.sensors.mocap {
            while let Some((t_delivered_s, sample)) = m.next_delivered(t_s) {
                self.summary.mocap_frames += 1;
                sink(Reading::Mocap {
                    t_delivered_s,
                    sample,
                });
            }
        }
    }

    /// The sensors themselves (their newest readings, parameters and current biases).
    pub fn sensors(&mut self) -> &mut Sensors {
        &mut self.sensors
    }

    /// What has been sampled so far.
    pub fn summary(&self) -> &SensorSummary {
        &self.summary
    }
}
