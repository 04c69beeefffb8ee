//! What a step of a [`DynamicWing`] asks for more than once, kept so that it is computed
//! once: the equations' solution at a state (and, kept in the wing itself, the drive's
//! voltage at a sub-step's start, middle and end: `DynamicWing::voltage_v`).
//!
//! A step on an inelastic stop solves the equations at its start for the holding moment, for
//! the first Runge-Kutta stage and for the first quadrature node, and at its end for the
//! holding moment, for the last node and for that node's report: the same arguments, bit for
//! bit, five to seven times (callgrind on the hummingbird: 11.3 solutions per wing and step,
//! about 0.42 k instructions each). The Runge-Kutta stages between them are solved at
//! states no other call asks for and do not go through the memo
//! ([`DynamicWing::stage_accelerations`]), so its entries hold the steps' ends of a pair's
//! two wings.
//!
//! The memo compares its arguments bit for bit and holds the results the computation gave,
//! so a run is the same with or without it. They are kept per thread (a wing set moves
//! between threads and is read from several at once: a cell in the wing would make it
//! neither) and keyed by the wing's [`WingKey`], which stands for its model and its drive,
//! the inputs besides the arguments (the model cannot change after a wing is built, and a
//! new drive takes a new key, `DynamicWing::set_drive`).

use std::cell::RefCell;
use std::sync::atomic::{AtomicU64, Ordering};

/// The free accelerations, the stroke acceleration with the pitch held and the holding
/// moment ([`DynamicWing::solve`]).
pub(in crate::actuated) type Solved = ([f64; 2], f64, f64);

/// A wing's model and drive, by a number drawn when the wing was built or its drive set
/// (copies keep it).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(in crate::actuated) struct WingKey(u64);

impl WingKey {
    /// A number no other wing or drive in this process has had.
    pub(in crate::actuated) fn fresh() -> Self {
        static NEXT: AtomicU64 = AtomicU64::new(0);
        Self(NEXT.fetch_add(1, Ordering::Relaxed))
    }
}

/// The arguments of a solution, as bits: the time, the state, the held loads, the wing's
/// key and the `free` flag. The `locked` flag does not enter a solution; nor does `free`
/// where the hinge's stops are inelastic or absent (an inelastic stop is a constraint the
/// integrator keeps: its moment is zero, as no stop's).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(in crate::actuated) struct SolveKey([u64; 13]);

impl SolveKey {
    /// The key of a solution at time `t` and state `y` under held generalized forces `q`
    /// and added inertia `added` (`free`: integrated as if without stops, where that
    /// matters).
    pub(in crate::actuated) fn new(
        wing: WingKey,
        t: f64,
        y: &[f64; 4],
        (q, added): ([f64; 2], [[f64; 2]; 2]),
        free: bool,
    ) -> Self {
        let b = f64::to_bits;
        Self([
            b(t),
            b(y[0]),
            b(y[1]),
            b(y[2]),
            b(y[3]),
            b(q[0]),
            b(q[1]),
            b(added[0][0]),
            b(added[0][1]),
            b(added[1][0]),
            b(added[1][1]),
            wing.0,
            u64::from(free),
        ])
    }

    /// No arguments' key (no wing is numbered u64::MAX).
    const NONE: Self = Self([u64::MAX; 13]);

    /// Word by word, the state first (the time is often the same).
    #[inline(always)]
    fn matches(&self, other: &Self) -> bool {
        let (a, b) = (&self.0, &other.0);
        a[1] == b[1] && a[2] == b[2] && a[3] == b[3] && a[4] == b[4] && a == b
    }
}

/// How many solutions a thread keeps: a step's two ends for each of a pair's two wings (the
/// right wing's step between the left wing's end and its next start).
const SOLVED: usize = 4;

/// The entries of one thread and the slot the next new entry replaces.
struct Entries {
    solved_keys: [SolveKey; SOLVED],
    solved: [Solved; SOLVED],
    next_solved: usize,
}

thread_local! {
    static ENTRIES: RefCell<Entries> = const {
        RefCell::new(Entries {
            solved_keys: [SolveKey::NONE; SOLVED],
            solved: [([0.0; 2], 0.0, 0.0); SOLVED],
            next_solved: 0,
        })
    };
}

/// The solution for `key`, computed by `solve` unless held.
pub(in crate::actuated) fn solved(key: SolveKey, solve: impl FnOnce() -> Solved) -> Solved {
    let held = ENTRIES.with_borrow(|e| {
        (0..SOLVED)
            .find(|&i| e.solved_keys[i].matches(&key))
            .map(|i| e.solved[i])
    });
    if let Some(s) = held {
        return s;
    }
    let s = solve();
    ENTRIES.with_borrow_mut(|e| {
        let i = e.next_solved;
        e.solved_keys[i] = key;
        e.solved[i] = s;
        e.next_solved = (i + 1) % SOLVED;
    });
    s
}

thread_local! {
    /// The last pitch angle's bits and its sine and cosine ([`sin_cos_pitch`]).
    static PITCH_TRIG: std::cell::Cell<(u64, f64, f64)> =
        const { std::cell::Cell::new((u64::MAX, f64::NAN, f64::NAN)) };
}

/// sin and cos of a pitch angle, rad, the last one's kept: a wing resting on its inelastic
/// stop (half the hummingbird's steps) solves its equations at one pitch angle over and
/// over (one sine and cosine, about 120 instructions, each time). Bit for bit `sin_cos`.
pub(in crate::actuated) fn sin_cos_pitch(theta_rad: f64) -> (f64, f64) {
    let key = theta_rad.to_bits();
    let (k, s, c) = PITCH_TRIG.get();
    if k == key {
        return (s, c);
    }
    let (s, c) = theta_rad.sin_cos();
    PITCH_TRIG.set((key, s, c));
    (s, c)
}

/// Frames whose angles' sines and cosines [`frame_trig`] keeps (four a wing: a step of
/// each of a pair's wings lies between a wing's report at a step's end and its loads at the
/// next step's start).
const FRAMES: usize = 8;

/// A frame's (phi's bits, theta's bits, [sin phi, cos phi, sin theta, cos theta]).
type FrameTrig = (u64, u64, [f64; 4]);

thread_local! {
    /// The last [`FRAMES`] frames' angles and their sines and cosines, and the slot the next
    /// one takes ([`frame_trig`]).
    static FRAME_TRIG: RefCell<([FrameTrig; FRAMES], usize)> =
        const { RefCell::new(([(u64::MAX, u64::MAX, [f64::NAN; 4]); FRAMES], 0)) };
}

/// [sin phi, cos phi, sin theta, cos theta] of a wing frame's stroke and pitch angles, rad,
/// the last [`FRAMES`] frames' kept: a step takes its start's frame for its loads and for
/// its report, the last step's report took it at its end, and a wing resting on its
/// inelastic stop keeps its pitch (two sines and cosines, about 230 instructions, each
/// time). Bit for bit `f64::sin_cos`.
pub(in crate::actuated) fn frame_trig(phi_rad: f64, theta_rad: f64) -> [f64; 4] {
    let (p, t) = (phi_rad.to_bits(), theta_rad.to_bits());
    FRAME_TRIG.with_borrow_mut(|(kept, next)| {
        if let Some(e) = kept.iter().find(|e| e.0 == p && e.1 == t) {
            return e.2;
        }
        let ((sp, cp), (st, ct)) = (phi_rad.sin_cos(), theta_rad.sin_cos());
        let trig = [sp, cp, st, ct];
        kept[*next] = (p, t, trig);
        *next = (*next + 1) % FRAMES;
        trig
    })
}
