//! A recorded flight and its resimulation in one log: an MCAP file (Foxglove) and a Rerun
//! recording with the two bodies as two frames and their differences as time series.
//!
//! MCAP (written with Foxglove's SDK, protobuf messages of its own schemas, on a context
//! of its own so no other sink sees them):
//! * `/tf/real`, `/tf/sim`: `foxglove.FrameTransform` world -> `real` and world -> `sim`
//!   (the recorded body and the simulated one; the 3D panel shows both frames);
//! * `/real/pose`, `/sim/pose`: `foxglove.PoseInFrame` in `world` (plot paths
//!   `/real/pose.pose.position.z` beside `/sim/pose.pose.position.z`);
//! * `/residual`: JSON (`flapwing.Residual`: `segment`, `position_error_m`,
//!   `attitude_error_deg`, `rate_error_rad_s` where the rates are known), at each recorded
//!   sample a segment covers;
//! * a `flapwing_comparison` metadata record (`summary`: the residual summary as JSON).
//!
//! `docs/foxglove/resimulate.json` is a Foxglove layout for it: the 3D panel following
//! `real` with both frames, and plots of the positions and the residuals.
//!
//! Rerun (timeline `sim_time`): `world/real` and `world/sim` (Transform3D with axes),
//! `plots/position_m/{x,y,z}` with a `real` and a `sim` series each, and
//! `plots/residual/{position_error_m,attitude_error_deg,rate_error_rad_s}`.

use std::collections::BTreeMap;
use std::path::Path;

use foxglove::messages::{FrameTransform, Pose, PoseInFrame};
use nalgebra::{UnitQuaternion, Vector3};

use crate::error::{Error, Result};
use crate::sample::{fox_quat, fox_vec, time_ns, timestamp};

/// The world frame's name in the comparison log.
pub const FRAME_WORLD: &str = "world";

/// One pose of a body at a time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackPoint {
    /// Time, s (t = 0: a wingbeat start).
    pub t_s: f64,
    /// Position, world, m.
    pub position_m: Vector3<f64>,
    /// Attitude, world_from_body.
    pub world_from_body: UnitQuaternion<f64>,
}

/// The difference between the two bodies at one recorded sample.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ResidualPoint {
    /// Time, s.
    #[serde(skip)]
    pub t_s: f64,
    /// The segment it belongs to (from 0).
    pub segment: u32,
    /// |simulated - recorded position|, m.
    pub position_error_m: f64,
    /// Angle of recorded^-1 * simulated attitude, deg.
    pub attitude_error_deg: f64,
    /// |simulated - recorded body rates|, rad/s, where the record has rates.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rate_error_rad_s: Option<f64>,
}

/// What one comparison log holds.
#[derive(Debug, Clone, Copy)]
pub struct Comparison<'a> {
    /// The recorded body.
    pub real: &'a [TrackPoint],
    /// The simulated body.
    pub simulated: &'a [TrackPoint],
    /// Their differences.
    pub residuals: &'a [ResidualPoint],
    /// The residual summary (JSON), for the metadata record.
    pub summary_json: &'a str,
}

const RESIDUAL_SCHEMA: &str = r#"{"type":"object","properties":{"segment":{"type":"integer"},"position_error_m":{"type":"number"},"attitude_error_deg":{"type":"number"},"rate_error_rad_s":{"type":"number"}}}"#;

fn fox(e: foxglove::FoxgloveError, path: &Path) -> Error {
    Error::io("cannot write", path, std::io::Error::other(e.to_string()))
}

/// Writes the comparison as MCAP to `path` (which must not exist).
pub fn write_mcap(path: &Path, c: &Comparison<'_>) -> Result<()> {
    let ctx = foxglove::Context::new();
    let writer = ctx
        .mcap_writer()
        .create_new_buffered_file(path)
        .map_err(|e| fox(e, path))?;
    let tf_real = ctx.channel_builder("/tf/real").build::<FrameTransform>();
    let tf_sim = ctx.channel_builder("/tf/sim").build::<FrameTransform>();
    let pose_real = ctx.channel_builder("/real/pose").build::<PoseInFrame>();
    let pose_sim = ctx.channel_builder("/sim/pose").build::<PoseInFrame>();
    let residual = ctx
        .channel_builder("/residual")
        .message_encoding("json")
        .schema(foxglove::Schema::new(
            "flapwing.Residual",
            "jsonschema",
            RESIDUAL_SCHEMA.as_bytes().to_vec(),
        ))
        .build_raw()
        .map_err(|e| fox(e, path))?;
    // Both bodies' samples in time order, so the file's messages are too.
    let mut events: Vec<(u64, u8, usize)> = Vec::new();
    events.extend(
        c.real
            .iter()
            .enumerate()
            .map(|(i, p)| (time_ns(p.t_s), 0, i)),
    );
    events.extend(
        c.simulated
            .iter()
            .enumerate()
            .map(|(i, p)| (time_ns(p.t_s), 1, i)),
    );
    events.extend(
        c.residuals
            .iter()
            .enumerate()
            .map(|(i, r)| (time_ns(r.t_s), 2, i)),
    );
    events.sort_unstable();
    for (t_ns, kind, i) in events {
        if kind == 2 {
            let json = serde_json::to_vec(&c.residuals[i])?;
            residual.log_with_meta(
                &json,
                foxglove::PartialMetadata {
                    log_time: Some(t_ns),
                },
            );
            continue;
        }
        let (p, frame, tf, pose) = if kind == 0 {
            (&c.real[i], "real", &tf_real, &pose_real)
        } else {
            (&c.simulated[i], "sim", &tf_sim, &pose_sim)
        };
        let stamp = Some(timestamp(t_ns));
        tf.log_with_time(
            &FrameTransform {
                timestamp: stamp,
                parent_frame_id: FRAME_WORLD.into(),
                child_frame_id: frame.into(),
                translation: Some(fox_vec(&p.position_m)),
                rotation: Some(fox_quat(&p.world_from_body)),
            },
            t_ns,
        );
        pose.log_with_time(
            &PoseInFrame {
                timestamp: stamp,
                frame_id: FRAME_WORLD.into(),
                pose: Some(Pose {
                    position: Some(fox_vec(&p.position_m)),
                    orientation: Some(fox_quat(&p.world_from_body)),
                }),
            },
            t_ns,
        );
    }
    writer
        .write_metadata(
            "flapwing_comparison",
            BTreeMap::from([("summary".to_owned(), c.summary_json.to_owned())]),
        )
        .map_err(|e| fox(e, path))?;
    writer.close().map_err(|e| fox(e, path))?;
    Ok(())
}

