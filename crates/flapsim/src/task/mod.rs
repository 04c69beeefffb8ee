//! Control tasks for learning and benchmarking: hover at a point, or recover from a random
//! attitude disturbance, with the control vector updated once per `action_wingbeats`
//! wingbeats and observations from the body's sensors ([`crate::sensors`]). The Gymnasium
//! environments of the Python package (`flapwing/Hover-v0`, `flapwing/Recover-v0`) are these
//! tasks; so is any Rust training loop.
//!
//! - Action: offsets from the hover trim on the vehicle's four control channels
//!   ([`Vehicle::control_channels`]; radians, or volts for actuated vehicles), each within
//!   +-[`Task::action_limit`]: three times the LQR design excursions of
//!   [`LqrWeights::control_max`] (the range the hover LQR saturates at), cut to what the
//!   vehicle accepts about its trim (actuator voltage limits, stroke amplitude at most 180
//!   deg, ...), so that every action in the box is controls the vehicle can fly (about the
//!   nominal trim: a randomised episode's trim moves the box's edges a little).
//! - Observation (12 numbers; 6 without motion capture): the IMU's newest delivered sample,
//!   gyro (rad/s) and specific force minus the trim's (m/s^2), body frame; then the newest
//!   motion-capture frame's position error from the hover point (m) and attitude error from
//!   the trim attitude as a rotation vector (rad). The sensors are switched on
//!   [`preroll_s`] (their longest latency) before the release, with the body held at its
//!   initial state, so the first observation already carries a reading of that state (the
//!   disturbance of a recovery task: the tilt of gravity in the accelerometer, the attitude
//!   error in motion capture) instead of zeros.
//! - Or, with [`TaskSpec::observe`] = [`Observation::Estimate`], the state estimated from
//!   those same readings by the error-state Kalman filter of [`crate::estimator`] (12
//!   numbers, needs motion capture): position error from the hover point (m, world),
//!   velocity (m/s, world), attitude error from the trim as a rotation vector (rad) and
//!   angular rate (rad/s, body), as the filter has them at its newest IMU sample (the IMU's
//!   latency behind), the filter starting from the trim pose ([`Prior::hover`]).
//! - Reward per action (from the true state after it): 1 - (e_p / L)^2 - (e_a / 10 deg)^2,
//!   with e_p the position error, L the body length and e_a the attitude error.
//! - Wind: a model with a `[wind]` table flies every episode in it, evaluated at each wing's
//!   hinge ([`crate::wind`]); the episode's turbulence seed is drawn from the episode seed, and
//!   the table's numbers can be randomised like any real field.
//! - Termination: position error beyond `max_position_body_lengths` body lengths, attitude
//!   error beyond `max_attitude_deg`, or a diverged simulation. Truncation: `duration_s`.

use nalgebra::{UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::actuated::periodic::PeriodicWings;
use crate::control::LqrWeights;
use crate::error::{Error, Result};
use crate::estimator::{Estimator, Prior};
use crate::model::{Vehicle, VehicleSpec};
use crate::randomize::Randomization;
use crate::sensors::{Noise, SensorParams, Sensors};
use crate::sim::{Mode, Simulation};
use crate::trim::{Trim, trim, trimmed_vehicle};

mod limits;
use limits::admissible_limit;

/// What a task asks and how it is scored.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TaskSpec {
    /// Episode length, s (the episode is truncated after it).
    pub duration_s: f64,
    /// Wingbeats per action (1: a control update every wingbeat).
    pub action_wingbeats: usize,
    /// Largest random initial roll and pitch error, deg (uniform in +-); 0 for hover.
    pub disturbance_deg: f64,
    /// Largest random initial velocity, each axis, body lengths per second.
    pub disturbance_body_lengths_s: f64,
    /// Termination: position error, body lengths.
    pub max_position_body_lengths: f64,
    /// Termination: attitude error, deg.
    pub max_attitude_deg: f64,
    /// What the agent observes.
    #[serde(default)]
    pub observe: Observation,
}

/// What a task's agent observes (see the module documentation).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Observation {
    /// The sensors' newest readings.
    #[default]
    Sensors,
    /// The estimator's state from every reading.
    Estimate,
}

