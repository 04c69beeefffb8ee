//! Synthetic flights for tests and demonstrations: a closed-loop hover of a "true" vehicle,
//! logged as `flapwing hover --mcap` logs it (states, controls, the model's sensors with
//! their noise), but with another model text (the nominal model a fit starts from)
//! embedded in the log.

use std::path::Path;

use flapsim::control::{Disturbance, HoverController, LqrWeights, run_hover};
use flapsim::sensor_run::SensorRun;
use flapsim::{Controls, Vehicle};
use flightlog::{LogOptions, Recorder, RunInfo};

use crate::data::{ImuFrame, MocapFrame};
use crate::error::{Error, Result};

/// What [`hover_log`] flew, for writing a CSV of the same flight.
#[derive(Debug, Clone)]
pub struct SyntheticFlight {
    /// The motion-capture frames (exposure times).
    pub mocap: Vec<MocapFrame>,
    /// The IMU samples (sample times).
    pub imu: Vec<ImuFrame>,
    /// (step, controls in force) at each wingbeat start.
    pub wingbeat_controls: Vec<Controls>,
}

/// Flies `true_toml`'s vehicle in a trimmed LQR hover from `disturbance` for `duration_s`
/// and logs it to `path` at `log_rate_hz` (`None`: every step) with its sensors drawn from
/// `seed`, embedding `nominal_toml` as the log's model (origin `nominal_origin`).
pub fn hover_log(
    true_toml: &str,
    nominal_toml: &str,
    nominal_origin: &str,
    path: &Path,
    disturbance: &Disturbance,
    duration_s: f64,
    log_rate_hz: Option<f64>,
    seed: u64,
) -> Result<SyntheticFlight> {
    let model = |e: flapsim::Error| Error::Model(e.to_string());
    let log = |e: flightlog::Error| Error::Log {
        path: path.to_owned(),
        detail: e.to_string(),
    };
    let vehicle = Vehicle::from_toml(true_toml, "true model").map_err(model)?;
    let trim = flapsim::trim::trim(&vehicle).map_err(model)?;
    let trimmed = flapsim::trim::trimmed_vehicle(&vehicle, &trim).map_err(model)?;
    let controller =
        HoverController::design(&trimmed, &trim, &LqrWeights::default(), 0).map_err(model)?;
    let settings = serde_json::json!({
        "duration_s": duration_s,
        "disturbance": disturbance,
        "open_loop": false,
        "delay_wingbeats": 0,
        "feedback": "true",
        "trim": trim,
    })
    .to_string();
    let info = RunInfo::new(
        "hover",
        "flapwing-identify synthetic hover",
        nominal_toml,
        nominal_origin,
        settings,
    );
    let opts = LogOptions {
        mcap: Some(path.to_owned()),
        log_rate_hz,
        sensors: true,
        ..LogOptions::default()
    };
    let mut rec = Recorder::create(&opts, &info, &trimmed).map_err(log)?;
    let mut sensors = SensorRun::new(&trimmed, seed).map_err(model)?;
    let per = trimmed.sim.steps_per_wingbeat as u64;
    let mut flight = SyntheticFlight {
        mocap: Vec::new(),
        imu: Vec::new(),
        wingbeat_controls: Vec::new(),
    };
    let mut failed = None;
    run_hover(
        &trimmed,
        &trim,
        Some(controller),
        disturbance,
        duration_s,
        |out| {
            if out.step % per == 0 {
                flight.wingbeat_controls.push(out.controls);
            }
            let mut r = rec.record(out);
            sensors.observe(out.t_s, &out.state, |reading| {
                match reading {
                    flapsim::sensor_run::Reading::Imu { sample, .. } => flight.imu.push(ImuFrame {
                        t_s: sample.t_s,
                        gyro_rad_s: sample.gyro_rad_s,
                        accel_m_s2: sample.accel_m_s2,
                    }),
                    flapsim::sensor_run::Reading::Mocap { sample, .. } => {
                        flight.mocap.push(MocapFrame {
                            t_s: sample.t_s,
                            position_m: sample.position_m,
                            attitude: sample.world_from_body,
                        })
                    }
                }
                if r.is_ok() {
                    r = rec.sensor(out.t_s, &reading);
                }
            });
            match r {
                Ok(()) => true,
                Err(e) => {
                    failed = Some(e);
                    false
                }
            }
        },
    )
    .map_err(model)?;
    if let Some(e) = failed {
        return Err(log(e));
    }
    rec.finish().map_err(log)?;
    Ok(flight)
}
