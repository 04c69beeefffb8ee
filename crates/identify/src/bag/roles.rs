//! Which topic of a ROS 2 bag plays which role, and its frame conventions: the roles file
//! (`--roles`, format in the crate's README.md) and what the flags fill in.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::conventions::{BodyConvention, Conventions};
use crate::error::{Error, Result};

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
