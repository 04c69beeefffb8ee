//! # flightlog
//!
//! Records flapwing runs to [MCAP](https://mcap.dev) (for Foxglove) and, with the `rerun`
//! feature, to [Rerun](https://rerun.io); replays, converts and checks MCAP logs.
//!
//! Recording: build a [`Recorder`] **before** the simulation starts (so an unwritable path
//! fails early), hand it every [`flapsim::StepOutput`] (it decimates to
//! [`LogOptions::log_rate_hz`] itself), report warnings and divergence with
//! [`Recorder::event`], and **call [`Recorder::finish`]** at the end, also after an error or
//! Ctrl-C. `Drop` finishes the file as a best effort but cannot report errors.
//!
//! Messages are protobuf: Foxglove's types from the foxglove crate and flapwing's own
//! ([`proto`], `proto/flapwing.proto`), with their descriptor sets embedded as the schemas.
//! `record` builds and encodes a sample into the open MCAP chunk; a writer thread compresses
//! and writes closed chunks. Errors of the writer thread come back from the next
//! `record`/`event` call and from `finish`. The file's bytes do not depend on the threads'
//! timing. With the `live` feature, [`LogOptions::foxglove`] serves the run to the Foxglove
//! app over its WebSocket protocol.
//!
//! ```no_run
//! use flightlog::{LogOptions, Recorder, RunInfo, SimSettings, Level};
//! let toml = flapsim::DROSOPHILA_TOML;
//! let vehicle = flapsim::Vehicle::from_toml(toml, "drosophila.toml")?;
//! let settings = SimSettings::new(flapsim::Mode::Free, 1.0, Some(2000.0), [0.0; 3]);
//! let info = RunInfo::new("simulate", "flapwing simulate --mcap run.mcap", toml,
//!                         "drosophila.toml", settings.to_json());
//! let opts = LogOptions { mcap: Some("run.mcap".into()), log_rate_hz: Some(2000.0),
//!                         ..LogOptions::default() };
//! let mut rec = Recorder::create(&opts, &info, &vehicle)?;
//! let mut sim = flapsim::Simulation::new(vehicle, flapsim::Mode::Free);
//! let n = (1.0 / sim.dt_s()).round() as u64;
//! for _ in 0..n {
//!     match sim.step() {
//!         Ok(out) => rec.record(&out)?,
//!         Err(e) => { rec.event(sim.time_s(), Level::Error, &e.to_string())?; break; }
//!     }
//! }
//! let stats = rec.finish()?;
//! # let _ = stats;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Reading: [`replay::read_summary`], [`replay::export_csv`], `replay::to_rrd` (feature
//! `rerun`) and [`check::check_log`]. They read today's protobuf logs and the JSON logs of
//! earlier versions, whatever complete chunks a truncated file (a killed run) holds, say
//! what was lost, and never panic on any input.
//!
//! ROS 2 bags (MCAP with `ros2msg` schemas and CDR messages): [`ros2`].
//!
//! The channels, schemas and metadata are listed in the crate's README.md.

pub mod check;
mod chunk;
pub mod compare;
mod decimate;
mod decode;
mod encode;
mod error;
mod estimate_msg;
mod json;
#[cfg(feature = "live")]
mod live;
mod mcap_write;
mod options;
mod pb;
pub mod proto;
mod read;
mod recorder;
pub mod replay;
#[cfg(feature = "rerun")]
mod rerun_sink;
pub mod ros2;
mod sample;
mod scene;
pub mod schema;
mod sensor_msg;
mod tabulate;
mod writer;

pub use error::{Error, Result};
#[cfg(feature = "live")]
pub use live::LiveWait;
pub use options::{Level, LogOptions, RunInfo, SimSettings, mode_name};
pub use recorder::{Decimator, LogStats, Recorder};
pub use writer::Flushed;
