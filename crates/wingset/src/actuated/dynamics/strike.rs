//! Where a strike's impulse lands among the body's steps. An inelastic stop stops the pitch at
//! once: the wing's rates jump, and the body receives the impulse of the wing's inertial
//! reaction, of the stop's angular impulse on the hinge, and (impulse-form added mass) of the
//! fluid's impulse jumping with the rates. A host's semi-implicit Euler step (rapier's,
//! MuJoCo's) hands a step's impulse to the body's velocity at the step's end and moves the
//! body by dt times that velocity, so an impulse J at tau into a step of dt moves the body by
//! dt J / m by the next step's end, where the exact motion moves it by (dt - tau) J / m.
//!
//! Reported whole in the step it falls in (as before 2026-12-06), the body's motion is
//! therefore a staircase in the strike's time: flat within a step and jumping by dt J / m
//! where the strike crosses a step boundary. Two things followed, both measured on the
//! hummingbird:
//! - the one-wingbeat map's derivatives missed how a body perturbation moves the strikes in
//!   time: the Floquet exponents converged to +0.560 1/s (200 to 1600 steps per wingbeat),
//!   not to the map's own +0.596;
//! - at 3200 steps per wingbeat a strike of the periodic orbit sat on a step boundary, and a
//!   perturbation of 6e-4 m/s moved it across: the map jumped (forward and backward
//!   differences 1.84 perturbations apart) and the exponents read +0.878 1/s.
//!
//! So the impulse is shared between the step it falls in and the next, as the hat function
//! of the strike's place in the step: 1 - tau/dt in its step and tau/dt in the next. The body
//! then moves by (1 - tau/dt) 2 dt J/m + (tau/dt) dt J/m = (2 dt - tau) J/m by the next
//! step's end, the exact motion's, and its velocity is exact from the next step's end on;
//! the map is continuous in the strike's time, with the exact slope. Measured: the
//! hummingbird's exponents +0.595, +0.595, +0.595, +0.596 and +0.596 1/s at 200, 400, 800,
//! 1600 and 3200 steps per wingbeat, and the jump at 3200 gone (`flapsim/tests/strike_loads.rs`;
//! since the trapezoid's three-step shares and the split scheme below, 2026-12-07, +0.5872 at
//! 400 and +0.5899 at 3200).
//!
//! That hat is exact for a host whose pose takes dt v_{k+1} (semi-implicit Euler). A host that
//! moves the body by the trapezoidal rule, dt (v_k + v_{k+1})/2 (flapsim's hosts under a
//! second-order sampling: `flapsim::host::trapezoid_pose`), moves it by (a + 1/2) dt J/m for
//! shares (a, 1 - a) over two steps, and with the semi-implicit hat its pose was off by
//! dt J / (2 m) at every strike, a first-order error: measured on the hummingbird's free
//! flight over two wingbeats, its position error halved with the step (1.7e-5, 8.8e-6,
//! 4.4e-6, 2.0e-6 and 8.7e-7 m at 100 to 1600 steps per wingbeat, against 6400). Shares
//! (a, b, c) over the strike's step and the two after move such a host's body by
//! (5a + 3b + c) dt J / (2 m) by the third step's end, where the exact motion moves it by
//! (3 dt - tau) J / m; with a + b + c = 1 and the shares continuous in the strike's time
//! (a strike at a step's end shared as one at the next step's start: s = tau/dt at 1 gives
//! (0, a, b) at 0), they are (3/2 - 3/2 s, 2 s - 1/2, -s/2): exact from the third step's end
//! on, and the one-wingbeat map stays continuous. (Two steps cannot be both exact and
//! continuous for this pose: (3/2 - s, s - 1/2) is exact but jumps where s wraps, which
//! left the hummingbird's Floquet exponents scattered at fine steps, +0.598 at 3200 and
//! +0.580 at 6400 steps per wingbeat.) Measured with the three-step hats: the position error
//! over two wingbeats falls 4x a halving.
//!
//! The share carried is the wing's state between steps ([`DynamicWing::carried_strike`]);
//! logs name the rule they were written with ([`StrikeShare`]).

use wingforce::{BodyMotion, Term, Wing, WingFrame};

use super::stage_loads::StrikeShare;

use super::points::StepStart;
use super::wing::{DynamicWing, WingState, WingStep};

