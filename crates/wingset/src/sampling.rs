//! Where in a step the wing set takes the loads it hands the host (issue 37).
//!
//! Every host integrates the body with a first-order scheme: rapier and MuJoCo use
//! semi-implicit Euler (v_{k+1} = v_k + dt a_k, then x_{k+1} = x_k + dt v_{k+1}), with the
//! load a_k held over [t_k, t_k + dt]. The velocity it produces is second-order accurate
//! when a_k is the step's mean load to O(dt^2), and first-order when it is the load at the
//! step's start (its error is dt/2 a' per step, summed over the run).
//!
//! - [`LoadSampling::StepStart`] (the only one before issue 37; logs written before it
//!   replay with it bit for bit, and the actuated built-in vehicles keep it, see their model
//!   files): the wings' kinematics at the wingbeat phase of t_k and the body's state at t_k.
//!   Measured on the fly (issue 37's table): the hover excursion's error falls as 1/N
//!   (3.6% at 100 steps per wingbeat, 0.8% at 400).
//! - [`LoadSampling::StepMean`] (the default for prescribed wings; `[sim] load_sampling`):
//!   as `Midpoint` below, with wingforce's `StepRule::StepMean`: the kinematic terms' means
//!   on pieces of at most 0.02 of the wingbeat, and the translational term's still-air
//!   quadrature error at the midpoint added to its one sample, so that odd step counts no
//!   longer alias (wingforce's `wing::step_mean` module says why and what it measured).
//!   While a controller holds the kinematics away from those the set was built with, a step
//!   takes its loads from samples plus the build's quadrature refinement, tabled once
//!   (module `set::held_correction`: one wing evaluation where the step mean takes 14, an
//!   error O(dt^2 dk), still second order).
//! - [`LoadSampling::Midpoint`] (the default from issue 37's first stop until the step mean;
//!   logs written with it replay with it bit for bit): loads that represent the step. Prescribed wings: the rotational, added-mass and
//!   wake-capture terms and the wings' inertial reaction are their means over the step
//!   (wingforce's `Wing::kinematic_loads_over_step`: the added mass's force and moment and
//!   the inertial reaction exactly from the wing's motion at the step's ends, the rest by
//!   Gauss-Legendre quadrature split at stroke reversals), tabled once per step of the
//!   wingbeat; the translational term, the only one the body's motion enters, at the step's
//!   midpoint, with the body's midpoint state predicted from the last two states the host
//!   passed: v(t_k + dt/2) = v_k + (v_k - v_{k-1})/2, the body rates likewise (with the
//!   body's inertia known, the rate damping taken implicitly for stability: `rate_damping`),
//!   and the attitude the set integrates itself from the rates by the trapezoidal rule (the
//!   loads are handed back in the host's frame, so a host's first-order attitude does not
//!   turn them). Actuated wings take their aerodynamic loads afresh at every Runge-Kutta
//!   stage (on inelastic hinge stops, at each segment's start and the sub-step's end and linear
//!   between them)
//!   and report the step's trapezoidal mean over their integrator's nodes (under
//!   `StepMean`, a step without hinge stops is split at a stroke reversal inside it: see
//!   `actuated::dynamics`). The first
//!   step, and the first after a host restarts the body ([`crate::WingSet::restart_motion`]),
//!   has no previous state and takes the body's state at t_k (one step's O(dt^2) error).
//!
//! Why a mean over the step and not a sample at its midpoint: the kinematic terms are pulses
//! inside the pitch flip, and one sample per step aliases them (the fly at 25 steps per
//! wingbeat: a cycle-mean added-mass force of 2% of the lift). Why the translational term at
//! the midpoint and not by quadrature: it needs the strip loop, the step's cost, at each node.
//! Why the body's midpoint state is extrapolated rather than iterated: a predictor-corrector
//! would need the host to step twice.
//!
//! Measured (docs/speed.md rows 25-26, `flapsim/tests/second_order.rs`,
//! `tests/python/test_second_order.py`): the fly's open-loop error falls 4x per halved step in
//! flapsim's host and in a numpy semi-implicit Euler host, at 1.10x the step's cost; at equal
//! steps its attitude error is 1/1000 of the step-start sampling's. What stays first order: a
//! host's own position and attitude (x_{k+1} = x_k + dt v_{k+1} reads the velocity at the
//! step's end: a bias of dt/2 (v(t) - v(0)) that does not grow; flapsim's `Simulation` moves
//! rapier's pose to the trapezoidal rule, other hosts keep it), a host's update of the body's
//! rates in a turn about more than one axis where it applies the torque through the inertia
//! and the gyroscopic term at the step's start (rapier's: measured first order on a rolling
//! and yawing fly; flapsim's `Simulation` and `RapierWings` hand it the midpoint rule's torque,
//! `flapsim::host::midpoint_torque_world`; a host that takes the gyroscopic term at the step's
//! start in the body frame, MuJoCo's plugin among them, adds
//! `WingSet::gyroscopic_correction_nm`), and a
//! wind field a host evaluates at the body's position at t_k. Under `Midpoint`, odd step counts put a
//! reversal on a step's midpoint, where the translational term's one sample aliases (the fly
//! at 25: a pitch error of 3.9 deg after 0.3 s open loop, against 0.08 at 26); under
//! `StepMean` the fly at 25 ends 0.07 deg off.

#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "snake_case")]
pub enum LoadSampling {
    /// The loads at the step's start (first order; the only one before issue 37).
    StepStart,
    /// The loads at the step's midpoint, the body's state there predicted (second order;
    /// the default from issue 37's first stop until the step mean; logs written with it
    /// replay with it bit for bit).
    Midpoint,
    /// As `Midpoint`, with the kinematic terms' means on pieces of at most
    /// [`wingforce::MAX_PIECE_PHASE`] of the wingbeat and the translational term's still-air
    /// quadrature error at the midpoint added to its one sample (second order; the default).
    #[default]
    StepMean,
}

impl LoadSampling {
    /// Both, in the order the documentation lists them.
    pub const ALL: [LoadSampling; 3] = [
        LoadSampling::StepStart,
        LoadSampling::Midpoint,
        LoadSampling::StepMean,
    ];

    /// The name in model files, logs and reports.
    pub fn name(self) -> &'static str {
        match self {
            LoadSampling::StepStart => "step_start",
            LoadSampling::Midpoint => "midpoint",
            LoadSampling::StepMean => "step_mean",
        }
    }

    /// The sampling named `name` ([`LoadSampling::name`]), if any.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.name() == name)
    }

    /// The allowed names, for error messages.
    pub fn allowed() -> &'static str {
        "\"step_mean\" (second order, the default), \"midpoint\" (second order, without the step mean's refinements) or \"step_start\" (first order)"
    }

    /// The fraction of the step at which the kinematics are sampled.
    pub(crate) fn step_fraction(self) -> f64 {
        if self.is_second_order() { 0.5 } else { 0.0 }
    }

    /// Whether the loads represent the step (the body's state predicted at its midpoint):
    /// [`LoadSampling::Midpoint`] and [`LoadSampling::StepMean`].
    pub fn is_second_order(self) -> bool {
        self != LoadSampling::StepStart
    }

    /// How a prescribed wing's kinematic loads represent the step (wingforce's
    /// [`wingforce::StepRule`]); `None` for the step-start sampling.
    pub fn step_rule(self) -> Option<wingforce::StepRule> {
        match self {
            LoadSampling::StepStart => None,
            LoadSampling::Midpoint => Some(wingforce::StepRule::Midpoint),
            LoadSampling::StepMean => Some(wingforce::StepRule::StepMean),
        }
    }
}
