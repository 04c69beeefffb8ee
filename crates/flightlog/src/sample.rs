//! One logged step as protobuf messages: the messages of a sample (channel order of
//! [`crate::schema::WingLayout::channels`], ten for two wings), built from a [`StepOutput`] with the Foxglove types of the
//! foxglove crate and flapwing's own ([`crate::proto`]). Numbers go in as the simulation
//! produced them (protobuf doubles carry NaN and infinity); only the Rerun view's numbers
//! ([`FrameData`]) are made finite.

use flapsim::StepOutput;
use flapsim::actuated::ActuatedWingOutput;
use foxglove::messages::{FrameTransform, PoseInFrame, Timestamp};
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};
use wingforce::Side;
use wingforce::WingForces;
use wingforce::wing::WingFrame;

use crate::proto;
use crate::schema::{FRAME_BODY, FRAME_WORLD, WingLayout};

/// Simulation time in integer nanoseconds (0 for negative or non-finite times).
pub(crate) fn time_ns(t_s: f64) -> u64 {
    let ns = (t_s * 1e9).round();
    if ns.is_finite() && ns > 0.0 {
        if ns >= u64::MAX as f64 {
            u64::MAX
        } else {
            ns as u64
        }
    } else {
        0
    }
}

/// Foxglove's time of `t_ns` (seconds saturate at u32::MAX: 136 years of simulated time).
pub(crate) fn timestamp(t_ns: u64) -> Timestamp {
    let sec = (t_ns / 1_000_000_000).min(u64::from(u32::MAX)) as u32;
    Timestamp::new(sec, (t_ns % 1_000_000_000) as u32)
}

/// What the recorder knows about each wing that does not change during a run.
#[derive(Debug, Clone, Copy)]
pub(crate) struct WingStatic {
    pub side: Side,
    pub hinge_in_body_m: Vector3<f64>,
    pub body_from_stroke: Matrix3<f64>,
}

impl WingStatic {
    /// Every wing of `vehicle`, in its order.
    pub fn of(vehicle: &flapsim::Vehicle) -> Vec<Self> {
        vehicle
            .wings
            .iter()
            .map(|w| WingStatic {
                side: w.mount().side,
                hinge_in_body_m: w.mount().hinge_in_body_m,
                body_from_stroke: *w.body_from_stroke(),
            })
            .collect()
    }
}

/// The rotation base_link_from_wing of a wing frame (see [`crate::schema::wing_frame_doc`]).
pub(crate) fn wing_rotation(w: &WingStatic, angles: &wingforce::WingAngles) -> UnitQuaternion<f64> {
    let fr = WingFrame::new(angles, w.side);
    let z = fr.e_le.cross(&fr.e_span);
    let m = w.body_from_stroke * Matrix3::from_columns(&[fr.e_le, fr.e_span, z]);
    UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(m))
}

pub(crate) fn fox_vec(v: &Vector3<f64>) -> foxglove::messages::Vector3 {
    foxglove::messages::Vector3 {
        x: v.x,
        y: v.y,
        z: v.z,
    }
}

pub(crate) fn fox_quat(q: &UnitQuaternion<f64>) -> foxglove::messages::Quaternion {
    foxglove::messages::Quaternion {
        x: q.i,
        y: q.j,
        z: q.k,
        w: q.w,
    }
}

fn angles(phi: f64, theta: f64, eta: f64) -> Option<proto::WingAngles> {
    Some(proto::WingAngles { phi, theta, eta })
}

/// The messages of one sample (`4 + 3 n` for `n` wings).
#[derive(Debug, Clone, Default)]
pub(crate) struct Sample {
    pub t_ns: u64,
    pub pose: PoseInFrame,
    /// world -> base_link, then base_link -> each wing's frame.
    pub transforms: Vec<FrameTransform>,
    pub state: proto::VehicleState,
    pub controls: proto::Controls,
    /// Per wing.
    pub kinematics: Vec<proto::WingKinematics>,
    /// Per wing.
    pub forces: Vec<proto::WingForces>,
}

impl Sample {
    /// An empty sample of `wings` wings.
    pub fn with_wings(wings: usize) -> Self {
        Self {
            transforms: vec![FrameTransform::default(); 1 + wings],
            kinematics: vec![proto::WingKinematics::default(); wings],
            forces: vec![proto::WingForces::default(); wings],
            ..Self::default()
        }
    }