impl DynamicWing {
    /// The impulse of a strike at `at` whose rates jump by `jump` (stroke, pitch; rad/s), as
    /// loads held over a step of `dt_s`: the inertial reaction's part linear in the
    /// accelerations at the strike (two reports differing only in them) with the stop's
    /// angular impulse on the wing as hinge moment; and the same with, under the impulse-form
    /// added mass, the fluid's impulse jump as added-mass force.
    pub(super) fn strike_loads(
        &self,
        wing: &Wing,
        body: &BodyMotion,
        at: &StepStart,
        jump: [f64; 2],
        dt_s: f64,
    ) -> (WingStep, WingStep) {
        let held = self.aero_at(wing, body, at).0;
        let per_s = [jump[0] / dt_s, jump[1] / dt_s];
        let mut inertial = self.report(wing, &held, None, per_s, at);
        inertial.add_scaled(&self.report(wing, &held, None, [0.0; 2], at), -1.0);
        let m = self.mass_matrix(at.state.theta_rad, &held.added);
        inertial.hinge_moment_nm += m[1][0] * per_s[0] + m[1][1] * per_s[1];
        let mut all = inertial;
        if self.model.aero {
            let side = wing.mount().side;
            let after = WingState {
                phi_dot_rad_s: at.state.phi_dot_rad_s + jump[0],
                theta_dot_rad_s: at.state.theta_dot_rad_s + jump[1],
                ..at.state
            };
            let before = WingFrame::new(&self.angles_at(&at.state, at.t_s, [0.0; 2]), side);
            let after = WingFrame::new(&self.angles_at(&after, at.t_s, [0.0; 2]), side);
            let none = wingforce::TermForce::default();
            let downstroke = at.phase.downstroke;
            if let Some(t) = wing.added_mass_over_step(&before, &after, dt_s, &none, downstroke) {
                let i = Term::AddedMass as usize;
                for term in [&mut all.forces.terms[i], &mut all.forces.total] {
                    term.force_n += t.force_n;
                    term.c_l += t.c_l;
                    term.c_d += t.c_d;
                }
            }
        }
        (inertial, all)
    }

    /// The shares of a strike's impulse at `t_s` that the step from `start_s` of `dt_s`
    /// and the next two report (the module's hats for the host's pose, [`StrikeShare`]).
    pub(super) fn strike_shares(&self, start_s: f64, t_s: f64, dt_s: f64) -> [f64; 3] {
        match self.strike_share {
            StrikeShare::TrapezoidalPose => {
                let s = ((t_s - start_s) / dt_s).clamp(0.0, 1.0);
                [1.5 - 1.5 * s, 2.0 * s - 0.5, -0.5 * s]
            }
            // As written before the trapezoid's (logs re-run bit for bit).
            StrikeShare::WholeInStep | StrikeShare::SemiImplicitPose => {
                let a = (1.0 - (t_s - start_s) / dt_s).clamp(0.0, 1.0);
                [a, 1.0 - a, 0.0]
            }
        }
    }

    /// Adds `w[0]` times `loads` to the share carried into the next step's report and
    /// `w[1]` times them to the one after.
    pub(super) fn carry_strike(&mut self, loads: &WingStep, w: [f64; 2]) {
        for (slot, w) in [&mut self.carried_strike, &mut self.carried_strike_after]
            .into_iter()
            .zip(w)
        {
            if w == 0.0 {
                continue;
            }
            match slot {
                Some(c) => c.add_scaled(loads, w),
                None => *slot = Some(loads.scaled(w)),
            }
        }
    }

    /// How a strike's impulse is shared among the body's steps ([`StrikeShare`]; the module).
    /// Under a rule that shares over two steps, the next step also reports the share another
    /// rule left for the step after it: the whole impulse still reaches the body, and none of
    /// it later than that rule would put it (a wing set started from wings that a host of the
    /// trapezoidal pose stepped, `WingSet::start_dynamic_from`, in a host that moves the body
    /// semi-implicitly). Taken at the step, so setting a rule and setting it back changes
    /// nothing.
    pub fn set_strike_share(&mut self, share: StrikeShare) {
        self.strike_share = share;
    }

    /// The strike shares this wing carries into its next step's report and into the one
    /// after ([`Self::set_strike_share`]; the module).
    pub fn carried_strike(&self) -> [Option<&WingStep>; 2] {
        [
            self.carried_strike.as_ref(),
            self.carried_strike_after.as_ref(),
        ]
    }

    /// See [`Self::set_strike_share`].
    pub fn strike_share_rule(&self) -> StrikeShare {
        self.strike_share
    }
}
