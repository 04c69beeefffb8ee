//! Rerun output (feature `rerun`): a 3D view of the flapping vehicle, force arrows and
//! time series, on the timeline `sim_time` (simulation time).
//!
//! Entities (world z up, `ViewCoordinates::RIGHT_HAND_Z_UP` on `world`):
//! * `world/body`: Transform3D world_from_body; `world/body/axes`: the body axes (static).
//! * `world/body/wing_left`, `world/body/wing_right` (and `world/body/wing_{label}` of every
//!   further wing, [`crate::schema::WingLayout`]): Transform3D body_from_wing (the wing
//!   frame of [`crate::schema::wing_frame_doc`]); `.../mesh`: the planform (static).
//! * `world/body/forces/<term>` and `world/body/forces/total`: one arrow per wing from its
//!   hinge, body frame, length = |F| / weight * body length (so an arrow as long as the body
//!   is a force equal to the weight).
//! * `plots/c_l/{label}`, `plots/c_d/{label}` per wing: C_L and C_D of each term and the
//!   total; `plots/lift_over_weight`; `plots/position_m` (x, y, z); `plots/attitude_deg`
//!   (roll, pitch, yaw).
//! * `events`: TextLog of the run events.
//! * Runs with a wind field: `plots/wind_m_s/{label}`: each wing's wind at its hinge,
//!   world frame (x, y, z).
//! * Runs flown on a state estimate: `world/estimate`: Transform3D world_from_body of the
//!   estimate, with `world/estimate/axes` (static, grey; the true body is `world/body`);
//!   `plots/estimate/position_m/{x,y,z}` and `plots/estimate/attitude_deg/{roll,pitch,yaw}`:
//!   the true and the estimated value of each axis in one plot;
//!   `plots/estimate/position_std_m`: the estimate's position standard deviation (x, y, z).
//!
//! The planform mesh is drawn from wingforce's blade-element strips (equal widths
//! `dr = span / n`): at each strip's radius `r_m` the chord is `c = area / dr`, the leading
//! edge lies at `x_cp + 0.25 c` (wingforce puts the translational centre of pressure a
//! quarter chord behind the leading edge) and the trailing edge at `LE - c`; rows at the root
//! and tip repeat the first and last strip.

use std::net::{TcpStream, ToSocketAddrs};
use std::time::Duration;

use flapsim::Vehicle;
use rerun::{RecordingStream, RecordingStreamBuilder};

use crate::error::{Error, Result};
use crate::estimate_msg::EstimateView;
use crate::options::{Level, LogOptions};
use crate::sample::FrameData;
use crate::scene::planform_mesh;
use crate::schema::{FORCE_PARTS, WingLayout};

const APP_ID: &str = "flapwing";
const TIMELINE: &str = "sim_time";

fn rr(e: impl std::fmt::Display) -> Error {
    Error::Rerun(e.to_string())
}

fn f3(v: [f64; 3]) -> [f32; 3] {
    v.map(|x| x as f32)
}

fn q4(q: [f64; 4]) -> rerun::Quaternion {
    rerun::Quaternion::from_xyzw(q.map(|x| x as f32))
}

/// One or more Rerun streams fed the same data.
pub(crate) struct RerunSink {
    streams: Vec<RecordingStream>,
    /// Arrow length per newton, m/N.
    arrow_m_per_n: f64,
    /// The vehicle's length, m (the estimate's axes).
    body_length_m: f64,
    /// Each wing's label (`left`, `right`, `pairs0_left`, ...).
    labels: Vec<String>,
}

