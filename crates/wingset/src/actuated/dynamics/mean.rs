//! A step's mean loads on the body where it has stops, or is sampled at its midpoint (second
//! order): the trapezoidal mean over the states the integrator passed, and a stop strike's
//! impulse at the strike (`step` calls it once its sub-steps are done).

use smallvec::SmallVec;
use wingforce::{BodyMotion, StrokePhase, Wing, WingFrame};

use super::equations::Held;
use super::points::{Aero, Loads, Nodes, StepStart, quadrature_nodes};
use super::stage_loads::StrikeShare;
use super::wing::{DynamicWing, WingState, WingStep};

/// What a step passed that its mean loads need (`step`).
#[derive(Debug, Clone, Copy)]
pub(super) struct StepPoints<'a> {
    /// The states the step passed: (time, state, the touch's left-side flag).
    pub(super) nodes: &'a [(f64, [f64; 4], bool)],
    /// The stroke reversals the step was split at: time and the stroke phase that starts
    /// there.
    pub(super) reversals: &'a [(f64, StrokePhase)],
    /// The state, time and stroke phase at the step's start.
    pub(super) start: StepStart,
    /// The loads at the step's start.
    pub(super) start_loads: Option<(Held, Option<Aero>)>,
    /// The last loads the integrator took: where and what.
    pub(super) last_loads: Option<Loads>,
    /// On an inelastic stop: the state whose loads the last sub-step took at its end.
    pub(super) predicted_end: Option<[f64; 4]>,
    /// Whether the stops are inelastic.
    pub(super) inelastic: bool,
    /// The step's length, s.
    pub(super) dt_s: f64,
}

/// A strike's loads that the next two steps report, with the three steps' shares
/// (`super::strike`).
pub(super) type Moved = Vec<(WingStep, [f64; 3])>;

