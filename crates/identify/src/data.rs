//! Flight data to fit: motion-capture frames, optional IMU samples, the controls in force
//! in each wingbeat, the body state at wingbeat starts (where a segment can restart) and the
//! vehicle model, read from a flapwing MCAP log ([`FlightData::from_mcap`]) or from a
//! motion-capture CSV as a lab would export it ([`FlightData::from_csv`], format in the
//! crate's README.md).
//!
//! Time: t = 0 is the start of a wingbeat, and wingbeat w spans [w / f, (w + 1) / f) at the
//! model's wingbeat frequency f (the simulation's step is 1 / (f N) with N =
//! `sim.steps_per_wingbeat`). A measurement taken at time t is compared with the simulated
//! state at the first step at or after t (what flapsim's sensors do: they sample the state
//! at the start of the step in which a sample falls due), at most one step (46 us for the
//! fruit fly) after t.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use flapsim::{Controls, State, Vehicle, VehicleSpec};
use flightlog::replay::{Table, read_summary, read_table};
use flightlog::schema::{TOPIC_CONTROLS, TOPIC_IMU, TOPIC_MOCAP, TOPIC_STATE};
use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use serde::Serialize;

use crate::error::{Error, Result};

pub use crate::frames::{ImuFrame, MocapFrame};

/// Where the state at a segment's start came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StartSource {
    /// The log's `/vehicle/state` at the wingbeat's first step (a simulated log's truth).
    LoggedState,
    /// Estimated from the motion-capture frames around the wingbeat start (see
    /// [`estimate_state`]).
    Mocap,
}

/// A wingbeat start with the body state there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WingbeatStart {
    /// Wingbeat index (t = wingbeat / f).
    pub wingbeat: u64,
    /// The body state at the wingbeat's first step.
    pub state: State,
    /// The wing set's memory of the step before, where the log holds it: a replay from
    /// here then continues bit for bit (see `flapsim::StepOutput::memory`).
    pub memory: Option<flapsim::StepMemory>,
}

/// A uniform wind over a time window (a `flapwing hover --disturbance gust_*`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Gust {
    /// Start, s.
    pub start_s: f64,
    /// Duration, s.
    pub duration_s: f64,
    /// Wind, world, m/s.
    pub velocity_m_s: [f64; 3],
}

/// Everything a fit needs from one flight.
#[derive(Debug, Clone)]
pub struct FlightData {
    /// The file the data came from.
    pub source: PathBuf,
    /// "mcap" or "csv".
    pub format: &'static str,
    /// The vehicle model's text (embedded in an MCAP log, or the `--model` file of a CSV).
    pub model_toml: String,
    /// Where the model came from (for error messages).
    pub model_origin: String,
    /// Motion-capture frames, in time order.
    pub mocap: Vec<MocapFrame>,
    /// IMU samples, in time order (empty without an IMU).
    pub imu: Vec<ImuFrame>,
    /// The controls in force in each wingbeat (`None` where none was logged).
    pub wingbeat_controls: Vec<Option<Controls>>,
    /// Wingbeat starts where a segment can restart, in order.
    pub starts: Vec<WingbeatStart>,
    /// Where the start states came from.
    pub start_source: StartSource,
    /// A uniform gust to replay (hover logs).
    pub gust: Option<Gust>,
    /// The run's wind field to replay (a log's `[wind]`: the hover settings' when the
    /// run's flags set one, else the embedded model's), with its reference point, the
    /// vehicle's start (world, m). The field is a deterministic function of the point and
    /// the time for its seed, so a segment restarted anywhere meets the wind the run met.
    pub wind: Option<(flapsim::WindSpec, Vector3<f64>)>,
    /// The controls were set at every wingbeat start (a closed-loop hover, a CSV): the
    /// replay sets them there too; otherwise only where they change (so that the wing
    /// phases are those of the original run, see `flapsim::Simulation::start_at_step`).
    pub controls_each_wingbeat: bool,
    /// What a truncated or damaged MCAP log lost, and what was recovered from it
    /// (flightlog's `ReplaySummary::damage`: "file truncated or damaged at byte N of M: ...;
    /// recovered K messages from C complete chunks"); `None` for a whole file and a CSV. The
    /// data above is what the complete chunks hold: callers should say so.
    pub damage: Option<String>,
    /// Every logged body state (a flapwing log's `/vehicle/state`: (step, state)), the
    /// recorded flight a resimulation is compared with; empty for a CSV and a bag.
    pub logged_states: Vec<(u64, State, Option<flapsim::StepMemory>)>,
    /// The trim the run's vehicle was built at (a `hover` log's settings): a replay builds
    /// its vehicle the same way (`flapsim::trim::trimmed_vehicle`) before setting the logged
    /// controls, so that it retraces the run bit for bit.
    pub trim: Option<flapsim::trim::Trim>,
    /// An actuated vehicle's wings started the run at rest at step 0 (a log of any run but
    /// a hover: `simulate`, Python); a hover, a CSV and a bag start them on their periodic
    /// motion (a flight recorded in the middle of a hover).
    pub wings_at_rest_at_start: bool,
}

