//! The JSON messages, built from a step's output. Field lists match [`crate::schema`].
//!
//! [`SampleJson`] writes the ten messages of a sample with hand-written code. Its output is,
//! byte for byte, what serde_json's compact serializer writes for the serde structs of the
//! `reference` module (kept for the tests): the same field order, and every number goes
//! through serde_json's own formatter. It reuses one buffer, formats the numbers that several
//! messages share (time, step, position, attitude) once, and keeps the text of the values that
//! do not change between samples (the wing hinges, the controls). It also keeps, per step of
//! the wingbeat, the text of each group of numbers (a wing's transform, its kinematics, each
//! force term, the body loads) with the exact bits it was formatted from ([`Memo`]): while the
//! controls hold, flapsim's kinematics repeat bit for bit every wingbeat, so in free flight the
//! wing transforms, kinematics and the rotational, added-mass and wake-capture terms are
//! copied instead of formatted, and in tethered flight nearly everything is. A group whose bits
//! differ is formatted anew, so the text never depends on the memo. The unit tests compare
//! both writers on real runs (with and without control changes) and on non-finite inputs.

use flapsim::StepOutput;
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};
use serde::Serialize;
use serde_json::ser::{CompactFormatter, Formatter};
use wingforce::Side;
use wingforce::wing::WingFrame;

/// Replaces non-finite numbers by 0 and remembers that it did.
#[derive(Debug, Default)]
pub(crate) struct Fin {
    pub nonfinite: bool,
}

impl Fin {
    #[inline]
    pub fn f(&mut self, x: f64) -> f64 {
        if x.is_finite() {
            x
        } else {
            self.nonfinite = true;
            0.0
        }
    }

    pub fn q(&mut self, q: &UnitQuaternion<f64>) -> Quat {
        Quat {
            x: self.f(q.i),
            y: self.f(q.j),
            z: self.f(q.k),
            w: self.f(q.w),
        }
    }
}

/// A sanitized quaternion {x, y, z, w}.
#[derive(Debug, Clone, Copy, Serialize)]
pub(crate) struct Quat {
    pub x: f64,
    pub y: f64,
    pub z: f64,
    pub w: f64,
}

/// `{sec, nsec}` (Foxglove's time).
#[derive(Debug, Clone, Copy, Serialize)]
pub(crate) struct Time {
    pub sec: u64,
    pub nsec: u32,
}

impl Time {
    pub fn from_ns(ns: u64) -> Self {
        Self {
            sec: ns / 1_000_000_000,
            nsec: (ns % 1_000_000_000) as u32,
        }
    }
}

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

#[derive(Debug, Serialize)]
pub(crate) struct Log<'a> {
    pub timestamp: Time,
    pub level: u8,
    pub message: &'a str,
    pub name: &'a str,
    pub file: &'a str,
    pub line: u32,
}

/// What the recorder knows about each wing that does not change during a run.
#[derive(Debug, Clone, Copy)]
pub(crate) struct WingStatic {
    pub side: Side,
    pub hinge_in_body_m: Vector3<f64>,
    pub body_from_stroke: Matrix3<f64>,
}

/// The rotation base_link_from_wing of a wing frame (see [`crate::schema::wing_frame_doc`]).
pub(crate) fn wing_rotation(w: &WingStatic, angles: &wingforce::WingAngles) -> UnitQuaternion<f64> {
    let fr = WingFrame::new(angles, w.side);
    let z = fr.e_le.cross(&fr.e_span);
    let m = w.body_from_stroke * Matrix3::from_columns(&[fr.e_le, fr.e_span, z]);
    UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(m))
}

/// The numbers a 3D view needs for one sample (all finite: sanitized).
#[derive(Debug, Clone, Copy, Default)]
#[cfg_attr(not(feature = "rerun"), allow(dead_code))]
pub(crate) struct FrameData {
    pub t_ns: u64,
    pub position: [f64; 3],
    /// world_from_body, x y z w.
    pub attitude: [f64; 4],
    pub euler_deg: [f64; 3],
    pub lift_over_weight: f64,
    /// Per wing: hinge (body frame), base_link_from_wing (x y z w).
    pub wing_hinge: [[f64; 3]; 2],
    pub wing_rotation: [[f64; 4]; 2],
    /// Per wing, per part (4 terms and total): force (body frame, N), C_L, C_D.
    pub force_n: [[[f64; 3]; 5]; 2],
    pub c_l: [[f64; 5]; 2],
    pub c_d: [[f64; 5]; 2],
    /// Per wing of an actuated vehicle: drive voltage (V), hinge moment (N m), pitch (deg).
    pub actuation: Option<[[f64; 3]; 2]>,
}

/// [`FrameData::actuation`] of a step (non-finite numbers as 0).
fn actuation_numbers(out: &StepOutput) -> Option<[[f64; 3]; 2]> {
    let fin = |x: f64| if x.is_finite() { x } else { 0.0 };
    out.actuated.as_ref().map(|a| {
        [0, 1].map(|i| {
            [
                fin(a[i].actuator.voltage_v),
                fin(a[i].hinge_moment_nm),
                fin(a[i].angles.theta.to_degrees()),
            ]
        })
    })
}

/// Messages per sample: channel indexes 0..10 of [`crate::schema::CHANNELS`] (events excluded).
pub(crate) const SAMPLE_MESSAGES: usize = 10;

/// Where one sample's messages lie in a byte buffer, and its Rerun numbers.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Built {
    pub t_ns: u64,
    /// Offset of the first message; message `i` ends at `ends[i]` and the next one starts
    /// there.
    pub start: usize,
    pub ends: [usize; SAMPLE_MESSAGES],
    #[cfg_attr(not(feature = "rerun"), allow(dead_code))]
    pub frame: FrameData,
}

impl Built {
    /// The JSON of message `i` (channel index `i`) in `bytes`, the buffer it was built into.
    #[inline]
    pub fn message<'a>(&self, bytes: &'a [u8], i: usize) -> &'a [u8] {
        let from = if i == 0 { self.start } else { self.ends[i - 1] };
        &bytes[from..self.ends[i]]
    }
}

/// `x` (finite) exactly as serde_json writes an f64.
#[inline]
fn num(b: &mut Vec<u8>, x: f64) {
    // Writing to a Vec cannot fail.
    let _ = CompactFormatter.write_f64(b, x);
}

