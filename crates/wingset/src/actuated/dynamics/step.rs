//! The sub-stepped integrator (stated in [`super`]): one body step of a [`DynamicWing`]
//! as held aerodynamic loads and Runge-Kutta sub-steps, the checks that end a run, the
//! stroke reversals and per-period stroke reference it tracks, and the loads it reports (their
//! mean over the points it passed: `mean`; each point's report: `report`).

use std::cell::Cell;

use wingforce::{BodyMotion, StrokePhase, Wing, WingFrame};

use super::equations::Held;
use super::mean::StepPoints;
use super::points::{Aero, Loads, Nodes, StepStart};
use super::stage_loads::{StageLoads, StrikeShare, motion_between};
use super::wing::{DynamicWing, WingState, WingStep};
use crate::error::{Error, Result};
use crate::sampling::LoadSampling;

/// Deepest penetration into a contact stop before a run stops with an error, rad (10 deg):
/// a stop is meant to be stiff, so a wing this deep in it says the contact is too soft for
/// the loads, not anything about the robot.
pub const MAX_PENETRATION_RAD: f64 = 10.0 * std::f64::consts::PI / 180.0;

/// The aerodynamic loads at a time and integrator state (phi, theta, phi_dot, theta_dot).
pub(in crate::actuated) type Reheld<'a> = &'a dyn Fn(f64, &[f64; 4]) -> Held;

impl DynamicWing {
    /// Whether a step takes the split scheme ([`StageLoads::Split`]): inelastic stops, a
    /// second-order sampling and one sub-step a step.
    pub(in crate::actuated) fn split_scheme(&self) -> bool {
        self.stage_loads == StageLoads::Split
            && self.model.hinge.contact.is_some_and(|c| c.is_inelastic())
            && self.sampling.is_second_order()
            && self.model.substeps.max(1) == 1
    }

    fn stroke_phase(&self) -> StrokePhase {
        StrokePhase {
            half_stroke: self.half_stroke,
            t_star: (self.t_s - self.last_reversal_s) * self.drive.freq_hz,
            downstroke: self.downstroke,
        }
    }

    /// Aerodynamic loads at the current state with zero accelerations (so the added-mass
    /// term holds only its velocity part), and the added inertia.
    fn aero_held(&self, wing: &Wing, body: &BodyMotion) -> (Held, Option<Aero>) {
        let at = StepStart {
            state: self.state,
            t_s: self.t_s,
            phase: self.stroke_phase(),
        };
        self.aero_at(wing, body, &at)
    }

    /// [`Self::aero_held`] at a given state, time and stroke phase.
    #[inline(always)]
    pub(super) fn aero_at(
        &self,
        wing: &Wing,
        body: &BodyMotion,
        at: &StepStart,
    ) -> (Held, Option<Aero>) {
        if !self.model.aero {
            return (Held::default(), None);
        }
        let a = self.angles_at(&at.state, at.t_s, [0.0, 0.0]);
        let side = wing.mount().side;
        let frame = self.frame(&a, side);
        let k = wing.kinematic_loads_in(&a, &at.phase, &frame);
        let f = wing.evaluate_with(&k, body);
        let q = wing.axis_moments(&frame, &f.total);
        (
            Held {
                q: [q.stroke_nm, q.pitch_nm],
                added: wing.added_inertia(&frame),
                free: false,
                locked: false,
            },
            Some((f.terms[0], frame)),
        )
    }

    fn y(&self) -> [f64; 4] {
        let s = &self.state;
        [s.phi_rad, s.theta_rad, s.phi_dot_rad_s, s.theta_dot_rad_s]
    }

    /// Advances the wing by `dt_s` with the body moving as given; returns the loads at the
    /// step's start. A pitch past the hinge's break limit (or, with contact stops, a wing
    /// pressed implausibly deep into a stop) or a non-finite state is an error.
    pub fn step(&mut self, wing: &mut Wing, body: &BodyMotion, dt_s: f64) -> Result<WingStep> {
        self.step_moving(wing, [body, body, body], dt_s)
    }

