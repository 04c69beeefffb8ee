//! The recorded flight a command reads (`identify`, `replay --resimulate`): a flapwing
//! log, a motion-capture CSV, or a ROS 2 bag whose topics are given roles by flags or a
//! roles file.

use std::path::{Path, PathBuf};

use anyhow::Result;
use flapwing_identify::bag::{ControlsRole, ImuRole, PoseRole};
use flapwing_identify::{BagRoles, BodyConvention, FlightData, QuaternionOrder, WorldConvention};

use crate::error::input_error;

/// The roles of a ROS 2 bag's topics and its frame conventions (flags over a roles file).
#[derive(Debug, Default, clap::Args)]
pub struct BagRoleArgs {
    /// A ROS 2 bag's roles and frame conventions, a TOML file ([pose], [imu], [controls],
    /// [frames]; format in crates/identify/README.md). The flags below override it.
    #[arg(long = "roles", value_name = "ROLES.toml", help_heading = "ROS 2 bags")]
    pub roles_file: Option<PathBuf>,
    /// The bag's topic with the body's pose (PoseStamped, PoseWithCovarianceStamped,
    /// Odometry, TransformStamped or TFMessage).
    #[arg(long = "pose-topic", value_name = "TOPIC", help_heading = "ROS 2 bags")]
    pub pose_topic: Option<String>,
    /// For a TFMessage pose topic: the body's frame (child_frame_id).
    #[arg(
        long = "child-frame",
        value_name = "FRAME",
        help_heading = "ROS 2 bags"
    )]
    pub child_frame: Option<String>,
    /// The bag's IMU topic (sensor_msgs/msg/Imu): its mean specific force checks the
    /// world frame; `identify --imu` fits to its samples, a resimulation compares its rates.
    #[arg(long = "imu-topic", value_name = "TOPIC", help_heading = "ROS 2 bags")]
    pub imu_topic: Option<String>,
    /// The bag's controls topic (a Float64MultiArray holds the vehicle's four control
    /// channels in data.0..3; other types name their fields in the roles file).
    #[arg(
        long = "controls-topic",
        value_name = "TOPIC",
        help_heading = "ROS 2 bags"
    )]
    pub controls_topic: Option<String>,
    /// The bag's world frame: enu (x east, y north, z up; ROS) or ned.
    #[arg(
        long = "world-frame",
        value_name = "enu|ned",
        help_heading = "ROS 2 bags"
    )]
    pub world_frame: Option<String>,
    /// The bag's body frame: flu (x forward, y left, z up; ROS) or frd.
    #[arg(
        long = "body-frame",
        value_name = "flu|frd",
        help_heading = "ROS 2 bags"
    )]
    pub body_frame: Option<String>,
    /// How the bag's quaternions fill their x, y, z, w fields: xyzw (ROS) or wxyz (a
    /// scalar-first quaternion written in order).
    #[arg(
        long = "quaternion-order",
        value_name = "xyzw|wxyz",
        help_heading = "ROS 2 bags"
    )]
    pub quaternion_order: Option<String>,
}

impl BagRoleArgs {
    /// True when any ROS 2 role or convention is given.
    pub fn names_bag_roles(&self) -> bool {
        self.roles_file.is_some()
            || self.pose_topic.is_some()
            || self.child_frame.is_some()
            || self.imu_topic.is_some()
            || self.controls_topic.is_some()
            || self.world_frame.is_some()
            || self.body_frame.is_some()
            || self.quaternion_order.is_some()
    }

