//! Protobuf encoding of the messages logged every sample, in one pass straight into the
//! open MCAP chunk ([`SampleEncoder`], on the simulation thread).
//!
//! prost writes a nested message's length before its fields, so it computes the length of
//! every sub-message (and of theirs) before writing it: for the sample's three levels of
//! nesting that is most of the encoding work. Every sub-message here is shorter than 128
//! bytes, so its length is one byte, written first as a zero and patched once the fields are
//! in. The bytes are exactly prost's (fields in tag order, proto3 defaults left out, a set
//! optional sub-message written even when empty); the tests check it on whole runs.

use flapsim::StepOutput;
use foxglove::messages::{ArrowPrimitive, FrameTransform, PoseInFrame, SceneUpdate};

use crate::chunk::RawChunk;
use crate::decimate::Decimator;
use crate::pb::{Pb, SAMPLE_BOUND};
use crate::proto;
use crate::sample::{Encoded, Sample, SampleBuilder, timestamp};
use crate::scene::ForceArrows;
use crate::schema::{FORCE_ARROWS_MAX_RATE_HZ, OPTIONAL_CHANNELS, WingLayout, channel_id};
use flapsim::actuated::ActuatedWingOutput;
use wingforce::WingForces;

/// Writes each logged step's messages into the open chunk: the ten of the sample and, at
/// most [`FORCE_ARROWS_MAX_RATE_HZ`] times per simulated second, its force arrows, after the
/// wing planforms with the very first step; and the events. Keeps the channels' sequence
/// numbers, and the messages built last (reused by the next step, and by the Rerun and live
/// views).
pub(crate) struct SampleEncoder {
    builder: SampleBuilder,
    sample: Sample,
    arrows: ForceArrows,
    arrow_message: SceneUpdate,
    arrow_decimator: Decimator,
    /// The wing planforms, until they go out with the first sample.
    planforms: Option<SceneUpdate>,
    /// Per channel: the layout's channels, then [`OPTIONAL_CHANNELS`].
    sequences: Vec<u32>,
    layout: WingLayout,
}

impl SampleEncoder {
    pub fn new(builder: SampleBuilder, arrows: ForceArrows, planforms: SceneUpdate) -> Self {
        let layout = WingLayout::new(builder.wings());
        Self {
            builder,
            sample: Sample::default(),
            arrows,
            arrow_message: SceneUpdate::default(),
            arrow_decimator: Decimator::new(Some(FORCE_ARROWS_MAX_RATE_HZ)),
            planforms: Some(planforms),
            sequences: vec![0; layout.channel_count() + OPTIONAL_CHANNELS.len()],
            layout,
        }
    }

    /// The messages of the last step given to [`SampleEncoder::sample`] (the views'
    /// sample when an MCAP output built it).
    #[cfg(any(feature = "rerun", feature = "live"))]
    pub fn last(&self) -> &Sample {
        &self.sample
    }

    fn next(&mut self, channel: usize) -> u32 {
        let s = self.sequences[channel];
        self.sequences[channel] = s.wrapping_add(1);
        s
    }

    /// Builds the messages of `out` with every wing's forces and actuator state (see
    /// [`SampleBuilder::build_wings`]) and appends their records to `raw`; the number of
    /// messages written.
    pub fn sample(
        &mut self,
        out: &StepOutput,
        wings: &[WingForces],
        actuated: Option<&[ActuatedWingOutput]>,
        raw: &mut RawChunk,
    ) -> u64 {
        let mut messages = self.layout.sample_messages() as u64;
        self.builder
            .build_wings(out, wings, actuated, &mut self.sample);
        let t_ns = self.sample.t_ns;
        let (scene_wings, scene_forces) = (self.layout.scene_wings(), self.layout.scene_forces());
        if let Some(mut scene) = self.planforms.take() {
            messages += 1;
            for e in &mut scene.entities {
                e.timestamp = Some(timestamp(t_ns));
            }
            let seq = self.next(scene_wings);
            raw.message(channel_id(scene_wings), seq, t_ns, &scene);
        }
        let Self {
            sample,
            sequences,
            arrows,
            arrow_message,
            ..
        } = self;
        each_encoder(sample, |i, bound, encode| {
            let seq = sequences[i];
            sequences[i] = seq.wrapping_add(1);
            raw.message_with(channel_id(i), seq, t_ns, bound, encode);
        });
        if self.arrow_decimator.take(out.t_s) {
            arrows.build(sample, arrow_message);
            let seq = self.next(scene_forces);
            let bound = arrow_scene_bound(&self.arrow_message);
            raw.message_with(channel_id(scene_forces), seq, t_ns, bound, |p| {
                arrow_scene(p, &self.arrow_message);
            });
            messages += 1;
        }
        messages
    }