fn log_err(path: &Path, detail: impl Into<String>) -> Error {
    Error::Log {
        path: path.to_owned(),
        detail: detail.into(),
    }
}

/// A table's column index by name.
fn col(t: &Table, name: &str) -> Option<usize> {
    t.columns.iter().position(|c| c == name)
}

/// A numeric cell: proto3 leaves zeros off the wire, so a missing field of a decoded message
/// reads as 0.
fn num(
    path: &Path,
    topic: &str,
    row: &[Option<String>],
    i: Option<usize>,
    field: &str,
) -> Result<f64> {
    match i.and_then(|i| row.get(i)).and_then(|c| c.as_deref()) {
        None => Ok(0.0),
        Some(s) => s
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| {
                log_err(
                    path,
                    format!("`{topic}` field `{field}` = `{s}` is not a finite number"),
                )
            }),
    }
}

fn vec3(
    path: &Path,
    topic: &str,
    t: &Table,
    row: &[Option<String>],
    prefix: &str,
) -> Result<Vector3<f64>> {
    let mut v = Vector3::zeros();
    for (k, axis) in ["x", "y", "z"].iter().enumerate() {
        let f = format!("{prefix}.{axis}");
        v[k] = num(path, topic, row, col(t, &f), &f)?;
    }
    Ok(v)
}

fn quat(
    path: &Path,
    topic: &str,
    t: &Table,
    row: &[Option<String>],
    prefix: &str,
) -> Result<UnitQuaternion<f64>> {
    let mut q = [0.0; 4];
    for (k, axis) in ["w", "x", "y", "z"].iter().enumerate() {
        let f = format!("{prefix}.{axis}");
        q[k] = num(path, topic, row, col(t, &f), &f)?;
    }
    unit_quaternion(q).ok_or_else(|| {
        log_err(
            path,
            format!(
                "`{topic}` field `{prefix}` = (w {}, x {}, y {}, z {}) is not a rotation: allowed a quaternion of norm 1 +- 1e-3",
                q[0], q[1], q[2], q[3]
            ),
        )
    })
}

/// A quaternion (w, x, y, z) of norm within 1e-3 of 1, normalized (kept bit for bit when
/// it is a unit quaternion to round-off, as a logged attitude is: a replay from it then
/// starts where the run was).
fn unit_quaternion(q: [f64; 4]) -> Option<UnitQuaternion<f64>> {
    let q = Quaternion::new(q[0], q[1], q[2], q[3]);
    let n = q.norm();
    if (n - 1.0).abs() <= 8.0 * f64::EPSILON {
        return Some(UnitQuaternion::new_unchecked(q));
    }
    ((n - 1.0).abs() <= 1e-3).then(|| UnitQuaternion::from_quaternion(q))
}

/// The wing set's memory logged with a state (`memory.*` of `/vehicle/state`; `None` in a
/// row without it: the step-start sampling, a restart, a log written before it).
fn step_memory(
    path: &Path,
    t: &Table,
    row: &[Option<String>],
) -> Result<Option<flapsim::StepMemory>> {
    let present = ["w", "x", "y", "z"].iter().any(|a| {
        col(t, &format!("memory.world_from_body.{a}"))
            .and_then(|i| row.get(i))
            .is_some_and(Option::is_some)
    });
    if !present {
        return Ok(None);
    }
    let step = num(path, TOPIC_STATE, row, col(t, "memory.step"), "memory.step")?;
    Ok(Some(flapsim::StepMemory {
        step: step as u64,
        velocity_m_s: vec3(path, TOPIC_STATE, t, row, "memory.velocity_m_s")?,
        rates_rad_s: vec3(path, TOPIC_STATE, t, row, "memory.rates_rad_s")?,
        mid_rates_rad_s: vec3(path, TOPIC_STATE, t, row, "memory.mid_rates_rad_s")?,
        world_from_body: quat(path, TOPIC_STATE, t, row, "memory.world_from_body")?,
    }))
}

