//! The recorder's MCAP output: the chunk being filled on the simulation thread and handed
//! to the writer thread when full or old, and the file's start (header, the run's metadata,
//! the model attachment, the schemas and channels) written when it is opened.

use std::collections::BTreeMap;
use std::fs::File;
use std::path::Path;

use flapsim::actuated::ActuatedWingOutput;
use flapsim::{StepOutput, Vehicle};
use wingforce::WingForces;

use crate::chunk::RawChunk;
use crate::encode::SampleEncoder;
use crate::error::{Error, Result};
use crate::mcap_write::McapWriter;
use crate::options::{LogOptions, RunInfo};
use crate::sample::{SampleBuilder, WingStatic, time_ns};
use crate::scene::ForceArrows;
use crate::schema::{
    self, ACTUATED_STAGE_LOADS_INTERPOLATED, ACTUATED_STAGE_LOADS_KEY, ACTUATED_STAGE_LOADS_SPLIT,
    ACTUATED_STEP_MEAN_KEY, ACTUATED_STEP_MEAN_SPLIT, BODY_ROTATION_KEY, BODY_ROTATION_MIDPOINT,
    MESSAGE_ENCODING, OPTIONAL_CHANNELS, SCHEMA_ENCODING, STRIKE_IMPULSE_KEY,
    STRIKE_IMPULSE_SHARED, STRIKE_IMPULSE_SHARED_TRAPEZOIDAL, WingLayout, channel_id,
};
use crate::writer::{Flushed, Writer};

/// Close the current chunk (so a killed run keeps it) at least this often, simulated time.
const FLUSH_INTERVAL_NS: u64 = 50_000_000;
/// Close the current chunk after this many samples (about 460 kB of protobuf).
const CHUNK_SAMPLES: u64 = 200;

/// The MCAP output: the chunk being filled here, and the writer thread.
pub(super) struct McapOut {
    pub(super) chunk: RawChunk,
    /// Log time of the first sample of the open chunk, and its samples.
    pub(super) chunk_start_ns: u64,
    pub(super) chunk_samples: u64,
    /// The run's samples so far and the newest one's time (what a closed chunk ends with).
    pub(super) upto: Flushed,
    pub(super) encoder: SampleEncoder,
    /// The MCAP ids of the optional channels ([`OPTIONAL_CHANNELS`]) this log declares.
    pub(super) optional_ids: [Option<u16>; OPTIONAL_CHANNELS.len()],
    pub(super) writer: Writer,
}

impl McapOut {
    /// Hands the open chunk (if it holds anything) to the writer thread.
    pub(super) fn close_chunk(&mut self) -> Result<()> {
        if self.chunk.is_empty() {
            return Ok(());
        }
        let next = self.writer.spare_chunk();
        let full = std::mem::replace(&mut self.chunk, next);
        self.chunk_samples = 0;
        self.writer.chunk(full, self.upto)
    }

    /// Adds a sample (every wing's forces and actuator state); the number of messages
    /// written.
    pub(super) fn sample(
        &mut self,
        out: &StepOutput,
        wings: &[WingForces],
        actuated: Option<&[ActuatedWingOutput]>,
    ) -> Result<u64> {
        let t_ns = time_ns(out.t_s);
        if self.chunk_samples > 0 && t_ns.saturating_sub(self.chunk_start_ns) >= FLUSH_INTERVAL_NS {
            self.close_chunk()?;
        }
        if self.chunk_samples == 0 {
            self.chunk_start_ns = t_ns;
        }
        let messages = self.encoder.sample(out, wings, actuated, &mut self.chunk);
        self.chunk_samples += 1;
        self.upto = Flushed {
            samples: self.upto.samples + 1,
            t_s: out.t_s,
        };
        if self.chunk_samples >= CHUNK_SAMPLES {
            self.close_chunk()?;
        }
        Ok(messages)
    }

    /// The event in a chunk of its own; returns once it is in the file.
    pub(super) fn event(&mut self, t_ns: u64, log: &foxglove::messages::Log) -> Result<()> {
        self.close_chunk()?;
        self.encoder.event(t_ns, log, &mut self.chunk);
        self.close_chunk()?;
        self.writer.sync()
    }
}

fn attachment_name(origin: &str) -> String {
    Path::new(origin)
        .file_name()
        .and_then(|n| n.to_str())
        .filter(|n| n.ends_with(".toml"))
        .unwrap_or("model.toml")
        .to_owned()
}

