//! The recorder: one object that writes a run to MCAP, Rerun and a live Foxglove view.
//!
//! [`Recorder::record`] runs on the simulation thread: it decimates, builds the sample's
//! protobuf messages and encodes them in one pass straight into the open MCAP chunk
//! ([`crate::encode`], a microsecond or two). A closed chunk goes to one writer thread
//! ([`crate::writer`]) that compresses it with zstd and writes it, so compression runs on the
//! machine's second core. Rerun's SDK batches on its own threads; the live Foxglove server
//! encodes only for subscribed channels. The file's bytes depend on the samples alone, never
//! on thread timing.
//!
//! This file is the [`Recorder`] and its outputs' fan-out; `mcap_out.rs` is the MCAP
//! output (the open chunk, and the file's start written when it is opened);
//! `wake_warnings.rs` the events about wings outside the wake-capture fits.

use std::collections::BTreeMap;
use std::path::PathBuf;

use flapsim::actuated::ActuatedWingOutput;
use flapsim::{Controls, StepOutput, Vehicle, WingSetOutput};
use wingforce::WingForces;

use crate::error::{Error, Result};
use crate::options::{Level, LogOptions, RunInfo};
#[cfg(any(feature = "rerun", feature = "live"))]
use crate::sample::{Sample, SampleBuilder, WingStatic};
use crate::sample::{time_ns, timestamp};
#[cfg(feature = "live")]
use crate::scene::ForceArrows;
use crate::schema::{OPT_ESTIMATE, OPT_INFLOW, OPT_WIND};
use crate::sensor_msg::SensorMessage;
use crate::writer::Flushed;

use mcap_out::{McapOut, open_mcap};
use wake_warnings::wake_capture_warnings;

mod mcap_out;
mod wake_warnings;

pub use crate::decimate::Decimator;

/// What a finished recording holds.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize)]
pub struct LogStats {
    /// Steps handed to [`Recorder::record`].
    pub steps_seen: u64,
    /// Steps logged after decimation.
    pub samples: u64,
    /// MCAP messages written (all channels, events included).
    pub mcap_messages: u64,
    /// Events written.
    pub events: u64,
    /// The MCAP file, if any.
    pub mcap_path: Option<PathBuf>,
    /// Its size, bytes.
    pub mcap_bytes: u64,
    /// The .rrd file, if any.
    pub rrd_path: Option<PathBuf>,
    /// Time of the last logged sample, s.
    pub last_t_s: f64,
}

/// Writes a run's logs. Create it before the simulation starts, call [`Recorder::record`]
/// for every step and [`Recorder::finish`] at the end (also after an error).
pub struct Recorder {
    mcap: Option<McapOut>,
    #[cfg(feature = "rerun")]
    rerun: Option<crate::rerun_sink::RerunSink>,
    #[cfg(feature = "live")]
    live: Option<crate::live::LiveSink>,
    /// The views' sample when there is no MCAP output (which builds its own).
    #[cfg(any(feature = "rerun", feature = "live"))]
    builder: SampleBuilder,
    #[cfg(any(feature = "rerun", feature = "live"))]
    sample: Sample,
    #[cfg(feature = "live")]
    arrows: ForceArrows,
    #[cfg(feature = "live")]
    arrow_message: foxglove::messages::SceneUpdate,
    decimator: Decimator,
    vehicle: Vehicle,
    controls: Option<Controls>,
    /// The log time and true state of the newest logged sample (what [`Recorder::wind`] and
    /// [`Recorder::estimate`] go with).
    last_sample: Option<(u64, flapsim::State)>,
    #[cfg(feature = "rerun")]
    estimate_statics: std::sync::atomic::AtomicBool,
    wake_warned: Vec<bool>,
    stats: LogStats,
    finished: bool,
}

impl std::fmt::Debug for Recorder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Recorder")
            .field("decimator", &self.decimator)
            .field("stats", &self.stats)
            .finish_non_exhaustive()
    }
}