/// A topic's table, or an error naming what the fit needs it for.
fn required_table(path: &Path, topic: &str, why: &str) -> Result<Table> {
    let t = read_table(path, topic).map_err(|e| match e {
        flightlog::Error::UnknownTopic { available, .. } => log_err(
            path,
            format!(
                "the log has no `{topic}` channel, which the fit needs ({why}); channels in the log: {available}. Record with `flapwing hover --mcap FILE` on a model with [sensors.mocap]"
            ),
        ),
        other => log_err(path, other.to_string()),
    })?;
    if t.rows.is_empty() {
        return Err(log_err(
            path,
            format!("the `{topic}` channel has no messages, and the fit needs them ({why})"),
        ));
    }
    Ok(t)
}

/// The model's wingbeat frequency, Hz, and steps per wingbeat.
pub(crate) fn timing(vehicle: &Vehicle) -> (f64, u64) {
    (vehicle.freq_hz(), vehicle.sim.steps_per_wingbeat as u64)
}

impl FlightData {
    /// Reads a log written by `flapwing hover` or `flapwing simulate` with sensors:
    /// `/sensors/mocap` (needed), `/sensors/imu` (optional), `/vehicle/controls` (needed)
    /// and `/vehicle/state` (the start states; without it they are estimated from the
    /// motion capture), the embedded model and, for `hover`, the disturbance's gust.
    pub fn from_mcap(path: impl AsRef<Path>) -> Result<Self> {
        Self::read_mcap(path.as_ref(), true)
    }

    /// [`FlightData::from_mcap`] for a resimulation: a log without motion capture is read
    /// too when it holds the body's states (they are the reference then).
    pub fn from_mcap_states(path: impl AsRef<Path>) -> Result<Self> {
        Self::read_mcap(path.as_ref(), false)
    }