/// The `flapwing` metadata record.
fn run_metadata(
    info: &RunInfo,
    vehicle: &Vehicle,
    log_rate_hz: Option<f64>,
) -> BTreeMap<String, String> {
    let mut md = BTreeMap::from([
        ("version".to_owned(), env!("CARGO_PKG_VERSION").to_owned()),
        ("command".to_owned(), info.command.clone()),
        ("command_line".to_owned(), info.command_line.clone()),
        ("model_toml".to_owned(), info.model_toml.clone()),
        ("model_origin".to_owned(), info.model_origin.clone()),
        ("settings".to_owned(), info.settings_json.clone()),
        ("vehicle".to_owned(), vehicle.name.clone()),
        (
            "log_rate_hz".to_owned(),
            log_rate_hz.map_or_else(|| "every step".to_owned(), |r| r.to_string()),
        ),
        (
            "dt_s".to_owned(),
            (1.0 / (vehicle.freq_hz() * vehicle.sim.steps_per_wingbeat as f64)).to_string(),
        ),
        ("weight_n".to_owned(), vehicle.weight_n().to_string()),
        (
            "added_mass_form".to_owned(),
            vehicle.wings[0].options().added_mass.name().to_owned(),
        ),
        (
            "inflow_model".to_owned(),
            vehicle.inflow_model().name().to_owned(),
        ),
        (
            "load_sampling".to_owned(),
            vehicle.load_sampling().name().to_owned(),
        ),
        (
            ACTUATED_STEP_MEAN_KEY.to_owned(),
            ACTUATED_STEP_MEAN_SPLIT.to_owned(),
        ),
        (
            BODY_ROTATION_KEY.to_owned(),
            BODY_ROTATION_MIDPOINT.to_owned(),
        ),
        ("wing_frame".to_owned(), schema::wing_frame_doc().to_owned()),
    ]);
    // How the run's actuated wings shared strikes and took their stops' loads (none: as
    // before either was written).
    use flapsim::actuated::dynamics::{StageLoads, StrikeShare};
    let share = match vehicle.strike_share() {
        StrikeShare::WholeInStep => None,
        StrikeShare::SemiImplicitPose => Some(STRIKE_IMPULSE_SHARED),
        StrikeShare::TrapezoidalPose => Some(STRIKE_IMPULSE_SHARED_TRAPEZOIDAL),
    };
    let stage_loads = match vehicle.sim.actuated_stage_loads {
        StageLoads::EveryStage => None,
        StageLoads::Interpolated => Some(ACTUATED_STAGE_LOADS_INTERPOLATED),
        StageLoads::Split => Some(ACTUATED_STAGE_LOADS_SPLIT),
    };
    for (key, value) in [
        (STRIKE_IMPULSE_KEY, share),
        (ACTUATED_STAGE_LOADS_KEY, stage_loads),
    ] {
        if let Some(v) = value {
            md.insert(key.to_owned(), v.to_owned());
        }
    }
    md
}

/// Creates the file and writes its start: header, the `flapwing` metadata, the model
/// attachment and the schemas and channels (in a chunk of their own); then hands the file to
/// a writer thread. A file that cannot be written is removed again.
pub(super) fn open_mcap(
    path: &Path,
    info: &RunInfo,
    vehicle: &Vehicle,
    options: &LogOptions,
) -> Result<McapOut> {
    let log_rate_hz = options.log_rate_hz;
    let layout = WingLayout::new(vehicle.wings.len());
    let declared = schema::declared_channels(&layout, options);
    let mut optional_ids = [None; OPTIONAL_CHANNELS.len()];
    for (i, c) in declared.iter().enumerate().skip(layout.channel_count()) {
        if let Some(k) = OPTIONAL_CHANNELS.iter().position(|o| o.0 == c.0) {
            optional_ids[k] = Some(channel_id(i));
        }
    }
    let file = File::create(path).map_err(|e| Error::io("cannot create", path, e))?;
    let start = || -> std::io::Result<McapWriter<std::io::BufWriter<File>>> {
        let mut w = McapWriter::new(
            std::io::BufWriter::with_capacity(64 * 1024, file),
            "",
            &format!("flapwing-flightlog/{}", env!("CARGO_PKG_VERSION")),
        )?;
        w.metadata(
            schema::METADATA_RUN,
            &run_metadata(info, vehicle, log_rate_hz),
        )?;
        w.attachment(
            0,
            0,
            &attachment_name(&info.model_origin),
            "application/toml",
            info.model_toml.as_bytes(),
        )?;
        for (i, (topic, name)) in declared.iter().enumerate() {
            let data = schema::schema_data(name).unwrap_or_default();
            let schema_id = w.add_schema(name, SCHEMA_ENCODING, &data)?;
            let id = w.add_channel(schema_id, topic, MESSAGE_ENCODING)?;
            if id != channel_id(i) {
                return Err(std::io::Error::other(
                    "internal: MCAP channel ids out of order",
                ));
            }
        }
        w.flush()?;
        Ok(w)
    };
    let writer = start()
        .map_err(|e| {
            let _ = std::fs::remove_file(path);
            Error::io("cannot write", path, e)
        })
        .and_then(|w| Writer::start(w, path))?;
    Ok(McapOut {
        chunk: RawChunk::default(),
        chunk_start_ns: 0,
        chunk_samples: 0,
        upto: Flushed::default(),
        encoder: SampleEncoder::new(
            SampleBuilder::new(
                WingStatic::of(vehicle),
                vehicle.weight_n(),
                vehicle.sim.steps_per_wingbeat as u64,
            ),
            ForceArrows::of(vehicle),
            crate::scene::wing_scene(vehicle, 0),
        ),
        optional_ids,
        writer,
    })
}
