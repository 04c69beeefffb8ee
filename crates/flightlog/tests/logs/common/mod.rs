//! Short drosophila runs (and other models') recorded with flightlog.

#![allow(dead_code)] // each test file uses part of this module

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::io::BufWriter;
use std::path::Path;

use flapsim::{Mode, RunSummary, Simulation, StepOutput, SummaryBuilder, Vehicle};
use flightlog::{LogOptions, LogStats, Recorder, RunInfo, SimSettings};

pub const ORIGIN: &str = "drosophila.toml";

/// One recorded run.
pub struct Run {
    pub outs: Vec<StepOutput>,
    pub summary: RunSummary,
    pub stats: LogStats,
    pub vehicle: Vehicle,
    pub settings: SimSettings,
}

/// Seconds in `wingbeats` drosophila wingbeats.
pub fn wingbeats(n: f64) -> f64 {
    let v = Vehicle::from_toml(flapsim::DROSOPHILA_TOML, ORIGIN).unwrap();
    n / v.freq_hz()
}

/// Records a free drosophila flight of `duration_s` exactly as `flapwing simulate` runs it.
pub fn record(opts: &LogOptions, command: &str, duration_s: f64) -> Run {
    record_mode(opts, command, duration_s, Mode::Free)
}

pub fn record_mode(opts: &LogOptions, command: &str, duration_s: f64, mode: Mode) -> Run {
    record_model(
        opts,
        command,
        duration_s,
        mode,
        flapsim::DROSOPHILA_TOML,
        ORIGIN,
    )
}

/// Records a run of the model `toml` (named `origin`).
pub fn record_model(
    opts: &LogOptions,
    command: &str,
    duration_s: f64,
    mode: Mode,
    toml: &str,
    origin: &str,
) -> Run {
    let vehicle = Vehicle::from_toml(toml, origin).unwrap();
    record_vehicle(opts, command, duration_s, mode, toml, origin, vehicle)
}

/// Records a run of `vehicle`, built from the model `toml` (named `origin`) with settings a
/// model file cannot state (a log of an older scheme, say); the log embeds `toml`.
pub fn record_vehicle(
    opts: &LogOptions,
    command: &str,
    duration_s: f64,
    mode: Mode,
    toml: &str,
    origin: &str,
    vehicle: Vehicle,
) -> Run {
    let settings = SimSettings::new(mode, duration_s, opts.log_rate_hz, [0.0; 3]);
    let info = RunInfo::new(
        command,
        format!("flapwing {command} --duration-s {duration_s}"),
        toml,
        origin,
        settings.to_json(),
    );
    let mut rec = Recorder::create(opts, &info, &vehicle).unwrap();
    let mut sim = Simulation::new(vehicle.clone(), mode);
    let dt = sim.dt_s();
    let mut sb = SummaryBuilder::new(vehicle.weight_n());
    let mut outs = Vec::new();
    let n = (duration_s / dt).round() as u64;
    for _ in 0..n {
        let out = *sim.step().unwrap();
        rec.record(&out).unwrap();
        sb.observe(&out, dt);
        outs.push(out);
    }
    let stats = rec.finish().unwrap();
    Run {
        outs,
        summary: sb.finish(sim.state()),
        stats,
        vehicle,
        settings,
    }
}

pub fn mcap_opts(path: &Path, rate: Option<f64>) -> LogOptions {
    LogOptions {
        mcap: Some(path.to_owned()),
        log_rate_hz: rate,
        ..LogOptions::default()
    }
}

/// Copies an MCAP file, changing the `flapwing` metadata with `edit`.
pub fn copy_with_metadata(src: &Path, dst: &Path, edit: impl Fn(&mut BTreeMap<String, String>)) {
    let bytes = std::fs::read(src).unwrap();
    let summary = mcap::Summary::read(&bytes).unwrap().unwrap();
    let mut w = mcap::WriteOptions::new()
        .compression_threads(0)
        .create(BufWriter::new(std::fs::File::create(dst).unwrap()))
        .unwrap();
    let mut idx = summary.metadata_indexes.clone();
    idx.sort_by_key(|i| i.offset);
    for i in &idx {
        let mut md = mcap::read::metadata(&bytes, i).unwrap();
        if md.name == "flapwing" {
            edit(&mut md.metadata);
        }
        w.write_metadata(&md).unwrap();
    }
    for i in &summary.attachment_indexes {
        let a = mcap::read::attachment(&bytes, i).unwrap();
        w.attach(&mcap::Attachment {
            data: Cow::Owned(a.data.into_owned()),
            ..a
        })
        .unwrap();
    }
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        w.write(&m.unwrap()).unwrap();
    }
    w.finish().unwrap();
}

