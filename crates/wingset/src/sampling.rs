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
//! - [`LoadSampling::Midpoint`] (the default; `[sim] load_sampling`): the loads at the step's midpoint
//!   t_k + dt/2, which represent the step to O(dt^2) (the midpoint rule): prescribed wings
//!   take their kinematics at the midpoint phase (from the same per-step table, so a step
//!   costs what it did), and the body's state at the midpoint is predicted from the last two
//!   states the host passed, v(t_k + dt/2) = v_k + (v_k - v_{k-1})/2 for the velocity and
//!   the body rates (the attitude turned by the body rates over dt/2). Actuated wings take
//!   their aerodynamic loads afresh at every Runge-Kutta stage (not held over the step) and
//!   report the trapezoidal mean over the step of the loads their integrator passed, as
//!   the hinge stops always did (`actuated::dynamics`). The first step, and the first
//!   after a host restarts the body ([`crate::WingSet::restart_motion`]), has no previous
//!   state and takes the body's state at t_k (one step's O(dt^2) error).
//!
//! Why the midpoint rather than a quadrature over the step: the prescribed wings' kinematic
//! loads come from a table computed once per step of the wingbeat; sampling it half a step
//! later costs nothing, where a two-node quadrature (the trapezoid) doubles the strip loop
//! per step, and the midpoint rule's error constant is half the trapezoid's. The body's
//! midpoint state is extrapolated rather than iterated (a predictor-corrector would need
//! the host to step twice).
//!
//! What stays first order: the host's position and attitude update, x_{k+1} = x_k + dt
//! v_{k+1}, reads the velocity at the step's end, so the positions carry a bias of
//! dt/2 (v(t) - v(0)) that does not grow with time (the rectangle rule's error on a
//! velocity that is itself second-order accurate); and the wind a host evaluates at the
//! body's position at t_k (a wind field's gradient along the flight, dt/2 v.grad(w)).

/// Where in a step the loads are taken: see the module documentation.
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "snake_case")]
pub enum LoadSampling {
    /// The loads at the step's start (first order; the only one before issue 37).
    StepStart,
    /// The loads at the step's midpoint, the body's state there predicted (second order;
    /// the default).
    #[default]
    Midpoint,
}

impl LoadSampling {
    /// Both, in the order the documentation lists them.
    pub const ALL: [LoadSampling; 2] = [LoadSampling::StepStart, LoadSampling::Midpoint];

    /// The name in model files, logs and reports.
    pub fn name(self) -> &'static str {
        match self {
            LoadSampling::StepStart => "step_start",
            LoadSampling::Midpoint => "midpoint",
        }
    }

    /// The sampling named `name` ([`LoadSampling::name`]), if any.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.name() == name)
    }

    /// The allowed names, for error messages.
    pub fn allowed() -> &'static str {
        "\"midpoint\" (second order, the default) or \"step_start\" (first order)"
    }

    /// The fraction of the step at which the kinematics are sampled.
    pub(crate) fn step_fraction(self) -> f64 {
        match self {
            LoadSampling::StepStart => 0.0,
            LoadSampling::Midpoint => 0.5,
        }
    }
}