    fn read_mcap(path: &Path, need_mocap: bool) -> Result<Self> {
        let summary = read_summary(path).map_err(|e| log_err(path, e.to_string()))?;
        let md = &summary.metadata;
        let model_toml = md.get("model_toml").cloned().unwrap_or_default();
        let model_origin = md
            .get("model_origin")
            .cloned()
            .unwrap_or_else(|| "the log's model".into());
        let spec = VehicleSpec::from_toml(&model_toml, &model_origin).map_err(|e| {
            log_err(
                path,
                format!("the model embedded in the log does not load: {e}"),
            )
        })?;
        let vehicle = spec.build(&model_origin).map_err(|e| {
            log_err(
                path,
                format!("the model embedded in the log does not load: {e}"),
            )
        })?;
        let (freq_hz, per) = timing(&vehicle);
        // The hover settings: trim (the angle-of-attack offset the controls message lacks)
        // and the disturbance's gust.
        let settings: serde_json::Value = md
            .get("settings")
            .and_then(|s| serde_json::from_str(s).ok())
            .unwrap_or(serde_json::Value::Null);
        let trim = settings
            .get("trim")
            .and_then(|t| serde_json::from_value::<flapsim::trim::Trim>(t.clone()).ok());
        let aoa_rad = settings
            .pointer("/trim/controls/aoa_rad")
            .and_then(serde_json::Value::as_f64)
            .unwrap_or(0.0);
        let gust = settings.get("disturbance").and_then(|d| {
            let g = d.get("gust_m_s")?.as_array()?;
            let mut v = [0.0; 3];
            for (o, x) in v.iter_mut().zip(g) {
                *o = x.as_f64()?;
            }
            let duration_s = d.get("gust_duration_s")?.as_f64()?;
            (v != [0.0; 3] && duration_s > 0.0).then_some(Gust {
                start_s: d.get("gust_start_s")?.as_f64()?,
                duration_s,
                velocity_m_s: v,
            })
        });
        // The run's wind field: the settings' (`hover` writes the one its flags made), else
        // the model's `[wind]`.
        let wind_spec = match settings.get("wind") {
            // `simulate --no-wind` of a model with a `[wind]`: still air.
            Some(serde_json::Value::Null) => None,
            Some(w) => Some(
                serde_json::from_value::<flapsim::WindSpec>(w.clone()).map_err(|e| {
                    log_err(path, format!("the settings' `wind` does not load: {e}"))
                })?,
            ),
            None => vehicle.wind.clone(),
        };
        let wind = wind_spec.map(|w| (w, vehicle.initial_position_m));

        // A log without motion capture still holds its states: a resimulation compares
        // with those (a fit then finds no measurement and says so).
        let mocap_t = match required_table(path, TOPIC_MOCAP, "its poses are the measurements") {
            Ok(t) => t,
            Err(_)
                if !need_mocap
                    && read_table(path, TOPIC_STATE).is_ok_and(|t| !t.rows.is_empty()) =>
            {
                Table::default()
            }
            Err(e) => return Err(e),
        };
        let mut mocap = Vec::with_capacity(mocap_t.rows.len());
        for row in &mocap_t.rows {
            let t_s = num(
                path,
                TOPIC_MOCAP,
                row,
                col(&mocap_t, "t_sample_s"),
                "t_sample_s",
            )?;
            mocap.push(MocapFrame {
                t_s,
                position_m: vec3(path, TOPIC_MOCAP, &mocap_t, row, "position_m")?,
                attitude: quat(path, TOPIC_MOCAP, &mocap_t, row, "attitude")?,
            });
        }
        mocap.sort_by(|a, b| a.t_s.total_cmp(&b.t_s));

        let mut imu = Vec::new();
        if let Ok(t) = read_table(path, TOPIC_IMU) {
            for row in &t.rows {
                imu.push(ImuFrame {
                    t_s: num(path, TOPIC_IMU, row, col(&t, "t_sample_s"), "t_sample_s")?,
                    gyro_rad_s: vec3(path, TOPIC_IMU, &t, row, "gyro_rad_s")?,
                    accel_m_s2: vec3(path, TOPIC_IMU, &t, row, "accel_m_s2")?,
                });
            }
            imu.sort_by(|a, b| a.t_s.total_cmp(&b.t_s));
        }

        let ctl = required_table(
            path,
            TOPIC_CONTROLS,
            "the controls are the inputs replayed through the model",
        )?;
        let mut wingbeat_controls: Vec<Option<Controls>> = Vec::new();
        for row in &ctl.rows {
            let f = |name: &str| num(path, TOPIC_CONTROLS, row, col(&ctl, name), name);
            let step = f("step")?;
            if !(step >= 0.0 && step < 1e15) {
                return Err(log_err(
                    path,
                    format!("`{TOPIC_CONTROLS}` field `step` = {step} is not a step index"),
                ));
            }
            let w = step as u64 / per;
            let c = Controls {
                mean_stroke_rad: f("mean_stroke_deg")?.to_radians(),
                amplitude_rad: f("amplitude_deg")?.to_radians(),
                pitch_bias_rad: f("pitch_bias_deg")?.to_radians(),
                aoa_rad,
                freq_hz: f("freq_hz")?,
                diff_amplitude_rad: f("diff_amplitude_deg")?.to_radians(),
                diff_pitch_bias_rad: f("diff_pitch_bias_deg")?.to_radians(),
                diff_mean_stroke_rad: f("diff_mean_stroke_deg")?.to_radians(),
                bias_v: f("drive.bias_v")?,
                amplitude_v: f("drive.amplitude_v")?,
                diff_amplitude_v: f("drive.diff_amplitude_v")?,
                diff_bias_v: f("drive.diff_bias_v")?,
                diff_second_harmonic: f("drive.diff_second_harmonic")?,
            };
            if c.freq_hz != 0.0 {
                return Err(log_err(
                    path,
                    format!(
                        "`{TOPIC_CONTROLS}` field `freq_hz` = {} at step {step}: the fit replays wingbeats of the model's frequency; allowed: 0 (no frequency control)",
                        c.freq_hz
                    ),
                ));
            }
            let w = w as usize;
            if wingbeat_controls.len() <= w {
                wingbeat_controls.resize(w + 1, None);
            }
            // The first sample of a wingbeat holds the controls of the whole wingbeat.
            wingbeat_controls[w].get_or_insert(c);
        }

        let mut logged_states: Vec<(u64, State, Option<flapsim::StepMemory>)> = Vec::new();
        if let Ok(t) = read_table(path, TOPIC_STATE) {
            for row in &t.rows {
                let step = num(path, TOPIC_STATE, row, col(&t, "step"), "step")?;
                if !(step >= 0.0 && step < 1e15) {
                    continue;
                }
                logged_states.push((
                    step as u64,
                    State {
                        position_m: vec3(path, TOPIC_STATE, &t, row, "position_m")?,
                        world_from_body: quat(path, TOPIC_STATE, &t, row, "attitude")?,
                        velocity_m_s: vec3(path, TOPIC_STATE, &t, row, "velocity_m_s")?,
                        angular_velocity_body_rad_s: vec3(
                            path,
                            TOPIC_STATE,
                            &t,
                            row,
                            "body_rates_rad_s",
                        )?,
                    },
                    step_memory(path, &t, row)?,
                ));
            }
            logged_states.sort_by_key(|s| s.0);
            logged_states.dedup_by_key(|s| s.0);
        }
        let mut starts: Vec<WingbeatStart> = logged_states
            .iter()
            .filter(|(step, ..)| step % per == 0)
            .map(|&(step, state, memory)| WingbeatStart {
                wingbeat: step / per,
                state,
                memory,
            })
            .collect();
        let start_source = if logged_states.is_empty() {
            starts = mocap_starts(&mocap, freq_hz, wingbeat_controls.len() as u64);
            StartSource::Mocap
        } else {
            StartSource::LoggedState
        };
        let controls_each_wingbeat = md.get("command").map(String::as_str) == Some("hover")
            && settings
                .get("open_loop")
                .and_then(serde_json::Value::as_bool)
                != Some(true);
        let wings_at_rest_at_start = md.get("command").map(String::as_str) != Some("hover");
        Ok(Self {
            controls_each_wingbeat,
            wings_at_rest_at_start,
            damage: summary.damage.clone(),
            source: path.to_owned(),
            format: "mcap",
            model_toml,
            model_origin,
            mocap,
            imu,
            wingbeat_controls,
            starts,
            start_source,
            gust,
            wind,
            logged_states,
            trim,
        })
    }