impl RerunSink {
    /// The streams `options` ask for (`None` if none).
    pub fn open(options: &LogOptions, vehicle: &Vehicle) -> Result<Option<Self>> {
        let mut streams = Vec::new();
        if options.rerun_spawn {
            let rec = RecordingStreamBuilder::new(APP_ID)
                .enabled(true)
                .spawn()
                .map_err(|e| {
                    Error::Rerun(format!(
                        "cannot spawn a Rerun viewer: {e}. Install the viewer so that `rerun` is \
                         on PATH (e.g. `cargo install rerun-cli --version 0.36.3 --locked` or \
                         `pip install rerun-sdk==0.36.3`), or write a file with --rrd instead"
                    ))
                })?;
            streams.push(rec);
        }
        if let Some(url) = &options.rerun_connect {
            probe_viewer(url)?;
            let rec = RecordingStreamBuilder::new(APP_ID)
                .enabled(true)
                .connect_grpc_opts(url.clone())
                .map_err(|e| {
                    Error::Rerun(format!(
                        "cannot connect to a Rerun viewer at `{url}`: {e} (the URL looks like \
                         rerun+http://127.0.0.1:9876/proxy)"
                    ))
                })?;
            streams.push(rec);
        }
        // The file last, so a viewer error leaves no file behind.
        if let Some(path) = &options.rrd {
            streams.push(Self::file_stream(path)?);
        }
        if streams.is_empty() {
            return Ok(None);
        }
        Self::new(streams, vehicle).map(Some)
    }

    /// A stream writing an .rrd file (created now).
    pub fn file_stream(path: &std::path::Path) -> Result<RecordingStream> {
        RecordingStreamBuilder::new(APP_ID)
            .enabled(true)
            .save(path)
            .map_err(|e| Error::Rerun(format!("cannot create `{}`: {e}", path.display())))
    }

    /// Logs the static scene (view coordinates, wing meshes, series names).
    pub fn new(streams: Vec<RecordingStream>, vehicle: &Vehicle) -> Result<Self> {
        let len = vehicle.length_m;
        let arrow_m_per_n = len / vehicle.weight_n();
        let sink = Self {
            streams,
            arrow_m_per_n,
            body_length_m: len,
            labels: WingLayout::new(vehicle.wings.len()).labels().to_vec(),
        };
        let wing_colors = [
            rerun::Rgba32::from_unmultiplied_rgba(90, 160, 255, 200),
            rerun::Rgba32::from_unmultiplied_rgba(255, 150, 80, 200),
        ];
        for rec in &sink.streams {
            rec.set_log_time_enabled(false);
            rec.log_static("world", &rerun::ViewCoordinates::RIGHT_HAND_Z_UP())
                .map_err(rr)?;
            let h = 0.5 * len as f32;
            rec.log_static(
                "world/body/axes",
                &rerun::Arrows3D::from_vectors([
                    [h, 0.0, 0.0],
                    [0.0, 0.4 * h, 0.0],
                    [0.0, 0.0, 0.4 * h],
                ])
                .with_colors([
                    rerun::Color::from_rgb(220, 40, 40),
                    rerun::Color::from_rgb(40, 200, 40),
                    rerun::Color::from_rgb(40, 80, 220),
                ]),
            )
            .map_err(rr)?;
            for (i, side) in sink.labels.iter().enumerate() {
                let (verts, tris) = planform_mesh(vehicle.wings[i].geometry());
                rec.log_static(
                    format!("world/body/wing_{side}/mesh"),
                    &rerun::Mesh3D::new(verts)
                        .with_triangle_indices(tris)
                        .with_albedo_factor(wing_colors[i % 2]),
                )
                .map_err(rr)?;
            }
            for kind in ["c_l", "c_d"] {
                for side in &sink.labels {
                    rec.log_static(
                        format!("plots/{kind}/{side}"),
                        &rerun::SeriesLines::new().with_names(FORCE_PARTS),
                    )
                    .map_err(rr)?;
                }
            }
            rec.log_static(
                "plots/position_m",
                &rerun::SeriesLines::new().with_names(["x", "y", "z"]),
            )
            .map_err(rr)?;
            rec.log_static(
                "plots/attitude_deg",
                &rerun::SeriesLines::new().with_names(["roll", "pitch", "yaw"]),
            )
            .map_err(rr)?;
            rec.log_static(
                "plots/lift_over_weight",
                &rerun::SeriesLines::new().with_names(["lift / weight"]),
            )
            .map_err(rr)?;
        }
        Ok(sink)
    }

    fn set_time(rec: &RecordingStream, t_ns: u64) {
        let ns = i64::try_from(t_ns).unwrap_or(i64::MAX);
        rec.set_time(TIMELINE, rerun::TimeCell::from_duration_nanos(ns));
    }

