//! The kinematic loads that represent a time step (issue 37): what a host that holds a load
//! over [t_k, t_k + dt] needs for a second-order trajectory.
//!
//! Of a prescribed wing's four terms only the translational one depends on the body's
//! motion; the rotational, added-mass and wake-capture terms are functions of the wingbeat
//! phase alone ([`crate::KinematicLoads`]). Sampled once per step they alias: they are pulses
//! inside the pitch flip (the fly's flip lasts 0.12 of the wingbeat, three steps at 25 steps
//! per wingbeat), and one sample per step turns a pulse's integral into an error that
//! depends on where the flip falls on the step grid and repeats every wingbeat. Measured on
//! the fly held tethered at 25 steps per wingbeat: a cycle-mean added-mass force of
//! +-1.3e-7 N and rotational force of +-3.2e-8 N (2% and 0.5% of the lift, their sign set by
//! the sampling point), against 1e-22 N at 50 steps and above.
//!
//! So the step's kinematic terms are their means over the step:
//! - the impulse-form added mass exactly: its force is -dP/dt of the fluid's impulse, so its
//!   mean is -(P(t_k + dt) - P(t_k))/dt ([`Wing::added_mass_over_step`]), and the impulse
//!   handed to the body over a wingbeat is zero whatever the step; its moment is dW/dt of
//!   an angular impulse W plus a remainder R without accelerations
//!   (`added_mass::impulse_moment_parts`), whose mean is (W_end - W_start)/dt plus R's
//!   quadrature (measured: the fly's tethered cycle-mean pitching moment at 25 steps per
//!   wingbeat, an odd count that puts a reversal on a step's midpoint, was 3.1e-11 N m with
//!   the whole moment by quadrature, 80% of it the added mass's);
//! - the other terms (and the added mass's moment, and the paper form) by three-point
//!   Gauss-Legendre quadrature (sixth order where the loads are smooth), on each side of a
//!   stroke reversal that falls inside the step: the wake-capture term restarts with t* at
//!   a reversal and jumps there, and a rule with a node at or across the jump would carry an
//!   O(dt) error that repeats every wingbeat (measured with Simpson's rule, whose end nodes
//!   sit on the reversals at an even step count: the fly's cycle-mean wake-capture force
//!   converged only as 1/N).
//!
//! Two rules ([`StepRule`]). `Midpoint` (issue 37's first) takes one three-point rule on each
//! side of a reversal and leaves the translational term, which the body's motion enters, to
//! one sample at the step's midpoint. That sample and that rule miss the narrow features
//! near a reversal: each strip's velocity passes through zero there at its own time and the
//! angle of attack folds through 90 deg, so the loads have kinks 0.004-0.01 of the wingbeat
//! apart (measured on the fly held still: the translational term's pitching moment turns
//! from 1.29e-10 to 2.07e-10 N m within 0.01 of the wingbeat before the reversal). At an even
//! step count the two half strokes see the same grid and the errors cancel in the cycle
//! mean; at an odd count they do not: the fly's tethered cycle-mean pitching moment at 25
//! steps per wingbeat was 4.8e-12 N m (translational 3.5e-12, rotational 2.4e-12, added mass
//! -1.3e-12), and 0.3 s of open-loop flight ended 3.9 deg off in pitch.
//!
//! `StepMean` (the default) cuts each side of a reversal into pieces of at most
//! [`MAX_PIECE_PHASE`] of the wingbeat and takes two-point Gauss-Legendre on each, also for
//! the translational term in still air; the difference between that mean and the still-air
//! value at the midpoint rides in the translational entry of the mean loads, and
//! [`Wing::evaluate_with`] adds it to the midpoint sample it takes with the body's motion.
//! The correction is exact for a body at rest in still air and leaves the part of the error
//! that the body's motion makes, second order and small where the body moves slowly against
//! the wing. Measured on the fly at 25 steps per wingbeat, 0.3 s open loop (reference 43.59
//! deg at 3200 steps): 47.50 deg with `Midpoint`; with three-point rules 44.60 deg on one
//! piece per side of a reversal, 43.52 at pieces of 0.02, 43.45 at 0.01 and 43.43 at 0.005;
//! with two-point rules on pieces of 0.02, 43.32 (at 20, 24, 27, 30 and 40 steps the two
//! rules agree within 0.11 deg, the body's part of the error). Each node costs a wing
//! evaluation, paid once per step of a wingbeat while the kinematics stay; a controller that
//! changes them every wingbeat pays them every step (the fly's 10 s hover at 25 steps per
//! wingbeat: 0.44 s with three-point rules, 0.37 s with two-point ones, against 0.92 s at
//! 100 steps per wingbeat with the step-start sampling).
//!
//! The state reported with them (angles, stroke phase, frame, for the translational term and
//! the logs) is the midpoint's, and the wing's frames at the step's start and end come with
//! them (what a host needs for other exact step means, e.g. the wing's inertial reaction).
//! A host that tables them per step of the wingbeat (the wing set does) pays their cost once
//! per wingbeat.

use nalgebra::Vector3;