impl Recorder {
    /// Opens every output in `options`: files are created and the MCAP start (header, the
    /// run's metadata, the model attachment, the schemas and channels) is written now, so a
    /// bad path fails before the run; the live server starts listening. With no output asked
    /// for, returns a recorder that records nothing.
    ///
    /// The log has channels and frames for every wing of `vehicle`
    /// ([`crate::schema::WingLayout`]); a vehicle with more than two wings is recorded with
    /// [`Recorder::record_wings`].
    ///
    /// Errors: an invalid `log_rate_hz` (not finite and > 0), an uncreatable file, a Rerun or
    /// Foxglove option without its feature, no Rerun viewer to spawn or connect to, an
    /// address the live server cannot listen on.
    pub fn create(options: &LogOptions, info: &RunInfo, vehicle: &Vehicle) -> Result<Self> {
        if let Some(r) = options.log_rate_hz
            && !(r.is_finite() && r > 0.0)
        {
            return Err(Error::Options(format!(
                "log rate {r} Hz is not allowed: a finite rate > 0 is required"
            )));
        }
        #[cfg(not(feature = "rerun"))]
        if options.rrd.is_some() || options.rerun_spawn || options.rerun_connect.is_some() {
            return Err(Error::Options(
                "Rerun output needs flightlog's `rerun` feature, which this build lacks".into(),
            ));
        }
        #[cfg(not(feature = "live"))]
        if options.foxglove.is_some() {
            return Err(Error::Options(
                "the live Foxglove view needs flightlog's `live` feature, which this build lacks"
                    .into(),
            ));
        }
        // Servers and viewers first (they fail most often), then files.
        #[cfg(feature = "live")]
        let live = match &options.foxglove {
            Some(addr) => Some(crate::live::LiveSink::start(
                addr,
                options,
                &crate::schema::WingLayout::new(vehicle.wings.len()),
            )?),
            None => None,
        };
        #[cfg(feature = "rerun")]
        let rerun = crate::rerun_sink::RerunSink::open(options, vehicle)?;
        let mcap = match &options.mcap {
            Some(path) => match open_mcap(path, info, vehicle, options) {
                Ok(m) => Some(m),
                Err(e) => {
                    #[cfg(feature = "rerun")]
                    if let Some(r) = rerun {
                        let _ = r.finish();
                        if let Some(rrd) = &options.rrd {
                            let _ = std::fs::remove_file(rrd);
                        }
                    }
                    return Err(e);
                }
            },
            None => None,
        };
        let mut rec = Recorder {
            mcap,
            #[cfg(feature = "rerun")]
            rerun,
            #[cfg(feature = "live")]
            live,
            #[cfg(any(feature = "rerun", feature = "live"))]
            builder: SampleBuilder::new(
                WingStatic::of(vehicle),
                vehicle.weight_n(),
                vehicle.sim.steps_per_wingbeat as u64,
            ),
            #[cfg(any(feature = "rerun", feature = "live"))]
            sample: Sample::default(),
            #[cfg(feature = "live")]
            arrows: ForceArrows::of(vehicle),
            #[cfg(feature = "live")]
            arrow_message: foxglove::messages::SceneUpdate::default(),
            decimator: Decimator::new(options.log_rate_hz),
            vehicle: vehicle.clone(),
            controls: None,
            last_sample: None,
            #[cfg(feature = "rerun")]
            estimate_statics: std::sync::atomic::AtomicBool::new(false),
            wake_warned: vec![false; vehicle.wings.len()],
            stats: LogStats {
                mcap_path: options.mcap.clone(),
                rrd_path: options.rrd.clone(),
                ..LogStats::default()
            },
            finished: false,
        };
        // The warnings about the model itself come first.
        rec.check_wake_capture(0.0)?;
        Ok(rec)
    }

    /// The TCP port the live Foxglove server listens on (`None` without one).
    pub fn foxglove_port(&self) -> Option<u16> {
        #[cfg(feature = "live")]
        return self.live.as_ref().map(crate::live::LiveSink::port);
        #[cfg(not(feature = "live"))]
        None
    }

    /// Warns (once per wing until it changes back) when a wing's wake-capture inputs lie
    /// outside the fitted range of the regressions.
    fn check_wake_capture(&mut self, t_s: f64) -> Result<()> {
        for message in wake_capture_warnings(&self.vehicle, &mut self.wake_warned) {
            self.event(t_s, Level::Warning, &message)?;
        }
        Ok(())
    }

