//! Topics, frames and the JSON Schemas of every channel.
//!
//! Foxglove types (`foxglove.PoseInFrame`, `foxglove.FrameTransform`, `foxglove.Log`) carry
//! Foxglove's own field lists. flapwing's schemas follow Foxglove's rules for custom JSON
//! schemas: every object is `"type": "object"` with `properties`, each `type` is a single
//! string (no unions, no null, no `$ref`), no arrays at all, enums as integers. Every
//! flapwing message has a boolean `nonfinite`: true when a NaN or infinity was replaced by 0
//! in it (JSON has no NaN). Foxglove-typed messages keep Foxglove's exact fields: a
//! non-finite value there is written as 0 and the flapwing message of the same sample and
//! time carries the flag.

use serde_json::{Map, Value, json};

/// Body pose, `foxglove.PoseInFrame` in frame [`FRAME_WORLD`].
pub const TOPIC_POSE: &str = "/vehicle/pose";
/// world -> base_link, `foxglove.FrameTransform`.
pub const TOPIC_TF_BODY: &str = "/tf/base_link";
/// base_link -> wing_left, `foxglove.FrameTransform`.
pub const TOPIC_TF_WING_LEFT: &str = "/tf/wing_left";
/// base_link -> wing_right, `foxglove.FrameTransform`.
pub const TOPIC_TF_WING_RIGHT: &str = "/tf/wing_right";
/// `flapwing.VehicleState`.
pub const TOPIC_STATE: &str = "/vehicle/state";
/// `flapwing.Controls`.
pub const TOPIC_CONTROLS: &str = "/vehicle/controls";
/// `flapwing.WingKinematics` of the left wing.
pub const TOPIC_KIN_LEFT: &str = "/wing/left/kinematics";
/// `flapwing.WingKinematics` of the right wing.
pub const TOPIC_KIN_RIGHT: &str = "/wing/right/kinematics";
/// `flapwing.WingForces` of the left wing.
pub const TOPIC_FORCES_LEFT: &str = "/wing/left/forces";
/// `flapwing.WingForces` of the right wing.
pub const TOPIC_FORCES_RIGHT: &str = "/wing/right/forces";
/// Run events, `foxglove.Log`.
pub const TOPIC_EVENTS: &str = "/events";

/// The world frame (z up).
pub const FRAME_WORLD: &str = "world";
/// The body frame (x forward, y left, z up, origin at the centre of mass).
pub const FRAME_BODY: &str = "base_link";
/// The left wing's frame (see [`wing_frame_doc`]).
pub const FRAME_WING_LEFT: &str = "wing_left";
/// The right wing's frame.
pub const FRAME_WING_RIGHT: &str = "wing_right";

/// Schema encoding of every channel.
pub const SCHEMA_ENCODING: &str = "jsonschema";
/// Message encoding of every channel.
pub const MESSAGE_ENCODING: &str = "json";

/// Name of the metadata record written when the run starts.
pub const METADATA_RUN: &str = "flapwing";
/// Name of the metadata record written by [`crate::Recorder::finish`].
pub const METADATA_END: &str = "flapwing.end";

/// The wing frames in words (also in the README).
pub fn wing_frame_doc() -> &'static str {
    "wing frame: origin at the hinge; x = e_le (chord direction towards the leading edge), \
     y = e_span (root to tip), z = x cross y (the wing normal n of wingforce's WingFrame on the \
     left wing, -n on the right); rotation base_link_from_wing = body_from_stroke * [e_le e_span z]"
}

/// Every channel: (topic, schema name).
pub const CHANNELS: [(&str, &str); 11] = [
    (TOPIC_POSE, "foxglove.PoseInFrame"),
    (TOPIC_TF_BODY, "foxglove.FrameTransform"),
    (TOPIC_TF_WING_LEFT, "foxglove.FrameTransform"),
    (TOPIC_TF_WING_RIGHT, "foxglove.FrameTransform"),
    (TOPIC_STATE, "flapwing.VehicleState"),
    (TOPIC_CONTROLS, "flapwing.Controls"),
    (TOPIC_KIN_LEFT, "flapwing.WingKinematics"),
    (TOPIC_KIN_RIGHT, "flapwing.WingKinematics"),
    (TOPIC_FORCES_LEFT, "flapwing.WingForces"),
    (TOPIC_FORCES_RIGHT, "flapwing.WingForces"),
    (TOPIC_EVENTS, "foxglove.Log"),
];

/// The names of the four terms and the total, in the order of the forces message's objects.
pub const FORCE_PARTS: [&str; 5] = [
    "translational",
    "rotational",
    "added_mass",
    "wake_capture",
    "total",
];