    /// Appends the record of a message on optional channel `optional` (an index of
    /// [`OPTIONAL_CHANNELS`]) to `raw`; `id` is the channel's MCAP id in this log.
    pub fn optional(
        &mut self,
        optional: usize,
        id: u16,
        t_ns: u64,
        message: &dyn Encoded,
        raw: &mut RawChunk,
    ) {
        let seq = self.next(self.layout.channel_count() + optional);
        raw.message(id, seq, t_ns, message);
    }

    /// Appends an event's record to `raw`.
    pub fn event(&mut self, t_ns: u64, log: &foxglove::messages::Log, raw: &mut RawChunk) {
        let events = self.layout.events();
        let seq = self.next(events);
        raw.message(channel_id(events), seq, t_ns, log);
    }
}

#[inline(always)]
pub(crate) fn pose_in_frame(p: &mut Pb, m: &PoseInFrame) {
    p.timestamp(1, &m.timestamp);
    p.string(2, &m.frame_id);
    p.pose(3, &m.pose);
}

#[inline(always)]
pub(crate) fn frame_transform(p: &mut Pb, m: &FrameTransform) {
    p.timestamp(1, &m.timestamp);
    p.string(2, &m.parent_frame_id);
    p.string(3, &m.child_frame_id);
    p.xyz(4, m.translation.map(|v| [v.x, v.y, v.z]));
    p.xyzw(5, m.rotation.map(|q| [q.x, q.y, q.z, q.w]));
}

#[inline(always)]
pub(crate) fn vehicle_state(p: &mut Pb, m: &proto::VehicleState) {
    p.head(&m.timestamp, m.step, m.t_s, m.phase);
    p.vec3(5, &m.position_m);
    p.vec3(6, &m.velocity_m_s);
    p.xyzw(7, m.attitude.map(|q| [q.x, q.y, q.z, q.w]));
    p.xyz(8, m.euler_deg.map(|e| [e.roll, e.pitch, e.yaw]));
    p.vec3(9, &m.body_rates_rad_s);
    p.vec3(10, &m.applied_force_body_n);
    p.vec3(11, &m.applied_moment_body_nm);
    p.double(12, m.lift_over_weight);
    if let Some(mem) = &m.memory {
        p.message(13, |p| {
            p.uint(1, mem.step);
            p.vec3(2, &mem.velocity_m_s);
            p.vec3(3, &mem.rates_rad_s);
            p.vec3(4, &mem.mid_rates_rad_s);
            p.xyzw(5, mem.world_from_body.map(|q| [q.x, q.y, q.z, q.w]));
        });
    }
}

#[inline(always)]
pub(crate) fn controls(p: &mut Pb, m: &proto::Controls) {
    p.head(&m.timestamp, m.step, m.t_s, m.phase);
    p.double(5, m.mean_stroke_deg);
    p.double(6, m.amplitude_deg);
    p.double(7, m.pitch_bias_deg);
    p.double(8, m.freq_hz);
    p.double(9, m.diff_amplitude_deg);
    p.double(10, m.diff_pitch_bias_deg);
    p.double(11, m.diff_mean_stroke_deg);
    if let Some(d) = &m.drive {
        p.message(12, |p| {
            p.double(1, d.bias_v);
            p.double(2, d.amplitude_v);
            p.double(3, d.diff_amplitude_v);
            p.double(4, d.diff_bias_v);
            p.double(5, d.diff_second_harmonic);
        });
    }
}

#[inline(always)]
pub(crate) fn wing_kinematics(p: &mut Pb, m: &proto::WingKinematics) {
    p.head(&m.timestamp, m.step, m.t_s, m.phase);
    p.angles(5, &m.angles_deg);
    p.angles(6, &m.angles_rad);
    p.angles(7, &m.rates_rad_s);
    p.angles(8, &m.accelerations_rad_s2);
    p.double(9, m.t_star);
    p.uint(10, m.half_stroke as u64);
    p.boolean(11, m.downstroke);
    if let Some(a) = &m.actuation {
        p.message(12, |p| {
            p.double(1, a.hinge_moment_nm);
            p.double(2, a.aero_pitch_moment_nm);
            p.double(3, a.aero_stroke_moment_nm);
            p.double(4, a.voltage_v);
            p.double(5, a.displacement_m);
            p.double(6, a.current_a);
        });
    }
}

