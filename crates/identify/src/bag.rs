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

use std::collections::BTreeMap;
use std::path::Path;

use flapsim::{Controls, Vehicle};
use flightlog::ros2::bag::{Bag, read_bag};
use flightlog::ros2::summary::{TopicTable, read_topic_table};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::conventions::{BodyConvention, Conventions};
use crate::csv::EXTRA_CONTROL_COLUMNS;
use crate::data::{FlightData, StartSource, check_supported, mocap_starts, timing};
use crate::error::{Error, Result};
use crate::frames::{ImuFrame, MocapFrame};

/// The pose role: the topic with the body's pose in the world.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PoseRole {
    /// The topic.
    pub topic: String,
    /// For a `tf2_msgs/msg/TFMessage` topic: the body's frame (`child_frame_id`).
    #[serde(default)]
    pub child_frame: Option<String>,
}

/// The IMU role.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ImuRole {
    /// The topic (`sensor_msgs/msg/Imu`).
    pub topic: String,
    /// The IMU's axes when they are not the pose's body convention.
    #[serde(default)]
    pub body: Option<BodyConvention>,
}

/// The controls role: the vehicle's inputs.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ControlsRole {
    /// The topic.
    pub topic: String,
    /// Control channel (the vehicle's four, e.g. `amplitude_rad`, and `pitch_bias_rad`,
    /// `aoa_rad`, `diff_mean_stroke_rad`) -> the message's field by dotted path, as
    /// `flapwing replay BAG --csv TOPIC` names its columns (`data.1`, `drive.amplitude`).
    #[serde(default)]
    pub fields: BTreeMap<String, String>,
}

/// Which topic of a bag plays which role, and the frame conventions.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BagRoles {
    /// The body's pose (required).
    pub pose: Option<PoseRole>,
    /// The IMU.
    pub imu: Option<ImuRole>,
    /// The controls; without them the vehicle flies its model's kinematics throughout.
    pub controls: Option<ControlsRole>,
    /// Frame conventions (default ENU, FLU, xyzw: ROS's).
    #[serde(default)]
    pub frames: Conventions,
    /// The bag time (ns) that is t = 0, a wingbeat start; default the first pose stamp.
    #[serde(default)]
    pub time_origin_ns: Option<u64>,
}

impl BagRoles {
    /// Reads a roles file's text (`origin` names it in errors).
    pub fn from_toml(text: &str, origin: &str) -> Result<Self> {
        toml::from_str(text).map_err(|e| {
            Error::Setting(format!(
                "roles file `{origin}`: {}; allowed tables: [pose] topic, child_frame; [imu] topic, body; [controls] topic, fields; [frames] world = \"enu\"|\"ned\", body = \"flu\"|\"frd\", quaternion = \"xyzw\"|\"wxyz\"; time_origin_ns",
                e.message().trim()
            ))
        })
    }

    /// One line for reports: the roles and the conventions.
    pub fn describe(&self) -> String {
        let mut parts = Vec::new();
        if let Some(p) = &self.pose {
            parts.push(format!("pose {}", p.topic));
        }
        if let Some(i) = &self.imu {
            parts.push(format!("IMU {}", i.topic));
        }
        match &self.controls {
            Some(c) => parts.push(format!("controls {}", c.topic)),
            None => parts.push("controls: the model's kinematics".into()),
        }
        format!("{}; {}", parts.join(", "), self.frames.describe())
    }
}

/// Pose message types and the field paths of their position, orientation and stamp.
const POSE_TYPES: [(&str, &str, &str, &str); 5] = [
    (
        "geometry_msgs/msg/PoseStamped",
        "pose.position",
        "pose.orientation",
        "header.stamp",
    ),
    (
        "geometry_msgs/msg/PoseWithCovarianceStamped",
        "pose.pose.position",
        "pose.pose.orientation",
        "header.stamp",
    ),
    (
        "nav_msgs/msg/Odometry",
        "pose.pose.position",
        "pose.pose.orientation",
        "header.stamp",
    ),
    (
        "geometry_msgs/msg/TransformStamped",
        "transform.translation",
        "transform.rotation",
        "header.stamp",
    ),
    (
        "tf2_msgs/msg/TFMessage",
        "transform.translation",
        "transform.rotation",
        "header.stamp",
    ),
];
const TF: &str = "tf2_msgs/msg/TFMessage";
const IMU: &str = "sensor_msgs/msg/Imu";