    /// Number of wings.
    pub fn wings(&self) -> usize {
        self.forces.len()
    }

    /// Calls `f(channel index, message)` for the sample's messages in channel order (the
    /// live view encodes them with prost; the MCAP file with
    /// [`crate::encode::each_encoder`]).
    #[cfg_attr(not(feature = "live"), allow(dead_code))]
    pub fn each(&self, mut f: impl FnMut(usize, &dyn Encoded)) {
        let n = self.wings();
        f(0, &self.pose);
        for (i, t) in self.transforms.iter().enumerate() {
            f(1 + i, t);
        }
        f(2 + n, &self.state);
        f(3 + n, &self.controls);
        for (i, k) in self.kinematics.iter().enumerate() {
            f(4 + n + i, k);
        }
        for (i, w) in self.forces.iter().enumerate() {
            f(4 + 2 * n + i, w);
        }
    }
}

/// A message that can be encoded into a byte buffer (object-safe part of `prost::Message`).
pub(crate) trait Encoded {
    fn len(&self) -> usize;
    fn put(&self, out: &mut Vec<u8>);
}

impl<M: prost::Message> Encoded for M {
    fn len(&self) -> usize {
        self.encoded_len()
    }
    fn put(&self, out: &mut Vec<u8>) {
        self.encode_raw(out);
    }
}

/// Builds the messages of each logged step.
#[derive(Debug, Clone)]
pub(crate) struct SampleBuilder {
    wings: Vec<WingStatic>,
    /// Each wing's frame name.
    frames: Vec<String>,
    weight_n: f64,
    /// Steps per wingbeat: a state at a wingbeat's first step carries the wing set's step
    /// memory (where a replay restarts a segment), the others do not need it.
    steps_per_wingbeat: u64,
}

impl SampleBuilder {
    pub fn new(wings: Vec<WingStatic>, weight_n: f64, steps_per_wingbeat: u64) -> Self {
        let layout = WingLayout::new(wings.len());
        let frames = (0..wings.len()).map(|i| layout.frame(i)).collect();
        Self {
            wings,
            frames,
            weight_n,
            steps_per_wingbeat: steps_per_wingbeat.max(1),
        }
    }

    /// Number of wings.
    pub fn wings(&self) -> usize {
        self.wings.len()
    }

    /// The messages of a two-winged vehicle's `out`, written over `s` (which keeps its frame
    /// names between samples).
    #[cfg(test)]
    pub fn build(&self, out: &StepOutput, s: &mut Sample) {
        self.build_wings(out, &out.wings, out.actuated.as_ref().map(|a| &a[..]), s);
    }