/// Writes the comparison as a Rerun recording to `path`.
#[cfg(feature = "rerun")]
pub fn write_rrd(path: &Path, c: &Comparison<'_>) -> Result<()> {
    let rec = crate::rerun_sink::RerunSink::file_stream(path)?;
    let rr = |e: rerun::RecordingStreamError| Error::Rerun(e.to_string());
    let f3 = |v: &Vector3<f64>| [v.x as f32, v.y as f32, v.z as f32];
    let q4 = |q: &UnitQuaternion<f64>| {
        rerun::Quaternion::from_xyzw([q.i as f32, q.j as f32, q.k as f32, q.w as f32])
    };
    rec.log_static("world", &rerun::ViewCoordinates::RIGHT_HAND_Z_UP())
        .map_err(rr)?;
    let axis_m = 1e-3;
    for (name, grey) in [("real", 255u8), ("sim", 150u8)] {
        rec.log_static(
            format!("world/{name}/axes"),
            &rerun::Arrows3D::from_vectors([
                [axis_m, 0.0, 0.0],
                [0.0, axis_m, 0.0],
                [0.0, 0.0, axis_m],
            ])
            .with_colors([
                rerun::Color::from_rgb(grey, 40, 40),
                rerun::Color::from_rgb(40, grey, 40),
                rerun::Color::from_rgb(40, 80, grey),
            ]),
        )
        .map_err(rr)?;
    }
    for axis in ["x", "y", "z"] {
        rec.log_static(
            format!("plots/position_m/{axis}"),
            &rerun::SeriesLines::new().with_names(["real", "sim"]),
        )
        .map_err(rr)?;
    }
    let track = |name: &str, points: &[TrackPoint]| -> Result<()> {
        for p in points {
            rec.set_time(
                "sim_time",
                rerun::TimeCell::from_duration_nanos(time_ns(p.t_s) as i64),
            );
            rec.log(
                format!("world/{name}"),
                &rerun::Transform3D::from_translation_rotation(
                    f3(&p.position_m),
                    q4(&p.world_from_body),
                ),
            )
            .map_err(rr)?;
        }
        Ok(())
    };
    track("real", c.real)?;
    track("sim", c.simulated)?;
    // The positions side by side: each axis a plot with the two series, at the recorded
    // samples (the simulated body at the same times is in the residuals' segments).
    let sim_at = |t: f64| {
        let i = c.simulated.partition_point(|p| p.t_s < t - 1e-12);
        c.simulated.get(i).filter(|p| (p.t_s - t).abs() < 1e-9)
    };
    for p in c.real {
        let Some(s) = sim_at(p.t_s) else { continue };
        rec.set_time(
            "sim_time",
            rerun::TimeCell::from_duration_nanos(time_ns(p.t_s) as i64),
        );
        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
            rec.log(
                format!("plots/position_m/{axis}"),
                &rerun::Scalars::new([p.position_m[k], s.position_m[k]]),
            )
            .map_err(rr)?;
        }
    }
    for r in c.residuals {
        rec.set_time(
            "sim_time",
            rerun::TimeCell::from_duration_nanos(time_ns(r.t_s) as i64),
        );
        rec.log(
            "plots/residual/position_error_m",
            &rerun::Scalars::single(r.position_error_m),
        )
        .map_err(rr)?;
        rec.log(
            "plots/residual/attitude_error_deg",
            &rerun::Scalars::single(r.attitude_error_deg),
        )
        .map_err(rr)?;
        if let Some(e) = r.rate_error_rad_s {
            rec.log(
                "plots/residual/rate_error_rad_s",
                &rerun::Scalars::single(e),
            )
            .map_err(rr)?;
        }
    }
    rec.flush_blocking()
        .map_err(|e| Error::Rerun(e.to_string()))?;
    Ok(())
}