/// `pkg/Type` (ROS 1 style) and `pkg/msg/Type` name the same type.
fn normalized(type_name: &str) -> String {
    let parts: Vec<&str> = type_name.split('/').collect();
    match parts.as_slice() {
        [pkg, ty] => format!("{pkg}/msg/{ty}"),
        _ => type_name.to_owned(),
    }
}

/// One topic decoded, with its cells addressable by column name.
struct Topic<'a> {
    path: &'a Path,
    name: &'a str,
    type_name: String,
    table: TopicTable,
    index: BTreeMap<String, usize>,
}

impl<'a> Topic<'a> {
    fn read(bag: &'a Bag, path: &'a Path, name: &'a str) -> Result<Self> {
        let table = read_topic_table(bag, name).map_err(|e| Error::Log {
            path: path.to_owned(),
            detail: e.to_string(),
        })?;
        let type_name = bag
            .channel_id(name)
            .map(|id| normalized(&bag.channels[&id].schema_name))
            .unwrap_or_default();
        let index = table
            .columns
            .iter()
            .enumerate()
            .map(|(i, c)| (c.clone(), i))
            .collect();
        Ok(Self {
            path,
            name,
            type_name,
            table,
            index,
        })
    }

    fn err(&self, detail: String) -> Error {
        Error::Log {
            path: self.path.to_owned(),
            detail: format!("topic `{}` ({}): {detail}", self.name, self.type_name),
        }
    }

    fn has(&self, column: &str) -> bool {
        self.index.contains_key(column)
    }

    /// The number in `column` of message `row`.
    fn num(&self, row: usize, column: &str) -> Result<f64> {
        let Some(&i) = self.index.get(column) else {
            return Err(self.err(format!(
                "message {row} has no field `{column}`; its fields: {}",
                self.table.columns[1..].join(", ")
            )));
        };
        let cell = self.table.rows[row].get(i).and_then(|c| c.as_deref());
        let Some(text) = cell else {
            return Err(self.err(format!("message {row} lacks the field `{column}`")));
        };
        text.parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| {
                self.err(format!(
                    "message {row}, field `{column}` = `{text}`: allowed a finite number"
                ))
            })
    }

    fn text(&self, row: usize, column: &str) -> Option<&str> {
        let &i = self.index.get(column)?;
        self.table.rows[row].get(i)?.as_deref()
    }

    fn vec3(&self, row: usize, prefix: &str) -> Result<Vector3<f64>> {
        Ok(Vector3::new(
            self.num(row, &format!("{prefix}.x"))?,
            self.num(row, &format!("{prefix}.y"))?,
            self.num(row, &format!("{prefix}.z"))?,
        ))
    }

    /// The stamp of message `row`, ns: `{prefix}.sec` and `.nanosec`, else the log time.
    fn stamp_ns(&self, row: usize, prefix: &str) -> Result<i128> {
        let sec = format!("{prefix}.sec");
        if self.has(&sec) {
            let s = self.num(row, &sec)?;
            let ns = self.num(row, &format!("{prefix}.nanosec"))?;
            return Ok(s as i128 * 1_000_000_000 + ns as i128);
        }
        Ok(self.num(row, "log_time_ns")? as i128)
    }

    fn rows(&self) -> usize {
        self.table.rows.len()
    }
}