    /// [`Self::step`] with the body's motion at the step's start, its midpoint and its end
    /// (`motions`): the loads are taken at the midpoint's motion, or, on inelastic stops
    /// under [`StageLoads::Split`] (`stage_loads`), each at the motion of its own time
    /// (linear between the start's and the end's).
    pub fn step_moving(
        &mut self,
        wing: &mut Wing,
        motions: [&BodyMotion; 3],
        dt_s: f64,
    ) -> Result<WingStep> {
        let [start_motion, body, end_motion] = motions;
        let n = self.model.substeps.max(1);
        let h = dt_s / n as f64;
        let start = StepStart {
            state: self.state,
            t_s: self.t_s,
            phase: self.stroke_phase(),
        };
        // With stops, or sampled at the midpoint (second order), a step reports its mean
        // loads over the step (below).
        let stops = self.model.hinge.contact.is_some() || self.sampling.is_second_order();
        let inelastic = self.model.hinge.contact.is_some_and(|c| c.is_inelastic());
        // Inelastic stops under the split scheme (`stage_loads`).
        let split_scheme = self.split_scheme();
        let motion_at = |t_s: f64| match split_scheme {
            true => motion_between(start_motion, end_motion, (t_s - start.t_s) / dt_s),
            false => *body,
        };
        let mut out = None;
        let mut frame_start = None;
        let mut nodes = Nodes::new();
        if stops {
            nodes.push((self.t_s, self.y(), false));
        }
        // With stops: the loads at the step's start (its first quadrature node) and the
        // last loads the integrator took (on an inelastic stop, the sub-step's end's, on the
        // state its last segment's path predicted: `predicted_end`), each computed once.
        let mut start_loads = None;
        // The last node's state, time and frame, where a report took it.
        let mut end_report_frame: Option<(StepStart, WingFrame)> = None;
        let mut moved = Vec::new();
        let last_loads: Cell<Option<Loads>> = Cell::new(None);
        // On an inelastic stop: the state whose loads the last sub-step took at its end
        // (`actuated::contact`), those of the step's last node.
        let mut predicted_end = None;
        let mut next_reference = None;
        // Stroke reversals the step was split at (the step mean without stops): time and the
        // stroke phase that starts there.
        // (With inelastic stops under the split scheme, too: `stage_loads`.)
        let split_reversals = self.sampling == LoadSampling::StepMean
            && (self.model.hinge.contact.is_none() || split_scheme);
        let mut reversals: Vec<(f64, StrokePhase)> = Vec::new();
        for sub in 0..n {
            self.take_volts(self.t_s, h);
            let (held, aero) = self.aero_held(wing, &motion_at(self.t_s));
            let y0 = self.y();
            let t0 = self.t_s;
            // An inelastic stop's segments take their own (`actuated::contact`).
            let k1a = match inelastic {
                true => None,
                false => Some(self.accelerations(t0, &y0, &held)),
            };
            if sub == 0 {
                frame_start = aero.as_ref().map(|(_, frame)| *frame);
                if stops {
                    start_loads = Some((held, aero));
                } else {
                    let k1a = k1a.unwrap_or_else(|| self.accelerations(t0, &y0, &held));
                    out = Some(self.report(wing, &held, aero, k1a, &start));
                }
            }
            let pd_old = self.angles([0.0; 2]).phi_dot;
            if !stops {
                nodes.clear();
            }
            let phase0 = self.stroke_phase();
            let freq_hz = self.drive.freq_hz;
            // The loads at a time and state (`Reheld`), the stroke phase that `phase` has at
            // `t_ref` going on from there: the sub-step's start's, or from a reversal at
            // `t_ref` within it, the half stroke's that starts there (`after`, t* = 0).
            let reheld_from = |t_ref: f64, phase: StrokePhase| {
                let (this, wing, last_loads, motion_at) = (&*self, &*wing, &last_loads, &motion_at);
                move |t_s: f64, y: &[f64; 4]| {
                    let at = StepStart {
                        state: WingState::from_y(y),
                        t_s,
                        phase: StrokePhase {
                            t_star: phase.t_star + (t_s - t_ref) * freq_hz,
                            ..phase
                        },
                    };
                    let (held, aero) = this.aero_at(wing, &motion_at(t_s), &at);
                    if stops {
                        last_loads.set(Some((at, held, aero)));
                    }
                    held
                }
            };
            let reheld = reheld_from(t0, phase0);
            let nodes_before = nodes.len();
            let y = self.advance(
                t0,
                &y0,
                h,
                &held,
                k1a,
                &mut nodes,
                &reheld,
                &mut predicted_end,
            )?;
            // The step mean without stops: a stroke reversal inside the sub-step splits it
            // (see `reversal_within`), each part integrated with its own half stroke's loads.
            let split = match split_reversals {
                true => self.reversal_within(wing, pd_old, t0, h, &y),
                false => None,
            };
            let y = match split {
                // On inelastic stops each part is advanced with its segments (strikes and
                // releases), the reversal's node taken on both sides.
                Some((tau, after)) if tau < h && inelastic => {
                    nodes.truncate(nodes_before);
                    let t_rev = t0 + tau;
                    let ya = self.advance(
                        t0,
                        &y0,
                        tau,
                        &held,
                        k1a,
                        &mut nodes,
                        &reheld,
                        &mut predicted_end,
                    )?;
                    if let Some(left) = nodes.last_mut() {
                        left.2 = true;
                    }
                    nodes.push((t_rev, ya, false));
                    let reheld_after = reheld_from(t_rev, after);
                    let held_after = reheld_after(t_rev, &ya);
                    // The part's length as the sub-step's end less the reversal: exact
                    // (Sterbenz), so that the part ends on t0 + h, the step's end.
                    let y = self.advance(
                        t_rev,
                        &ya,
                        (t0 + h) - t_rev,
                        &held_after,
                        None,
                        &mut nodes,
                        &reheld_after,
                        &mut predicted_end,
                    )?;
                    reversals.push((t_rev, after));
                    y
                }
                Some((tau, after)) if tau < h => {
                    nodes.pop();
                    let t_rev = t0 + tau;
                    let ya = self.rk4(t0, &y0, tau, &held, k1a, Some(&reheld)).0;
                    nodes.push((t_rev, ya, true));
                    nodes.push((t_rev, ya, false));
                    let reheld_after = reheld_from(t_rev, after);
                    let held_after = reheld_after(t_rev, &ya);
                    let k1b = self.accelerations(t_rev, &ya, &held_after);
                    let y = self
                        .rk4(
                            t_rev,
                            &ya,
                            h - tau,
                            &held_after,
                            Some(k1b),
                            Some(&reheld_after),
                        )
                        .0;
                    nodes.push((t0 + h, y, false));
                    reversals.push((t_rev, after));
                    y
                }
                _ => y,
            };
            self.state = WingState::from_y(&y);
            self.t_s = t0 + h;
            self.check(wing)?;
            if split_reversals {
                let pd = self.angles([0.0; 2]).phi_dot.abs();
                match split {
                    Some((tau, after)) => {
                        self.last_reversal_s = t0 + tau;
                        self.half_stroke = after.half_stroke;
                        self.downstroke = after.downstroke;
                        self.half_stroke_peak_rate_rad_s = pd;
                    }
                    None => {
                        self.half_stroke_peak_rate_rad_s = self.half_stroke_peak_rate_rad_s.max(pd)
                    }
                }
            } else {
                self.track_reversal(pd_old, t0, h);
            }
            // Split: the rate on both sides of each jump and reversal within the sub-step.
            let mut within: Vec<(f64, f64)> = Vec::new();
            if split_scheme {
                for k in (nodes_before.max(1))..nodes.len() {
                    let (a, b) = (&nodes[k - 1], &nodes[k]);
                    if a.2 && a.0 == b.0 && a.0 < self.t_s {
                        let rate = |y: &[f64; 4]| {
                            self.angles_at(&WingState::from_y(y), a.0, [0.0; 2]).phi_dot
                        };
                        within.extend([(a.0, rate(&a.1)), (b.0, rate(&b.1))]);
                    }
                }
            }
            if let Some(r) = self.track_period(wing, &within) {
                if stops {
                    // Taken up after the step's mean loads, which are those the integrator
                    // used over the step (the period's reference).
                    next_reference = Some(r);
                } else {
                    wing.set_stroke_reference(Some(r));
                }
            }
        }
        if stops {
            let points = StepPoints {
                nodes: &nodes,
                reversals: &reversals,
                start,
                start_loads,
                last_loads: last_loads.get(),
                predicted_end,
                inelastic,
                dt_s,
            };
            (end_report_frame, moved) = self.step_mean(wing, &points, &motion_at, &mut out);
            if next_reference.is_some() {
                wing.set_stroke_reference(next_reference);
            }
        }
        let out = out.as_mut().expect("at least one sub-step");
        // The strikes' shares for the next step (`super::strike`), taken out after the added
        // mass's change of impulse (which holds the fluid's part), and those carried in.
        // A rule that shares over two steps reports here a share another rule left for the
        // step after this one (`DynamicWing::set_strike_share`).
        let mut carried = self.carried_strike.take();
        if let Some(after) = self.carried_strike_after.take() {
            match self.strike_share {
                StrikeShare::TrapezoidalPose => self.carried_strike = Some(after),
                _ => match &mut carried {
                    Some(c) => c.add_scaled(&after, 1.0),
                    None => carried = Some(after),
                },
            }
        }
        // The wing's frame at the step's end (the added mass's impulse takes its axes and
        // angular velocity, not its angular acceleration): the last node's report's, where
        // that node is the end.
        let end_frame = frame_start.map(|_| match end_report_frame {
            Some((at, frame)) if at.t_s == self.t_s && at.state == self.state => frame,
            _ => self.frame(&self.angles([0.0; 2]), wing.mount().side),
        });
        if let Some(start) = frame_start {
            // The impulse-form added mass is -dP/dt of the fluid's impulse. Held over the
            // step, its value at the step's start would hand the body an impulse that differs
            // from the fluid's change by O(dt) each step, and those errors do not cancel
            // over a wingbeat (a cycle-mean force of 0.4-1% of the term's peak, measured on
            // the built-in vehicles at 100 steps per wingbeat). The force over the step is
            // therefore the change of P across it: the fluid's momentum is conserved step
            // by step and the cycle mean is zero to the motion's periodicity.
            let end = end_frame.unwrap_or(start);
            let i = wingforce::Term::AddedMass as usize;
            let downstroke = out.forces.phase.downstroke;
            if let Some(t) =
                wing.added_mass_over_step(&start, &end, dt_s, &out.forces.terms[i], downstroke)
            {
                out.forces.total.force_n += t.force_n - out.forces.terms[i].force_n;
                out.forces.total.c_l += t.c_l - out.forces.terms[i].c_l;
                out.forces.total.c_d += t.c_d - out.forces.terms[i].c_d;
                out.forces.terms[i] = t;
            }
        }
        for (loads, [_, next, after]) in moved {
            out.add_scaled(&loads, -(next + after));
            self.carry_strike(&loads, [next, after]);
        }
        if let Some(c) = carried {
            out.add_scaled(&c, 1.0);
        }
        Ok(*out)
    }