    /// True when a view wants the sample: Rerun, or the live view while a client subscribes
    /// (so an unwatched live run without a file builds no messages).
    #[cfg(any(feature = "rerun", feature = "live"))]
    fn view_wanted(&self) -> bool {
        #[cfg(feature = "rerun")]
        if self.rerun.is_some() {
            return true;
        }
        #[cfg(feature = "live")]
        if self
            .live
            .as_ref()
            .is_some_and(crate::live::LiveSink::wanted)
        {
            return true;
        }
        false
    }

    /// Takes one step's output of a two-winged vehicle; logs it if the decimation picks it.
    /// Blocks only when the writer thread is two chunks behind. Errors of the writer thread
    /// (a full disk, say) come back here. A [`StepOutput`] holds the first pair's wings
    /// only: a vehicle with more wings is an error here ([`Recorder::record_wings`] takes
    /// them all).
    pub fn record(&mut self, out: &StepOutput) -> Result<()> {
        let n = self.vehicle.wings.len();
        if n != 2 {
            return Err(Error::Options(format!(
                "{}: a step output holds two wings of its {n}; record them with Recorder::record_wings",
                self.vehicle.name
            )));
        }
        self.record_inner(out, &out.wings, out.actuated.as_ref().map(|a| &a[..]))
    }

    /// Takes one step's output with the wing set's output of the same step (every wing's
    /// forces and actuator state, e.g. `Simulation::wing_set().output()` after the step);
    /// logs it if the decimation picks it, with the pairs' inflow states where the wake
    /// answers (`/inflow`, when the options ask for it). For any number of wings; errors as
    /// [`Recorder::record`], and when `wings` does not hold the vehicle's wings.
    pub fn record_wings(&mut self, out: &StepOutput, wings: &WingSetOutput) -> Result<()> {
        let n = self.vehicle.wings.len();
        if wings.wings.len() != n || !(wings.actuated.is_empty() || wings.actuated.len() == n) {
            return Err(Error::Options(format!(
                "{}: the wing set output holds {} wings ({} actuated), the vehicle {n}",
                self.vehicle.name,
                wings.wings.len(),
                wings.actuated.len()
            )));
        }
        let actuated = (!wings.actuated.is_empty()).then_some(&wings.actuated[..]);
        self.record_inner(out, &wings.wings, actuated)?;
        if !wings.inflow.is_empty() {
            self.inflow(out.t_s, &wings.inflow)?;
        }
        Ok(())
    }

    fn record_inner(
        &mut self,
        out: &StepOutput,
        wings: &[WingForces],
        actuated: Option<&[ActuatedWingOutput]>,
    ) -> Result<()> {
        self.stats.steps_seen += 1;
        if self.controls != Some(out.controls) {
            if self.controls.is_some() && self.vehicle.apply_controls(&out.controls).is_ok() {
                self.check_wake_capture(out.t_s)?;
            }
            self.controls = Some(out.controls);
        }
        if !self.decimator.take(out.t_s) {
            return Ok(());
        }
        self.stats.samples += 1;
        self.stats.last_t_s = out.t_s;
        self.last_sample = Some((time_ns(out.t_s), out.state));
        if let Some(m) = &mut self.mcap {
            self.stats.mcap_messages += m.sample(out, wings, actuated)?;
        }
        #[cfg(any(feature = "rerun", feature = "live"))]
        self.view(out, wings, actuated)?;
        #[cfg(not(any(feature = "rerun", feature = "live")))]
        let _ = actuated;
        Ok(())
    }