    /// The roles file, overridden by the flags.
    pub fn bag_roles(&self) -> Result<BagRoles> {
        let mut roles = match &self.roles_file {
            Some(p) => {
                let text = flapsim::model::read_model_file(p).map_err(|e| {
                    input_error(format!("--roles: cannot read `{}`: {e}", p.display()))
                })?;
                BagRoles::from_toml(&text, &p.display().to_string()).map_err(classify)?
            }
            None => BagRoles::default(),
        };
        if let Some(t) = &self.pose_topic {
            let child_frame = roles.pose.take().and_then(|p| p.child_frame);
            roles.pose = Some(PoseRole {
                topic: t.clone(),
                child_frame,
            });
        }
        if let Some(c) = &self.child_frame {
            let Some(p) = roles.pose.as_mut() else {
                return Err(input_error(
                    "--child-frame names the body's frame of a TF pose topic: give --pose-topic too",
                ));
            };
            p.child_frame = Some(c.clone());
        }
        if let Some(t) = &self.imu_topic {
            let body = roles.imu.take().and_then(|i| i.body);
            roles.imu = Some(ImuRole {
                topic: t.clone(),
                body,
            });
        }
        if let Some(t) = &self.controls_topic {
            let fields = roles.controls.take().map(|c| c.fields).unwrap_or_default();
            roles.controls = Some(ControlsRole {
                topic: t.clone(),
                fields,
            });
        }
        fn pick<T: Copy>(flag: &str, value: &str, options: &[(&str, T)]) -> Result<T> {
            let lower = value.to_ascii_lowercase();
            options
                .iter()
                .find(|(n, _)| *n == lower)
                .map(|(_, v)| *v)
                .ok_or_else(|| {
                    let names: Vec<&str> = options.iter().map(|(n, _)| *n).collect();
                    input_error(format!(
                        "{flag} `{value}` is not a convention; allowed: {}",
                        names.join(", ")
                    ))
                })
        }
        if let Some(v) = &self.world_frame {
            roles.frames.world = pick(
                "--world-frame",
                v,
                &[("enu", WorldConvention::Enu), ("ned", WorldConvention::Ned)],
            )?;
        }
        if let Some(v) = &self.body_frame {
            roles.frames.body = pick(
                "--body-frame",
                v,
                &[("flu", BodyConvention::Flu), ("frd", BodyConvention::Frd)],
            )?;
        }
        if let Some(v) = &self.quaternion_order {
            roles.frames.quaternion = pick(
                "--quaternion-order",
                v,
                &[
                    ("xyzw", QuaternionOrder::Xyzw),
                    ("wxyz", QuaternionOrder::Wxyz),
                ],
            )?;
        }
        Ok(roles)
    }
}

/// Reads the flight in `file`: a CSV (needs `model`), a ROS 2 bag when `roles` names any
/// role (needs `model`), else a flapwing log (a bag given without roles is refused with its
/// topics). Also says whether it was a flapwing log; stderr says what a bag gave. A log
/// without motion capture is read only `for_resimulation` (its states are the reference).
pub fn read_flight(
    file: &Path,
    model: Option<&str>,
    roles: &BagRoleArgs,
    for_resimulation: bool,
) -> Result<(FlightData, bool)> {
    let is_csv = file
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"));
    let bag = !is_csv && roles.names_bag_roles();
    if !(is_csv || bag) {
        let read = if for_resimulation {
            FlightData::from_mcap_states(file)
        } else {
            FlightData::from_mcap(file)
        };
        let data = read.map_err(|e| {
            // A ROS 2 bag given without its roles: say what is missing.
            match flightlog::ros2::bag::read_bag(file) {
                Ok(b) if b.has_ros2() => input_error(format!(
                    "`{}` is a ROS 2 bag, not a flapwing log: name the topic with the body's pose (--pose-topic TOPIC or --roles FILE) and the vehicle (--model); its topics: {}",
                    file.display(),
                    b.topics()
                )),
                _ => classify(e),
            }
        })?;
        return Ok((data, true));
    }
    let Some(model) = model else {
        let what = if bag { "a ROS 2 bag" } else { "a CSV flight" };
        return Err(input_error(format!(
            "`{}` is {what}: give the vehicle it flew with --model FILE|NAME",
            file.display()
        )));
    };
    let src = crate::vehicle::read_vehicle(Some(model))?;
    if !bag {
        let data = FlightData::from_csv(file, &src.text, &src.origin).map_err(classify)?;
        return Ok((data, false));
    }
    let roles = roles.bag_roles()?;
    let data = FlightData::from_bag(file, &src.text, &src.origin, &roles).map_err(classify)?;
    crate::output::note(&format!(
        "ROS 2 bag `{}`: {}; {} poses over {:.3} s, {} IMU samples, {} wingbeats",
        file.display(),
        roles.describe(),
        data.mocap.len(),
        data.duration_s(),
        data.imu.len(),
        data.wingbeat_controls.len()
    ));
    Ok((data, false))
}

/// flapwing-identify's bad-input errors become the CLI's bad input (exit 2).
pub fn classify(e: flapwing_identify::Error) -> anyhow::Error {
    if e.is_bad_input() {
        input_error(e.to_string())
    } else {
        anyhow::Error::new(e)
    }
}
