//! Topics, frames and the protobuf schemas of every channel.
//!
//! Foxglove types (`foxglove.PoseInFrame`, `foxglove.FrameTransform`, `foxglove.Log`,
//! `foxglove.SceneUpdate`) and
//! their descriptor sets come from the foxglove crate; flapwing's own types are in
//! `proto/flapwing.proto` ([`crate::proto`]). Every channel has schema encoding `protobuf`
//! (the data is a serialized `FileDescriptorSet`) and message encoding `protobuf`.

use foxglove::Encode;

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
/// The wing planforms, `foxglove.SceneUpdate` (once, with the first sample).
pub const TOPIC_SCENE: &str = "/scene/wings";
/// Each wing's total aerodynamic force as an arrow, `foxglove.SceneUpdate` (every sample).
pub const TOPIC_SCENE_FORCES: &str = "/scene/forces";

/// IMU readings, `flapwing.ImuReading` (logs with sensors only, see [`SENSOR_CHANNELS`]).
pub const TOPIC_IMU: &str = "/sensors/imu";
/// Motion-capture frames, `flapwing.MocapReading` (logs with sensors only).
pub const TOPIC_MOCAP: &str = "/sensors/mocap";
/// Each wing's wind at its hinge, `flapwing.Wind` (logs of runs with a wind field only, see
/// [`WIND_CHANNEL`]).
pub const TOPIC_WIND: &str = "/wind";
/// Each wing pair's dynamic inflow states, `flapwing.Inflow` (logs of vehicles whose wake
/// answers only, see [`INFLOW_CHANNEL`]).
pub const TOPIC_INFLOW: &str = "/inflow";
/// The state estimator's estimate and covariance, `flapwing.Estimate` (logs of runs flown on
/// the estimate only, see [`ESTIMATE_CHANNEL`]).
pub const TOPIC_ESTIMATE: &str = "/estimate";

/// The world frame (z up).
pub const FRAME_WORLD: &str = "world";
/// The body frame (x forward, y left, z up, origin at the centre of mass).
pub const FRAME_BODY: &str = "base_link";
/// The left wing's frame (see [`wing_frame_doc`]).
pub const FRAME_WING_LEFT: &str = "wing_left";
/// The right wing's frame.
pub const FRAME_WING_RIGHT: &str = "wing_right";

/// Schema encoding of every channel.
pub const SCHEMA_ENCODING: &str = "protobuf";
/// Message encoding of every channel.
pub const MESSAGE_ENCODING: &str = "protobuf";

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

/// Every channel of a two-winged vehicle's log: (topic, schema name). Logs of other wing
/// counts have each wing's channels ([`WingLayout::channels`]).
pub const CHANNELS: [(&str, &str); 13] = [
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
    (TOPIC_SCENE, "foxglove.SceneUpdate"),
    (TOPIC_SCENE_FORCES, "foxglove.SceneUpdate"),
];

/// The most force arrows (`/scene/forces` messages) per simulated second: logs at a higher
/// rate (full rate: 21,800 samples per second of drosophila flight) have arrows on the
/// samples that [`crate::Decimator`] picks at this rate, which at the CLI's default of 2000 Hz is
/// every sample. Arrows at every step of a full-rate log cost 16 % more bytes to compress,
/// and 200 arrows per wingbeat show nothing that 20 do not.
pub const FORCE_ARROWS_MAX_RATE_HZ: f64 = 2000.0;

/// The MCAP channel id of channel `index` of [`CHANNELS`] (added in order, numbered from 1).
pub(crate) fn channel_id(index: usize) -> u16 {
    index as u16 + 1
}

/// The sensor channels, declared after [`CHANNELS`] (channel ids 14 and 15 in a two-winged
/// vehicle's log) when
/// [`crate::LogOptions::sensors`] is set; one message per delivered reading
/// ([`crate::Recorder::sensor`]).
pub const SENSOR_CHANNELS: [(&str, &str); 2] = [
    (TOPIC_IMU, "flapwing.ImuReading"),
    (TOPIC_MOCAP, "flapwing.MocapReading"),
];