/// Stamps must increase strictly along a topic: a recorder writes messages in arrival
/// order, and equal or falling header stamps mean a clock reset or a merged recording.
fn check_order(topic: &Topic<'_>, stamps: &[(usize, i128)]) -> Result<()> {
    for w in stamps.windows(2) {
        let ((ia, a), (ib, b)) = (w[0], w[1]);
        if b <= a {
            return Err(topic.err(format!(
                "message {ib} is stamped {b} ns, not after message {ia} ({a} ns): the stamps must increase strictly (a clock reset or a merged recording: split the bag, or sort and de-duplicate it)"
            )));
        }
    }
    Ok(())
}

/// (row, stamp ns, position, [x, y, z, w]) of every pose of the pose topic.
type RawPose = (usize, i128, Vector3<f64>, [f64; 4]);

fn read_poses(topic: &Topic<'_>, role: &PoseRole) -> Result<Vec<RawPose>> {
    let allowed = || {
        POSE_TYPES
            .iter()
            .map(|t| t.0)
            .collect::<Vec<_>>()
            .join(", ")
    };
    let Some(&(_, pos, ori, stamp)) = POSE_TYPES.iter().find(|t| t.0 == topic.type_name) else {
        return Err(topic.err(format!(
            "not a pose message; allowed types for the pose role: {}",
            allowed()
        )));
    };
    let quat = |row: usize, prefix: &str| -> Result<[f64; 4]> {
        Ok([
            topic.num(row, &format!("{prefix}.x"))?,
            topic.num(row, &format!("{prefix}.y"))?,
            topic.num(row, &format!("{prefix}.z"))?,
            topic.num(row, &format!("{prefix}.w"))?,
        ])
    };
    let mut out = Vec::with_capacity(topic.rows());
    if topic.type_name != TF {
        for row in 0..topic.rows() {
            out.push((
                row,
                topic.stamp_ns(row, stamp)?,
                topic.vec3(row, pos)?,
                quat(row, ori)?,
            ));
        }
        return Ok(out);
    }
    // A TF topic carries many frames: the body's is the transform with its child frame.
    let mut children = std::collections::BTreeSet::new();
    for row in 0..topic.rows() {
        for k in 0.. {
            let Some(child) = topic.text(row, &format!("transforms.{k}.child_frame_id")) else {
                break;
            };
            children.insert(child.to_owned());
            if role.child_frame.as_deref() == Some(child) {
                let p = format!("transforms.{k}.");
                out.push((
                    row,
                    topic.stamp_ns(row, &format!("{p}{stamp}"))?,
                    topic.vec3(row, &format!("{p}{pos}"))?,
                    quat(row, &format!("{p}{ori}"))?,
                ));
            }
        }
    }
    let seen = children.into_iter().collect::<Vec<_>>().join(", ");
    match &role.child_frame {
        None => Err(topic.err(format!(
            "a TF topic needs the body's frame: set [pose] child_frame (or --child-frame) to one of its child frames: {seen}"
        ))),
        Some(c) if out.is_empty() => Err(topic.err(format!(
            "no transform has the child frame `{c}`; its child frames: {seen}"
        ))),
        Some(_) => Ok(out),
    }
}