use super::Wing;
use crate::forces::{KinematicLoads, StepKinematicLoads};
use crate::frame::WingFrame;
use crate::mount::BodyMotion;
use crate::terms::{Term, TermForce};

/// Three-point Gauss-Legendre nodes on [0, 1] and their weights.
const GAUSS3: [(f64, f64); 3] = [
    (0.5 - 0.387_298_334_620_741_7, 5.0 / 18.0),
    (0.5, 8.0 / 18.0),
    (0.5 + 0.387_298_334_620_741_7, 5.0 / 18.0),
];

/// How [`Wing::loads_over_step`] represents a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepRule {
    /// The kinematic terms by three-point Gauss-Legendre on each side of a reversal; the
    /// translational term left to the caller's one sample at the midpoint.
    Midpoint,
    /// Two-point Gauss-Legendre on pieces of at most [`MAX_PIECE_PHASE`] on each side of a
    /// reversal, and the translational term's
    /// still-air quadrature error at the midpoint carried as a correction in the
    /// translational entry, which [`Wing::evaluate_with`] adds to its midpoint sample.
    StepMean,
}

/// Longest piece of a step, wingbeat fraction, that [`StepRule::StepMean`] integrates by one
/// two-point rule.
pub const MAX_PIECE_PHASE: f64 = 0.02;

/// Two-point Gauss-Legendre nodes on [0, 1] and their weights.
const GAUSS2: [(f64, f64); 2] = [
    (0.5 - 0.288_675_134_594_812_9, 0.5),
    (0.5 + 0.288_675_134_594_812_9, 0.5),
];

impl Wing {
    /// The kinematic loads that represent a step of `dt_s` from wingbeat phase
    /// `phase_start` to `phase_end` (see the module documentation).
    pub fn kinematic_loads_over_step(
        &self,
        phase_start: f64,
        phase_end: f64,
        dt_s: f64,
    ) -> StepKinematicLoads {
        self.loads_over_step(phase_start, phase_end, dt_s, StepRule::Midpoint)
    }

    /// The loads that represent a step under `rule` ([`StepRule`]).
    pub fn loads_over_step(
        &self,
        phase_start: f64,
        phase_end: f64,
        dt_s: f64,
        rule: StepRule,
    ) -> StepKinematicLoads {
        let (start, end, mut mean) = self.step_ends(phase_start, phase_end);
        let (cuts, n_cuts) = self.reversal_cuts(phase_start, phase_end);
        let span = phase_end - phase_start;
        let mut sums = [TermForce::default(); 4];
        // The added mass's moment: the remainder R's mean (stroke frame), the rest exactly.
        let mut remainder_s = Vector3::zeros();
        let max_piece = match rule {
            StepRule::Midpoint => f64::INFINITY,
            StepRule::StepMean => MAX_PIECE_PHASE,
        };
        let correct = rule == StepRule::StepMean;
        let nodes: &[(f64, f64)] = if correct { &GAUSS2 } else { &GAUSS3 };
        let mut translational = TermForce::default();
        for piece in cuts[..n_cuts].windows(2) {
            let (q0, q1) = (piece[0], piece[1]);
            let parts = ((q1 - q0) / max_piece).ceil().max(1.0) as usize;
            for part in 0..parts {
                // The piece's own ends exactly (one part: the rule before the step mean).
                let at = |k: usize| match k {
                    0 => q0,
                    k if k == parts => q1,
                    k => q0 + (q1 - q0) * k as f64 / parts as f64,
                };
                let (p0, p1) = (at(part), at(part + 1));
                for &(x, w) in nodes {
                    let node = self.kinematic_loads(p0 + x * (p1 - p0));
                    let weight = w * (p1 - p0) / span;
                    if correct {
                        let t = &self.evaluate_with(&node, &BodyMotion::default()).terms[0];
                        translational.force_n += weight * t.force_n;
                        translational.moment_hinge_nm += weight * t.moment_hinge_nm;
                        translational.c_l += weight * t.c_l;
                        translational.c_d += weight * t.c_d;
                    }
                    if let Some((_, r)) = self.added_mass_moment_parts(&node.frame) {
                        remainder_s += weight * r;
                    }
                    for term in [Term::Rotational, Term::AddedMass, Term::WakeCapture] {
                        let i = term as usize;
                        let (n, t) = (&node.terms[i], &mut sums[i]);
                        t.force_n += weight * n.force_n;
                        t.moment_hinge_nm += weight * n.moment_hinge_nm;
                        t.c_l += weight * n.c_l;
                        t.c_d += weight * n.c_d;
                    }
                }
            }
        }
        if correct {
            let at_mid = &self.evaluate_with(&mean, &BodyMotion::default()).terms[0];
            mean.terms[0] = TermForce {
                force_n: translational.force_n - at_mid.force_n,
                moment_hinge_nm: translational.moment_hinge_nm - at_mid.moment_hinge_nm,
                c_l: translational.c_l - at_mid.c_l,
                c_d: translational.c_d - at_mid.c_d,
            };
        }
        mean.terms[1..].copy_from_slice(&sums[1..]);
        self.exact_added_mass(&mut mean, &start, &end, dt_s, remainder_s);
        StepKinematicLoads { mean, start, end }
    }