    /// One classical fourth-order Runge-Kutta step of length `h` from (t0, y0) with the
    /// loads `held` at the start (`k1a`: the accelerations there, when known) and held over
    /// the step, or, given `stage`, taken afresh at each later stage; returns the new
    /// state and the three later stage states.
    pub(in crate::actuated) fn rk4(
        &self,
        t0: f64,
        y0: &[f64; 4],
        h: f64,
        held: &Held,
        k1a: Option<[f64; 2]>,
        stage: Option<Reheld>,
    ) -> ([f64; 4], [[f64; 4]; 3]) {
        let at = |t: f64, y: &[f64; 4]| match stage {
            Some(f) => Held {
                free: held.free,
                locked: held.locked,
                ..f(t, y)
            },
            None => *held,
        };
        let deriv = |a: [f64; 2], y: &[f64; 4]| [y[2], y[3], a[0], a[1]];
        let add = |y: &[f64; 4], k: &[f64; 4], s: f64| {
            [
                y[0] + s * k[0],
                y[1] + s * k[1],
                y[2] + s * k[2],
                y[3] + s * k[3],
            ]
        };
        let k1 = deriv(k1a.unwrap_or_else(|| self.accelerations(t0, y0, held)), y0);
        let y2 = add(y0, &k1, 0.5 * h);
        let k2 = deriv(
            self.stage_accelerations(t0 + 0.5 * h, &y2, &at(t0 + 0.5 * h, &y2)),
            &y2,
        );
        let y3 = add(y0, &k2, 0.5 * h);
        let k3 = deriv(
            self.stage_accelerations(t0 + 0.5 * h, &y3, &at(t0 + 0.5 * h, &y3)),
            &y3,
        );
        let y4 = add(y0, &k3, h);
        let k4 = deriv(self.stage_accelerations(t0 + h, &y4, &at(t0 + h, &y4)), &y4);
        let mut y = [0.0; 4];
        for i in 0..4 {
            y[i] = y0[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
        (y, [y2, y3, y4])
    }

    fn check(&self, wing: &Wing) -> Result<()> {
        let s = &self.state;
        let side = match wing.mount().side {
            wingforce::Side::Left => "left",
            wingforce::Side::Right => "right",
        };
        if ![s.phi_rad, s.theta_rad, s.phi_dot_rad_s, s.theta_dot_rad_s]
            .iter()
            .all(|x| x.is_finite())
        {
            return Err(Error::Diverged {
                t_s: self.t_s,
                step: 0,
                reason: format!("{side} wing state is not finite: {s:?}"),
            });
        }
        let h = &self.model.hinge;
        let dev = s.theta_rad - h.rest_rad;
        if dev.abs() > h.break_rad {
            return Err(Error::Diverged {
                t_s: self.t_s,
                step: 0,
                reason: format!(
                    "{side} wing pitched {:.1} deg from its hinge rest angle, past the stops at +-{:.1} deg (the hinge's break limit): the hinge (k_h = {:e} N m/rad) is too soft for this drive",
                    dev.to_degrees(),
                    h.break_rad.to_degrees(),
                    h.stiffness_nm_rad
                ),
            });
        }
        if let Some(c) = &h.contact {
            let delta = c.penetration(dev).0;
            if delta > MAX_PENETRATION_RAD {
                return Err(Error::Diverged {
                    t_s: self.t_s,
                    step: 0,
                    reason: format!(
                        "{side} wing pressed {:.1} deg into its stop at +-{:.1} deg (more than {:.0} deg): the stop contact (stiffness {:e} N m/rad) is too soft for the loads; shorten [actuation.hinge.stop] contact_time_s",
                        delta.to_degrees(),
                        c.angle_rad.to_degrees(),
                        MAX_PENETRATION_RAD.to_degrees(),
                        c.stiffness_nm_rad
                    ),
                });
            }
        }
        Ok(())
    }
}