    /// Hands the sample to the Rerun and live views that want it (the messages the MCAP
    /// output built, or built here without one).
    #[cfg(any(feature = "rerun", feature = "live"))]
    fn view(
        &mut self,
        out: &StepOutput,
        wings: &[WingForces],
        actuated: Option<&[ActuatedWingOutput]>,
    ) -> Result<()> {
        if !self.view_wanted() {
            return Ok(());
        }
        let sample = match &self.mcap {
            Some(m) => m.encoder.last(),
            None => {
                self.builder
                    .build_wings(out, wings, actuated, &mut self.sample);
                &self.sample
            }
        };
        #[cfg(feature = "rerun")]
        if let Some(r) = &self.rerun {
            r.frame(&crate::sample::FrameData::of(sample))?;
        }
        #[cfg(feature = "live")]
        if let Some(l) = &mut self.live {
            let (vehicle, t_ns) = (&self.vehicle, sample.t_ns);
            l.scene(|| crate::scene::wing_scene(vehicle, t_ns), t_ns);
            l.sample(sample);
            if l.forces_wanted() {
                self.arrows.build(sample, &mut self.arrow_message);
                l.forces(t_ns, &self.arrow_message);
            }
        }
        Ok(())
    }

    /// Logs one delivered sensor reading to `/sensors/imu` or `/sensors/mocap` at the
    /// simulation time `t_s` of the step it arrived at (every reading, no decimation). The
    /// log must have been created with [`LogOptions::sensors`]; the live view serves them
    /// too, Rerun does not show sensors.
    pub fn sensor(&mut self, t_s: f64, reading: &flapsim::sensor_run::Reading) -> Result<()> {
        let t_ns = time_ns(t_s);
        #[cfg(feature = "live")]
        let live = self.live.as_ref().is_some_and(|l| {
            l.optional_wanted(crate::schema::OPT_IMU) || l.optional_wanted(crate::schema::OPT_MOCAP)
        });
        #[cfg(not(feature = "live"))]
        let live = false;
        if self.mcap.is_none() && !live {
            return Ok(());
        }
        let msg = SensorMessage::of(reading, t_ns);
        if let Some(m) = &mut self.mcap {
            let Some(id) = m.optional_ids[msg.channel()] else {
                return Err(Error::Options(
                    "sensor readings need a log created with LogOptions::sensors".into(),
                ));
            };
            m.encoder
                .optional(msg.channel(), id, t_ns, msg.encoded(), &mut m.chunk);
            self.stats.mcap_messages += 1;
        }
        #[cfg(feature = "live")]
        if let Some(l) = &mut self.live {
            l.optional(msg.channel(), t_ns, msg.encoded());
        }
        Ok(())
    }

    /// The log time of the newest logged sample if it is the step at `t_s` (`None`: that
    /// step was not logged).
    fn sampled(&self, t_s: f64) -> Option<(u64, flapsim::State)> {
        let t_ns = time_ns(t_s);
        self.last_sample.filter(|(t, _)| *t == t_ns)
    }

    /// Whether a message on optional channel `opt` has anywhere to go: the MCAP log, or a
    /// live view that serves the channel.
    fn optional_wanted(&self, opt: usize) -> bool {
        #[cfg(feature = "live")]
        let live = self.live.as_ref().is_some_and(|l| l.optional_wanted(opt));
        #[cfg(not(feature = "live"))]
        let live = false;
        let _ = opt;
        self.mcap.is_some() || live
    }

    /// Writes `msg` on optional channel `opt` at log time `t_ns` to the MCAP log (which must
    /// declare it: `option` names the [`LogOptions`] field that does) and the live view.
    fn write_optional(
        &mut self,
        opt: usize,
        t_ns: u64,
        msg: &dyn crate::sample::Encoded,
        option: &str,
    ) -> Result<()> {
        if let Some(m) = &mut self.mcap {
            let Some(id) = m.optional_ids[opt] else {
                return Err(Error::Options(format!(
                    "{} messages need a log created with LogOptions::{option}",
                    crate::schema::OPTIONAL_CHANNELS[opt].0
                )));
            };
            m.encoder.optional(opt, id, t_ns, msg, &mut m.chunk);
            self.stats.mcap_messages += 1;
        }
        #[cfg(feature = "live")]
        if let Some(l) = &mut self.live {
            l.optional(opt, t_ns, msg);
        }
        Ok(())
    }