    /// The loads of a step from samples alone: the added mass's force and the part of its
    /// moment that jumps with the accelerations exactly from the wing's motion at the
    /// step's ends (as in [`Wing::loads_over_step`]), every other kinematic term and the
    /// added mass's remainder at the midpoint of each side of a stroke reversal in the step
    /// (the step's midpoint when there is none), and no still-air correction in the
    /// translational entry. It costs one kinematic evaluation where the step mean costs one
    /// per quadrature node; what it misses, [`Wing::loads_over_step`] minus it, is the
    /// quadrature's refinement over the midpoint, O(dt^2) where the loads are smooth (the
    /// wing set carries it across a controller's small changes of the kinematics: its
    /// `held_correction` module).
    pub fn sampled_loads_over_step(
        &self,
        phase_start: f64,
        phase_end: f64,
        dt_s: f64,
    ) -> StepKinematicLoads {
        let (start, end, mut mean) = self.step_ends(phase_start, phase_end);
        let remainder = |f: &WingFrame| {
            self.added_mass_moment_parts(f)
                .map_or_else(Vector3::zeros, |(_, r)| r)
        };
        let mut remainder_s = remainder(&mean.frame);
        // A step across a reversal: each side at its own midpoint (the wake capture jumps
        // there, and one sample of a jump is an O(1) error in the step's mean).
        let (cuts, n_cuts) = self.reversal_cuts(phase_start, phase_end);
        if n_cuts > 2 {
            let span = phase_end - phase_start;
            let mut sums = [TermForce::default(); 4];
            remainder_s = Vector3::zeros();
            for piece in cuts[..n_cuts].windows(2) {
                let node = self.kinematic_loads(0.5 * (piece[0] + piece[1]));
                let weight = (piece[1] - piece[0]) / span;
                remainder_s += weight * remainder(&node.frame);
                for (t, n) in sums.iter_mut().zip(&node.terms).skip(1) {
                    t.force_n += weight * n.force_n;
                    t.moment_hinge_nm += weight * n.moment_hinge_nm;
                    t.c_l += weight * n.c_l;
                    t.c_d += weight * n.c_d;
                }
            }
            mean.terms[1..].copy_from_slice(&sums[1..]);
        }
        self.exact_added_mass(&mut mean, &start, &end, dt_s, remainder_s);
        StepKinematicLoads { mean, start, end }
    }

    /// The wing's frames at a step's start and end, and its kinematic loads at the step's
    /// midpoint (what every representation of the step starts from).
    fn step_ends(
        &self,
        phase_start: f64,
        phase_end: f64,
    ) -> (WingFrame, WingFrame, KinematicLoads) {
        let (k, side) = (&self.kinematics, self.mount.side);
        (
            WingFrame::new(&k.angles(phase_start), side),
            WingFrame::new(&k.angles(phase_end), side),
            self.kinematic_loads(0.5 * (phase_start + phase_end)),
        )
    }

    /// The ends of the pieces of the step from `phase_start` to `phase_end` between stroke
    /// reversals, and how many of them are used (at most two reversals in a step of at most
    /// 1/10 of the wingbeat).
    fn reversal_cuts(&self, phase_start: f64, phase_end: f64) -> ([f64; 4], usize) {
        let k = &self.kinematics;
        let mut cuts = [phase_start, phase_end, phase_end, phase_end];
        let mut n_cuts = 2;
        let mut a = phase_start;
        while n_cuts < 4 && k.stroke_phase(a).half_stroke != k.stroke_phase(phase_end).half_stroke {
            let h0 = k.stroke_phase(a).half_stroke;
            let (mut lo, mut hi) = (a, phase_end);
            for _ in 0..60 {
                let m = 0.5 * (lo + hi);
                if m <= lo || m >= hi {
                    break;
                }
                if k.stroke_phase(m).half_stroke == h0 {
                    lo = m;
                } else {
                    hi = m;
                }
            }
            cuts[n_cuts - 1] = hi;
            cuts[n_cuts] = phase_end;
            n_cuts += 1;
            a = hi;
        }
        (cuts, n_cuts)
    }

    /// Replaces the added-mass entry of a step's `mean` loads by its exact mean force and
    /// its moment's mean: (W_end - W_start)/dt exactly (the part that jumps with the
    /// accelerations) plus `remainder_s`, the remainder's mean (stroke frame).
    fn exact_added_mass(
        &self,
        mean: &mut KinematicLoads,
        start: &WingFrame,
        end: &WingFrame,
        dt_s: f64,
        remainder_s: Vector3<f64>,
    ) {
        let i = Term::AddedMass as usize;
        if let Some(mut exact) =
            self.added_mass_over_step(start, end, dt_s, &mean.terms[i], mean.phase.downstroke)
        {
            if let (Some((w0, _)), Some((w1, _))) = (
                self.added_mass_moment_parts(start),
                self.added_mass_moment_parts(end),
            ) {
                exact.moment_hinge_nm =
                    self.cache.body_from_stroke * ((w1 - w0) / dt_s + remainder_s);
            }
            mean.terms[i] = exact;
        }
    }
}
