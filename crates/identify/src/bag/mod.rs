//! Flight data from a ROS 2 bag: which topic plays which role (the body's pose, the IMU,
//! the drive or the controls) and the recording's frame conventions ([`BagRoles`], from
//! flags or a TOML file, format in the crate's README.md), read into the same
//! [`FlightData`] a CSV gives.
//!
//! Pose messages: `geometry_msgs/msg/PoseStamped`, `geometry_msgs/msg/PoseWithCovarianceStamped`,
//! `nav_msgs/msg/Odometry`, `geometry_msgs/msg/TransformStamped` and `tf2_msgs/msg/TFMessage`
//! (the transform whose `child_frame_id` is the role's `child_frame`). IMU:
//! `sensor_msgs/msg/Imu` (`angular_velocity`, `linear_acceleration`: specific force, REP 145),
//! mounted along the body axes at the centre of mass. Controls: any message; its fields are
//! named per control channel (a `std_msgs/msg/Float64MultiArray` defaults to `data.0..3` =
//! the vehicle's four channels in order) and hold from their stamp (zero-order hold): a
//! wingbeat flies the controls in force at its start. Times are the messages' header stamps
//! (the log time for a message without a header); t = 0, a wingbeat start, is the first pose
//! stamp unless the roles name another (`time_origin_ns`). Frames are converted in
//! [`crate::conventions`], nowhere else.

use std::path::Path;

use flapsim::Controls;
use flightlog::ros2::bag::read_bag;

use crate::conventions::Conventions;
use crate::data::{FlightData, StartSource, mocap_starts, recorded_vehicle, timing};
use crate::error::{Error, Result};
use crate::frames::{ImuFrame, MocapFrame};

mod checks;
mod roles;
#[cfg(test)]
mod tests;
mod topics;

pub use checks::MAX_MEAN_TILT_DEG;
pub use roles::{BagRoles, ControlsRole, ImuRole, PoseRole};

use checks::{check_attitudes, check_gravity};
use topics::{IMU, Topic, check_order, read_controls, read_poses};

impl FlightData {
    /// Reads a ROS 2 bag flown by the vehicle of `model_toml` (from `model_origin`), its
    /// topics taking the roles of `roles`.
    pub fn from_bag(
        path: impl AsRef<Path>,
        model_toml: &str,
        model_origin: &str,
        roles: &BagRoles,
    ) -> Result<Self> {
        let path = path.as_ref();
        let vehicle = recorded_vehicle(model_toml, model_origin, "a bag's flight")?;
        let bag = read_bag(path).map_err(|e| Error::Log {
            path: path.to_owned(),
            detail: e.to_string(),
        })?;
        if let (false, Some(damage)) = (bag.has_ros2(), &bag.damage) {
            return Err(Error::Log {
                path: path.to_owned(),
                detail: format!("nothing to read before the damage: {damage}"),
            });
        }
        if !bag.has_ros2() {
            return Err(Error::Log {
                path: path.to_owned(),
                detail: format!(
                    "not a ROS 2 bag: no channel has a ros2msg schema (topics: {})",
                    bag.topics()
                ),
            });
        }
        let Some(pose_role) = &roles.pose else {
            return Err(Error::Setting(format!(
                "`{}` is a ROS 2 bag: name the topic with the body's pose ([pose] topic in a roles file, or --pose-topic); its topics: {}",
                path.display(),
                bag.topics()
            )));
        };
        let frames = roles.frames;
        let pose = Topic::read(&bag, path, &pose_role.topic)?;
        let raw = read_poses(&pose, pose_role)?;
        check_order(&pose, &raw.iter().map(|r| (r.0, r.1)).collect::<Vec<_>>())?;
        let Some(first) = raw.first() else {
            return Err(pose.err("has no messages".into()));
        };
        let t0_ns = roles.time_origin_ns.map_or(first.1, i128::from);
        let t_s = |ns: i128| (ns - t0_ns) as f64 * 1e-9;
        let mut mocap = Vec::with_capacity(raw.len());
        for &(row, ns, p, q) in raw.iter().filter(|r| r.1 >= t0_ns) {
            let attitude = frames.attitude(q).map_err(|norm| {
                pose.err(format!(
                    "message {row}: the orientation [x, y, z, w] = {q:?} has norm {norm}; allowed a unit quaternion (norm 1 +- 1e-3) stored {}",
                    frames.quaternion.name()
                ))
            })?;
            mocap.push(MocapFrame {
                t_s: t_s(ns),
                position_m: frames.position(p),
                attitude,
            });
        }
        if mocap.is_empty() {
            return Err(pose.err(format!(
                "no pose is stamped at or after time_origin_ns = {t0_ns}"
            )));
        }
        check_attitudes(&pose, &mocap, &frames, &vehicle)?;

        let mut imu = Vec::new();
        if let Some(role) = &roles.imu {
            let topic = Topic::read(&bag, path, &role.topic)?;
            if topic.type_name != IMU {
                return Err(topic.err(format!("the IMU role needs {IMU}")));
            }
            let axes = Conventions {
                body: role.body.unwrap_or(frames.body),
                ..frames
            };
            let mut stamps = Vec::with_capacity(topic.rows());
            for row in 0..topic.rows() {
                let ns = topic.stamp_ns(row, "header.stamp")?;
                stamps.push((row, ns));
                if ns < t0_ns {
                    continue;
                }
                imu.push(ImuFrame {
                    t_s: t_s(ns),
                    gyro_rad_s: axes.body_vector(topic.vec3(row, "angular_velocity")?),
                    accel_m_s2: axes.body_vector(topic.vec3(row, "linear_acceleration")?),
                });
            }
            check_order(&topic, &stamps)?;
            check_gravity(&topic, &imu, &mocap)?;
        }

        let (freq_hz, per) = timing(&vehicle);
        let wingbeats = (mocap.last().map_or(0.0, |f| f.t_s) * freq_hz).floor() as usize + 1;
        let wingbeat_controls: Vec<Option<Controls>> = match &roles.controls {
            None => vec![Some(Controls::default()); wingbeats],
            Some(role) => {
                let topic = Topic::read(&bag, path, &role.topic)?;
                let stamped = read_controls(&topic, role, &vehicle)?;
                // A stamp within half a step of a wingbeat start counts as at it (stamps
                // are whole nanoseconds).
                let half_step_ns = (0.5e9 / (freq_hz * per as f64)).round() as i128;
                (0..wingbeats)
                    .map(|w| {
                        let start_ns = t0_ns + (w as f64 * 1e9 / freq_hz).round() as i128;
                        let i = stamped.partition_point(|(ns, _)| *ns <= start_ns + half_step_ns);
                        i.checked_sub(1).map(|i| stamped[i].1)
                    })
                    .collect()
            }
        };
        let starts = mocap_starts(&mocap, freq_hz, wingbeat_controls.len() as u64);
        Ok(Self {
            controls_each_wingbeat: true,
            damage: bag.damage.clone(),
            source: path.to_owned(),
            format: "ros2",
            model_toml: model_toml.to_owned(),
            model_origin: model_origin.to_owned(),
            mocap,
            imu,
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
}
