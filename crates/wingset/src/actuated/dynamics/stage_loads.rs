//! How a wing on inelastic hinge stops takes its aerodynamic loads within a step
//! ([`StageLoads`]) and shares a strike's impulse among the body's steps ([`StrikeShare`],
//! stated in `strike`), and the body's motion at a node's time.
//!
//! # The split scheme (since 2026-12-07, the default)
//! A step takes its loads at each segment's start and at the sub-step's end, on the state the
//! segment's path reaches with its start's loads held (the midpoint rule's path,
//! `DynamicWing::segment_end`), and linear in time between them (`actuated::contact`).
//! Besides, under [`StageLoads::Split`]:
//! - a step is split at a stroke reversal inside it, each part advanced with its own half
//!   stroke's loads, as a step without stops is (`DynamicWing::reversal_within`: the
//!   wake-capture term restarts there, the loads jump);
//! - the stroke reference's profile takes the rate on both sides of each jump (a strike moves
//!   the stroke with the pitch) and reversal within a step (`DynamicWing::track_period`);
//! - each node's loads are taken at the body's motion of the node's own time, linear between
//!   the step's start and its end, the end's extrapolated from the start and the midpoint the
//!   wing set predicts (`DynamicWing::step_moving`).
//!
//! The first two were O(h) errors once per half stroke: the hummingbird's tethered mean force
//! over two wingbeats converged at first order before (errors 1.3e-5 and 5.8e-6 N at 400 and
//! 800 steps per wingbeat, against 6400), at second order with them (1.2e-6 and 3.2e-7 N;
//! `flapsim/tests/strike_loads.rs`).
//!
//! # Tried and not kept: carrying the end's loads to the next step
//! The end's loads, taken on the predicted state, can serve as the next step's start's (a
//! predictor-corrector in PEC mode, where the split scheme is PECE: Lambert 1991, *Numerical
//! Methods for Ordinary Differential Systems*, ch. 4): one evaluation a step where there are
//! two, and still second order. Measured on the hummingbird: the step 13 % cheaper (2.08x a
//! prescribed step, against about 2.4x), but 30 open-loop wingbeats 3.0x further from the
//! fine run at every count (0.046 deg against 0.015 at 400 steps per wingbeat, 0.011
//! against 0.0039 at 800): at equal error the carried scheme needs about 1.7x the steps, so
//! it costs more per simulated second, and the split scheme evaluates afresh at each step's
//! start. (Carried, a node's loads must also see the body at the node's time: taken at the
//! midpoint's motion, as the interpolated scheme takes them, every node would see it half a
//! step late, a first-order lag; the split scheme keeps that.)

use wingforce::BodyMotion;

/// How a wing on inelastic hinge stops takes its aerodynamic loads within a step. Logs name
/// it (`flightlog`'s `actuated_stage_loads`), so a log re-runs as it was written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StageLoads {
    /// Afresh at every Runge-Kutta stage (logs written before 2026-12-07).
    EveryStage,
    /// At each segment's start and the sub-step's end, linear between them (the morning of
    /// 2026-12-07).
    Interpolated,
    /// As `Interpolated`, with the step split at stroke reversals, the stroke reference's
    /// profile sampled on both sides of each jump, and each node's loads at the body's motion
    /// of its time (module documentation).
    #[default]
    Split,
}

/// How a strike's impulse is shared between the body step it falls in and the next (`strike`'s module
/// documentation). Logs name it (`flightlog`'s `strike_impulse`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StrikeShare {
    /// Whole in its step (logs written before 2026-12-06).
    WholeInStep,
    /// 1 - tau/dt in its step and tau/dt in the next: exact for a host that moves the body
    /// by dt v_{k+1} (semi-implicit Euler: MuJoCo's, rapier's own). The default: a wing
    /// set does not know its host.
    #[default]
    SemiImplicitPose,
    /// 3/2 (1 - tau/dt) in its step, 2 tau/dt - 1/2 in the next and -tau/(2 dt) in the one
    /// after: exact for a host that moves the body by dt (v_k + v_{k+1})/2 (flapsim's hosts
    /// under a second-order sampling), and continuous in the strike's time.
    TrapezoidalPose,
}

/// The body's motion at a time `s` of the way through a step from `start` to `end` (linear).
pub(super) fn motion_between(start: &BodyMotion, end: &BodyMotion, s: f64) -> BodyMotion {
    BodyMotion {
        velocity_m_s: start.velocity_m_s + s * (end.velocity_m_s - start.velocity_m_s),
        angular_velocity_rad_s: start.angular_velocity_rad_s
            + s * (end.angular_velocity_rad_s - start.angular_velocity_rad_s),
    }
}