    /// Logs each wing pair's dynamic inflow states for the step at `t_s` to `/inflow`
    /// ([`crate::schema::INFLOW_CHANNEL`]): the states the step's loads were taken at
    /// (`flapsim::WingSetOutput::inflow`). Call it after [`Recorder::record`] of the same
    /// step: it is written only when that step was logged. The MCAP log must have been
    /// created with [`LogOptions::inflow`] (the live view then serves `/inflow` too).
    pub fn inflow(&mut self, t_s: f64, pairs: &[wingforce::inflow::InflowState]) -> Result<()> {
        let Some((t_ns, _)) = self.sampled(t_s) else {
            return Ok(());
        };
        if self.optional_wanted(OPT_INFLOW) {
            let msg = crate::estimate_msg::inflow(t_ns, t_s, pairs);
            self.write_optional(OPT_INFLOW, t_ns, &msg, "inflow")?;
        }
        Ok(())
    }

    /// Logs each wing's wind for the step at `t_s` to `/wind` ([`schema::WIND_CHANNEL`]):
    /// `wing_winds_world_m_s` per wing in the vehicle's order (left, right, then any further
    /// pairs), what
    /// [`flapsim::Simulation::wing_winds_m_s`] gives after the step (it includes the uniform
    /// part), and `uniform_world_m_s`, the uniform wind of
    /// [`flapsim::Simulation::set_wind`]; world frame, m/s. Call it after
    /// [`Recorder::record`] of the same step: it is written only when that step was logged
    /// (the log's sample times). The MCAP log must have been created with
    /// [`LogOptions::wind`] (the live view then serves `/wind` too); Rerun shows it under
    /// `plots/wind_m_s/<wing>`.
    ///
    /// [`schema::WIND_CHANNEL`]: crate::schema::WIND_CHANNEL
    pub fn wind(
        &mut self,
        t_s: f64,
        uniform_world_m_s: &nalgebra::Vector3<f64>,
        wing_winds_world_m_s: &[nalgebra::Vector3<f64>],
    ) -> Result<()> {
        let Some((t_ns, _)) = self.sampled(t_s) else {
            return Ok(());
        };
        if self.optional_wanted(OPT_WIND) {
            let msg = crate::estimate_msg::wind(t_ns, t_s, uniform_world_m_s, wing_winds_world_m_s);
            self.write_optional(OPT_WIND, t_ns, &msg, "wind")?;
        }
        #[cfg(feature = "rerun")]
        if let Some(r) = &self.rerun {
            r.wind(t_ns, wing_winds_world_m_s)?;
        }
        Ok(())
    }

    /// Logs the state estimator's newest estimate (its nominal state at its own time, the
    /// standard deviations and the full error-state covariance, and the estimate carried to
    /// `t_s` at constant rates, [`flapsim::estimator::Estimator::state_at`]) for the step
    /// at `t_s` to `/estimate` ([`schema::ESTIMATE_CHANNEL`]). Call it after
    /// [`Recorder::record`] of the same step: it is written only when that step was logged.
    /// The MCAP log must have been created with [`LogOptions::estimate`] (the live view then
    /// serves `/estimate` too); Rerun shows the estimate against the truth
    /// (`plots/estimate/...`, `world/estimate`).
    ///
    /// [`schema::ESTIMATE_CHANNEL`]: crate::schema::ESTIMATE_CHANNEL
    pub fn estimate(&mut self, t_s: f64, filter: &flapsim::estimator::Estimator) -> Result<()> {
        let Some((t_ns, truth)) = self.sampled(t_s) else {
            return Ok(());
        };
        #[cfg(not(feature = "rerun"))]
        let _ = truth;
        #[cfg(feature = "rerun")]
        let rerun = self.rerun.is_some();
        #[cfg(not(feature = "rerun"))]
        let rerun = false;
        if !rerun && !self.optional_wanted(OPT_ESTIMATE) {
            return Ok(());
        }
        let msg = crate::estimate_msg::estimate(t_ns, t_s, filter);
        self.write_optional(OPT_ESTIMATE, t_ns, &msg, "estimate")?;
        #[cfg(feature = "rerun")]
        if let Some(r) = &self.rerun {
            let (roll, pitch, yaw) = truth.euler_rad();
            let view = crate::estimate_msg::EstimateView::of(
                &msg,
                truth.position_m.into(),
                [roll, pitch, yaw].map(f64::to_degrees),
            );
            let first = !self
                .estimate_statics
                .swap(true, std::sync::atomic::Ordering::Relaxed);
            r.estimate(&view, first)?;
        }
        Ok(())
    }