    /// Logs one sample.
    pub fn frame(&self, f: &FrameData) -> Result<()> {
        let part_colors = [
            rerun::Color::from_rgb(230, 60, 60),
            rerun::Color::from_rgb(60, 180, 75),
            rerun::Color::from_rgb(70, 120, 230),
            rerun::Color::from_rgb(200, 80, 200),
            rerun::Color::from_rgb(240, 240, 240),
        ];
        for rec in &self.streams {
            Self::set_time(rec, f.t_ns);
            rec.log(
                "world/body",
                &rerun::Transform3D::from_translation_rotation(f3(f.position), q4(f.attitude)),
            )
            .map_err(rr)?;
            for (side, w) in self.labels.iter().zip(&f.wings) {
                rec.log(
                    format!("world/body/wing_{side}"),
                    &rerun::Transform3D::from_translation_rotation(f3(w.hinge), q4(w.rotation)),
                )
                .map_err(rr)?;
            }
            for (j, part) in FORCE_PARTS.iter().enumerate() {
                let vecs = f
                    .wings
                    .iter()
                    .map(|w| f3(w.force_n[j].map(|x| x * self.arrow_m_per_n)));
                rec.log(
                    format!("world/body/forces/{part}"),
                    &rerun::Arrows3D::from_vectors(vecs)
                        .with_origins(f.wings.iter().map(|w| f3(w.hinge)))
                        .with_colors(vec![part_colors[j]; f.wings.len()]),
                )
                .map_err(rr)?;
            }
            for (side, w) in self.labels.iter().zip(&f.wings) {
                rec.log(format!("plots/c_l/{side}"), &rerun::Scalars::new(w.c_l))
                    .map_err(rr)?;
                rec.log(format!("plots/c_d/{side}"), &rerun::Scalars::new(w.c_d))
                    .map_err(rr)?;
            }
            rec.log(
                "plots/lift_over_weight",
                &rerun::Scalars::single(f.lift_over_weight),
            )
            .map_err(rr)?;
            rec.log("plots/position_m", &rerun::Scalars::new(f.position))
                .map_err(rr)?;
            rec.log("plots/attitude_deg", &rerun::Scalars::new(f.euler_deg))
                .map_err(rr)?;
            if let Some(a) = &f.actuation {
                for (side, [volt, hinge, pitch]) in self.labels.iter().zip(a.iter().copied()) {
                    rec.log(
                        format!("plots/actuation/{side}/voltage_v"),
                        &rerun::Scalars::single(volt),
                    )
                    .map_err(rr)?;
                    rec.log(
                        format!("plots/actuation/{side}/hinge_moment_nm"),
                        &rerun::Scalars::single(hinge),
                    )
                    .map_err(rr)?;
                    rec.log(
                        format!("plots/actuation/{side}/pitch_deg"),
                        &rerun::Scalars::single(pitch),
                    )
                    .map_err(rr)?;
                }
            }
        }
        Ok(())
    }

    /// Logs each wing's wind (world frame, m/s) at `t_ns`.
    pub fn wind(&self, t_ns: u64, wing_winds_world_m_s: &[nalgebra::Vector3<f64>]) -> Result<()> {
        for rec in &self.streams {
            Self::set_time(rec, t_ns);
            for (w, side) in wing_winds_world_m_s.iter().zip(&self.labels) {
                let v = [w.x, w.y, w.z].map(|x| if x.is_finite() { x } else { 0.0 });
                rec.log(format!("plots/wind_m_s/{side}"), &rerun::Scalars::new(v))
                    .map_err(rr)?;
            }
        }
        Ok(())
    }

