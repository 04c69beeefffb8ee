//! A bag's topics decoded by role: the pose messages, the controls, and the order of
//! their stamps.

use std::collections::BTreeMap;
use std::path::Path;

use flapsim::{Controls, Vehicle};
use flightlog::ros2::bag::Bag;
use flightlog::ros2::summary::{TopicTable, read_topic_table};
use nalgebra::Vector3;

use crate::csv::EXTRA_CONTROL_COLUMNS;
use crate::error::{Error, Result};

use super::roles::{ControlsRole, PoseRole};

/// Pose message types and the field paths of their position, orientation and stamp.
pub(super) const POSE_TYPES: [(&str, &str, &str, &str); 5] = [
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
pub(super) const TF: &str = "tf2_msgs/msg/TFMessage";
pub(super) const IMU: &str = "sensor_msgs/msg/Imu";

/// `pkg/Type` (ROS 1 style) and `pkg/msg/Type` name the same type.
pub(super) fn normalized(type_name: &str) -> String {
    let parts: Vec<&str> = type_name.split('/').collect();
    match parts.as_slice() {
        [pkg, ty] => format!("{pkg}/msg/{ty}"),
        _ => type_name.to_owned(),
    }
}

/// One topic decoded, with its cells addressable by column name.
pub(super) struct Topic<'a> {
    path: &'a Path,
    name: &'a str,
    pub(super) type_name: String,
    table: TopicTable,
    index: BTreeMap<String, usize>,
}

impl<'a> Topic<'a> {
    pub(super) fn read(bag: &'a Bag, path: &'a Path, name: &'a str) -> Result<Self> {
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

    pub(super) fn err(&self, detail: String) -> Error {
        Error::Log {
            path: self.path.to_owned(),
            detail: format!("topic `{}` ({}): {detail}", self.name, self.type_name),
        }
    }

    pub(super) fn has(&self, column: &str) -> bool {
        self.index.contains_key(column)
    }

    /// The number in `column` of message `row`.
    pub(super) fn num(&self, row: usize, column: &str) -> Result<f64> {
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

    pub(super) fn text(&self, row: usize, column: &str) -> Option<&str> {
        let &i = self.index.get(column)?;
        self.table.rows[row].get(i)?.as_deref()
    }

    pub(super) fn vec3(&self, row: usize, prefix: &str) -> Result<Vector3<f64>> {
        Ok(Vector3::new(
            self.num(row, &format!("{prefix}.x"))?,
            self.num(row, &format!("{prefix}.y"))?,
            self.num(row, &format!("{prefix}.z"))?,
        ))
    }

    /// The stamp of message `row`, ns: `{prefix}.sec` and `.nanosec`, else the log time.
    pub(super) fn stamp_ns(&self, row: usize, prefix: &str) -> Result<i128> {
        let sec = format!("{prefix}.sec");
        if self.has(&sec) {
            let s = self.num(row, &sec)?;
            let ns = self.num(row, &format!("{prefix}.nanosec"))?;
            return Ok(s as i128 * 1_000_000_000 + ns as i128);
        }
        Ok(self.num(row, "log_time_ns")? as i128)
    }

    pub(super) fn rows(&self) -> usize {
        self.table.rows.len()
    }
}

/// Stamps must increase strictly along a topic: a recorder writes messages in arrival
/// order, and equal or falling header stamps mean a clock reset or a merged recording.
pub(super) fn check_order(topic: &Topic<'_>, stamps: &[(usize, i128)]) -> Result<()> {
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
pub(super) type RawPose = (usize, i128, Vector3<f64>, [f64; 4]);

pub(super) fn read_poses(topic: &Topic<'_>, role: &PoseRole) -> Result<Vec<RawPose>> {
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
pub(super) fn read_controls(
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