/// The wind channel, declared after [`CHANNELS`] and the sensor channels (if any) when
/// [`crate::LogOptions::wind`] is set; one message per logged sample
/// ([`crate::Recorder::wind`]).
pub const WIND_CHANNEL: (&str, &str) = (TOPIC_WIND, "flapwing.Wind");

/// The estimate channel, declared last when [`crate::LogOptions::estimate`] is set; one
/// message per logged sample ([`crate::Recorder::estimate`]).
pub const ESTIMATE_CHANNEL: (&str, &str) = (TOPIC_ESTIMATE, "flapwing.Estimate");

/// The induced-flow channel, declared last when [`crate::LogOptions::inflow`] is set; one
/// message per logged sample ([`crate::Recorder::inflow`]).
pub const INFLOW_CHANNEL: (&str, &str) = (TOPIC_INFLOW, "flapwing.Inflow");

/// Every optional channel, in the order they are declared after [`CHANNELS`] (those a log's
/// options ask for; channel ids follow on from 14 without gaps).
pub const OPTIONAL_CHANNELS: [(&str, &str); 5] = [
    SENSOR_CHANNELS[0],
    SENSOR_CHANNELS[1],
    WIND_CHANNEL,
    ESTIMATE_CHANNEL,
    INFLOW_CHANNEL,
];

/// Index of /sensors/imu in [`OPTIONAL_CHANNELS`].
#[cfg(feature = "live")]
pub(crate) const OPT_IMU: usize = 0;
/// Index of /sensors/mocap in [`OPTIONAL_CHANNELS`].
#[cfg(feature = "live")]
pub(crate) const OPT_MOCAP: usize = 1;
/// Index of /wind in [`OPTIONAL_CHANNELS`].
pub(crate) const OPT_WIND: usize = 2;
/// Index of /estimate in [`OPTIONAL_CHANNELS`].
pub(crate) const OPT_ESTIMATE: usize = 3;
/// Index of /inflow in [`OPTIONAL_CHANNELS`].
pub(crate) const OPT_INFLOW: usize = 4;

/// The channels a log of a vehicle with `wings` and `options` declares, in order (the
/// wings' [`WingLayout::channels`], then those of [`OPTIONAL_CHANNELS`] it asks for):
/// (topic, schema name). For two wings the first thirteen are [`CHANNELS`].
pub fn declared_channels(
    wings: &WingLayout,
    options: &crate::options::LogOptions,
) -> Vec<(String, &'static str)> {
    let wanted = [
        options.sensors,
        options.sensors,
        options.wind,
        options.estimate,
        options.inflow,
    ];
    wings
        .channels()
        .into_iter()
        .chain(
            OPTIONAL_CHANNELS
                .iter()
                .zip(wanted)
                .filter(|(_, w)| *w)
                .map(|(c, _)| ((*c).0.to_owned(), (*c).1)),
        )
        .collect()
}

/// The per-wing names of a log: the channels and frames of each of a vehicle's wings, in the
/// vehicle's order. Wing `i` of pair `p = i / 2` is labelled by its side (`left` for even
/// `i`, `right` for odd): `left` and `right` for the first pair (so two-winged logs keep the
/// names above), `pairs{k}_left` and `pairs{k}_right` for the model file's `[[pairs]]` entry
/// `k = p - 1` (flapsim's `Vehicle::wing_name` "pairs[k] left"). Wing `label` has the frame
/// `wing_{label}` (`/tf/wing_{label}`) and the channels `/wing/{label}/kinematics` and
/// `/wing/{label}/forces`.
///
/// The channels are, in order: `/vehicle/pose`, `/tf/base_link`, each wing's `/tf/wing_*`,
/// `/vehicle/state`, `/vehicle/controls`, each wing's kinematics, each wing's forces,
/// `/events`, `/scene/wings`, `/scene/forces` (`7 + 3 n` for `n` wings; [`CHANNELS`] for two).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct WingLayout {
    labels: Vec<String>,
}

impl WingLayout {
    /// The layout of `n` wings.
    pub fn new(n: usize) -> Self {
        Self {
            labels: (0..n).map(wing_label).collect(),
        }
    }