#[inline]
fn uint(b: &mut Vec<u8>, x: u64) {
    let _ = CompactFormatter.write_u64(b, x);
}

#[inline]
fn boolean(b: &mut Vec<u8>, v: bool) {
    b.extend_from_slice(if v { b"true" } else { b"false" });
}

/// The text before each number of an object of numbers: `{"k0":`, `,"k1":`, ...
type Keys<const N: usize> = [&'static [u8]; N];
const XYZW: Keys<4> = [b"{\"x\":", b",\"y\":", b",\"z\":", b",\"w\":"];
const XYZ: Keys<3> = [XYZW[0], XYZW[1], XYZW[2]];
const PHI_THETA_ETA: Keys<3> = [b"{\"phi\":", b",\"theta\":", b",\"eta\":"];
const ROLL_PITCH_YAW: Keys<3> = [b"{\"roll\":", b",\"pitch\":", b",\"yaw\":"];

/// `{"k0":a0,"k1":a1,...}` (the numbers finite). Constant keys keep their copies inlined.
#[inline]
fn object<const N: usize>(b: &mut Vec<u8>, keys: Keys<N>, a: [f64; N]) {
    for (key, x) in keys.into_iter().zip(a) {
        b.extend_from_slice(key);
        num(b, x);
    }
    b.push(b'}');
}

/// `{"x":..,"y":..,"z":..}`, sanitized; returns the numbers written.
#[inline]
fn vec3(b: &mut Vec<u8>, fin: &mut Fin, v: &Vector3<f64>) -> [f64; 3] {
    let a = [fin.f(v.x), fin.f(v.y), fin.f(v.z)];
    object(b, XYZ, a);
    a
}

/// `{"x":..,"y":..,"z":..,"w":..}`, sanitized; returns x y z w.
#[inline]
fn quat(b: &mut Vec<u8>, fin: &mut Fin, q: &UnitQuaternion<f64>) -> [f64; 4] {
    let a = [fin.f(q.i), fin.f(q.j), fin.f(q.k), fin.f(q.w)];
    object(b, XYZW, a);
    a
}

/// `{"phi":..,"theta":..,"eta":..}`, sanitized.
#[inline]
fn angles3(b: &mut Vec<u8>, fin: &mut Fin, phi: f64, theta: f64, eta: f64) {
    object(b, PHI_THETA_ETA, [fin.f(phi), fin.f(theta), fin.f(eta)]);
}

/// Longest wingbeat, in steps, whose text [`SampleJson`] keeps (about 3 KB per step); a longer
/// one shares the slots and simply finds fewer matches.
const MAX_MEMO_SLOTS: usize = 2048;

/// The text of one group of numbers per slot (a step of the wingbeat), with the bits of the
/// inputs it was written from (`K` of them) and what else the writer returned (`X`). A slot
/// whose bits match is copied; otherwise it is written anew and kept. The key is every input
/// the text depends on, so the output is the same with or without the memo.
#[derive(Debug)]
struct Memo<const K: usize, X> {
    slots: Vec<Option<MemoEntry<K, X>>>,
}

#[derive(Debug)]
struct MemoEntry<const K: usize, X> {
    key: [u64; K],
    text: Vec<u8>,
    extra: X,
}

impl<const K: usize, X: Copy> Memo<K, X> {
    fn new(slots: usize) -> Self {
        Self {
            slots: std::iter::repeat_with(|| None).take(slots).collect(),
        }
    }

    /// Appends the text of `key` to `b`: the kept text if slot `slot` holds the same bits,
    /// else what `write` appends (then kept). Returns the writer's extra value; `hits` counts
    /// the copies.
    #[inline]
    fn write(
        &mut self,
        slot: usize,
        key: [u64; K],
        b: &mut Vec<u8>,
        hits: &mut u64,
        write: impl FnOnce(&mut Vec<u8>) -> X,
    ) -> X {
        let entry = &mut self.slots[slot];
        if let Some(e) = entry
            && e.key == key
        {
            *hits += 1;
            b.extend_from_slice(&e.text);
            return e.extra;
        }
        let start = b.len();
        let extra = write(b);
        let text = &b[start..];
        match entry {
            Some(e) => {
                e.key = key;
                e.text.clear();
                e.text.extend_from_slice(text);
                e.extra = extra;
            }
            None => {
                *entry = Some(MemoEntry {
                    key,
                    text: text.to_vec(),
                    extra,
                })
            }
        }
        extra
    }
}

/// The bits of `xs`, for a [`Memo`] key.
#[inline]
fn bits<const K: usize>(xs: [f64; K]) -> [u64; K] {
    xs.map(f64::to_bits)
}

/// What the state message's memo keeps besides its text: the sanitized Euler angles (deg)
/// and lift over weight, and whether one of its numbers was not finite.
#[derive(Debug, Clone, Copy)]
struct StateNumbers {
    euler_deg: [f64; 3],
    lift_over_weight: f64,
    nonfinite: bool,
}

/// What a force part's memo keeps besides its text: the sanitized force, C_L and C_D, and
/// whether one of its numbers was not finite.
#[derive(Debug, Clone, Copy)]
struct PartNumbers {
    force_n: [f64; 3],
    c_l: f64,
    c_d: f64,
    nonfinite: bool,
}

/// Every memo of [`SampleJson`], indexed by the same slot.
#[derive(Debug)]
struct Memos {
    /// The step of the wingbeat is `step % period`.
    period: u64,
    /// Per wing: the transform after its timestamp (and the rotation written).
    wing_tf: [Memo<3, [f64; 4]>; 2],
    /// The state message from `euler_deg` to `lift_over_weight`.
    state: Memo<13, StateNumbers>,
    /// Per wing: the kinematics message from `angles_deg` to `t_star`.
    kinematics: [Memo<10, bool>; 2],
    /// Per wing and part (4 terms and total): the part object.
    parts: [[Memo<8, PartNumbers>; 5]; 2],
    /// Groups copied instead of formatted.
    hits: u64,
}

impl Memos {
    fn new(steps_per_wingbeat: usize) -> Self {
        let n = steps_per_wingbeat.clamp(1, MAX_MEMO_SLOTS);
        Self {
            period: n as u64,
            wing_tf: [Memo::new(n), Memo::new(n)],
            state: Memo::new(n),
            kinematics: [Memo::new(n), Memo::new(n)],
            parts: [0, 1].map(|_| [0, 1, 2, 3, 4].map(|_| Memo::new(n))),
            hits: 0,
        }
    }
}

/// The control inputs of the controls message, as bits (the cache key): the seven kinematic
/// ones, the five drive ones, and whether the drive ones are written (an actuated vehicle).
fn controls_key(c: &flapsim::Controls, drive: bool) -> [u64; 13] {
    [
        c.mean_stroke_rad.to_bits(),
        c.amplitude_rad.to_bits(),
        c.pitch_bias_rad.to_bits(),
        c.freq_hz.to_bits(),
        c.diff_amplitude_rad.to_bits(),
        c.diff_pitch_bias_rad.to_bits(),
        c.diff_mean_stroke_rad.to_bits(),
        c.bias_v.to_bits(),
        c.amplitude_v.to_bits(),
        c.diff_amplitude_v.to_bits(),
        c.diff_bias_v.to_bits(),
        c.diff_second_harmonic.to_bits(),
        u64::from(drive),
    ]
}

/// Writes the JSON of every message of a sample (see the module docs).
#[derive(Debug)]
pub(crate) struct SampleJson {
    wings: [WingStatic; 2],
    weight_n: f64,
    /// `{"timestamp":{"sec":..,"nsec":..}`: the start of every message.
    ts: Vec<u8>,
    /// `ts` and `,"step":..,"t_s":..,"phase":..`: the start of the flapwing messages.
    head: Vec<u8>,
    /// The sanitized position and attitude objects (pose, body transform and state), kept
    /// while their bits (`pose_key`) do not change; their numbers, and whether one of them
    /// was not finite.
    pose_key: Option<[u64; 7]>,
    position: Vec<u8>,
    attitude: Vec<u8>,
    pose_numbers: ([f64; 3], [f64; 4]),
    pose_bad: bool,
    /// Each wing's hinge object (constant) and its sanitized numbers.
    hinge: [Vec<u8>; 2],
    hinge_m: [[f64; 3]; 2],
    /// The controls fields `"mean_stroke_deg":..,...,"diff_mean_stroke_deg":..` for the
    /// inputs `controls_key`, and whether one of them was not finite.
    controls_key: Option<[u64; 13]>,
    controls: Vec<u8>,
    controls_bad: bool,
    /// The text of the number groups per step of the wingbeat.
    memos: Memos,
}

impl SampleJson {
    /// A writer for a vehicle with these wings and weight whose wingbeat lasts
    /// `steps_per_wingbeat` steps (the period of its memo; any value gives the same text).
    pub fn new(wings: [WingStatic; 2], weight_n: f64, steps_per_wingbeat: usize) -> Self {
        let mut hinge = [Vec::new(), Vec::new()];
        let mut hinge_m = [[0.0; 3]; 2];
        for i in 0..2 {
            // The flag of a Foxglove message is carried by the state message: dropped here.
            hinge_m[i] = vec3(
                &mut hinge[i],
                &mut Fin::default(),
                &wings[i].hinge_in_body_m,
            );
        }
        Self {
            wings,
            weight_n,
            ts: Vec::with_capacity(64),
            head: Vec::with_capacity(128),
            pose_key: None,
            position: Vec::with_capacity(96),
            attitude: Vec::with_capacity(128),
            pose_numbers: ([0.0; 3], [0.0; 4]),
            pose_bad: false,
            hinge,
            hinge_m,
            controls_key: None,
            controls: Vec::with_capacity(320),
            controls_bad: false,
            memos: Memos::new(steps_per_wingbeat),
        }
    }

    /// Number groups copied from the memo so far (instead of formatted).
    #[cfg(test)]
    pub fn memo_hits(&self) -> u64 {
        self.memos.hits
    }

    /// Appends the ten messages of `out` to `b` (in channel order) and says where they are.
    pub fn build(&mut self, out: &StepOutput, b: &mut Vec<u8>) -> Built {
        let t_ns = time_ns(out.t_s);
        let start = b.len();
        let mut ends = [0; SAMPLE_MESSAGES];
        let mut frame = FrameData {
            t_ns,
            wing_hinge: self.hinge_m,
            actuation: actuation_numbers(out),
            ..FrameData::default()
        };
        let s = &out.state;
        let memos = &mut self.memos;
        let slot = (out.step % memos.period) as usize;
        let hits = &mut memos.hits;

        // Shared pieces. `fin` is the state message's flag: it covers the time, the phase,
        // the position and the attitude, which the Foxglove messages also carry.
        let time_bad = !(out.t_s.is_finite() && out.phase.is_finite());
        let mut fin = Fin::default();
        let t_s = fin.f(out.t_s);
        let phase = fin.f(out.phase);
        let ts = Time::from_ns(t_ns);
        self.ts.clear();
        self.ts.extend_from_slice(b"{\"timestamp\":{\"sec\":");
        uint(&mut self.ts, ts.sec);
        self.ts.extend_from_slice(b",\"nsec\":");
        uint(&mut self.ts, u64::from(ts.nsec));
        self.ts.push(b'}');
        self.head.clear();
        self.head.extend_from_slice(&self.ts);
        self.head.extend_from_slice(b",\"step\":");
        uint(&mut self.head, out.step);
        self.head.extend_from_slice(b",\"t_s\":");
        num(&mut self.head, t_s);
        self.head.extend_from_slice(b",\"phase\":");
        num(&mut self.head, phase);
        let (p, q) = (&s.position_m, &s.world_from_body);
        let pose_key = bits([p.x, p.y, p.z, q.i, q.j, q.k, q.w]);
        if self.pose_key != Some(pose_key) {
            let mut f = Fin::default();
            self.position.clear();
            self.attitude.clear();
            self.pose_numbers = (
                vec3(&mut self.position, &mut f, p),
                quat(&mut self.attitude, &mut f, q),
            );
            self.pose_bad = f.nonfinite;
            self.pose_key = Some(pose_key);
        }
        (frame.position, frame.attitude) = self.pose_numbers;
        fin.nonfinite |= self.pose_bad;

        // 0: pose.
        b.extend_from_slice(&self.ts);
        b.extend_from_slice(b",\"frame_id\":\"");
        b.extend_from_slice(crate::schema::FRAME_WORLD.as_bytes());
        b.extend_from_slice(b"\",\"pose\":{\"position\":");
        b.extend_from_slice(&self.position);
        b.extend_from_slice(b",\"orientation\":");
        b.extend_from_slice(&self.attitude);
        b.extend_from_slice(b"}}");
        ends[0] = b.len();

        // 1: body transform.
        b.extend_from_slice(&self.ts);
        transform_frames(b, crate::schema::FRAME_WORLD, crate::schema::FRAME_BODY);
        b.extend_from_slice(&self.position);
        b.extend_from_slice(b",\"rotation\":");
        b.extend_from_slice(&self.attitude);
        b.push(b'}');
        ends[1] = b.len();

        // 2, 3: wing transforms.
        for (i, w) in self.wings.iter().enumerate() {
            let a = &out.wings[i].angles;
            b.extend_from_slice(&self.ts);
            let key = bits([a.phi, a.theta, a.eta]);
            frame.wing_rotation[i] = memos.wing_tf[i].write(slot, key, b, hits, |b| {
                let child = if i == 0 {
                    crate::schema::FRAME_WING_LEFT
                } else {
                    crate::schema::FRAME_WING_RIGHT
                };
                transform_frames(b, crate::schema::FRAME_BODY, child);
                b.extend_from_slice(&self.hinge[i]);
                b.extend_from_slice(b",\"rotation\":");
                let q = quat(b, &mut Fin::default(), &wing_rotation(w, a));
                b.push(b'}');
                q
            });
            ends[2 + i] = b.len();
        }

        // 4: vehicle state.
        b.extend_from_slice(&self.head);
        b.extend_from_slice(b",\"position_m\":");
        b.extend_from_slice(&self.position);
        b.extend_from_slice(b",\"velocity_m_s\":");
        vec3(b, &mut fin, &s.velocity_m_s);
        b.extend_from_slice(b",\"attitude\":");
        b.extend_from_slice(&self.attitude);
        let (w, f, m) = (
            &s.angular_velocity_body_rad_s,
            &out.total.force_n,
            &out.total.moment_nm,
        );
        let key = bits([
            q.i, q.j, q.k, q.w, w.x, w.y, w.z, f.x, f.y, f.z, m.x, m.y, m.z,
        ]);
        let weight_n = self.weight_n;
        let state = memos.state.write(slot, key, b, hits, |b| {
            let mut fin = Fin::default();
            let (roll, pitch, yaw) = s.euler_rad();
            let euler_deg = [
                fin.f(roll.to_degrees()),
                fin.f(pitch.to_degrees()),
                fin.f(yaw.to_degrees()),
            ];
            b.extend_from_slice(b",\"euler_deg\":");
            object(b, ROLL_PITCH_YAW, euler_deg);
            b.extend_from_slice(b",\"body_rates_rad_s\":");
            vec3(b, &mut fin, w);
            b.extend_from_slice(b",\"applied_force_body_n\":");
            vec3(b, &mut fin, f);
            b.extend_from_slice(b",\"applied_moment_body_nm\":");
            vec3(b, &mut fin, m);
            let vertical = (s.world_from_body * f).z;
            let lift_over_weight = fin.f(vertical / weight_n);
            b.extend_from_slice(b",\"lift_over_weight\":");
            num(b, lift_over_weight);
            StateNumbers {
                euler_deg,
                lift_over_weight,
                nonfinite: fin.nonfinite,
            }
        });
        b.extend_from_slice(b",\"nonfinite\":");
        boolean(b, fin.nonfinite || state.nonfinite);
        b.push(b'}');
        ends[4] = b.len();
        frame.euler_deg = state.euler_deg;
        frame.lift_over_weight = state.lift_over_weight;

        // 5: controls (their text is kept while they do not change).
        let c = &out.controls;
        let drive = out.actuated.is_some();
        let key = controls_key(c, drive);
        if self.controls_key != Some(key) {
            let mut f = Fin::default();
            let cb = &mut self.controls;
            cb.clear();
            cb.extend_from_slice(b"\"mean_stroke_deg\":");
            num(cb, f.f(c.mean_stroke_rad.to_degrees()));
            cb.extend_from_slice(b",\"amplitude_deg\":");
            num(cb, f.f(c.amplitude_rad.to_degrees()));
            cb.extend_from_slice(b",\"pitch_bias_deg\":");
            num(cb, f.f(c.pitch_bias_rad.to_degrees()));
            cb.extend_from_slice(b",\"freq_hz\":");
            num(cb, f.f(c.freq_hz));
            cb.extend_from_slice(b",\"diff_amplitude_deg\":");
            num(cb, f.f(c.diff_amplitude_rad.to_degrees()));
            cb.extend_from_slice(b",\"diff_pitch_bias_deg\":");
            num(cb, f.f(c.diff_pitch_bias_rad.to_degrees()));
            cb.extend_from_slice(b",\"diff_mean_stroke_deg\":");
            num(cb, f.f(c.diff_mean_stroke_rad.to_degrees()));
            if drive {
                cb.extend_from_slice(b",\"drive\":{\"bias_v\":");
                num(cb, f.f(c.bias_v));
                cb.extend_from_slice(b",\"amplitude_v\":");
                num(cb, f.f(c.amplitude_v));
                cb.extend_from_slice(b",\"diff_amplitude_v\":");
                num(cb, f.f(c.diff_amplitude_v));
                cb.extend_from_slice(b",\"diff_bias_v\":");
                num(cb, f.f(c.diff_bias_v));
                cb.extend_from_slice(b",\"diff_second_harmonic\":");
                num(cb, f.f(c.diff_second_harmonic));
                cb.push(b'}');
            }
            self.controls_bad = f.nonfinite;
            self.controls_key = Some(key);
        }
        b.extend_from_slice(&self.head);
        b.push(b',');
        b.extend_from_slice(&self.controls);
        b.extend_from_slice(b",\"nonfinite\":");
        boolean(b, self.controls_bad || time_bad);
        b.push(b'}');
        ends[5] = b.len();

        // 6, 7: kinematics.
        for (i, wf) in out.wings.iter().enumerate() {
            let a = &wf.angles;
            b.extend_from_slice(&self.head);
            let key = bits([
                a.phi,
                a.theta,
                a.eta,
                a.phi_dot,
                a.theta_dot,
                a.eta_dot,
                a.phi_ddot,
                a.theta_ddot,
                a.eta_ddot,
                wf.phase.t_star,
            ]);
            let bad = memos.kinematics[i].write(slot, key, b, hits, |b| {
                let mut f = Fin::default();
                b.extend_from_slice(b",\"angles_deg\":");
                angles3(
                    b,
                    &mut f,
                    a.phi.to_degrees(),
                    a.theta.to_degrees(),
                    a.eta.to_degrees(),
                );
                b.extend_from_slice(b",\"angles_rad\":");
                angles3(b, &mut f, a.phi, a.theta, a.eta);
                b.extend_from_slice(b",\"rates_rad_s\":");
                angles3(b, &mut f, a.phi_dot, a.theta_dot, a.eta_dot);
                b.extend_from_slice(b",\"accelerations_rad_s2\":");
                angles3(b, &mut f, a.phi_ddot, a.theta_ddot, a.eta_ddot);
                b.extend_from_slice(b",\"t_star\":");
                num(b, f.f(wf.phase.t_star));
                f.nonfinite
            });
            b.extend_from_slice(b",\"half_stroke\":");
            let _ = CompactFormatter.write_i64(b, wf.phase.half_stroke);
            b.extend_from_slice(b",\"downstroke\":");
            boolean(b, wf.phase.downstroke);
            // An actuated wing's hinge and actuator (its angles above are the dynamics').
            let mut act_bad = false;
            if let Some(act) = &out.actuated {
                let x = &act[i];
                let mut f = Fin::default();
                b.extend_from_slice(b",\"actuation\":{\"hinge_moment_nm\":");
                num(b, f.f(x.hinge_moment_nm));
                b.extend_from_slice(b",\"aero_pitch_moment_nm\":");
                num(b, f.f(x.aero_pitch_nm));
                b.extend_from_slice(b",\"aero_stroke_moment_nm\":");
                num(b, f.f(x.aero_stroke_nm));
                b.extend_from_slice(b",\"voltage_v\":");
                num(b, f.f(x.actuator.voltage_v));
                b.extend_from_slice(b",\"displacement_m\":");
                num(b, f.f(x.actuator.displacement_m));
                b.extend_from_slice(b",\"current_a\":");
                num(b, f.f(x.actuator.current_a));
                b.push(b'}');
                act_bad = f.nonfinite;
            }
            b.extend_from_slice(b",\"nonfinite\":");
            boolean(b, bad || act_bad || time_bad);
            b.push(b'}');
            ends[6 + i] = b.len();
        }

        // 8, 9: forces.
        for (i, wf) in out.wings.iter().enumerate() {
            let hinge = &self.wings[i].hinge_in_body_m;
            let mut bad = false;
            b.extend_from_slice(&self.head);
            let terms = [
                &wf.terms[0],
                &wf.terms[1],
                &wf.terms[2],
                &wf.terms[3],
                &wf.total,
            ];
            for (j, (t, key)) in terms.iter().zip(PART_KEYS).enumerate() {
                b.extend_from_slice(key);
                let (f, m) = (&t.force_n, &t.moment_hinge_nm);
                let key = bits([f.x, f.y, f.z, m.x, m.y, m.z, t.c_l, t.c_d]);
                let part = memos.parts[i][j].write(slot, key, b, hits, |b| {
                    let mut fin = Fin::default();
                    let force_n = vec3(b, &mut fin, f);
                    b.extend_from_slice(b",\"moment_nm\":");
                    vec3(b, &mut fin, &t.moment_about_com_nm(hinge));
                    let (c_l, c_d) = (fin.f(t.c_l), fin.f(t.c_d));
                    b.extend_from_slice(b",\"c_l\":");
                    num(b, c_l);
                    b.extend_from_slice(b",\"c_d\":");
                    num(b, c_d);
                    b.push(b'}');
                    PartNumbers {
                        force_n,
                        c_l,
                        c_d,
                        nonfinite: fin.nonfinite,
                    }
                });
                bad |= part.nonfinite;
                frame.force_n[i][j] = part.force_n;
                frame.c_l[i][j] = part.c_l;
                frame.c_d[i][j] = part.c_d;
            }
            b.extend_from_slice(b",\"nonfinite\":");
            boolean(b, bad || time_bad);
            b.push(b'}');
            ends[8 + i] = b.len();
        }
        Built {
            t_ns,
            start,
            ends,
            frame,
        }
    }
}

/// What precedes each part object of the forces message, up to its `force_n` value.
const PART_KEYS: [&[u8]; 5] = [
    b",\"translational\":{\"force_n\":",
    b",\"rotational\":{\"force_n\":",
    b",\"added_mass\":{\"force_n\":",
    b",\"wake_capture\":{\"force_n\":",
    b",\"total\":{\"force_n\":",
];

/// `,"parent_frame_id":"..","child_frame_id":"..","translation":` (frame names need no
/// escaping).
#[inline]
fn transform_frames(b: &mut Vec<u8>, parent: &str, child: &str) {
    b.extend_from_slice(b",\"parent_frame_id\":\"");
    b.extend_from_slice(parent.as_bytes());
    b.extend_from_slice(b"\",\"child_frame_id\":\"");
    b.extend_from_slice(child.as_bytes());
    b.extend_from_slice(b"\",\"translation\":");
}

/// A `foxglove.Log` message.
pub(crate) fn log_message(t_ns: u64, level: u8, message: &str) -> serde_json::Result<Vec<u8>> {
    serde_json::to_vec(&Log {
        timestamp: Time::from_ns(t_ns),
        level,
        message,
        name: "flapwing",
        file: "",
        line: 0,
    })
}

/// The serde structs of the sample messages and the serde_json writer they replace: the
/// reference [`SampleJson`] is checked against.
#[cfg(test)]
pub(crate) mod reference {
    use super::*;
    use wingforce::TermForce;

    impl Fin {
        pub fn v(&mut self, v: &Vector3<f64>) -> Vec3 {
            Vec3 {
                x: self.f(v.x),
                y: self.f(v.y),
                z: self.f(v.z),
            }
        }
    }

    #[derive(Debug, Clone, Copy, Serialize)]
    pub(crate) struct Vec3 {
        pub x: f64,
        pub y: f64,
        pub z: f64,
    }

    #[derive(Debug, Serialize)]
    pub(crate) struct Pose {
        pub position: Vec3,
        pub orientation: Quat,
    }

    #[derive(Debug, Serialize)]
    pub(crate) struct PoseInFrame<'a> {
        pub timestamp: Time,
        pub frame_id: &'a str,
        pub pose: Pose,
    }

    #[derive(Debug, Serialize)]
    pub(crate) struct FrameTransform<'a> {
        pub timestamp: Time,
        pub parent_frame_id: &'a str,
        pub child_frame_id: &'a str,
        pub translation: Vec3,
        pub rotation: Quat,
    }

    #[derive(Debug, Serialize)]
    pub(crate) struct Euler {
        pub roll: f64,
        pub pitch: f64,
        pub yaw: f64,
    }

    #[derive(Debug, Serialize)]
    pub(crate) struct VehicleState {
        pub timestamp: Time,
        pub step: u64,
        pub t_s: f64,
        pub phase: f64,
        pub position_m: Vec3,
        pub velocity_m_s: Vec3,
        pub attitude: Quat,
        pub euler_deg: Euler,
        pub body_rates_rad_s: Vec3,
        pub applied_force_body_n: Vec3,
        pub applied_moment_body_nm: Vec3,
        pub lift_over_weight: f64,
        pub nonfinite: bool,
    }

    #[derive(Debug, Serialize)]
    pub(crate) struct Controls {
        pub timestamp: Time,
        pub step: u64,
        pub t_s: f64,
        pub phase: f64,
        pub mean_stroke_deg: f64,
        pub amplitude_deg: f64,
        pub pitch_bias_deg: f64,
        pub freq_hz: f64,
        pub diff_amplitude_deg: f64,
        pub diff_pitch_bias_deg: f64,
        pub diff_mean_stroke_deg: f64,
        #[serde(skip_serializing_if = "Option::is_none")]
        pub drive: Option<DriveControls>,
        pub nonfinite: bool,
    }

    #[derive(Debug, Serialize)]
    pub(crate) struct DriveControls {
        pub bias_v: f64,
        pub amplitude_v: f64,
        pub diff_amplitude_v: f64,
        pub diff_bias_v: f64,
        pub diff_second_harmonic: f64,
    }

    #[derive(Debug, Serialize)]
    pub(crate) struct Angles3 {
        pub phi: f64,
        pub theta: f64,
        pub eta: f64,
    }

    #[derive(Debug, Serialize)]
    pub(crate) struct WingKinematics {
        pub timestamp: Time,
        pub step: u64,
        pub t_s: f64,
        pub phase: f64,
        pub angles_deg: Angles3,
        pub angles_rad: Angles3,
        pub rates_rad_s: Angles3,
        pub accelerations_rad_s2: Angles3,
        pub t_star: f64,
        pub half_stroke: i64,
        pub downstroke: bool,
        #[serde(skip_serializing_if = "Option::is_none")]
        pub actuation: Option<Actuation>,
        pub nonfinite: bool,
    }

    #[derive(Debug, Serialize)]
    pub(crate) struct Actuation {
        pub hinge_moment_nm: f64,
        pub aero_pitch_moment_nm: f64,
        pub aero_stroke_moment_nm: f64,
        pub voltage_v: f64,
        pub displacement_m: f64,
        pub current_a: f64,
    }

    #[derive(Debug, Clone, Copy, Serialize)]
    pub(crate) struct Part {
        pub force_n: Vec3,
        pub moment_nm: Vec3,
        pub c_l: f64,
        pub c_d: f64,
    }

    #[derive(Debug, Serialize)]
    pub(crate) struct WingForces {
        pub timestamp: Time,
        pub step: u64,
        pub t_s: f64,
        pub phase: f64,
        pub translational: Part,
        pub rotational: Part,
        pub added_mass: Part,
        pub wake_capture: Part,
        pub total: Part,
        pub nonfinite: bool,
    }

    /// Every message of one sample, serialized, in channel order (events excluded), plus
    /// the numbers the Rerun sink needs.
    #[derive(Debug)]
    pub(crate) struct Sample {
        pub t_ns: u64,
        /// JSON bytes per channel index 0..10 (index of [`crate::schema::CHANNELS`]).
        pub messages: Vec<(usize, Vec<u8>)>,
        pub frame: FrameData,
    }

    fn arr(v: &Vec3) -> [f64; 3] {
        [v.x, v.y, v.z]
    }
    fn arr4(q: &Quat) -> [f64; 4] {
        [q.x, q.y, q.z, q.w]
    }

    fn part(fin: &mut Fin, t: &TermForce, hinge: &Vector3<f64>) -> Part {
        Part {
            force_n: fin.v(&t.force_n),
            moment_nm: fin.v(&t.moment_about_com_nm(hinge)),
            c_l: fin.f(t.c_l),
            c_d: fin.f(t.c_d),
        }
    }

    /// Builds every message of one step's output.
    pub(crate) fn sample(
        out: &StepOutput,
        wings: &[WingStatic; 2],
        weight_n: f64,
    ) -> serde_json::Result<Sample> {
        let t_ns = time_ns(out.t_s);
        let ts = Time::from_ns(t_ns);
        let s = &out.state;
        let mut frame = FrameData {
            t_ns,
            actuation: super::actuation_numbers(out),
            ..FrameData::default()
        };
        let mut messages = Vec::with_capacity(10);

        // Vehicle state.
        let time_bad = !(out.t_s.is_finite() && out.phase.is_finite());
        let mut fin = Fin::default();
        let t_s = fin.f(out.t_s);
        let phase = fin.f(out.phase);
        let (roll, pitch, yaw) = s.euler_rad();
        let vertical = (s.world_from_body * out.total.force_n).z;
        let state = VehicleState {
            timestamp: ts,
            step: out.step,
            t_s,
            phase,
            position_m: fin.v(&s.position_m),
            velocity_m_s: fin.v(&s.velocity_m_s),
            attitude: fin.q(&s.world_from_body),
            euler_deg: Euler {
                roll: fin.f(roll.to_degrees()),
                pitch: fin.f(pitch.to_degrees()),
                yaw: fin.f(yaw.to_degrees()),
            },
            body_rates_rad_s: fin.v(&s.angular_velocity_body_rad_s),
            applied_force_body_n: fin.v(&out.total.force_n),
            applied_moment_body_nm: fin.v(&out.total.moment_nm),
            lift_over_weight: fin.f(vertical / weight_n),
            nonfinite: false,
        };
        let state = VehicleState {
            nonfinite: fin.nonfinite,
            ..state
        };
        frame.position = arr(&state.position_m);
        frame.attitude = arr4(&state.attitude);
        frame.euler_deg = [
            state.euler_deg.roll,
            state.euler_deg.pitch,
            state.euler_deg.yaw,
        ];
        frame.lift_over_weight = state.lift_over_weight;

        // Foxglove pose and body transform (sanitized the same way; the flag is on the state).
        let pose = PoseInFrame {
            timestamp: ts,
            frame_id: crate::schema::FRAME_WORLD,
            pose: Pose {
                position: state.position_m,
                orientation: state.attitude,
            },
        };
        messages.push((0, serde_json::to_vec(&pose)?));
        let tf = FrameTransform {
            timestamp: ts,
            parent_frame_id: crate::schema::FRAME_WORLD,
            child_frame_id: crate::schema::FRAME_BODY,
            translation: state.position_m,
            rotation: state.attitude,
        };
        messages.push((1, serde_json::to_vec(&tf)?));

        // Wing transforms.
        for (i, w) in wings.iter().enumerate() {
            let mut f = Fin::default();
            let q = wing_rotation(w, &out.wings[i].angles);
            let tf = FrameTransform {
                timestamp: ts,
                parent_frame_id: crate::schema::FRAME_BODY,
                child_frame_id: if i == 0 {
                    crate::schema::FRAME_WING_LEFT
                } else {
                    crate::schema::FRAME_WING_RIGHT
                },
                translation: f.v(&w.hinge_in_body_m),
                rotation: f.q(&q),
            };
            frame.wing_hinge[i] = arr(&tf.translation);
            frame.wing_rotation[i] = arr4(&tf.rotation);
            messages.push((2 + i, serde_json::to_vec(&tf)?));
        }
        messages.push((4, serde_json::to_vec(&state)?));

        // Controls.
        let c = &out.controls;
        let mut f = Fin::default();
        let controls = Controls {
            timestamp: ts,
            step: out.step,
            t_s,
            phase,
            mean_stroke_deg: f.f(c.mean_stroke_rad.to_degrees()),
            amplitude_deg: f.f(c.amplitude_rad.to_degrees()),
            pitch_bias_deg: f.f(c.pitch_bias_rad.to_degrees()),
            freq_hz: f.f(c.freq_hz),
            diff_amplitude_deg: f.f(c.diff_amplitude_rad.to_degrees()),
            diff_pitch_bias_deg: f.f(c.diff_pitch_bias_rad.to_degrees()),
            diff_mean_stroke_deg: f.f(c.diff_mean_stroke_rad.to_degrees()),
            drive: out.actuated.is_some().then(|| DriveControls {
                bias_v: f.f(c.bias_v),
                amplitude_v: f.f(c.amplitude_v),
                diff_amplitude_v: f.f(c.diff_amplitude_v),
                diff_bias_v: f.f(c.diff_bias_v),
                diff_second_harmonic: f.f(c.diff_second_harmonic),
            }),
            nonfinite: false,
        };
        let controls = Controls {
            nonfinite: f.nonfinite || time_bad,
            ..controls
        };
        messages.push((5, serde_json::to_vec(&controls)?));

        // Kinematics per wing.
        for (i, wf) in out.wings.iter().enumerate() {
            let a = &wf.angles;
            let mut f = Fin::default();
            let k = WingKinematics {
                timestamp: ts,
                step: out.step,
                t_s,
                phase,
                angles_deg: Angles3 {
                    phi: f.f(a.phi.to_degrees()),
                    theta: f.f(a.theta.to_degrees()),
                    eta: f.f(a.eta.to_degrees()),
                },
                angles_rad: Angles3 {
                    phi: f.f(a.phi),
                    theta: f.f(a.theta),
                    eta: f.f(a.eta),
                },
                rates_rad_s: Angles3 {
                    phi: f.f(a.phi_dot),
                    theta: f.f(a.theta_dot),
                    eta: f.f(a.eta_dot),
                },
                accelerations_rad_s2: Angles3 {
                    phi: f.f(a.phi_ddot),
                    theta: f.f(a.theta_ddot),
                    eta: f.f(a.eta_ddot),
                },
                t_star: f.f(wf.phase.t_star),
                half_stroke: wf.phase.half_stroke,
                downstroke: wf.phase.downstroke,
                actuation: out.actuated.as_ref().map(|act| {
                    let x = &act[i];
                    Actuation {
                        hinge_moment_nm: f.f(x.hinge_moment_nm),
                        aero_pitch_moment_nm: f.f(x.aero_pitch_nm),
                        aero_stroke_moment_nm: f.f(x.aero_stroke_nm),
                        voltage_v: f.f(x.actuator.voltage_v),
                        displacement_m: f.f(x.actuator.displacement_m),
                        current_a: f.f(x.actuator.current_a),
                    }
                }),
                nonfinite: false,
            };
            let k = WingKinematics {
                nonfinite: f.nonfinite || time_bad,
                ..k
            };
            messages.push((6 + i, serde_json::to_vec(&k)?));
        }

        // Forces per wing.
        for (i, wf) in out.wings.iter().enumerate() {
            let hinge = &wings[i].hinge_in_body_m;
            let mut f = Fin::default();
            let parts = [
                part(&mut f, &wf.terms[0], hinge),
                part(&mut f, &wf.terms[1], hinge),
                part(&mut f, &wf.terms[2], hinge),
                part(&mut f, &wf.terms[3], hinge),
                part(&mut f, &wf.total, hinge),
            ];
            for (j, p) in parts.iter().enumerate() {
                frame.force_n[i][j] = arr(&p.force_n);
                frame.c_l[i][j] = p.c_l;
                frame.c_d[i][j] = p.c_d;
            }
            let m = WingForces {
                timestamp: ts,
                step: out.step,
                t_s,
                phase,
                translational: parts[0],
                rotational: parts[1],
                added_mass: parts[2],
                wake_capture: parts[3],
                total: parts[4],
                nonfinite: f.nonfinite || time_bad,
            };
            messages.push((8 + i, serde_json::to_vec(&m)?));
        }
        Ok(Sample {
            t_ns,
            messages,
            frame,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use flapsim::{Mode, Simulation, Vehicle};

    fn statics(v: &Vehicle) -> [WingStatic; 2] {
        [0, 1].map(|i| {
            let w = &v.wings[i];
            WingStatic {
                side: w.mount().side,
                hinge_in_body_m: w.mount().hinge_in_body_m,
                body_from_stroke: *w.body_from_stroke(),
            }
        })
    }

    /// Both writers agree on every message of every output (one `SampleJson` for all, so the
    /// caches are exercised), and on the Rerun numbers. Returns the number groups copied
    /// from the memo.
    fn check(v: &Vehicle, outs: &[StepOutput]) -> u64 {
        let wings = statics(v);
        let mut json = SampleJson::new(wings, v.weight_n(), v.sim.steps_per_wingbeat);
        let mut buf = Vec::new();
        for out in outs {
            let want = reference::sample(out, &wings, v.weight_n()).unwrap();
            // Alternate between a fresh buffer and appending, as the recorder does.
            if out.step % 3 == 0 {
                buf.clear();
            }
            let got = json.build(out, &mut buf);
            assert_eq!(got.t_ns, want.t_ns);
            assert_eq!(want.messages.len(), SAMPLE_MESSAGES);
            for (i, (index, data)) in want.messages.iter().enumerate() {
                assert_eq!(*index, i);
                assert_eq!(
                    std::str::from_utf8(got.message(&buf, i)).unwrap(),
                    std::str::from_utf8(data).unwrap(),
                    "message {i} of step {}",
                    out.step
                );
            }
            assert_eq!(format!("{:?}", got.frame), format!("{:?}", want.frame));
        }
        json.memo_hits()
    }

    fn run(toml: &str, mode: Mode, steps: usize, controls: bool) -> (Vehicle, Vec<StepOutput>) {
        let v = Vehicle::from_toml(toml, "model.toml").unwrap();
        let mut sim = Simulation::new(v.clone(), mode);
        let mut outs = Vec::new();
        for k in 0..steps {
            if controls && k % 37 == 0 {
                let mut c = flapsim::Controls::default();
                if v.drive_controlled() {
                    c.amplitude_v = -5.0 * (k % 5) as f64;
                    c.diff_second_harmonic = -0.01 * (k % 3) as f64;
                } else {
                    c.amplitude_rad = 0.01 * (k % 5) as f64;
                    c.diff_pitch_bias_rad = -0.003 * (k % 3) as f64;
                }
                sim.set_controls(c);
            }
            match sim.step() {
                Ok(o) => outs.push(*o),
                Err(_) => break,
            }
        }
        (v, outs)
    }

    /// The memo is used: with steady controls, flapsim's kinematics repeat bit for bit every
    /// wingbeat, so after the first wingbeat of 4 every number group of a tethered sample is
    /// copied (2 transforms, the state, 2 kinematics, 10 force parts: 15 per sample), and in
    /// free flight at least those that depend on the kinematics alone (the transforms, the
    /// kinematics, the rotational, added-mass and wake-capture parts: 10 per sample). With
    /// controls changing every 37 steps there are fewer copies, and the text must still
    /// match.
    #[test]
    fn matches_serde_json_on_real_runs() {
        for (toml, mode, controls, least_hits_per_sample) in [
            (flapsim::DROSOPHILA_TOML, Mode::Free, false, 10),
            (flapsim::DROSOPHILA_TOML, Mode::Tethered, false, 15),
            (flapsim::DROSOPHILA_TOML, Mode::LONGITUDINAL, true, 0),
            (flapsim::ROBOBEE_KINEMATIC_TOML, Mode::Free, true, 0),
            (flapsim::ROBOBEE_TOML, Mode::Free, true, 0),
            (flapsim::HUMMINGBIRD_TOML, Mode::Tethered, false, 0),
            (flapsim::BUMBLEBEE_TOML, Mode::Free, false, 10),
        ] {
            let (v, outs) = run(toml, mode, 400, controls);
            assert!(outs.len() > 100);
            let hits = check(&v, &outs);
            let later = (outs.len() - v.sim.steps_per_wingbeat) as u64;
            assert!(
                hits >= least_hits_per_sample * later,
                "{mode:?}: {hits} memo hits, expected at least {least_hits_per_sample} x {later}"
            );
        }
    }

    #[test]
    fn matches_serde_json_on_odd_numbers() {
        let (v, outs) = run(flapsim::DROSOPHILA_TOML, Mode::Free, 40, false);
        let odd = [
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            -0.0,
            0.0,
            1e300,
            -1e-300,
            5e-324,
            f64::MAX,
            f64::MIN_POSITIVE,
            123456789.0,
            1e16,
            1e-7,
            0.1,
        ];
        let mut all = Vec::new();
        for (k, x) in odd.iter().copied().enumerate() {
            // Put the value in one field group at a time, then everywhere at once.
            for g in 0..12 {
                let mut o = outs[k % outs.len()];
                o.step = (k * 12 + g) as u64;
                let w = g % 2;
                match g {
                    0 => o.t_s = x,
                    1 => o.phase = x,
                    2 => o.state.position_m.y = x,
                    3 => o.state.velocity_m_s.z = x,
                    4 => o.state.angular_velocity_body_rad_s.x = x,
                    5 => o.total.force_n.z = x,
                    6 => o.controls.freq_hz = x,
                    7 => o.wings[w].angles.eta_ddot = x,
                    8 => o.wings[w].phase.t_star = x,
                    9 => o.wings[w].terms[2].c_d = x,
                    10 => o.wings[w].total.force_n.x = x,
                    _ => {
                        o.t_s = x;
                        o.phase = x;
                        o.state.position_m.x = x;
                        o.controls.mean_stroke_rad = x;
                        o.wings[0].angles.phi = x;
                        o.wings[1].terms[0].moment_hinge_nm.y = x;
                        o.wings[0].phase.half_stroke = i64::MIN;
                    }
                }
                all.push(o);
            }
        }
        check(&v, &all);
    }
}
