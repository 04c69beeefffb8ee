//! Conversion of a log to a Rerun recording ([`to_rrd`], feature `rerun`), with the
//! entities of a live recording.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Serialize;

use crate::error::{Error, Result};
use crate::json::Json;
use crate::options::Level;
use crate::read::read_log;
use crate::schema::{TOPIC_EVENTS, TOPIC_STATE};

/// What [`to_rrd`] wrote.
#[cfg(feature = "rerun")]
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct RrdStats {
    /// Samples converted (times with a state, every wing's transform and forces).
    pub frames: u64,
    /// Events converted.
    pub events: u64,
    /// `/estimate` messages converted (those with a state at their log time).
    pub estimates: u64,
    /// `/wind` messages converted.
    pub winds: u64,
}

/// Converts a log to a Rerun recording at `out` (replaced if it exists), with the entities
/// of a live recording (the estimate against the truth and the wing winds of logs that
/// have `/estimate` and `/wind`). The wing meshes come from the embedded model.
#[cfg(feature = "rerun")]
pub fn to_rrd(path: impl AsRef<Path>, out: impl AsRef<Path>) -> Result<RrdStats> {
    use crate::sample::{FrameData, WingView};
    use crate::schema::{FORCE_PARTS, WingLayout};

    let path = path.as_ref();
    let log = read_log(path)?;
    let md = log.run_metadata();
    let toml = md.get("model_toml").map(String::as_str).unwrap_or("");
    let origin = md
        .get("model_origin")
        .map(String::as_str)
        .unwrap_or("model");
    let vehicle = flapsim::Vehicle::from_toml(toml, origin).map_err(|e| {
        Error::Embedded(format!(
            "the model embedded in `{}` does not load: {e}",
            path.display()
        ))
    })?;

    // The wings' channels are those of the embedded model's wings.
    let layout = WingLayout::new(vehicle.wings.len());
    let n = layout.len();
    // Assemble samples by log time; flags say which parts arrived (the state, then each
    // wing's transform, then each wing's forces).
    type Slot = (FrameData, Vec<bool>);
    fn slot(frames: &mut BTreeMap<u64, Slot>, t: u64, n: usize) -> &mut Slot {
        frames.entry(t).or_insert_with(|| {
            (
                FrameData {
                    t_ns: t,
                    wings: vec![WingView::default(); n],
                    ..FrameData::default()
                },
                vec![false; 1 + 2 * n],
            )
        })
    }
    let mut frames: BTreeMap<u64, Slot> = BTreeMap::new();
    for m in log.on(TOPIC_STATE) {
        let Some(v) = log.parse(m) else { continue };
        let (Some(p), Some(q)) = (v.vec3_at("position_m"), v.quat_at("attitude")) else {
            continue;
        };
        let s = slot(&mut frames, m.log_time, n);
        s.0.position = p;
        s.0.attitude = q;
        s.0.euler_deg = [
            v.f64_at("euler_deg.roll").unwrap_or(0.0),
            v.f64_at("euler_deg.pitch").unwrap_or(0.0),
            v.f64_at("euler_deg.yaw").unwrap_or(0.0),
        ];
        s.0.lift_over_weight = v.f64_at("lift_over_weight").unwrap_or(0.0);
        s.1[0] = true;
    }
    for i in 0..n {
        for m in log.on(&layout.tf_topic(i)) {
            let Some(v) = log.parse(m) else { continue };
            let (Some(t), Some(q)) = (v.vec3_at("translation"), v.quat_at("rotation")) else {
                continue;
            };
            let s = slot(&mut frames, m.log_time, n);
            s.0.wings[i].hinge = t;
            s.0.wings[i].rotation = q;
            s.1[1 + i] = true;
        }
    }
    for i in 0..n {
        for m in log.on(&layout.forces_topic(i)) {
            let Some(v) = log.parse(m) else { continue };
            let s = slot(&mut frames, m.log_time, n);
            let mut ok = true;
            for (j, part) in FORCE_PARTS.iter().enumerate() {
                match (
                    v.vec3_at(&format!("{part}.force_n")),
                    v.f64_at(&format!("{part}.c_l")),
                    v.f64_at(&format!("{part}.c_d")),
                ) {
                    (Some(f), Some(cl), Some(cd)) => {
                        s.0.wings[i].force_n[j] = f;
                        s.0.wings[i].c_l[j] = cl;
                        s.0.wings[i].c_d[j] = cd;
                    }
                    _ => ok = false,
                }
            }
            if ok {
                s.1[1 + n + i] = true;
            }
        }
    }
    let out = out.as_ref();
    let stream = crate::rerun_sink::RerunSink::file_stream(out)?;
    let sink = crate::rerun_sink::RerunSink::new(vec![stream], &vehicle)?;
    let mut n = 0u64;
    for (frame, seen) in frames.values() {
        if seen.iter().all(|&x| x) {
            sink.frame(frame)?;
            n += 1;
        }
    }
    let mut estimates = 0u64;
    for m in log.on(crate::schema::TOPIC_ESTIMATE) {
        let Some(v) = log.parse(m) else { continue };
        let Some((truth, _)) = frames.get(&m.log_time).filter(|(_, seen)| seen[0]) else {
            continue;
        };
        let (Some(p), Some(q)) = (v.vec3_at("position_world_m"), v.quat_at("attitude")) else {
            continue;
        };
        let fin = |x: f64| if x.is_finite() { x } else { 0.0 };
        let view = crate::estimate_msg::EstimateView {
            t_ns: m.log_time,
            position: p.map(fin),
            true_position: truth.position.map(fin),
            attitude: q.map(fin),
            euler_deg: ["roll", "pitch", "yaw"]
                .map(|a| fin(v.f64_at(&format!("euler_deg.{a}")).unwrap_or(0.0))),
            true_euler_deg: truth.euler_deg.map(fin),
            position_std: v
                .vec3_at("std.position_world_m")
                .unwrap_or_default()
                .map(fin),
        };
        sink.estimate(&view, estimates == 0)?;
        estimates += 1;
    }
    let mut winds = 0u64;
    for m in log.on(crate::schema::TOPIC_WIND) {
        let Some(v) = log.parse(m) else { continue };
        let Some(Json::Arr(items)) = v.get("wing_winds_world_m_s") else {
            continue;
        };
        let w: Vec<nalgebra::Vector3<f64>> = items
            .iter()
            .map(|w| {
                let c = |k: &str| w.f64_at(k).unwrap_or(0.0);
                nalgebra::Vector3::new(c("x"), c("y"), c("z"))
            })
            .collect();
        sink.wind(m.log_time, &w)?;
        winds += 1;
    }
    let mut events = 0u64;
    for m in log.on(TOPIC_EVENTS) {
        let Some(v) = log.parse(m) else { continue };
        let level = v
            .get("level")
            .and_then(Json::as_i64)
            .and_then(Level::from_int)
            .unwrap_or(Level::Info);
        sink.event(
            m.log_time,
            level,
            v.get("message").and_then(Json::as_str).unwrap_or(""),
        )?;
        events += 1;
    }
    sink.finish()?;
    Ok(RrdStats {
        frames: n,
        events,
        estimates,
        winds,
    })
}