#[inline(always)]
pub(crate) fn wing_forces(p: &mut Pb, m: &proto::WingForces) {
    p.head(&m.timestamp, m.step, m.t_s, m.phase);
    p.force_term(5, &m.translational);
    p.force_term(6, &m.rotational);
    p.force_term(7, &m.added_mass);
    p.force_term(8, &m.wake_capture);
    p.force_term(9, &m.total);
}

#[inline(always)]
fn arrow(p: &mut Pb, a: &ArrowPrimitive) {
    p.pose(1, &a.pose);
    p.double(2, a.shaft_length);
    p.double(3, a.shaft_diameter);
    p.double(4, a.head_length);
    p.double(5, a.head_diameter);
    p.xyzw(6, a.color.map(|c| [c.r, c.g, c.b, c.a]));
}

/// A `foxglove.SceneUpdate` of entities with arrows only (`/scene/forces`).
///
/// Entities with other primitives, metadata or a lifetime, and deletions, are not written:
/// [`crate::scene::ForceArrows`] makes none (a debug assertion checks it).
pub(crate) fn arrow_scene(p: &mut Pb, m: &SceneUpdate) {
    debug_assert!(m.deletions.is_empty());
    for e in &m.entities {
        debug_assert!(e.lifetime.is_none() && e.metadata.is_empty() && e.cubes.is_empty());
        debug_assert!(e.triangles.is_empty() && e.lines.is_empty() && e.texts.is_empty());
        p.message(2, |p| {
            p.timestamp(1, &e.timestamp);
            p.string(2, &e.frame_id);
            p.string(3, &e.id);
            p.boolean(5, e.frame_locked);
            for a in &e.arrows {
                p.message(7, |p| arrow(p, a));
            }
        });
    }
}

/// Room enough for [`arrow_scene`]'s encoding of `m`.
pub(crate) fn arrow_scene_bound(m: &SceneUpdate) -> usize {
    let entity = |e: &foxglove::messages::SceneEntity| {
        // The fixed fields and each arrow (under 200 bytes) with slack for long lengths.
        128 + e.frame_id.len() + e.id.len() + 256 * e.arrows.len()
    };
    64 + m.entities.iter().map(entity).sum::<usize>()
}