    /// Reads a motion-capture CSV (format in the crate's README.md) flown by the vehicle of
    /// `model_toml` (from `model_origin`).
    pub fn from_csv(path: impl AsRef<Path>, model_toml: &str, model_origin: &str) -> Result<Self> {
        let path = path.as_ref();
        let vehicle = recorded_vehicle(model_toml, model_origin, "a CSV flight")?;
        let (freq_hz, _) = timing(&vehicle);
        let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
            what: "read",
            path: path.to_owned(),
            source,
        })?;
        let csv = crate::csv::parse(path, &text, &vehicle)?;
        let mut wingbeat_controls: Vec<Option<Controls>> = Vec::new();
        for (t, c) in &csv.controls {
            let w = (t * freq_hz).floor().max(0.0) as usize;
            if wingbeat_controls.len() <= w {
                wingbeat_controls.resize(w + 1, None);
            }
            wingbeat_controls[w].get_or_insert(*c);
        }
        let starts = mocap_starts(&csv.mocap, freq_hz, wingbeat_controls.len() as u64);
        Ok(Self {
            controls_each_wingbeat: true,
            damage: None,
            source: path.to_owned(),
            format: "csv",
            model_toml: model_toml.to_owned(),
            model_origin: model_origin.to_owned(),
            mocap: csv.mocap,
            imu: csv.imu,
            wingbeat_controls,
            starts,
            start_source: StartSource::Mocap,
            gust: None,
            wind: None,
            logged_states: Vec::new(),
            trim: None,
            wings_at_rest_at_start: false,
        })
    }

    /// Duration covered by the motion capture, s.
    pub fn duration_s(&self) -> f64 {
        match (self.mocap.first(), self.mocap.last()) {
            (Some(a), Some(b)) => b.t_s - a.t_s,
            _ => 0.0,
        }
    }
}