    /// The messages of `out` with every wing's forces (`wings`, the vehicle's order) and
    /// actuator state (`actuated`, `None` for prescribed kinematics), written over `s`.
    pub fn build_wings(
        &self,
        out: &StepOutput,
        wings: &[WingForces],
        actuated: Option<&[ActuatedWingOutput]>,
        s: &mut Sample,
    ) {
        let n = self.wings.len();
        if s.wings() != n || s.transforms.len() != 1 + n {
            *s = Sample::with_wings(n);
        }
        let t_ns = time_ns(out.t_s);
        let ts = Some(timestamp(t_ns));
        let st = &out.state;
        s.t_ns = t_ns;

        let position = Some(fox_vec(&st.position_m));
        let orientation = Some(fox_quat(&st.world_from_body));
        s.pose.timestamp = ts;
        set_name(&mut s.pose.frame_id, FRAME_WORLD);
        s.pose.pose = Some(foxglove::messages::Pose {
            position,
            orientation,
        });

        let (body, wing_tfs) = s.transforms.split_at_mut(1);
        let body = &mut body[0];
        frames(body, FRAME_WORLD, FRAME_BODY);
        body.timestamp = ts;
        body.translation = position;
        body.rotation = orientation;
        for (i, tf) in wing_tfs.iter_mut().enumerate() {
            frames(tf, FRAME_BODY, &self.frames[i]);
            tf.timestamp = ts;
            tf.translation = Some(fox_vec(&self.wings[i].hinge_in_body_m));
            let q = wing_rotation(&self.wings[i], &wings[i].angles);
            tf.rotation = Some(fox_quat(&q));
        }

        let (roll, pitch, yaw) = st.euler_rad();
        let f = &out.total.force_n;
        s.state = proto::VehicleState {
            timestamp: ts,
            step: out.step,
            t_s: out.t_s,
            phase: out.phase,
            position_m: Some((&st.position_m).into()),
            velocity_m_s: Some((&st.velocity_m_s).into()),
            attitude: Some((&st.world_from_body).into()),
            euler_deg: Some(proto::Euler {
                roll: roll.to_degrees(),
                pitch: pitch.to_degrees(),
                yaw: yaw.to_degrees(),
            }),
            body_rates_rad_s: Some((&st.angular_velocity_body_rad_s).into()),
            applied_force_body_n: Some(f.into()),
            applied_moment_body_nm: Some((&out.total.moment_nm).into()),
            lift_over_weight: (st.world_from_body * f).z / self.weight_n,
            memory: out
                .memory
                .filter(|_| out.step % self.steps_per_wingbeat == 0)
                .map(|m| proto::StepMemory {
                    step: m.step,
                    velocity_m_s: Some((&m.velocity_m_s).into()),
                    rates_rad_s: Some((&m.rates_rad_s).into()),
                    mid_rates_rad_s: Some((&m.mid_rates_rad_s).into()),
                    world_from_body: Some((&m.world_from_body).into()),
                }),
        };

        let c = &out.controls;
        s.controls = proto::Controls {
            timestamp: ts,
            step: out.step,
            t_s: out.t_s,
            phase: out.phase,
            mean_stroke_deg: c.mean_stroke_rad.to_degrees(),
            amplitude_deg: c.amplitude_rad.to_degrees(),
            pitch_bias_deg: c.pitch_bias_rad.to_degrees(),
            freq_hz: c.freq_hz,
            diff_amplitude_deg: c.diff_amplitude_rad.to_degrees(),
            diff_pitch_bias_deg: c.diff_pitch_bias_rad.to_degrees(),
            diff_mean_stroke_deg: c.diff_mean_stroke_rad.to_degrees(),
            drive: actuated.map(|_| proto::Drive {
                bias_v: c.bias_v,
                amplitude_v: c.amplitude_v,
                diff_amplitude_v: c.diff_amplitude_v,
                diff_bias_v: c.diff_bias_v,
                diff_second_harmonic: c.diff_second_harmonic,
            }),
        };

        for (i, wf) in wings.iter().enumerate().take(n) {
            let a = &wf.angles;
            s.kinematics[i] = proto::WingKinematics {
                timestamp: ts,
                step: out.step,
                t_s: out.t_s,
                phase: out.phase,
                angles_deg: angles(a.phi.to_degrees(), a.theta.to_degrees(), a.eta.to_degrees()),
                angles_rad: angles(a.phi, a.theta, a.eta),
                rates_rad_s: angles(a.phi_dot, a.theta_dot, a.eta_dot),
                accelerations_rad_s2: angles(a.phi_ddot, a.theta_ddot, a.eta_ddot),
                t_star: wf.phase.t_star,
                half_stroke: wf.phase.half_stroke,
                downstroke: wf.phase.downstroke,
                actuation: actuated.map(|act| {
                    let x = &act[i];
                    proto::Actuation {
                        hinge_moment_nm: x.hinge_moment_nm,
                        aero_pitch_moment_nm: x.aero_pitch_nm,
                        aero_stroke_moment_nm: x.aero_stroke_nm,
                        voltage_v: x.actuator.voltage_v,
                        displacement_m: x.actuator.displacement_m,
                        current_a: x.actuator.current_a,
                    }
                }),
            };
            let hinge = &self.wings[i].hinge_in_body_m;
            let term = |t: &wingforce::TermForce| {
                Some(proto::ForceTerm {
                    force_n: Some((&t.force_n).into()),
                    moment_nm: Some((&t.moment_about_com_nm(hinge)).into()),
                    c_l: t.c_l,
                    c_d: t.c_d,
                })
            };
            s.forces[i] = proto::WingForces {
                timestamp: ts,
                step: out.step,
                t_s: out.t_s,
                phase: out.phase,
                translational: term(&wf.terms[0]),
                rotational: term(&wf.terms[1]),
                added_mass: term(&wf.terms[2]),
                wake_capture: term(&wf.terms[3]),
                total: term(&wf.total),
            };
        }
    }
}