fn num(desc: &str) -> Value {
    json!({"type": "number", "description": desc})
}
fn int(desc: &str) -> Value {
    json!({"type": "integer", "description": desc})
}
fn boolean(desc: &str) -> Value {
    json!({"type": "boolean", "description": desc})
}
fn string(desc: &str) -> Value {
    json!({"type": "string", "description": desc})
}
fn obj(title: Option<&str>, desc: &str, props: Vec<(&str, Value)>) -> Value {
    let mut p = Map::new();
    for (k, v) in props {
        p.insert(k.to_owned(), v);
    }
    let mut o = Map::new();
    if let Some(t) = title {
        o.insert("title".into(), Value::String(t.into()));
    }
    o.insert("description".into(), Value::String(desc.into()));
    o.insert("type".into(), Value::String("object".into()));
    o.insert("properties".into(), Value::Object(p));
    Value::Object(o)
}
fn time(desc: &str) -> Value {
    obj(
        Some("time"),
        desc,
        vec![
            ("sec", json!({"type": "integer", "minimum": 0})),
            (
                "nsec",
                json!({"type": "integer", "minimum": 0, "maximum": 999_999_999}),
            ),
        ],
    )
}
fn vec3(title: Option<&str>, desc: &str) -> Value {
    obj(
        title,
        desc,
        vec![("x", num("x")), ("y", num("y")), ("z", num("z"))],
    )
}
fn quat(title: Option<&str>, desc: &str) -> Value {
    obj(
        title,
        desc,
        vec![
            ("x", num("x")),
            ("y", num("y")),
            ("z", num("z")),
            ("w", num("w")),
        ],
    )
}
fn angles3(desc: &str) -> Value {
    obj(
        None,
        desc,
        vec![
            ("phi", num("stroke angle")),
            ("theta", num("pitch angle")),
            ("eta", num("deviation angle")),
        ],
    )
}
fn common(props: &mut Vec<(&'static str, Value)>) {
    props.push(("timestamp", time("simulation time")));
    props.push(("step", int("physics step index k")));
    props.push(("t_s", num("simulation time t_k, s")));
    props.push(("phase", num("wingbeat phase at t_k, cycles")));
}

/// The JSON Schema text of a schema name used by flapwing (`None` for other names).
pub fn schema_text(name: &str) -> Option<String> {
    let v = match name {
        "foxglove.PoseInFrame" => {
            let mut v = obj(
                Some("foxglove.PoseInFrame"),
                "A timestamped pose for an object or reference frame in 3D space",
                vec![
                    ("timestamp", time("Timestamp of pose")),
                    (
                        "frame_id",
                        string("Frame of reference for pose position and orientation"),
                    ),
                    (
                        "pose",
                        obj(
                            Some("foxglove.Pose"),
                            "Pose in 3D space",
                            vec![
                                (
                                    "position",
                                    vec3(
                                        Some("foxglove.Vector3"),
                                        "Point denoting position in 3D space",
                                    ),
                                ),
                                (
                                    "orientation",
                                    quat(
                                        Some("foxglove.Quaternion"),
                                        "Quaternion denoting orientation in 3D space",
                                    ),
                                ),
                            ],
                        ),
                    ),
                ],
            );
            v["$comment"] = json!("foxglove/schemas PoseInFrame, written by flapwing");
            v
        }
        "foxglove.FrameTransform" => obj(
            Some("foxglove.FrameTransform"),
            "A transform between two reference frames in 3D space",
            vec![
                ("timestamp", time("Timestamp of transform")),
                ("parent_frame_id", string("Name of the parent frame")),
                ("child_frame_id", string("Name of the child frame")),
                (
                    "translation",
                    vec3(
                        Some("foxglove.Vector3"),
                        "Translation component of the transform",
                    ),
                ),
                (
                    "rotation",
                    quat(
                        Some("foxglove.Quaternion"),
                        "Rotation component of the transform",
                    ),
                ),
            ],
        ),
        "foxglove.Log" => obj(
            Some("foxglove.Log"),
            "A log message",
            vec![
                ("timestamp", time("Timestamp of log message")),
                (
                    "level",
                    json!({"type": "integer", "minimum": 0, "maximum": 5,
                           "description": "Log level: 1 DEBUG, 2 INFO, 3 WARNING, 4 ERROR, 5 FATAL"}),
                ),
                ("message", string("Log message")),
                ("name", string("Process or node name")),
                ("file", string("Filename")),
                (
                    "line",
                    json!({"type": "integer", "minimum": 0, "description": "Line number in the file"}),
                ),
            ],
        ),
        "flapwing.VehicleState" => {
            let mut p = Vec::new();
            common(&mut p);
            p.push((
                "position_m",
                vec3(None, "centre of mass, world frame (z up), m"),
            ));
            p.push((
                "velocity_m_s",
                vec3(None, "centre of mass, world frame, m/s"),
            ));
            p.push(("attitude", quat(None, "world_from_body quaternion")));
            p.push((
                "euler_deg",
                obj(
                    None,
                    "roll, pitch (positive nose up), yaw, deg",
                    vec![
                        ("roll", num("deg")),
                        ("pitch", num("deg")),
                        ("yaw", num("deg")),
                    ],
                ),
            ));
            p.push((
                "body_rates_rad_s",
                vec3(None, "angular velocity, body frame, rad/s"),
            ));
            p.push((
                "applied_force_body_n",
                vec3(
                    None,
                    "total load on the body except gravity (both wings, all terms, wing inertia), body frame, N",
                ),
            ));
            p.push((
                "applied_moment_body_nm",
                vec3(None, "its moment about the centre of mass, body frame, N m"),
            ));
            p.push((
                "lift_over_weight",
                num("world-vertical component of the applied force over the weight"),
            ));
            p.push((
                "nonfinite",
                boolean("a NaN or infinity in this message was replaced by 0"),
            ));
            obj(
                Some("flapwing.VehicleState"),
                "The body's state at t_k and the load applied over [t_k, t_k + dt]",
                p,
            )
        }
        "flapwing.Controls" => {
            let mut p = Vec::new();
            common(&mut p);
            for (k, d) in [
                ("mean_stroke_deg", "mean stroke angle offset, deg"),
                ("amplitude_deg", "stroke amplitude offset, deg"),
                ("pitch_bias_deg", "pitch bias offset, deg"),
                ("freq_hz", "frequency offset, Hz"),
                ("diff_amplitude_deg", "left minus right amplitude, deg"),
                ("diff_pitch_bias_deg", "left minus right pitch bias, deg"),
                (
                    "diff_mean_stroke_deg",
                    "left minus right mean stroke angle, deg",
                ),
            ] {
                p.push((k, num(d)));
            }
            p.push((
                "drive",
                obj(
                    None,
                    "actuated wings only (absent for prescribed kinematics): the drive control offsets",
                    vec![
                        ("bias_v", num("drive bias offset, V")),
                        ("amplitude_v", num("drive amplitude offset, V")),
                        (
                            "diff_amplitude_v",
                            num("left minus right drive amplitude, V"),
                        ),
                        ("diff_bias_v", num("left minus right drive bias, V")),
                        (
                            "diff_second_harmonic",
                            num("left minus right second-harmonic fraction"),
                        ),
                    ],
                ),
            ));
            p.push((
                "nonfinite",
                boolean("a NaN or infinity in this message was replaced by 0"),
            ));
            obj(
                Some("flapwing.Controls"),
                "Control inputs in force during the step",
                p,
            )
        }
        "flapwing.WingKinematics" => {
            let mut p = Vec::new();
            common(&mut p);
            p.push(("angles_deg", angles3("wing angles, deg")));
            p.push(("angles_rad", angles3("wing angles, rad")));
            p.push(("rates_rad_s", angles3("time derivatives, rad/s")));
            p.push((
                "accelerations_rad_s2",
                angles3("second time derivatives, rad/s^2"),
            ));
            p.push((
                "t_star",
                num("time since the last stroke reversal over the period (the paper's t*)"),
            ));
            p.push((
                "half_stroke",
                int("half strokes completed since phase 0 (0 = first downstroke)"),
            ));
            p.push(("downstroke", boolean("true in a downstroke")));
            p.push((
                "actuation",
                obj(
                    None,
                    "actuated wings only (absent for prescribed kinematics): the hinge and the actuator",
                    vec![
                        (
                            "hinge_moment_nm",
                            num("hinge spring and damper moment on the wing about the pitch axis, N m"),
                        ),
                        (
                            "aero_pitch_moment_nm",
                            num("aerodynamic moment about the pitch axis, N m"),
                        ),
                        (
                            "aero_stroke_moment_nm",
                            num("aerodynamic moment about the stroke axis, N m"),
                        ),
                        ("voltage_v", num("drive voltage, V")),
                        (
                            "displacement_m",
                            num("piezo tip displacement, m (0 for a motor)"),
                        ),
                        ("current_a", num("motor current, A (0 for a piezo)")),
                    ],
                ),
            ));
            p.push((
                "nonfinite",
                boolean("a NaN or infinity in this message was replaced by 0"),
            ));
            obj(
                Some("flapwing.WingKinematics"),
                "One wing's kinematic state at t_k",
                p,
            )
        }
        "flapwing.WingForces" => {
            let mut p = Vec::new();
            common(&mut p);
            for part in FORCE_PARTS {
                p.push((
                    part,
                    obj(
                        None,
                        "force and moment on the body from this wing, body frame",
                        vec![
                            ("force_n", vec3(None, "force, body frame, N")),
                            (
                                "moment_nm",
                                vec3(None, "moment about the centre of mass, body frame, N m"),
                            ),
                            (
                                "c_l",
                                num("lift coefficient on the reference scale 0.5 rho V_ref^2 S"),
                            ),
                            (
                                "c_d",
                                num("drag coefficient on the reference scale 0.5 rho V_ref^2 S"),
                            ),
                        ],
                    ),
                ));
            }
            p.push((
                "nonfinite",
                boolean("a NaN or infinity in this message was replaced by 0"),
            ));
            obj(
                Some("flapwing.WingForces"),
                "One wing's aerodynamic forces per term and in total at t_k",
                p,
            )
        }
        _ => return None,
    };
    Some(v.to_string())
}
