//! The protobuf writer the sample encoder and the chunk builder share ([`Pb`]): fields
//! straight into a buffer sized for the whole message, nested lengths patched in place.

use foxglove::messages::Timestamp;

use crate::proto;

/// A protobuf writer into a buffer with room for the whole message (field tags below 16:
/// one-byte keys). The caller sizes the buffer by the message's bound ([`SAMPLE_BOUND`],
/// [`crate::encode::arrow_scene_bound`]); the writer keeps its position in a register, where appending to a
/// `Vec` would reload the vector's length and capacity around every byte written.
#[derive(Debug)]
pub(crate) struct Pb<'a> {
    buf: &'a mut [u8],
    n: usize,
}

const VARINT: u8 = 0;
const FIXED64: u8 = 1;
const LEN: u8 = 2;

/// Room enough for any of the sample's messages, strings aside: the largest, a
/// `flapwing.VehicleState` with its step memory, every field set and the longest varints,
/// takes about 440 bytes, a `flapwing.WingForces` 433 (their sub-messages are shorter than
/// 128 bytes, so their lengths take one byte, except the step memory's: two).
pub(crate) const SAMPLE_BOUND: usize = 512;

impl<'a> Pb<'a> {
    pub fn new(buf: &'a mut [u8]) -> Self {
        Self { buf, n: 0 }
    }

    /// Bytes written.
    pub fn len(&self) -> usize {
        self.n
    }

    #[inline(always)]
    pub(crate) fn put(&mut self, bytes: &[u8]) {
        self.buf[self.n..self.n + bytes.len()].copy_from_slice(bytes);
        self.n += bytes.len();
    }

    #[inline(always)]
    pub(crate) fn byte(&mut self, b: u8) {
        self.buf[self.n] = b;
        self.n += 1;
    }

    #[inline(always)]
    pub(crate) fn key(&mut self, tag: u8, wire: u8) {
        debug_assert!(tag < 16);
        self.byte((tag << 3) | wire);
    }

    #[inline(always)]
    pub(crate) fn varint(&mut self, mut v: u64) {
        while v >= 0x80 {
            self.byte((v as u8) | 0x80);
            v >>= 7;
        }
        self.byte(v as u8);
    }

    /// A `double` field (left out when it equals 0.0, as proto3 does; -0.0 too).
    #[inline(always)]
    pub fn double(&mut self, tag: u8, v: f64) {
        if v != 0.0 {
            debug_assert!(tag < 16);
            let mut b = [0u8; 9];
            b[0] = (tag << 3) | FIXED64;
            b[1..].copy_from_slice(&v.to_le_bytes());
            self.put(&b);
        }
    }

    /// A sub-message of `N` `double` fields numbered from 1, none of them zero: `B` (= 2 +
    /// 9 N) bytes written at once. Vectors and quaternions are rarely zero, so this is the
    /// path nearly all of them take.
    #[inline(always)]
    fn doubles<const N: usize, const B: usize>(&mut self, tag: u8, v: [f64; N]) {
        debug_assert!(tag < 16 && B == 2 + 9 * N && B < 0x80);
        let mut b = [0u8; B];
        b[0] = (tag << 3) | LEN;
        b[1] = (B - 2) as u8;
        for (i, x) in v.iter().enumerate() {
            b[2 + 9 * i] = ((i as u8 + 1) << 3) | FIXED64;
            b[3 + 9 * i..11 + 9 * i].copy_from_slice(&x.to_le_bytes());
        }
        self.put(&b);
    }

    /// A `uint32`, `uint64` or `int64` field (an int64 as its two's complement u64).
    #[inline(always)]
    pub fn uint(&mut self, tag: u8, v: u64) {
        if v != 0 {
            self.key(tag, VARINT);
            self.varint(v);
        }
    }

    #[inline(always)]
    pub fn boolean(&mut self, tag: u8, v: bool) {
        if v {
            self.key(tag, VARINT);
            self.byte(1);
        }
    }

