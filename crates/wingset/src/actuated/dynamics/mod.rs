//! One wing as a two-degree-of-freedom system: stroke phi driven by an actuator (or
//! prescribed), pitch theta free about a compliant hinge, deviation prescribed at zero.
//!
//! # Equations of motion
//! The wing is a thin rigid plate with mass m, centre of mass at span r_c and chordwise x_c
//! (towards the leading edge) from the hinge, inertia J = int r^2 dm about the stroke axis
//! with the wing normal to the stroke plane, B = int x^2 dm about the pitch axis, and the
//! product C = int r x dm, lumped as m r_c x_c. Its kinetic energy about the hinge, with
//! omega = phi_dot k_phi + theta_dot k_theta ([`wingforce::WingFrame`]), is
//!
//!   T = 1/2 B theta_dot^2 + 1/2 (J + B cos^2 theta) phi_dot^2 - C sin(theta) phi_dot theta_dot
//!
//! and Lagrange's equations with the actuator reflected to the stroke axis (inertia J_a,
//! stiffness k_a + k_t, damping c_s, torque per volt g; see [`super::actuator`]) and the
//! hinge (stiffness k_h, damping c_h, rest angle theta_r) are
//!
//!   (J + J_a + B cos^2 theta) phi_ddot - C sin(theta) theta_ddot
//!       - 2 B sin(theta) cos(theta) phi_dot theta_dot - C cos(theta) theta_dot^2
//!       = g V(t) - (k_a + k_t)(phi - phi_0) - c_s phi_dot + Q_phi,aero
//!   B theta_ddot - C sin(theta) phi_ddot + B sin(theta) cos(theta) phi_dot^2
//!       = -k_h (theta - theta_r) - c_h theta_dot + Q_theta,aero
//!
//! where Q_aero are wingforce's four terms projected on the two axes
//! ([`wingforce::Wing::axis_moments`]), evaluated with the wing's actual angles and rates,
//! and the hinge's moment includes its stops' contact when it has them ([`super::stop`]).
//! A prescribed stroke keeps only the second equation, with phi(t) from the kinematics.
//!
//! Re-derived (issue 24). For a thin plate with points r = s e_span + x e_le about the
//! hinge, the inertia tensor is I = int (|r|^2 1 - r r^T) dm, that is
//! (J + B) 1 - J e_s e_s^T - B e_l e_l^T - C (e_s e_l^T + e_l e_s^T). With
//! [`wingforce::WingFrame`]'s axes k_phi = (0, 0, -s), k_theta = -s e_span and
//! e_le = cos(theta) t + sin(theta) z (s = +-1 by side): omega . e_span = -s theta_dot,
//! omega . e_le = -s sin(theta) phi_dot and |omega|^2 = phi_dot^2 + theta_dot^2, so
//! omega^T I omega / 2 is T above on both sides (s^2 = 1). The B cos^2 theta term is the
//! plate's inertia about the stroke axis growing from J (wing normal to the stroke plane)
//! to J + B (wing flat); the product term has the sign written, and C < 0 (centre of mass
//! behind the axis) makes the trailing edge lag the stroke's acceleration. Lagrange's
//! equations of T give the two equations term by term (the time derivatives of
//! p_phi = (J + B cos^2) phi_dot - C sin theta_dot and p_theta = B theta_dot - C sin
//! phi_dot, and dT/dtheta = -B sin cos phi_dot^2 - C cos phi_dot theta_dot): the
//! equations and the code were right, nothing changed. Checked in `tests/wing_inertia.rs`:
//! without drive, damping and aerodynamics the energy is kept to 3e-12 and, with no stroke
//! spring (phi cyclic), p_phi to 9e-13 over 20 000 steps of large coupled motion; a 1 deg
//! prescribed sinusoidal stroke drives the pitch as B psi_dd + c_h psi_d + k_h psi = C phi_dd
//! says, to 1e-4 in amplitude and 1e-4 deg in phase, for the centre of mass on either side
//! of the axis.
//!
//! # Integrator
//! Each body step of length dt is split into `substeps` equal sub-steps. At the start of a
//! sub-step the aerodynamic loads are evaluated once (the translational strip loop runs
//! there, at the current angles, rates and body motion) and held over the sub-step; the
//! added mass, which is proportional to the angular accelerations, is not held but moved to
//! the inertia side as the matrix A of [`wingforce::Wing::added_inertia`] (holding it would
//! be unstable once A rivals the wing's own inertia). The structural equations above are
//! then advanced by the classical fourth-order Runge-Kutta method over the sub-step. So the
//! structure (inertia, springs, actuator, drive) is integrated to fourth order and the
//! aerodynamic coupling to first order in the sub-step, the same zero-order hold the body
//! itself gets from the simulator. The tests bound both: without aerodynamics the stroke
//! and pitch modes keep their analytic frequency to 0.5% and their energy to 1e-6 over 100
//! periods at 100 steps per period; with aerodynamics, halving the sub-step changes the
//! mean lift by well under 1%.
//!
//! Hinge stops ([`super::stop`] states how and what they cost): a compliant stop is stiff,
//! and near or in it the sub-step is cut into contact steps, with the touch and the clamp's
//! onset located within them; an inelastic stop (restitution 0) is a constraint, and the
//! sub-step is split only where the wing strikes it (an impulse that stops the pitch) and
//! where it leaves it. A strike changes the pitch rate within microseconds (or at once),
//! inside a body step, and a held load or a load sampled once per step would carry an
//! error that slides with where in the step the strike falls (measured: the hummingbird's
//! M_u changed sign between step sizes; `flapsim/tests/strike_loads.rs`). With stops,
//! therefore:
//! - the aerodynamic loads are taken afresh at every Runge-Kutta stage of a sub-step clear
//!   of a compliant stop, and at the start of every contact step near or in one; on an
//!   inelastic stop, at each segment's start (the sub-step split at touches and releases)
//!   and at the sub-step's end (on the state the segment's path reaches with its start's
//!   loads held) and linear in time between them (`actuated::contact`: second order, as the body's
//!   step is, for two evaluations per segment where every stage took four; logs written
//!   before 2026-12-07 re-run with the loads at every stage);
//! - a step reports its mean loads: the trapezoidal mean over the states the integrator
//!   passed (sub-step ends; the touch with the accelerations on both of its sides; near a
//!   compliant stop the contact steps and the clamp's onset; an inelastic stop's release),
//!   thinned where no rate has moved by 0.1% of the step's largest, each node's
//!   accelerations shifted by one constant so that their mean is the step's smooth change
//!   of rate (the inertial and added-mass impulses stay exact). An inelastic strike's
//!   impulse is not shared out over the step's nodes: its reaction is taken where the wing
//!   struck (shared, it would act along axes that turn with the stroke over the step). It is
//!   shared between the step it falls in and the next by its place in the step, so that the
//!   body moves as the impulse moves it (`strike.rs`). The angles and actuator
//!   it reports are the mid-step mean motion's.
//!
//! Under the step mean (`LoadSampling::StepMean`) a sub-step without stops that crosses a
//! stroke reversal is split there, each part integrated with its own half stroke's loads,
//! and the step's mean takes both sides of the reversal as nodes: the wake-capture term
//! restarts at a reversal, and a Runge-Kutta step or a trapezoid across that jump is first
//! order. A reversal counts only after a half stroke (a peak rate of at least 1% of the
//! nominal), and a step ending within round-off of a drive period's end ends that period.
//! With the three, the RoboBee's trajectory converges at second order over many periods
//! (`flapsim/tests/second_order.rs`); the midpoint sampling keeps the loads as they were
//! before (logs written with it, or with the step mean before the split, replay with it).
//!
//! Without stops and at the step-start sampling a step reports its start, as before. A vehicle with compliant stops costs
//! about 3.5x more per step than before the mean loads (`flapwing validate`: 11.4 s against
//! 3.2 s); the hummingbird's inelastic stops cost 2.5x a prescribed step in wall time since
//! their segments' loads are interpolated (3.2x before; docs/speed.md, row 8).
//!
//! Neglected: the body's own acceleration and rotation in the wing's equations (the wing
//! reacts on the body, the body does not shake the wing), the actuator's reaction other
//! than its reflected inertia about the stroke axis, and gravity on the wing.

mod equations;
mod mean;
mod memo;
mod model;
mod points;
mod report;
mod reversal;
mod stage_loads;
mod step;
mod strike;
mod wing;

pub(super) use equations::Held;
pub use model::{Hinge, Stroke, WingDynamics, WingInertia};
pub(super) use points::Nodes;
pub use stage_loads::{StageLoads, StrikeShare};
pub use step::MAX_PENETRATION_RAD;
pub(super) use step::Reheld;
pub use wing::{ActuatedWingOutput, DynamicWing, WingState, WingStep};