impl TaskSpec {
    /// Hover: start at the trim with the sensors' noise only, hold the point for 0.2 s.
    pub fn hover() -> Self {
        Self {
            duration_s: 0.2,
            action_wingbeats: 1,
            disturbance_deg: 0.0,
            disturbance_body_lengths_s: 0.0,
            max_position_body_lengths: 2.0,
            max_attitude_deg: 60.0,
            observe: Observation::Sensors,
        }
    }
    /// Recovery: start with up to 10 deg of roll and pitch error (the 5 deg disturbance of
    /// `flapwing hover`, doubled) and up to 1 body length/s of velocity.
    pub fn recover() -> Self {
        Self {
            disturbance_deg: 10.0,
            disturbance_body_lengths_s: 1.0,
            ..Self::hover()
        }
    }
}

/// How long a task's sensors run before an episode starts: their longest latency (IMU or
/// motion capture), so that each has delivered the sample it took at the start of the
/// pre-roll by the episode's first observation.
pub fn preroll_s(p: &SensorParams) -> f64 {
    p.mocap
        .map_or(p.imu.latency_s, |m| m.latency_s.max(p.imu.latency_s))
}

/// The result of one action.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TaskStep {
    /// Observation after the action.
    pub observation: Vec<f64>,
    /// Reward of the action.
    pub reward: f64,
    /// The episode ended (left the flight envelope or diverged).
    pub terminated: bool,
    /// The episode reached its duration.
    pub truncated: bool,
    /// Why it terminated, in words.
    pub reason: Option<String>,
}

/// One vehicle's task: a simulation with sensors, reset per episode.
#[derive(Debug)]
pub struct Task {
    spec: TaskSpec,
    origin: String,
    model_text: String,
    randomization: Option<Randomization>,
    vehicle: Vehicle,
    trim: Trim,
    /// An actuated vehicle's wings on their periodic motion at the trim with the body at
    /// rest, where every episode starts them (`None` for prescribed kinematics): they depend
    /// on the vehicle and its trim only (not on the episode's disturbance), so they are
    /// settled once per vehicle, not at every reset (the hummingbird's take 40 drive periods).
    settled: Option<Option<PeriodicWings>>,
    sim: Simulation,
    sensors: Option<Sensors>,
    /// The filter fed by the sensors (observing the estimate).
    estimator: Option<Estimator>,
    /// How long the sensors ran before the episode started (their clock leads the
    /// simulation's by this), s.
    preroll_s: f64,
    accel_trim: Vector3<f64>,
    reference_m: Vector3<f64>,
    limit: [f64; 4],
    draws: Vec<(String, f64)>,
    t_end_s: f64,
    done: bool,
}

impl Task {
    /// A task for the model `text` (from `origin`), trimmed once; `randomization` redraws
    /// the model's parameters at every reset.
    pub fn new(
        text: &str,
        origin: &str,
        spec: TaskSpec,
        randomization: Option<Randomization>,
    ) -> Result<Self> {
        let v = wingforce::Validator::new("task");
        v.positive("duration_s", spec.duration_s)?;
        if spec.action_wingbeats == 0 {
            return Err(v
                .invalid("action_wingbeats", 0, "at least 1 wingbeat per action")
                .into());
        }
        v.non_negative(
            "disturbance_body_lengths_s",
            spec.disturbance_body_lengths_s,
        )?;
        v.positive("max_position_body_lengths", spec.max_position_body_lengths)?;
        // An attitude error is at most 180 deg: a larger limit never terminates.
        v.within_open_low("max_attitude_deg", spec.max_attitude_deg, 0.0, 180.0)?;
        // A start beyond the termination limit would end every episode at its first action.
        if !(spec.disturbance_deg >= 0.0 && spec.disturbance_deg < spec.max_attitude_deg) {
            return Err(v
                .invalid(
                    "disturbance_deg",
                    spec.disturbance_deg,
                    &format!(
                        "at least 0 and below max_attitude_deg ({} deg), where an episode terminates",
                        spec.max_attitude_deg
                    ),
                )
                .into());
        }
        let vehicle = VehicleSpec::from_toml(text, origin)?.build(origin)?;
        let steps = vehicle.sim.steps_per_wingbeat;
        if steps.checked_mul(spec.action_wingbeats).is_none() {
            return Err(v
                .invalid(
                    "action_wingbeats",
                    spec.action_wingbeats,
                    &format!(
                        "at most {} ({steps} steps per wingbeat)",
                        usize::MAX / steps.max(1)
                    ),
                )
                .into());
        }
        if vehicle.sensors.is_none() {
            return Err(Error::Analysis(format!(
                "{origin}: a task observes through the model's sensors, and it has no [sensors] table (see models/drosophila.toml)"
            )));
        }
        if spec.observe == Observation::Estimate
            && vehicle.sensors.is_some_and(|s| s.mocap.is_none())
        {
            return Err(Error::Input(format!(
                "{origin}: observe = \"estimate\" needs motion capture ([sensors.mocap]) for the estimator; allowed without it: observe = \"sensors\""
            )));
        }
        if let Some(r) = &randomization {
            r.check(text, origin)?;
        }
        let t = trim(&vehicle)?;
        let sim = Simulation::new(trimmed_vehicle(&vehicle, &t)?, Mode::Free);
        let design = LqrWeights::default().control_max(&vehicle).map(|u| 3.0 * u);
        let limit = admissible_limit(&vehicle, &t, design)?;
        let mut task = Self {
            spec,
            origin: origin.to_owned(),
            model_text: text.to_owned(),
            randomization,
            reference_m: vehicle.initial_position_m,
            vehicle,
            trim: t,
            settled: None,
            sim,
            sensors: None,
            estimator: None,
            preroll_s: 0.0,
            accel_trim: Vector3::zeros(),
            limit,
            draws: Vec::new(),
            t_end_s: 0.0,
            done: true,
        };
        task.reset(0)?;
        Ok(task)
    }