impl DynamicWing {
    /// A strike changes the pitch rate within microseconds, inside a step: loads
    /// sampled once per step (at its start, or at its mean motion) would carry
    /// sampling errors of the order of their jump, which move with where in the step
    /// the strike falls and so ripple in every cycle mean and derivative the body
    /// sees (measured: the hummingbird's M_u between -34.5 and +1.3 1/(m s) over the
    /// step sizes, docs/commands.md). With stops a step therefore reports its mean
    /// loads: the trapezoidal mean over the states the integrator passed (the touch
    /// and release splits and the contact steps that resolve a strike, else the
    /// sub-step ends), each with the step's mean accelerations (change of rate over
    /// the step, whose impulse is the wing's change of momentum). The angles, the
    /// actuator and the stroke phase reported are the mid-step motion's.
    /// An inelastic stop's strike is an impulse: the rates jump at the touch (the
    /// node taken on both sides). Its reaction is taken at the strike, with the wing
    /// where it struck, and only the smooth rest of the step's change of rate is
    /// shared among the nodes (shared, the impulse would act along axes that turn
    /// with the stroke over the step, an error that slides with where in the step the
    /// strike falls).
    ///
    /// Writes the mean into `out`; returns the last node's state, time and frame where its
    /// report took them, and the strikes' shares that the next steps report.
    #[inline(always)]
    pub(super) fn step_mean(
        &self,
        wing: &Wing,
        points: &StepPoints,
        motion_at: &impl Fn(f64) -> BodyMotion,
        out: &mut Option<WingStep>,
    ) -> (Option<(StepStart, WingFrame)>, Moved) {
        let StepPoints {
            nodes,
            reversals,
            start,
            start_loads,
            last_loads,
            predicted_end,
            inelastic,
            dt_s,
        } = *points;
        let mut end_report_frame = None;
        let mut moved = Moved::new();
        let jumps: Vec<(usize, [f64; 2])> = (1..nodes.len())
            .filter(|&k| nodes[k - 1].2 && nodes[k].0 == nodes[k - 1].0)
            .map(|k| {
                let (a, b) = (&nodes[k - 1].1, &nodes[k].1);
                (k - 1, [b[2] - a[2], b[3] - a[3]])
            })
            .filter(|(_, j)| j[0] != 0.0 || j[1] != 0.0)
            .collect();
        let (s0, s1) = (start.state, self.state);
        let jumped = jumps
            .iter()
            .fold([0.0; 2], |a, (_, j)| [a[0] + j[0], a[1] + j[1]]);
        let acc = [
            (s1.phi_dot_rad_s - s0.phi_dot_rad_s - jumped[0]) / dt_s,
            (s1.theta_dot_rad_s - s0.theta_dot_rad_s - jumped[1]) / dt_s,
        ];
        // A node's stroke phase: that of the last reversal the step was split at before
        // it (at a reversal, the node on its left side keeps the half stroke ending
        // there), else the step start's.
        let f = self.drive.freq_hz;
        let at = |t_s: f64, y: &[f64; 4], left: bool| StepStart {
            state: WingState::from_y(y),
            t_s,
            phase: match reversals
                .iter()
                .rev()
                .find(|(t_rev, _)| t_s > *t_rev || (t_s == *t_rev && !left))
            {
                Some((t_rev, after)) => StrokePhase {
                    t_star: (t_s - t_rev) * f,
                    ..*after
                },
                None => StrokePhase {
                    t_star: start.phase.t_star + (t_s - start.t_s) * f,
                    ..start.phase
                },
            },
        };
        let strikes: Vec<(StepStart, [f64; 2])> = jumps
            .iter()
            .map(|&(k, j)| (at(nodes[k].0, &nodes[k].1, nodes[k].2), j))
            .collect();
        let mid = at(
            start.t_s + 0.5 * dt_s,
            &[
                0.5 * (s0.phi_rad + s1.phi_rad),
                0.5 * (s0.theta_rad + s1.theta_rad),
                (s1.phi_rad - s0.phi_rad) / dt_s,
                (s1.theta_rad - s0.theta_rad) / dt_s,
            ],
            false,
        );
        let mut kept = Nodes::new();
        quadrature_nodes(nodes, &mut kept);
        // A node's loads: the first sub-step's start, the loads the integrator took there,
        // or afresh.
        let node_loads = |k: usize, at: &StepStart| match (k, last_loads) {
            (0, _) => start_loads.expect("the first sub-step's loads"),
            (_, Some((last, held, aero))) if last == *at => (held, aero),
            // The end's loads on the state the last segment's path predicted there
            // (those its integration took; `actuated::contact`).
            (_, Some((last, held, aero)))
                if k + 1 == kept.len()
                    && last.t_s == at.t_s
                    && last.phase == at.phase
                    && predicted_end.map(|y| WingState::from_y(&y)) == Some(last.state) =>
            {
                (held, aero)
            }
            _ => self.aero_at(wing, &motion_at(at.t_s), at),
        };
        let mean = {
            // Each node's loads and accelerations (the strike's spike resolved by the
            // contact steps), the accelerations then shifted by one constant so that
            // their mean is the step's change of rate: the impulse the body receives
            // stays exact.
            let span_s = kept.last().map_or(0.0, |n| n.0) - kept[0].0;
            let mut points: SmallVec<[_; 4]> = SmallVec::new();
            let mut mean_acc = [0.0; 2];
            for (k, (t_s, y, free)) in kept.iter().enumerate() {
                let before = if k > 0 { t_s - kept[k - 1].0 } else { 0.0 };
                let after = kept.get(k + 1).map_or(0.0, |n| n.0 - t_s);
                let w = 0.5 * (before + after) / span_s;
                if w > 0.0 {
                    let at = at(*t_s, y, *free);
                    let (held, aero) = node_loads(k, &at);
                    // A reversal's left side is no touch: on inelastic stops its
                    // accelerations are the stops' (elsewhere the flag changes nothing).
                    let at_reversal = inelastic && reversals.iter().any(|r| r.0 == *t_s);
                    let a = self.accelerations(
                        *t_s,
                        y,
                        &Held {
                            free: *free && !at_reversal,
                            ..held
                        },
                    );
                    mean_acc[0] += w * a[0];
                    mean_acc[1] += w * a[1];
                    points.push((at, held, aero, a, w));
                }
            }
            let shift = [acc[0] - mean_acc[0], acc[1] - mean_acc[1]];
            // The report's motion (angles, actuator, stroke phase) is the mid-step one;
            // its loads are the nodes' weighted sum.
            let mean = out.insert(self.motion(acc, &mid));
            let last = points.len().saturating_sub(1);
            for (k, (node, held, aero, a, w)) in points.iter().enumerate() {
                let a = [a[0] + shift[0], a[1] + shift[1]];
                let (report, frame) = self.report_framed(wing, held, *aero, a, node);
                if k == last {
                    end_report_frame = Some((*node, frame));
                }
                mean.add_scaled(&report, *w);
            }
            mean
        };
        for (at, jump) in strikes {
            if self.strike_share == StrikeShare::WholeInStep {
                // As before 2026-12-06 (`super::strike`), operation for operation.
                let held = self.aero_at(wing, &motion_at(at.t_s), &at).0;
                let per_s = [jump[0] / dt_s, jump[1] / dt_s];
                mean.add_scaled(&self.report(wing, &held, None, per_s, &at), 1.0);
                mean.add_scaled(&self.report(wing, &held, None, [0.0; 2], &at), -1.0);
                let m = self.mass_matrix(at.state.theta_rad, &held.added);
                mean.hinge_moment_nm += m[1][0] * per_s[0] + m[1][1] * per_s[1];
                continue;
            }
            // The impulse (its fluid part is in the added mass's change of impulse
            // over the step, below): this step reports its share, the next steps the
            // rest (`super::strike`).
            let (inertial, loads) = self.strike_loads(wing, &motion_at(at.t_s), &at, jump, dt_s);
            mean.add_scaled(&inertial, 1.0);
            let shares = self.strike_shares(start.t_s, at.t_s, dt_s);
            if shares[1] != 0.0 || shares[2] != 0.0 {
                moved.push((loads, shares));
            }
        }
        (end_report_frame, moved)
    }
}