/// A log message decoded by the descriptor set its channel's schema embeds (protobuf, as the
/// recorder writes them), as JSON-like values: every field of the descriptor by name (proto3
/// scalars left off the wire read back as their defaults), sub-messages only when present.
/// Panics on a message that does not decode, or that holds fields its schema lacks.
pub fn decode(m: &mcap::Message) -> serde_json::Value {
    use prost_reflect::{DescriptorPool, DynamicMessage, Kind, ReflectMessage, Value};
    use serde_json::{Value as J, json};
    fn message(m: &DynamicMessage) -> J {
        assert!(
            m.unknown_fields().next().is_none(),
            "fields outside the schema"
        );
        let mut o = serde_json::Map::new();
        for f in m.descriptor().fields() {
            if matches!(f.kind(), Kind::Message(_)) && !f.is_list() && !m.has_field(&f) {
                continue;
            }
            o.insert(f.name().to_owned(), value(&m.get_field(&f)));
        }
        J::Object(o)
    }
    fn value(v: &Value) -> J {
        match v {
            Value::Bool(b) => json!(b),
            Value::I32(x) | Value::EnumNumber(x) => json!(x),
            Value::I64(x) => json!(x),
            Value::U32(x) => json!(x),
            Value::U64(x) => json!(x),
            Value::F32(x) => json!(x),
            Value::F64(x) => json!(x),
            Value::String(s) => json!(s),
            Value::Message(m) => message(m),
            Value::List(items) => J::Array(items.iter().map(value).collect()),
            other => panic!("unexpected protobuf value {other:?}"),
        }
    }
    let schema = m
        .channel
        .schema
        .as_ref()
        .expect("every channel has a schema");
    assert_eq!(schema.encoding, "protobuf");
    assert_eq!(m.channel.message_encoding, "protobuf");
    let pool = DescriptorPool::decode(&schema.data[..]).expect("a FileDescriptorSet");
    let desc = pool
        .get_message_by_name(&schema.name)
        .unwrap_or_else(|| panic!("{} not in its own descriptor set", schema.name));
    message(&DynamicMessage::decode(desc, &m.data[..]).expect("the message decodes"))
}

/// One force arrow of a decoded `/scene/forces` message (see [`force_arrows`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ForceArrow {
    pub frame_id: String,
    pub frame_locked: bool,
    pub id: String,
    /// Where the arrow starts, in its frame.
    pub position: nalgebra::Vector3<f64>,
    /// From its start to its tip (shaft and head), in its frame, m.
    pub vector: nalgebra::Vector3<f64>,
}

/// The arrows of a decoded `/scene/forces` message: one entity per wing (left, right) with one
/// arrow each, which points along its pose's +x axis.
pub fn force_arrows(v: &serde_json::Value) -> Vec<ForceArrow> {
    let f = |v: &serde_json::Value, k: &str| v[k].as_f64().unwrap_or_else(|| panic!("{k}: {v}"));
    let entities = v["entities"].as_array().expect("entities");
    assert_eq!(entities.len(), 2, "{v}");
    entities
        .iter()
        .map(|e| {
            let arrows = e["arrows"].as_array().expect("arrows");
            assert_eq!(arrows.len(), 1, "{e}");
            let a = &arrows[0];
            let (p, o) = (&a["pose"]["position"], &a["pose"]["orientation"]);
            let q = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
                f(o, "w"),
                f(o, "x"),
                f(o, "y"),
                f(o, "z"),
            ));
            let length = f(a, "shaft_length") + f(a, "head_length");
            ForceArrow {
                frame_id: e["frame_id"].as_str().expect("frame_id").to_owned(),
                frame_locked: e["frame_locked"].as_bool().expect("frame_locked"),
                id: e["id"].as_str().expect("id").to_owned(),
                position: nalgebra::Vector3::new(f(p, "x"), f(p, "y"), f(p, "z")),
                vector: q * nalgebra::Vector3::x() * length,
            }
        })
        .collect()
}