    /// Logs a run event (a `foxglove.Log` on /events, a Rerun TextLog) at simulation time
    /// `t_s` in an MCAP chunk of its own; returns once it is in the file.
    pub fn event(&mut self, t_s: f64, level: Level, message: &str) -> Result<()> {
        let t_ns = time_ns(t_s);
        let log = foxglove::messages::Log {
            timestamp: Some(timestamp(t_ns)),
            level: level as i32,
            message: message.to_owned(),
            name: "flapwing".to_owned(),
            file: String::new(),
            line: 0,
        };
        if let Some(m) = &mut self.mcap {
            m.event(t_ns, &log)?;
            self.stats.mcap_messages += 1;
        }
        #[cfg(feature = "rerun")]
        if let Some(r) = &self.rerun {
            r.event(t_ns, level, message)?;
        }
        #[cfg(feature = "live")]
        if let Some(l) = &mut self.live {
            l.event(t_ns, &log);
        }
        self.stats.events += 1;
        Ok(())
    }

    /// Blocks until a client of the live Foxglove server has subscribed to one of its
    /// channels (so what is recorded from now on reaches it), `timeout` passes (`None`: no
    /// limit) or `cancel` returns true (checked every 20 ms; e.g. Ctrl-C). Without a live
    /// server: [`LiveWait::NoServer`] at once.
    #[cfg(feature = "live")]
    pub fn wait_for_live_client(
        &self,
        timeout: Option<std::time::Duration>,
        cancel: impl Fn() -> bool,
    ) -> crate::live::LiveWait {
        match &self.live {
            Some(l) => l.wait_for_client(timeout, cancel),
            None => crate::live::LiveWait::NoServer,
        }
    }

    /// How much of the run is in the MCAP file at this moment (`None` without one): a kill
    /// now keeps at least these samples. The writer thread advances it each time a closed
    /// chunk is written and flushed; it trails the run by at most the chunk being filled and
    /// the two newest closed chunks.
    pub fn flushed(&self) -> Option<Flushed> {
        self.mcap.as_ref().map(|m| m.writer.flushed())
    }

    /// What has been recorded so far (the file size is known after [`Recorder::finish`]).
    pub fn stats(&self) -> &LogStats {
        &self.stats
    }

    /// Finishes every output: writes the `flapwing.end` metadata, the MCAP summary and
    /// footer, and the Rerun footer; ends the writer thread and stops the live server. Call
    /// it at the end of every run, including after an error.
    pub fn finish(mut self) -> Result<LogStats> {
        self.finish_inner()
    }

    fn finish_inner(&mut self) -> Result<LogStats> {
        if self.finished {
            return Ok(self.stats.clone());
        }
        self.finished = true;
        let mut first_error = None;
        if let Some(mut m) = self.mcap.take() {
            let end = BTreeMap::from([
                ("steps_seen".to_owned(), self.stats.steps_seen.to_string()),
                ("samples".to_owned(), self.stats.samples.to_string()),
                ("messages".to_owned(), self.stats.mcap_messages.to_string()),
                ("events".to_owned(), self.stats.events.to_string()),
                ("last_t_s".to_owned(), self.stats.last_t_s.to_string()),
            ]);
            match m.close_chunk().and_then(|()| m.writer.finish(end)) {
                Ok(bytes) => self.stats.mcap_bytes = bytes,
                Err(e) => first_error = Some(e),
            }
        }
        #[cfg(feature = "rerun")]
        if let Some(r) = self.rerun.take()
            && let Err(e) = r.finish()
        {
            first_error.get_or_insert(e);
        }
        #[cfg(feature = "live")]
        if let Some(l) = self.live.take() {
            l.stop();
        }
        first_error.map_or_else(|| Ok(self.stats.clone()), Err)
    }
}

impl Drop for Recorder {
    /// Best-effort finish; errors are ignored (call [`Recorder::finish`] to see them).
    fn drop(&mut self) {
        let _ = self.finish_inner();
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn recorder_can_move_between_threads() {
        fn send_sync<T: Send + Sync>() {}
        send_sync::<super::Recorder>();
    }
}