    /// The task's settings.
    pub fn spec(&self) -> &TaskSpec {
        &self.spec
    }
    /// The vehicle of the current episode (randomised, untrimmed).
    pub fn vehicle(&self) -> &Vehicle {
        &self.vehicle
    }
    /// The current episode's trim.
    pub fn trim(&self) -> &Trim {
        &self.trim
    }
    /// The simulation (for inspection).
    pub fn simulation(&self) -> &Simulation {
        &self.sim
    }
    /// The largest action magnitude per channel.
    pub fn action_limit(&self) -> [f64; 4] {
        self.limit
    }
    /// Length of an observation.
    pub fn observation_len(&self) -> usize {
        if self.vehicle.sensors.is_some_and(|s| s.mocap.is_some()) {
            12
        } else {
            6
        }
    }
    /// This episode's randomised parameters (model path, drawn scale).
    pub fn draws(&self) -> &[(String, f64)] {
        &self.draws
    }
    /// Simulation steps per action.
    pub fn steps_per_action(&self) -> u64 {
        (self.vehicle.sim.steps_per_wingbeat as u64)
            .saturating_mul(self.spec.action_wingbeats as u64)
    }

    /// The reward at the edge of the envelope, given when the state is no longer finite.
    pub fn worst_reward(&self) -> f64 {
        let s = &self.spec;
        1.0 - s.max_position_body_lengths.powi(2) - (s.max_attitude_deg / 10.0).powi(2)
    }