/// The vehicle `model_toml` (from `model_origin`) that flew `what`, a recording
/// with no wind field of its own: it must load and have no
/// `[wind]` (a recorded flight is replayed in still air).
pub(crate) fn recorded_vehicle(
    model_toml: &str,
    model_origin: &str,
    what: &str,
) -> Result<Vehicle> {
    let vehicle = Vehicle::from_toml(model_toml, model_origin)
        .map_err(|e| Error::Model(format!("`{model_origin}` does not load: {e}")))?;
    if vehicle.wind.is_some() {
        return Err(Error::Model(format!(
            "`{model_origin}` has a [wind] field; {what} is replayed in still air: remove it"
        )));
    }
    Ok(vehicle)
}

/// Frames used on each side of a wingbeat start by [`estimate_state`].
pub const START_FIT_FRAMES: usize = 3;

/// Wingbeat starts whose state the motion capture can estimate: every wingbeat with
/// [`START_FIT_FRAMES`] frames on each side.
pub(crate) fn mocap_starts(
    mocap: &[MocapFrame],
    freq_hz: f64,
    wingbeats: u64,
) -> Vec<WingbeatStart> {
    let mut out = Vec::new();
    for w in 0..wingbeats {
        let t = w as f64 / freq_hz;
        if let Some(state) = estimate_state(mocap, t) {
            out.push(WingbeatStart {
                wingbeat: w,
                state,
                memory: None,
            });
        }
    }
    out
}

/// The body state at time `t_s` from the motion capture: the 2 k frames nearest in time
/// (k = [`START_FIT_FRAMES`] before and after `t_s`); position and velocity from a
/// least-squares quadratic in (t - t_s) of each coordinate, attitude and body angular
/// velocity from the same quadratic of the rotation vector of each frame relative to the
/// frame nearest `t_s` (small rotations). `None` without k frames on each side.
pub fn estimate_state(mocap: &[MocapFrame], t_s: f64) -> Option<State> {
    let k = START_FIT_FRAMES;
    let i = mocap.partition_point(|f| f.t_s < t_s);
    if i < k || i + k > mocap.len() {
        return None;
    }
    let frames = &mocap[i - k..i + k];
    let nearest = frames
        .iter()
        .min_by(|a, b| (a.t_s - t_s).abs().total_cmp(&(b.t_s - t_s).abs()))?;
    let q_ref = nearest.attitude;
    let mut xs = Vec::with_capacity(frames.len());
    let mut ys: Vec<[f64; 6]> = Vec::with_capacity(frames.len());
    for f in frames {
        let r = (q_ref.inverse() * f.attitude).scaled_axis();
        xs.push(f.t_s - t_s);
        ys.push([
            f.position_m.x,
            f.position_m.y,
            f.position_m.z,
            r.x,
            r.y,
            r.z,
        ]);
    }
    // Normal equations of y = a + b x + c x^2 (x scaled for conditioning).
    let scale = xs.iter().fold(0.0f64, |m, x| m.max(x.abs())).max(1e-12);
    let mut ata = nalgebra::Matrix3::<f64>::zeros();
    let mut aty = nalgebra::Matrix3x6::<f64>::zeros();
    for (x, y) in xs.iter().zip(&ys) {
        let u = x / scale;
        let row = nalgebra::Vector3::new(1.0, u, u * u);
        ata += row * row.transpose();
        for c in 0..6 {
            for r in 0..3 {
                aty[(r, c)] += row[r] * y[c];
            }
        }
    }
    let coef = ata.try_inverse()? * aty;
    let at = |c: usize| coef[(0, c)];
    let rate = |c: usize| coef[(1, c)] / scale;
    let position_m = Vector3::new(at(0), at(1), at(2));
    let velocity_m_s = Vector3::new(rate(0), rate(1), rate(2));
    let r0 = Vector3::new(at(3), at(4), at(5));
    let world_from_body = q_ref * UnitQuaternion::from_scaled_axis(r0);
    let omega = Vector3::new(rate(3), rate(4), rate(5));
    let state = State {
        position_m,
        world_from_body,
        velocity_m_s,
        angular_velocity_body_rad_s: omega,
    };
    state.first_non_finite().is_none().then_some(state)
}

/// Wingbeats of `data` that have controls, counted.
pub(crate) fn controlled_wingbeats(data: &FlightData) -> BTreeMap<u64, Controls> {
    data.wingbeat_controls
        .iter()
        .enumerate()
        .filter_map(|(w, c)| c.map(|c| (w as u64, c)))
        .collect()
}