/// The controls in each stamped message of the controls topic.
fn read_controls(
    topic: &Topic<'_>,
    role: &ControlsRole,
    vehicle: &Vehicle,
) -> Result<Vec<(i128, Controls)>> {
    let channels = vehicle.control_channels();
    let mut allowed: Vec<&str> = channels.to_vec();
    allowed.extend(EXTRA_CONTROL_COLUMNS);
    let mut fields = role.fields.clone();
    if fields.is_empty() {
        if !topic.type_name.ends_with("MultiArray") {
            return Err(topic.err(format!(
                "name the fields of the controls: [controls] fields = {{ {} = \"FIELD\", ... }} (fields by dotted path as `flapwing replay BAG --csv {}` names them); only a std_msgs/msg/Float64MultiArray defaults to data.0..3",
                channels[0], topic.name
            )));
        }
        for (k, c) in channels.iter().enumerate() {
            fields.insert((*c).to_owned(), format!("data.{k}"));
        }
    }
    for (name, field) in &fields {
        if !allowed.contains(&name.as_str()) {
            return Err(topic.err(format!(
                "[controls] fields names `{name}`, which is not a control of `{}`; allowed: {}",
                vehicle.name,
                allowed.join(", ")
            )));
        }
        if !topic.has(field) {
            return Err(topic.err(format!(
                "[controls] fields.{name} = `{field}` is not a field of the message; its fields: {}",
                topic.table.columns[1..].join(", ")
            )));
        }
    }
    let missing: Vec<&str> = channels
        .iter()
        .copied()
        .filter(|c| !fields.contains_key(*c))
        .collect();
    if !missing.is_empty() {
        return Err(topic.err(format!(
            "[controls] fields lacks the control channel(s) {} of `{}` (all four are needed: {})",
            missing.join(", "),
            vehicle.name,
            channels.join(", ")
        )));
    }
    let mut out = Vec::with_capacity(topic.rows());
    let mut stamps = Vec::with_capacity(topic.rows());
    for row in 0..topic.rows() {
        let t = topic.stamp_ns(row, "header.stamp")?;
        let mut u = [0.0; 4];
        for (o, c) in u.iter_mut().zip(channels) {
            *o = topic.num(row, &fields[c])?;
        }
        let mut c = vehicle.controls_with(&Controls::default(), &u);
        let extra =
            |name: &str| -> Result<f64> { fields.get(name).map_or(Ok(0.0), |f| topic.num(row, f)) };
        c.pitch_bias_rad += extra("pitch_bias_rad")?;
        c.aoa_rad += extra("aoa_rad")?;
        c.diff_mean_stroke_rad += extra("diff_mean_stroke_rad")?;
        stamps.push((row, t));
        out.push((t, c));
    }
    check_order(topic, &stamps)?;
    Ok(out)
}

/// The largest mean tilt from the hover attitude a recorded flight is taken to have, deg.
/// Insects and flapping robots fly within a few tens of degrees of their hover attitude
/// (a fruit fly's body pitch changes by about 20 deg between hover and 1 m/s); a mean beyond
/// this says the frames are misread. A mismatch of both the world's and the body's vertical
/// (NED/FRD read as ENU/FLU) leaves the body's z axis up, so the check is against the
/// model's own hover attitude, not only the body's z axis.
pub const MAX_MEAN_TILT_DEG: f64 = 60.0;

/// The recorded attitudes, on average, lie within [`MAX_MEAN_TILT_DEG`] of the vehicle's
/// hover attitude (its trim; the body's z axis up when the vehicle has no hover trim).
fn check_attitudes(
    topic: &Topic<'_>,
    mocap: &[MocapFrame],
    frames: &Conventions,
    vehicle: &Vehicle,
) -> Result<()> {
    let (up_in_body, hover) = match flapsim::trim::trim(vehicle) {
        Ok(t) => (
            t.attitude().inverse() * Vector3::z(),
            format!(
                "`{}`'s hover attitude (body pitch {:.1} deg)",
                vehicle.name,
                t.pitch_rad.to_degrees()
            ),
        ),
        Err(_) => (Vector3::z(), "upright (body z axis up)".to_owned()),
    };
    if mocap.is_empty() {
        return Ok(());
    }
    let mean_cos = mocap
        .iter()
        .map(|f| (f.attitude * up_in_body).z)
        .sum::<f64>()
        / mocap.len() as f64;
    let tilt_deg = mean_cos.clamp(-1.0, 1.0).acos().to_degrees();
    if tilt_deg <= MAX_MEAN_TILT_DEG {
        return Ok(());
    }
    Err(topic.err(format!(
        "with {} the body is on average {tilt_deg:.0} deg from {hover} over {} frames (a flight stays within about {MAX_MEAN_TILT_DEG:.0} deg of it): the frame conventions given do not match the bag's; check [frames] world (--world-frame enu|ned), body (--body-frame flu|frd) and quaternion (--quaternion-order xyzw|wxyz)",
        frames.describe(),
        mocap.len()
    )))
}