    /// Starts an episode; everything random in it (parameters, disturbance, sensor noise)
    /// comes from `seed`. Returns the first observation.
    pub fn reset(&mut self, seed: u64) -> Result<Vec<f64>> {
        let mut rng = Noise::new(seed);
        if let Some(r) = &self.randomization {
            let (text, draws) = r.draw(&self.model_text, &self.origin, &mut rng)?;
            let spec = VehicleSpec::from_toml(&text, &self.origin)?;
            self.vehicle = spec.build(&self.origin)?;
            self.trim = trim(&self.vehicle)?;
            self.settled = None;
            self.draws = draws;
        }
        let mut v = trimmed_vehicle(&self.vehicle, &self.trim)?;
        let s = &self.spec;
        let mut u = || 2.0 * rng.uniform() - 1.0;
        let (roll, pitch) = (
            (s.disturbance_deg * u()).to_radians(),
            (s.disturbance_deg * u()).to_radians(),
        );
        let vel = s.disturbance_body_lengths_s * v.length_m;
        let velocity = Vector3::new(vel * u(), vel * u(), vel * u());
        v.initial_attitude =
            self.trim.attitude() * UnitQuaternion::from_euler_angles(roll, pitch, 0.0);
        v.initial_velocity_m_s = velocity;
        self.reference_m = v.initial_position_m;
        let periodic = match &self.settled {
            Some(p) => p,
            None => self
                .settled
                .insert(crate::actuated::periodic::settle_at_rest(&v)?),
        };
        let g = v.gravity_m_s2;
        let params = v
            .sensors
            .ok_or_else(|| Error::Analysis(format!("{}: no [sensors] table", self.origin)))?;
        let wind = v.wind.clone();
        self.sim = Simulation::new(v, Mode::Free);
        if let Some(p) = periodic {
            self.sim.start_wings_from(p);
        }
        // Pre-roll: the sensors run for their longest latency before the release, seeing
        // the body held at its initial (disturbed) state, so that the first observation is
        // a delivered reading of that state rather than zeros (an IMU latency of 5 ms is
        // longer than a 4.6 ms wingbeat). Held, the body has no acceleration: the
        // accelerometer reads gravity in the tilted body frame, motion capture the pose.
        self.preroll_s = preroll_s(&params);
        let mut sensors = Sensors::new(&params, g, rng.next_seed());
        // The model's `[wind]` (its numbers randomisable like any real field); the episode's
        // turbulence comes from the episode seed, drawn after everything else so that a model
        // without wind draws what it always drew.
        if let Some(mut w) = wind {
            if let Some(t) = &mut w.turbulence {
                t.seed = rng.next_seed();
            }
            let field = crate::wind::Wind::from_spec(&w, &self.origin, self.reference_m)?;
            self.sim.set_wind_model(Some(field));
        }
        self.estimator = match self.spec.observe {
            Observation::Sensors => None,
            Observation::Estimate => Some(Estimator::new(
                &params,
                g,
                &Prior::hover(&self.vehicle, self.trim.attitude()),
            )?),
        };
        let s0 = self.sim.state();
        sensors.observe(0.0, &s0);
        sensors.observe(self.preroll_s, &s0);
        self.sensors = Some(sensors);
        self.feed_estimator(self.preroll_s);
        // The specific force at hover is +g along the world vertical: subtracted so that
        // the observation is zero at the trim.
        self.accel_trim = self.trim.attitude().inverse() * Vector3::new(0.0, 0.0, g);
        self.t_end_s = self.spec.duration_s;
        self.done = false;
        Ok(self.observe())
    }

    /// Hands the estimator (if observing the estimate) every reading delivered by the
    /// sensors' time `t_s`, oldest first.
    fn feed_estimator(&mut self, t_s: f64) {
        let (Some(f), Some(sensors)) = (&mut self.estimator, &mut self.sensors) else {
            return;
        };
        while let Some((_, s)) = sensors.imu.next_delivered(t_s) {
            f.imu(&s);
        }
        if let Some(m) = &mut sensors.mocap {
            while let Some((_, s)) = m.next_delivered(t_s) {
                f.mocap(&s);
            }
        }
    }

    /// The estimator's newest state as an observation (see the module documentation).
    fn estimate_observation(&self, f: &Estimator) -> Vec<f64> {
        // At its own newest sample time the filter's state is not carried anywhere.
        let s = f.state_at(f.time_s().unwrap_or(0.0));
        let d = (self.trim.attitude().inverse() * s.world_from_body).scaled_axis();
        (s.position_m - self.reference_m)
            .iter()
            .chain(s.velocity_m_s.iter())
            .chain(d.iter())
            .chain(s.angular_velocity_body_rad_s.iter())
            .copied()
            .collect()
    }

    fn observe(&mut self) -> Vec<f64> {
        if let Some(f) = &self.estimator {
            return self.estimate_observation(f);
        }
        let t = self.sim.time_s() + self.preroll_s;
        let mut o = Vec::with_capacity(12);
        let Some(sensors) = &mut self.sensors else {
            return vec![0.0; self.observation_len()];
        };
        match sensors.imu.read(t) {
            Some(s) => {
                o.extend_from_slice(s.gyro_rad_s.as_slice());
                o.extend_from_slice((s.accel_m_s2 - self.accel_trim).as_slice());
            }
            None => o.extend_from_slice(&[0.0; 6]),
        }
        if let Some(m) = &mut sensors.mocap {
            match m.read(t) {
                Some(f) => {
                    o.extend_from_slice((f.position_m - self.reference_m).as_slice());
                    let d = (self.trim.attitude().inverse() * f.world_from_body).scaled_axis();
                    o.extend_from_slice(d.as_slice());
                }
                None => o.extend_from_slice(&[0.0; 6]),
            }
        }
        o
    }