    #[inline(always)]
    pub fn string(&mut self, tag: u8, s: &str) {
        if !s.is_empty() {
            self.key(tag, LEN);
            self.varint(s.len() as u64);
            self.put(s.as_bytes());
        }
    }

    /// A sub-message written by `fields`.
    #[inline(always)]
    pub fn message(&mut self, tag: u8, fields: impl FnOnce(&mut Self)) {
        self.key(tag, LEN);
        let at = self.n;
        self.n += 1;
        fields(self);
        let len = self.n - at - 1;
        if len < 0x80 {
            self.buf[at] = len as u8;
        } else {
            self.long_length(at, len);
        }
    }

    /// Moves the fields of a sub-message of `len` bytes at `at` up to make room for its
    /// length, which takes more than one byte.
    #[cold]
    #[inline(never)]
    pub(crate) fn long_length(&mut self, at: usize, len: usize) {
        let mut head = [0u8; 10];
        let (mut v, mut k) = (len as u64, 0);
        while v >= 0x80 {
            head[k] = (v as u8) | 0x80;
            v >>= 7;
            k += 1;
        }
        head[k] = v as u8;
        k += 1;
        self.buf.copy_within(at + 1..self.n, at + k);
        self.buf[at..at + k].copy_from_slice(&head[..k]);
        self.n += k - 1;
    }

    #[inline(always)]
    pub(crate) fn timestamp(&mut self, tag: u8, t: &Option<Timestamp>) {
        if let Some(t) = t {
            self.message(tag, |p| {
                p.uint(1, u64::from(t.sec()));
                p.uint(2, u64::from(t.nsec()));
            });
        }
    }

    #[inline(always)]
    pub(crate) fn xyz(&mut self, tag: u8, v: Option<[f64; 3]>) {
        match v {
            Some(v) if v.iter().all(|x| *x != 0.0) => self.doubles::<3, 29>(tag, v),
            Some([x, y, z]) => self.message(tag, |p| {
                p.double(1, x);
                p.double(2, y);
                p.double(3, z);
            }),
            None => {}
        }
    }

    #[inline(always)]
    pub(crate) fn xyzw(&mut self, tag: u8, q: Option<[f64; 4]>) {
        match q {
            Some(q) if q.iter().all(|x| *x != 0.0) => self.doubles::<4, 38>(tag, q),
            Some([x, y, z, w]) => self.message(tag, |p| {
                p.double(1, x);
                p.double(2, y);
                p.double(3, z);
                p.double(4, w);
            }),
            None => {}
        }
    }

    #[inline(always)]
    pub(crate) fn pose(&mut self, tag: u8, pose: &Option<foxglove::messages::Pose>) {
        if let Some(pose) = pose {
            self.message(tag, |p| {
                p.xyz(1, pose.position.map(|v| [v.x, v.y, v.z]));
                p.xyzw(2, pose.orientation.map(|q| [q.x, q.y, q.z, q.w]));
            });
        }
    }

    /// The common head of flapwing's messages: timestamp, step, t_s, phase.
    #[inline(always)]
    pub(crate) fn head(&mut self, ts: &Option<Timestamp>, step: u64, t_s: f64, phase: f64) {
        self.timestamp(1, ts);
        self.uint(2, step);
        self.double(3, t_s);
        self.double(4, phase);
    }

    #[inline(always)]
    pub(crate) fn angles(&mut self, tag: u8, a: &Option<proto::WingAngles>) {
        self.xyz(tag, a.map(|a| [a.phi, a.theta, a.eta]));
    }

    #[inline(always)]
    pub(crate) fn vec3(&mut self, tag: u8, v: &Option<proto::Vector3>) {
        self.xyz(tag, v.map(|v| [v.x, v.y, v.z]));
    }

    #[inline(always)]
    pub(crate) fn force_term(&mut self, tag: u8, t: &Option<proto::ForceTerm>) {
        if let Some(t) = t {
            self.message(tag, |p| {
                p.vec3(1, &t.force_n);
                p.vec3(2, &t.moment_nm);
                p.double(3, t.c_l);
                p.double(4, t.c_d);
            });
        }
    }
}