    /// Number of wings.
    pub fn len(&self) -> usize {
        self.labels.len()
    }

    /// True for no wings.
    pub fn is_empty(&self) -> bool {
        self.labels.is_empty()
    }

    /// The wings' labels (`left`, `right`, `pairs0_left`, ...).
    pub fn labels(&self) -> &[String] {
        &self.labels
    }

    /// Wing `i`'s frame, `wing_{label}`.
    pub fn frame(&self, i: usize) -> String {
        format!("wing_{}", self.labels[i])
    }

    /// Wing `i`'s transform topic, `/tf/wing_{label}`.
    pub fn tf_topic(&self, i: usize) -> String {
        format!("/tf/wing_{}", self.labels[i])
    }

    /// Wing `i`'s kinematics topic, `/wing/{label}/kinematics`.
    pub fn kinematics_topic(&self, i: usize) -> String {
        format!("/wing/{}/kinematics", self.labels[i])
    }

    /// Wing `i`'s forces topic, `/wing/{label}/forces`.
    pub fn forces_topic(&self, i: usize) -> String {
        format!("/wing/{}/forces", self.labels[i])
    }

    /// Messages per sample (every channel before `/events`).
    pub fn sample_messages(&self) -> usize {
        4 + 3 * self.len()
    }

    /// Index of `/events` in [`WingLayout::channels`].
    pub fn events(&self) -> usize {
        4 + 3 * self.len()
    }

    /// Index of `/scene/wings`.
    pub fn scene_wings(&self) -> usize {
        5 + 3 * self.len()
    }

    /// Index of `/scene/forces`.
    pub fn scene_forces(&self) -> usize {
        6 + 3 * self.len()
    }

    /// Number of always-declared channels, `7 + 3 n`.
    pub fn channel_count(&self) -> usize {
        7 + 3 * self.len()
    }

    /// The always-declared channels: (topic, schema name).
    pub fn channels(&self) -> Vec<(String, &'static str)> {
        let n = self.len();
        let mut c = Vec::with_capacity(self.channel_count());
        c.push((TOPIC_POSE.to_owned(), "foxglove.PoseInFrame"));
        c.push((TOPIC_TF_BODY.to_owned(), "foxglove.FrameTransform"));
        c.extend((0..n).map(|i| (self.tf_topic(i), "foxglove.FrameTransform")));
        c.push((TOPIC_STATE.to_owned(), "flapwing.VehicleState"));
        c.push((TOPIC_CONTROLS.to_owned(), "flapwing.Controls"));
        c.extend((0..n).map(|i| (self.kinematics_topic(i), "flapwing.WingKinematics")));
        c.extend((0..n).map(|i| (self.forces_topic(i), "flapwing.WingForces")));
        c.push((TOPIC_EVENTS.to_owned(), "foxglove.Log"));
        c.push((TOPIC_SCENE.to_owned(), "foxglove.SceneUpdate"));
        c.push((TOPIC_SCENE_FORCES.to_owned(), "foxglove.SceneUpdate"));
        c
    }

    /// The wings of a log, from its `/wing/{label}/forces` topics in channel order (`None`
    /// when it has none).
    pub fn from_topics<'a>(topics: impl IntoIterator<Item = &'a str>) -> Option<Self> {
        let labels: Vec<String> = topics
            .into_iter()
            .filter_map(|t| t.strip_prefix("/wing/")?.strip_suffix("/forces"))
            .filter(|l| !l.is_empty() && !l.contains('/'))
            .map(str::to_owned)
            .collect();
        (!labels.is_empty()).then_some(Self { labels })
    }
}

/// Wing `i`'s label (see [`WingLayout`]).
pub fn wing_label(i: usize) -> String {
    let side = if i % 2 == 0 { "left" } else { "right" };
    match i / 2 {
        0 => side.to_owned(),
        p => format!("pairs{}_{side}", p - 1),
    }
}

/// The names of the four terms and the total, in the order of the forces message's objects.
pub const FORCE_PARTS: [&str; 5] = [
    "translational",
    "rotational",
    "added_mass",
    "wake_capture",
    "total",
];

