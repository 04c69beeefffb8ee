//! The sensor flags of `simulate` and `hover`: sample the model's `[sensors]` through the
//! run (flapsim::sensor_run) and log every delivered reading to `/sensors/imu` and
//! `/sensors/mocap`.

use flapsim::sensor_run::SensorRun;
use flightlog::Recorder;

use crate::error::input_error;

/// Sensor flags shared by the commands that fly a vehicle.
#[derive(Debug, Clone, clap::Args)]
pub struct SensorArgs {
    /// Seed of every random draw of the model's sensors (turn-on biases, noise, bias walk);
    /// the same seed gives the same readings. Default 0.
    #[arg(long = "sensor-seed", value_name = "N")]
    pub sensor_seed: Option<u64>,
    /// Do not sample the model's [sensors].
    #[arg(long = "no-sensors", conflicts_with = "sensor_seed")]
    pub no_sensors: bool,
}

/// The run's sensors: the model's `[sensors]` unless `--no-sensors`; none for a model
/// without the table (an error if `--sensor-seed` asked for them).
pub fn start(args: &SensorArgs, vehicle: &flapsim::Vehicle) -> anyhow::Result<Option<SensorRun>> {
    if args.no_sensors || (vehicle.sensors.is_none() && args.sensor_seed.is_none()) {
        return Ok(None);
    }
    SensorRun::new(vehicle, args.sensor_seed.unwrap_or(0))
        .map(Some)
        .map_err(|e| input_error(format!("--sensor-seed: {e}")))
}

/// Shows the sensors one step and logs what they deliver.
pub fn observe(
    run: &mut Option<SensorRun>,
    rec: &mut Option<Recorder>,
    out: &flapsim::StepOutput,
) -> anyhow::Result<()> {
    let Some(run) = run.as_mut() else {
        return Ok(());
    };
    let mut result = Ok(());
    run.observe(out.t_s, &out.state, |r| {
        if let (Some(rec), true) = (rec.as_mut(), result.is_ok()) {
            result = rec.sensor(out.t_s, &r);
        }
    });
    Ok(result?)
}

/// One line of the text reports: what was sampled.
pub fn describe(s: &flapsim::sensor_run::SensorSummary) -> String {
    let mocap = match s.mocap_rate_hz {
        Some(r) => format!(", {} motion-capture frames at {r} Hz", s.mocap_frames),
        None => String::new(),
    };
    format!(
        "sensors (seed {}): {} IMU samples at {} Hz{mocap}",
        s.seed, s.imu_samples, s.imu_rate_hz
    )
}