/// Sets a frame name, keeping the string's allocation.
fn set_name(s: &mut String, name: &str) {
    if s != name {
        s.clear();
        s.push_str(name);
    }
}

fn frames(tf: &mut FrameTransform, parent: &str, child: &str) {
    set_name(&mut tf.parent_frame_id, parent);
    set_name(&mut tf.child_frame_id, child);
}

/// The numbers a 3D view needs for one sample (all finite: non-finite numbers as 0).
#[derive(Debug, Clone, Default)]
#[cfg_attr(not(feature = "rerun"), allow(dead_code))]
pub(crate) struct FrameData {
    pub t_ns: u64,
    pub position: [f64; 3],
    /// world_from_body, x y z w.
    pub attitude: [f64; 4],
    pub euler_deg: [f64; 3],
    pub lift_over_weight: f64,
    /// Per wing.
    pub wings: Vec<WingView>,
    /// Per wing of an actuated vehicle: drive voltage (V), hinge moment (N m), pitch (deg).
    pub actuation: Option<Vec<[f64; 3]>>,
}

/// One wing's numbers in a [`FrameData`].
#[derive(Debug, Clone, Copy, Default)]
#[cfg_attr(not(feature = "rerun"), allow(dead_code))]
pub(crate) struct WingView {
    /// Hinge (body frame), m; base_link_from_wing (x y z w).
    pub hinge: [f64; 3],
    pub rotation: [f64; 4],
    /// Per part (4 terms and total): force (body frame, N), C_L, C_D.
    pub force_n: [[f64; 3]; 5],
    pub c_l: [f64; 5],
    pub c_d: [f64; 5],
}

#[cfg_attr(not(feature = "rerun"), allow(dead_code))]
fn fin(x: f64) -> f64 {
    if x.is_finite() { x } else { 0.0 }
}

#[cfg(feature = "rerun")]
impl FrameData {
    /// The view of a sample's messages.
    pub fn of(s: &Sample) -> Self {
        let v3 = |v: Option<foxglove::messages::Vector3>| {
            v.map_or([0.0; 3], |v| [fin(v.x), fin(v.y), fin(v.z)])
        };
        let q4 = |q: Option<foxglove::messages::Quaternion>| {
            q.map_or([0.0, 0.0, 0.0, 1.0], |q| {
                [fin(q.x), fin(q.y), fin(q.z), fin(q.w)]
            })
        };
        let p3 = |v: Option<proto::Vector3>| v.map_or([0.0; 3], |v| [fin(v.x), fin(v.y), fin(v.z)]);
        let mut f = FrameData {
            t_ns: s.t_ns,
            position: v3(s.transforms[0].translation),
            attitude: q4(s.transforms[0].rotation),
            euler_deg: s
                .state
                .euler_deg
                .map_or([0.0; 3], |e| [fin(e.roll), fin(e.pitch), fin(e.yaw)]),
            lift_over_weight: fin(s.state.lift_over_weight),
            ..FrameData::default()
        };
        let n = s.wings();
        f.wings = vec![WingView::default(); n];
        for (i, wv) in f.wings.iter_mut().enumerate() {
            wv.hinge = v3(s.transforms[1 + i].translation);
            wv.rotation = q4(s.transforms[1 + i].rotation);
            let w = &s.forces[i];
            let parts = [
                w.translational,
                w.rotational,
                w.added_mass,
                w.wake_capture,
                w.total,
            ];
            for (j, t) in parts.iter().enumerate() {
                let t = t.unwrap_or_default();
                wv.force_n[j] = p3(t.force_n);
                wv.c_l[j] = fin(t.c_l);
                wv.c_d[j] = fin(t.c_d);
            }
        }
        if n > 0 && s.kinematics.iter().all(|k| k.actuation.is_some()) {
            f.actuation = Some(
                s.kinematics
                    .iter()
                    .map(|k| {
                        let a = k.actuation.unwrap_or_default();
                        let pitch_deg = k.angles_deg.map_or(0.0, |a| a.theta);
                        [fin(a.voltage_v), fin(a.hinge_moment_nm), fin(pitch_deg)]
                    })
                    .collect(),
            );
        }
        f
    }
}