/// Hovering or flying slowly, the mean specific force an IMU reads points up (about g):
/// when it points down in flapwing's world the world convention (or the IMU's axes) given
/// is not the bag's.
fn check_gravity(topic: &Topic<'_>, imu: &[ImuFrame], mocap: &[MocapFrame]) -> Result<()> {
    let mut sum = Vector3::zeros();
    let mut n = 0usize;
    for s in imu {
        let i = mocap
            .partition_point(|f| f.t_s < s.t_s)
            .min(mocap.len() - 1);
        sum += mocap[i].attitude * s.accel_m_s2;
        n += 1;
    }
    if n == 0 || sum.z / n as f64 > 0.0 {
        return Ok(());
    }
    Err(topic.err(format!(
        "the mean specific force, turned into the world by the poses' attitudes, is {:.3} m/s^2 up: it points down, so the IMU's axes or the world convention given do not match the bag's (a flight's mean specific force is about +g, up); check [frames] world (--world-frame enu|ned) and [imu] body",
        sum.z / n as f64
    )))
}

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
        let vehicle = Vehicle::from_toml(model_toml, model_origin)
            .map_err(|e| Error::Model(format!("`{model_origin}` does not load: {e}")))?;
        check_supported(&vehicle, path)?;
        if vehicle.wind.is_some() {
            return Err(Error::Model(format!(
                "`{model_origin}` has a [wind] field; a recorded flight is replayed in still air: remove it"
            )));
        }
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
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::conventions::{QuaternionOrder, WorldConvention};

    #[test]
    fn a_roles_file_reads_every_table() {
        let r = BagRoles::from_toml(
            r#"
time_origin_ns = 12
[pose]
topic = "/tf"
child_frame = "fly"
[imu]
topic = "/imu"
body = "frd"
[controls]
topic = "/drive"
fields = { amplitude_rad = "data.1" }
[frames]
world = "ned"
quaternion = "wxyz"
"#,
            "roles.toml",
        )
        .unwrap();
        assert_eq!(r.time_origin_ns, Some(12));
        assert_eq!(r.pose.as_ref().unwrap().child_frame.as_deref(), Some("fly"));
        assert_eq!(r.imu.as_ref().unwrap().body, Some(BodyConvention::Frd));
        assert_eq!(
            r.controls.as_ref().unwrap().fields["amplitude_rad"],
            "data.1"
        );
        assert_eq!(r.frames.world, WorldConvention::Ned);
        assert_eq!(r.frames.body, BodyConvention::Flu, "the default body frame");
        assert_eq!(r.frames.quaternion, QuaternionOrder::Wxyz);
        assert_eq!(
            r.describe(),
            "pose /tf, IMU /imu, controls /drive; world NED, body FLU, quaternion wxyz"
        );
    }

    #[test]
    fn a_bad_roles_file_names_the_file_the_field_and_what_is_allowed() {
        for (text, names) in [
            ("[pose]\ntopik = \"/p\"\n", "topik"),
            ("[frames]\nworld = \"nwu\"\n", "nwu"),
            ("[cameras]\n", "cameras"),
        ] {
            let e = BagRoles::from_toml(text, "r.toml").unwrap_err().to_string();
            assert!(
                e.contains("roles file `r.toml`") && e.contains(names),
                "{e}"
            );
            assert!(e.contains("world = \"enu\"|\"ned\""), "{e}");
        }
    }

    #[test]
    fn type_names_of_both_spellings_match() {
        assert_eq!(
            normalized("geometry_msgs/PoseStamped"),
            "geometry_msgs/msg/PoseStamped"
        );
        assert_eq!(
            normalized("geometry_msgs/msg/PoseStamped"),
            "geometry_msgs/msg/PoseStamped"
        );
    }
}