    /// Applies `action` (offsets on the four control channels from the trim) for
    /// `action_wingbeats` wingbeats. An action outside +-`action_limit` or not finite is an
    /// error (never clamped); stepping a finished episode is an error.
    pub fn step(&mut self, action: &[f64]) -> Result<TaskStep> {
        match self.step_interruptible(action, &mut || true)? {
            Some(s) => Ok(s),
            None => Err(Error::Analysis("the action was interrupted".into())),
        }
    }

    /// [`Task::step`], asking `keep_going` before every simulation step whether to go on:
    /// when it says no, the action stops there, the episode ends (reset before stepping
    /// again) and the result is `Ok(None)`. The Python bindings use it to honour Ctrl-C
    /// during long actions.
    pub fn step_interruptible(
        &mut self,
        action: &[f64],
        keep_going: &mut dyn FnMut() -> bool,
    ) -> Result<Option<TaskStep>> {
        if self.done {
            return Err(Error::Analysis(
                "the episode has ended: call reset before stepping again".into(),
            ));
        }
        if action.len() != 4 {
            return Err(Error::Analysis(format!(
                "an action has 4 channels ({}), got {}",
                self.vehicle.control_channels().join(", "),
                action.len()
            )));
        }
        for (i, (a, lim)) in action.iter().zip(self.limit).enumerate() {
            if !a.is_finite() || a.abs() > lim {
                return Err(Error::Analysis(format!(
                    "action[{i}] ({}) = {a} is outside the allowed +-{lim}",
                    self.vehicle.control_channels()[i]
                )));
            }
        }
        let drive = self.vehicle.drive_controlled();
        self.sim
            .set_controls(self.trim.controls.with_channels(drive, action));
        let mut reason = None;
        for _ in 0..self.steps_per_action() {
            if !keep_going() {
                self.done = true;
                return Ok(None);
            }
            if let Err(e) = self.sim.step() {
                reason = Some(e.to_string());
                break;
            }
            let t_sensors = self.sim.time_s() + self.preroll_s;
            if let Some(s) = &mut self.sensors {
                s.observe(t_sensors, &self.sim.state());
            }
            self.feed_estimator(t_sensors);
        }
        let s = self.sim.state();
        let l = self.vehicle.length_m;
        let e_p = (s.position_m - self.reference_m).norm();
        let e_a = (self.trim.attitude().inverse() * s.world_from_body).angle();
        let reward = 1.0 - (e_p / l).powi(2) - (e_a / 10f64.to_radians()).powi(2);
        if reason.is_none() && e_p > self.spec.max_position_body_lengths * l {
            reason = Some(format!(
                "position error {:.2} body lengths exceeds {}",
                e_p / l,
                self.spec.max_position_body_lengths
            ));
        }
        if reason.is_none() && e_a.to_degrees() > self.spec.max_attitude_deg {
            reason = Some(format!(
                "attitude error {:.1} deg exceeds {} deg",
                e_a.to_degrees(),
                self.spec.max_attitude_deg
            ));
        }
        let terminated = reason.is_some();
        let truncated = !terminated && self.sim.time_s() >= self.t_end_s - 0.5 * self.sim.dt_s();
        self.done = terminated || truncated;
        Ok(Some(TaskStep {
            observation: self.observe(),
            reward: if reward.is_finite() {
                reward
            } else {
                self.worst_reward()
            },
            terminated,
            truncated,
            reason,
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fly() -> &'static str {
        crate::builtin_model("drosophila").unwrap()
    }

    #[test]
    fn task_settings_that_end_every_episode_at_once_are_refused() {
        let bad = [
            TaskSpec {
                max_attitude_deg: 1e300,
                ..TaskSpec::hover()
            },
            TaskSpec {
                disturbance_deg: 60.0,
                ..TaskSpec::recover()
            },
        ];
        for (spec, field) in bad.iter().zip(["max_attitude_deg", "disturbance_deg"]) {
            let e = Task::new(fly(), "fly", *spec, None)
                .unwrap_err()
                .to_string();
            assert!(e.contains(field), "{e}");
        }
    }
}