    /// Logs an estimate against the truth; `first` also logs the static parts (series names,
    /// the estimated body's axes).
    pub fn estimate(&self, e: &EstimateView, first: bool) -> Result<()> {
        const AXES: [&str; 3] = ["x", "y", "z"];
        const ANGLES: [&str; 3] = ["roll", "pitch", "yaw"];
        for rec in &self.streams {
            if first {
                for a in AXES {
                    rec.log_static(
                        format!("plots/estimate/position_m/{a}"),
                        &rerun::SeriesLines::new().with_names(["true", "estimated"]),
                    )
                    .map_err(rr)?;
                }
                for a in ANGLES {
                    rec.log_static(
                        format!("plots/estimate/attitude_deg/{a}"),
                        &rerun::SeriesLines::new().with_names(["true", "estimated"]),
                    )
                    .map_err(rr)?;
                }
                rec.log_static(
                    "plots/estimate/position_std_m",
                    &rerun::SeriesLines::new().with_names(AXES),
                )
                .map_err(rr)?;
                let h = 0.4 * self.body_length_m as f32;
                rec.log_static(
                    "world/estimate/axes",
                    &rerun::Arrows3D::from_vectors([[h, 0.0, 0.0], [0.0, h, 0.0], [0.0, 0.0, h]])
                        .with_colors([rerun::Color::from_rgb(150, 150, 150); 3]),
                )
                .map_err(rr)?;
            }
            Self::set_time(rec, e.t_ns);
            rec.log(
                "world/estimate",
                &rerun::Transform3D::from_translation_rotation(f3(e.position), q4(e.attitude)),
            )
            .map_err(rr)?;
            for (i, a) in AXES.iter().enumerate() {
                rec.log(
                    format!("plots/estimate/position_m/{a}"),
                    &rerun::Scalars::new([e.true_position[i], e.position[i]]),
                )
                .map_err(rr)?;
            }
            for (i, a) in ANGLES.iter().enumerate() {
                rec.log(
                    format!("plots/estimate/attitude_deg/{a}"),
                    &rerun::Scalars::new([e.true_euler_deg[i], e.euler_deg[i]]),
                )
                .map_err(rr)?;
            }
            rec.log(
                "plots/estimate/position_std_m",
                &rerun::Scalars::new(e.position_std),
            )
            .map_err(rr)?;
        }
        Ok(())
    }

    /// Logs a run event.
    pub fn event(&self, t_ns: u64, level: Level, message: &str) -> Result<()> {
        let lvl = match level {
            Level::Debug => rerun::TextLogLevel::DEBUG,
            Level::Info => rerun::TextLogLevel::INFO,
            Level::Warning => rerun::TextLogLevel::WARN,
            Level::Error => rerun::TextLogLevel::ERROR,
            Level::Fatal => rerun::TextLogLevel::CRITICAL,
        };
        for rec in &self.streams {
            Self::set_time(rec, t_ns);
            rec.log("events", &rerun::TextLog::new(message).with_level(lvl))
                .map_err(rr)?;
        }
        Ok(())
    }

    /// Flushes and closes every stream (the .rrd footer is written when the last handle of
    /// a stream is dropped).
    pub fn finish(self) -> Result<()> {
        let mut first = None;
        for rec in self.streams {
            if let Err(e) = rec.flush_blocking()
                && first.is_none()
            {
                first = Some(Error::Rerun(format!("flush failed: {e}")));
            }
            drop(rec);
        }
        first.map_or(Ok(()), Err)
    }
}

/// Fails clearly when nothing listens at the viewer URL (gRPC connects lazily otherwise).
fn probe_viewer(url: &str) -> Result<()> {
    let Some((_, rest)) = url.split_once("://") else {
        return Err(Error::Rerun(format!(
            "`{url}` is not a Rerun viewer URL (expected e.g. rerun+http://127.0.0.1:9876/proxy)"
        )));
    };
    let host_port = rest.split('/').next().unwrap_or(rest);
    let addrs: Vec<_> = match host_port.to_socket_addrs() {
        Ok(a) => a.collect(),
        Err(e) => {
            return Err(Error::Rerun(format!(
                "cannot resolve the Rerun viewer address `{host_port}`: {e}"
            )));
        }
    };
    for a in &addrs {
        if TcpStream::connect_timeout(a, Duration::from_secs(2)).is_ok() {
            return Ok(());
        }
    }
    Err(Error::Rerun(format!(
        "no Rerun viewer is listening at `{url}`: start one with `rerun` (it listens on \
         rerun+http://127.0.0.1:9876/proxy), or write a file with --rrd instead"
    )))
}