/// Calls `f(channel index, bound, encoder)` for the messages of a sample, in channel order
/// (see [`Sample::each`], which gives them to prost); `bound` is room enough for the
/// message.
pub(crate) fn each_encoder(s: &Sample, mut f: impl FnMut(usize, usize, &dyn Fn(&mut Pb))) {
    let n = s.wings();
    f(0, SAMPLE_BOUND + s.pose.frame_id.len(), &|p| {
        pose_in_frame(p, &s.pose)
    });
    for (i, t) in s.transforms.iter().enumerate() {
        let strings = t.parent_frame_id.len() + t.child_frame_id.len();
        f(1 + i, SAMPLE_BOUND + strings, &|p| frame_transform(p, t));
    }
    f(2 + n, SAMPLE_BOUND, &|p| vehicle_state(p, &s.state));
    f(3 + n, SAMPLE_BOUND, &|p| controls(p, &s.controls));
    for (i, k) in s.kinematics.iter().enumerate() {
        f(4 + n + i, SAMPLE_BOUND, &|p| wing_kinematics(p, k));
    }
    for (i, w) in s.forces.iter().enumerate() {
        f(4 + 2 * n + i, SAMPLE_BOUND, &|p| wing_forces(p, w));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::{SampleBuilder, WingStatic};
    use crate::scene::ForceArrows;
    use flapsim::{Mode, Simulation, Vehicle};

    /// What `encode` writes into a buffer of `bound` bytes.
    fn enc(bound: usize, encode: impl FnOnce(&mut Pb)) -> Vec<u8> {
        let mut b = vec![0; bound];
        let mut p = Pb::new(&mut b);
        encode(&mut p);
        let n = p.len();
        b.truncate(n);
        b
    }

    /// The sample's messages and arrows encoded by prost and here: (channel, bytes) each.
    fn both(s: &Sample, arrows: &SceneUpdate) -> [Vec<(usize, Vec<u8>)>; 2] {
        let mut by_prost = Vec::new();
        s.each(|i, m| {
            let mut b = Vec::new();
            m.put(&mut b);
            by_prost.push((i, b));
        });
        by_prost.push((99, prost::Message::encode_to_vec(arrows)));
        let mut here = Vec::new();
        each_encoder(s, |i, bound, encode| {
            let b = enc(bound, encode);
            assert!(b.len() + 64 < bound, "{i}: {} bytes", b.len());
            here.push((i, b));
        });
        let bound = arrow_scene_bound(arrows);
        let b = enc(bound, |p| arrow_scene(p, arrows));
        assert!(b.len() + 100 < bound, "arrows: {} bytes", b.len());
        here.push((99, b));
        [by_prost, here]
    }

    #[test]
    fn one_pass_encoding_gives_prosts_bytes() {
        let models = [
            (flapsim::DROSOPHILA_TOML, Mode::Free),
            (flapsim::DROSOPHILA_TOML, Mode::Tethered),
            (flapsim::ROBOBEE_TOML, Mode::Free),
        ];
        for (toml, mode) in models {
            let vehicle = Vehicle::from_toml(toml, "model.toml").unwrap();
            let builder = SampleBuilder::new(
                WingStatic::of(&vehicle),
                vehicle.weight_n(),
                vehicle.sim.steps_per_wingbeat as u64,
            );
            let arrows = ForceArrows::of(&vehicle);
            let mut sim = Simulation::new(vehicle, mode);
            let (mut s, mut a) = (Sample::default(), SceneUpdate::default());
            for _ in 0..300 {
                let out = *sim.step().unwrap();
                builder.build(&out, &mut s);
                arrows.build(&s, &mut a);
                let [p, h] = both(&s, &a);
                assert_eq!(p, h, "step {}", out.step);
            }
            assert!(s.kinematics[0].actuation.is_some() == (toml == flapsim::ROBOBEE_TOML));
        }
    }

    #[test]
    fn one_pass_encoding_of_special_values() {
        let vehicle = Vehicle::from_toml(flapsim::DROSOPHILA_TOML, "d.toml").unwrap();
        let builder = SampleBuilder::new(
            WingStatic::of(&vehicle),
            vehicle.weight_n(),
            vehicle.sim.steps_per_wingbeat as u64,
        );
        let arrows = ForceArrows::of(&vehicle);
        let mut sim = Simulation::new(vehicle, Mode::Free);
        let mut out = *sim.step().unwrap();
        let (mut s, mut a) = (Sample::default(), SceneUpdate::default());
        let specials = [0.0, -0.0, f64::NAN, f64::INFINITY, -1e300, 5e-324, 1.0];
        for (k, &x) in specials.iter().enumerate() {
            out.step = [0, 1, 127, 128, u64::MAX, 1 << 35, 300][k];
            out.t_s = [0.0, 1e-9, 4.3e9, 1.5, 0.0, 2.0, 7.0][k];
            out.phase = x;
            out.state.position_m.x = x;
            out.state.velocity_m_s.y = -x;
            out.wings[0].angles.eta = x;
            out.wings[1].phase.half_stroke = [0, -1, i64::MIN, 1, i64::MAX, 5, -300][k];
            out.wings[1].phase.downstroke = k % 2 == 0;
            out.wings[0].total.force_n = nalgebra::Vector3::new(x, -x, 0.5);
            out.wings[1].total.force_n = nalgebra::Vector3::new(-x, 0.0, 0.0);
            out.wings[1].terms[2].c_l = x;
            out.controls.freq_hz = x;
            builder.build(&out, &mut s);
            arrows.build(&s, &mut a);
            let [p, h] = both(&s, &a);
            assert_eq!(p, h, "value {x}");
        }
        // Absent sub-messages and empty strings are left out as prost leaves them out.
        let mut s = Sample::with_wings(2);
        s.forces[1].total = Some(proto::ForceTerm::default());
        let a = SceneUpdate {
            deletions: Vec::new(),
            entities: vec![foxglove::messages::SceneEntity::default(); 2],
        };
        let [p, h] = both(&s, &a);
        assert_eq!(p, h);
    }

    #[test]
    fn long_sub_messages_take_longer_lengths() {
        for n in [0usize, 1, 127, 128, 300, 20_000] {
            let name = "x".repeat(n);
            let m = PoseInFrame {
                frame_id: name.clone(),
                ..PoseInFrame::default()
            };
            let here = enc(n + 64, |p| p.message(3, |p| pose_in_frame(p, &m)));
            let wrapped = foxglove::messages::SceneEntity {
                id: name,
                ..Default::default()
            };
            let b = enc(n + 64, |p| p.message(2, |p| p.string(3, &wrapped.id)));
            let prost_b = prost::Message::encode_to_vec(&SceneUpdate {
                deletions: Vec::new(),
                entities: vec![wrapped],
            });
            assert_eq!(b, prost_b, "{n}");
            let mut prost_here = vec![(3 << 3) | 2];
            prost::encoding::encode_varint(prost::Message::encoded_len(&m) as u64, &mut prost_here);
            prost::Message::encode_raw(&m, &mut prost_here);
            assert_eq!(here, prost_here, "{n}");
        }
    }
}
