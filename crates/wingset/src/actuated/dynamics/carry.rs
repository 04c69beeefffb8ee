//! What a step of a wing on inelastic hinge stops hands the next: the loads it took at its
//! end, which the next step takes as its start's (a predictor-corrector in PEC mode, the
//! corrected state's loads never evaluated), and the end's frame and report.
//!
//! # Why the end's loads serve as the next start's
//! A step takes its loads at its start and at its end, on the state its path reaches with the
//! start's loads held (`actuated::contact`; under the carry that path is the midpoint rule's,
//! `DynamicWing::segment_end`), and linear between them. The corrected end (the path with
//! the interpolated loads) differs from that predicted one by O(h^2) in the rates and O(h^3)
//! in the angles, so the loads there differ by O(h^2): taken as the next step's start
//! loads, they move its accelerations by O(h^2), its state by O(h^3) a step, and the run
//! stays second order (a predictor-corrector pair in PEC mode keeps the corrector's order
//! where the predictor's error is of that order: Lambert 1991, *Numerical Methods for
//! Ordinary Differential Systems*, ch. 4; measured in `flapsim/tests/strike_loads.rs`). One
//! evaluation a step where there were two.
//!
//! The body moves meanwhile: each node's loads are taken with the body's motion at the
//! node's time (linear between the step's start and its end, the end's extrapolated from the
//! start and the midpoint the wing set predicts: `DynamicWing::step_moving`), so the end's
//! loads are the next start's in the body's motion too. (Taken with the midpoint's motion,
//! as a step without the carry takes them, every node's loads would see the body half a step
//! late: a first-order lag, measured on the hummingbird's 30 open-loop wingbeats, errors
//! 5.8e-4, 3.5e-4 and 1.9e-4 at 400, 800 and 1600 steps per wingbeat.)
//!
//! # The end's report
//! A step whose only nodes are its start and its end (no strike, no release, no stroke
//! reversal split) reports the trapezoidal mean of the two nodes' reports, each at its own
//! accelerations: the end's is then the next start's, and is carried too. (A step with a
//! strike shifts its nodes' accelerations so that their mean is the step's change of rate,
//! `dynamics::step`; in a smooth step the trapezoid's own accelerations differ from it by
//! O(h^2), and their cycle mean vanishes with the trapezoidal rule's error on a periodic
//! motion.)
//!
//! # What else the carried scheme does
//! Under [`StageLoads::Carried`] a step on inelastic stops is also split at a stroke
//! reversal inside it, each part advanced with its own half stroke's loads, as a step
//! without stops is (`DynamicWing::reversal_within`: the wake-capture term restarts there),
//! and the stroke reference's profile takes the rate on both sides of each jump and reversal
//! within a step (`DynamicWing::track_period`). Both were O(h) errors once per half stroke:
//! the hummingbird's tethered mean force over two wingbeats converged at first order
//! before (errors 1.3e-5 and 5.8e-6 N at 400 and 800 steps per wingbeat), at second order
//! with them (1.2e-6 and 3.2e-7 N).
//!
//! # When the carry is not taken
//! The next step takes the carry only where it is the step's own start: the same state and
//! half stroke (a reversal the step tracked starts a new half stroke), a time and a stroke
//! phase within round-off (the carry's validity must not hang on the last bit of a sum:
//! decided on exact times, the hummingbird's one-wingbeat map jumped where a reversal split
//! summed the step's end otherwise), and the wing's inflow field unchanged. A new drive, a
//! new state, a new stroke reference and a restart of the body's motion
//! (`WingSet::restart_motion`) drop it.

use nalgebra::{Vector2, Vector3};
use wingforce::{BodyMotion, Wing, WingFrame};

use super::equations::Held;
use super::step::{Aero, StepStart};
use super::wing::WingStep;

/// How a wing on inelastic hinge stops takes its aerodynamic loads within a step. Logs name
/// it (`flightlog`'s `actuated_stage_loads`), so a log re-runs as it was written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StageLoads {
    /// Afresh at every Runge-Kutta stage (logs written before 2026-12-07).
    EveryStage,
    /// At each segment's start and the sub-step's end, linear between them
    /// (2026-12-07).
    Interpolated,
    /// As `Interpolated`, with the end's loads (and, after a smooth step, its report) taken
    /// as the next step's start's and each node's loads at the body's motion at its time
    /// (module documentation).
    #[default]
    Carried,
}

/// The end of a step as the next step may take it (module documentation).
#[derive(Debug, Clone)]
pub(super) struct Carry {
    /// The end node: state, time and stroke phase.
    pub(super) at: StepStart,
    /// The loads taken there (on the predicted end's state).
    pub(super) held: Held,
    pub(super) aero: Option<Aero>,
    /// The wing's frame at the end's state with no accelerations (the added mass's impulse,
    /// `Wing::added_mass_over_step`).
    pub(super) frame: Option<WingFrame>,
    /// The end node's report at its own accelerations (a smooth step's).
    pub(super) report: Option<WingStep>,
    /// The wing's inflow field when the loads were taken.
    pub(super) inflow: (Vector3<f64>, Vector2<f64>),
}

impl Carry {
    /// Whether this is the start `at` of the next step of `wing` (module documentation).
    pub(super) fn is_start(&self, at: &StepStart, dt_s: f64, wing: &Wing) -> bool {
        let (a, b) = (&self.at, at);
        // The end node's time is the sub-step's end as its last segment summed it (after a
        // reversal split, t_rev + (h - tau)): within round-off of the step's.
        (a.t_s - b.t_s).abs() <= 1e-9 * dt_s
            && a.state == b.state
            && a.phase.half_stroke == b.phase.half_stroke
            && a.phase.downstroke == b.phase.downstroke
            && (a.phase.t_star - b.phase.t_star).abs() <= 1e-9
            && self.inflow == wing.inflow_field()
    }
}

/// The body's motion at a time `s` of the way through a step from `start` to `end` (linear).
pub(super) fn motion_between(start: &BodyMotion, end: &BodyMotion, s: f64) -> BodyMotion {
    BodyMotion {
        velocity_m_s: start.velocity_m_s + s * (end.velocity_m_s - start.velocity_m_s),
        angular_velocity_rad_s: start.angular_velocity_rad_s
            + s * (end.angular_velocity_rad_s - start.angular_velocity_rad_s),
    }
}