/// The schema data (a serialized protobuf `FileDescriptorSet`) of a schema name used by
/// flapwing (`None` for other names).
pub fn schema_data(name: &str) -> Option<Vec<u8>> {
    fn foxglove<T: Encode>() -> Option<Vec<u8>> {
        T::get_schema().map(|s| s.data.into_owned())
    }
    match name {
        "foxglove.PoseInFrame" => foxglove::<foxglove::messages::PoseInFrame>(),
        "foxglove.FrameTransform" => foxglove::<foxglove::messages::FrameTransform>(),
        "foxglove.Log" => foxglove::<foxglove::messages::Log>(),
        "foxglove.SceneUpdate" => foxglove::<foxglove::messages::SceneUpdate>(),
        "flapwing.VehicleState"
        | "flapwing.Controls"
        | "flapwing.WingKinematics"
        | "flapwing.WingForces"
        | "flapwing.ImuReading"
        | "flapwing.MocapReading"
        | "flapwing.Wind"
        | "flapwing.Estimate"
        | "flapwing.Inflow" => Some(crate::proto::FILE_DESCRIPTOR_SET.to_vec()),
        _ => None,
    }
}

/// The metadata key that says how the logged run's actuated wings took the step mean, and
/// its value since they split their steps at stroke reversals (wingset's
/// `DynamicWing::reversal_within`, issue 37).
pub const ACTUATED_STEP_MEAN_KEY: &str = "actuated_step_mean";
/// See [`ACTUATED_STEP_MEAN_KEY`].
pub const ACTUATED_STEP_MEAN_SPLIT: &str = "split_at_reversals";

/// The metadata key that says how the logged run advanced the body's angular velocity, and
/// its value since a second-order sampling's runs take the midpoint rule (flapsim's
/// `host::midpoint_torque_world`, 2026-12-06). A second-order log without it re-runs with
/// rapier's own update (`SimSpec::rotation_at_step_start`).
pub const BODY_ROTATION_KEY: &str = "body_rotation";
/// See [`BODY_ROTATION_KEY`].
pub const BODY_ROTATION_MIDPOINT: &str = "midpoint";

/// The metadata key that says how the logged run's actuated wings shared a hinge stop's
/// strike between the body step it falls in and the next (wingset's `actuated::StrikeShare`),
/// and its values: [`STRIKE_IMPULSE_SHARED`] for the semi-implicit pose's hat (2026-12-06),
/// [`STRIKE_IMPULSE_SHARED_TRAPEZOIDAL`] for the trapezoidal pose's (2026-12-07, what
/// flapsim's hosts use under a second-order sampling). A log without it re-runs with the
/// whole impulse in its step.
pub const STRIKE_IMPULSE_KEY: &str = "strike_impulse";
/// See [`STRIKE_IMPULSE_KEY`].
pub const STRIKE_IMPULSE_SHARED: &str = "shared_with_next_step";
/// See [`STRIKE_IMPULSE_KEY`].
pub const STRIKE_IMPULSE_SHARED_TRAPEZOIDAL: &str = "shared_for_the_trapezoidal_pose";

/// The metadata key that says how the logged run's actuated wings on inelastic hinge stops
/// took their aerodynamic loads within a step (wingset's `actuated::StageLoads`), and its
/// values: [`ACTUATED_STAGE_LOADS_SPLIT`] since the steps are split at stroke reversals
/// (`actuated::dynamics::stage_loads`, the afternoon of 2026-12-07),
/// [`ACTUATED_STAGE_LOADS_INTERPOLATED`] for the loads at each segment's start and the
/// sub-step's end and linear in time between them (`actuated::contact`, the morning of
/// 2026-12-07). A log without it re-runs with
/// the loads taken afresh at every Runge-Kutta stage.
pub const ACTUATED_STAGE_LOADS_KEY: &str = "actuated_stage_loads";
/// See [`ACTUATED_STAGE_LOADS_KEY`].
pub const ACTUATED_STAGE_LOADS_INTERPOLATED: &str = "interpolated_between_segment_ends";
/// See [`ACTUATED_STAGE_LOADS_KEY`].
pub const ACTUATED_STAGE_LOADS_SPLIT: &str = "interpolated_split_at_reversals";
