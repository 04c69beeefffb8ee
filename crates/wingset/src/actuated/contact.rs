//! The integrator's contact steps near and in the hinge stops (the law is [`super::stop`],
//! which also states how the steps are chosen and split): the part of
//! [`DynamicWing`]'s sub-step that only a hinge with stops takes.

use super::dynamics::{DynamicWing, Held, Nodes, Reheld, StageLoads, Stroke};
use super::stop::{MAX_CONTACT_STEPS, StopContact, hermite_root, illinois_root};

/// Most segments (touches and releases) of one sub-step on an inelastic stop.
const MAX_STOP_EVENTS: usize = 64;
use crate::error::{Error, Result};

impl DynamicWing {
    /// Advances the structure over one sub-step of length `h`: away from the stops, one
    /// Runge-Kutta step with the loads `held` at its start and `reheld` at its later stages;
    /// near or in a stop, contact steps short enough for the contact, each with the loads
    /// `reheld` at its start and split where the wing touches a stop (see [`super::stop`]).
    /// Without stops the loads are held over the sub-step under the step-start sampling and
    /// taken afresh at every stage under a second-order one. `k1a`: the accelerations at
    /// (t0, y0) when known; `predicted_end`: see [`Self::advance_inelastic`].
    /// Every state it passes after (t0, y0), the end included, is pushed on `nodes` with its
    /// time: the points between which the motion is smooth (a strike's touch and release
    /// splits, the contact steps that resolve it), for the step's mean loads; a node's flag
    /// says to take its accelerations without the stops (the touch's left side).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn advance(
        &self,
        t0: f64,
        y0: &[f64; 4],
        h: f64,
        held: &Held,
        k1a: Option<[f64; 2]>,
        nodes: &mut Nodes,
        reheld: Reheld,
        predicted_end: &mut Option<[f64; 4]>,
    ) -> Result<[f64; 4]> {
        let k1 = || k1a.unwrap_or_else(|| self.accelerations(t0, y0, held));
        let Some(stop) = self.model().hinge.contact else {
            // Second order (LoadSampling::Midpoint or StepMean): the loads taken afresh at
            // every stage. (Linear between the sub-step's ends, as on an inelastic stop, the
            // RoboBee's wing, a lightly damped pitch mode driven below its resonance, came
            // out 170 times further from its fine run's velocity after 30 wingbeats at 100
            // steps per wingbeat: 1.4e-2 against 8.2e-5.)
            let stage = self.load_sampling().is_second_order().then_some(reheld);
            let y = self.rk4(t0, y0, h, held, Some(k1()), stage).0;
            nodes.push((t0 + h, y, false));
            return Ok(y);
        };
        if stop.is_inelastic() {
            return self.advance_inelastic(&stop, t0, y0, h, held, nodes, reheld, predicted_end);
        }
        let (y, stages) = self.rk4(t0, y0, h, held, Some(k1()), Some(reheld));
        let rest = self.model().hinge.rest_rad;
        // Clear of the stops: even at its rate the pitch cannot reach one within h.
        let clear = |y: &[f64; 4]| stop.angle_rad - (y[1] - rest).abs() - y[3].abs() * h > 0.0;
        if clear(y0) && clear(&y) && stages.iter().all(clear) {
            nodes.push((t0 + h, y, false));
            return Ok(y);
        }
        let m_eff = self.pitch_inertia_effective(&self.mass_matrix(y0[1], &held.added));
        let n = (h / stop.max_step_s(m_eff)).ceil().max(1.0);
        if n.is_nan() || n > MAX_CONTACT_STEPS as f64 {
            return Err(Error::Analysis(format!(
                "the hinge stops' contact (stiffness {:e} N m/rad, damping ratio {:.2}, effective pitch inertia {:e} kg m^2) needs {n:.0} contact steps in a sub-step of {:e} s, more than {MAX_CONTACT_STEPS}: lengthen [actuation.hinge.stop] contact_time_s (or lower its stiffness_nm_rad), or shorten the step",
                stop.stiffness_nm_rad, stop.damping_ratio, m_eff, h
            )));
        }
        let n = n as usize;
        let hc = h / n as f64;
        let mut y = *y0;
        for k in 0..n {
            let t = t0 + k as f64 * hc;
            // The aerodynamic loads held over each contact step are taken at its start: a
            // strike changes the rates they depend on within a few contact steps.
            let held = &if k == 0 { *held } else { reheld(t, &y) };
            let free = Held {
                free: true,
                ..*held
            };
            if stop.penetration(y[1] - rest).0 >= 0.0 {
                // In a stop: the contact force is continuous until the wing leaves, but its
                // slope jumps where the clamp takes over (k_c delta + c delta_dot falls
                // through zero): split the step there too, found by regula falsi
                // (Illinois) on the contact's own Runge-Kutta steps.
                let y1 = self.rk4(t, &y, hc, held, None, None).0;
                let push = |y: &[f64; 4]| self.stop_push(&stop, y, held);
                let (p0, p1) = (push(&y), push(&y1));
                if !(p0 > 0.0 && p1 <= 0.0) {
                    y = y1;
                    nodes.push((t + hc, y, false));
                    continue;
                }
                let (tau, ya) =
                    illinois_root(hc, (p0, p1), y1, (40, 1e-13 * p0, 1e-13 * hc), |tau| {
                        let ya = self.rk4(t, &y, tau, held, None, None).0;
                        (push(&ya), ya)
                    });
                nodes.push((t + tau, ya, false));
                y = self.rk4(t + tau, &ya, hc - tau, held, None, None).0;
                nodes.push((t + hc, y, false));
                continue;
            }
            // Out of the stops: the step as if there were none. If that ends in a stop, the
            // wing touched it within the step, where the contact force jumps (the dashpot):
            // find the touch on the contact-free path, a first guess on the step's cubic
            // Hermite interpolant refined by Newton on the contact-free part's own
            // Runge-Kutta step (to round-off), put the wing exactly on the stop and finish
            // the step with the contact on from its first stage.
            let yf = self.rk4(t, &y, hc, &free, None, None).0;
            if stop.penetration(yf[1] - rest).0 < 0.0 {
                y = yf;
                nodes.push((t + hc, y, false));
                continue;
            }
            let s = (yf[1] - rest).signum();
            let g = |y: &[f64; 4]| s * (y[1] - rest) - stop.angle_rad;
            let mut f = hermite_root(g(&y), s * y[3], g(&yf), s * yf[3], hc);
            let mut ya = self.rk4(t, &y, f * hc, &free, None, None).0;
            for _ in 0..6 {
                let (ga, rate) = (g(&ya), s * ya[3]);
                if rate.is_nan() || rate <= 0.0 || ga.abs() <= 1e-15 * stop.angle_rad {
                    break;
                }
                let next = (f - ga / (rate * hc)).clamp(0.0, 1.0);
                if next == f {
                    break;
                }
                f = next;
                ya = self.rk4(t, &y, f * hc, &free, None, None).0;
            }
            ya[1] = rest + s * stop.angle_rad;
            // The contact force jumps at the touch (the dashpot): the node is taken twice,
            // with the accelerations just before (free) and just after.
            nodes.push((t + f * hc, ya, true));
            nodes.push((t + f * hc, ya, false));
            let held = reheld(t + f * hc, &ya);
            y = self
                .rk4(t + f * hc, &ya, (1.0 - f) * hc, &held, None, None)
                .0;
            nodes.push((t + hc, y, false));
        }
        Ok(y)
    }

    /// [`Self::advance`] with an inelastic stop (restitution 0, a constraint; see
    /// [`super::stop`]): the sub-step in segments, each one Runge-Kutta step: free (split at
    /// a touch, where the strike's impulse stops the pitch) or resting on the stop (split
    /// where the wing leaves it).
    ///
    /// A segment's loads are evaluated at its start (afresh after a touch or a release: the
    /// rates, and so the loads, jump or turn there) and at the sub-step's end, on the state
    /// the segment's own path reaches with its start's loads held, and taken linear in time
    /// between the two at the later Runge-Kutta stages and along the path the touch and the
    /// release are searched on. Held loads put an O(h^2) error in the predicted rates, so the
    /// end's loads, and with them the loads over the segment, are second-order accurate, as
    /// the body's step is; two evaluations per segment where the loads at every stage took
    /// four, and the release's search takes none (it took four per iteration: three stages
    /// and the holding moment's). The end's
    /// state is written to `predicted_end` when the last segment reaches the sub-step's end:
    /// the step's mean loads take its loads as their last node's
    /// (`dynamics::step`). With [`StageLoads::EveryStage`] (logs written before
    /// 2026-12-07) the loads are taken afresh at every stage instead.
    #[allow(clippy::too_many_arguments)]
    fn advance_inelastic(
        &self,
        stop: &StopContact,
        t0: f64,
        y0: &[f64; 4],
        h: f64,
        held: &Held,
        nodes: &mut Nodes,
        reheld: Reheld,
        predicted_end: &mut Option<[f64; 4]>,
    ) -> Result<[f64; 4]> {
        let rest = self.model().hinge.rest_rad;
        let end = t0 + h;
        let (mut t, mut y) = (t0, *y0);
        let mut loads = *held;
        let every_stage = self.stage_loads() == StageLoads::EveryStage;
        *predicted_end = None;
        // After the wing leaves a stop, the next segment is free even where round-off
        // leaves the holding moment a hair above zero.
        let mut released = false;
        for segment in 0..MAX_STOP_EVENTS {
            if segment > 0 {
                loads = reheld(t, &y);
            }
            // The constraint at the segment's start: a wing at or past a stop and moving
            // into it strikes it now.
            let (s, beyond) = stop.beyond_rad(rest, y[1]);
            if beyond >= 0.0 && (s * y[3] > 0.0 || beyond > 0.0) {
                y[1] = stop.stop_theta_rad(rest, s);
                if s * y[3] > 0.0 {
                    nodes.push((t, y, true));
                    y = self.strike(&y, &loads);
                    nodes.push((t, y, false));
                    // The rates jumped: the segment's loads are the struck wing's (with the
                    // loads at every stage, its stages took them afresh).
                    if !every_stage {
                        loads = reheld(t, &y);
                    }
                }
            }
            let rem = end - t;
            let resting = !released
                && self
                    .stop_hold_nm(t, &y, &loads)
                    .is_some_and(|hold| hold >= 0.0);
            released = false;
            // The segment's path: held on the stop or free of it.
            let base = Held {
                locked: resting,
                free: !resting,
                ..loads
            };
            // Its loads at the later stages: linear between its start's and its end's (see
            // above), or afresh at each.
            let k1 = self.accelerations(t, &y, &base);
            let predicted = (!every_stage).then(|| self.segment_end(t, &y, end, &base, k1, reheld));
            let lerped;
            let stage: Reheld = match predicted {
                Some((_, l_b)) => {
                    lerped = lerp_loads(t, loads, end, l_b);
                    &lerped
                }
                None => reheld,
            };
            if resting {
                let lock = base;
                let hold_after = |tau: f64| {
                    let ya = self.rk4(t, &y, tau, &lock, Some(k1), Some(stage)).0;
                    // The sub-step's end exactly (its loads are then the step's last node's).
                    let ta = if tau == rem { end } else { t + tau };
                    let hold = self.stop_hold_nm(ta, &ya, &stage(ta, &ya));
                    (ya, hold.unwrap_or(f64::NAN))
                };
                let (y1, h1) = hold_after(rem);
                if h1 >= 0.0 {
                    y = y1;
                    t = end;
                    nodes.push((t, y, false));
                    *predicted_end = predicted.map(|p| p.0);
                    break;
                }
                // The wing leaves within: regula falsi (Illinois) on the holding moment
                // along the held path.
                let h0 = self.stop_hold_nm(t, &y, &loads).unwrap_or(0.0);
                let tol = (60, 1e-12 * h0.abs().max(1e-300), 1e-13 * h);
                let (tau, ya) = illinois_root(rem, (h0, h1), y1, tol, |tau| {
                    let (ya, pa) = hold_after(tau);
                    (pa, ya)
                });
                t += tau;
                y = ya;
                nodes.push((t, y, false));
                released = true;
                continue;
            }
            // Free: one step as if there were no stop; if it (or a stage) passes a stop,
            // the wing touched it within: find the touch on that path, strike, go on.
            let free = base;
            let (y1, stages) = self.rk4(t, &y, rem, &free, Some(k1), Some(stage));
            let past = |y: &[f64; 4]| stop.beyond_rad(rest, y[1]).1 > 0.0;
            let path = |tau: f64| self.rk4(t, &y, tau, &free, Some(k1), Some(stage)).0;
            // Where only a stage passed a stop, the path itself may not: look along it
            // (eighths of the step) for a point past the stop.
            let crossed = past(&y1)
                || (stages.iter().any(past) && (1..8).any(|k| past(&path(rem * k as f64 / 8.0))));
            if !crossed {
                y = y1;
                t = end;
                nodes.push((t, y, false));
                *predicted_end = predicted.map(|p| p.0);
                break;
            }
            let side = if past(&y1) {
                y1[1] - rest
            } else {
                stages
                    .iter()
                    .find(|st| past(st))
                    .map_or(0.0, |st| st[1] - rest)
            }
            .signum();
            let g = |y: &[f64; 4]| side * (y[1] - stop.stop_theta_rad(rest, side));
            // The touch on the free path: where the step ends past the stop, a first guess
            // on the step's cubic Hermite interpolant refined by Newton on the path's own
            // Runge-Kutta steps (to round-off); where only a point within passed it,
            // bisection.
            let mut tau;
            let mut ya;
            if past(&y1) && g(&y) <= 0.0 {
                let mut f = hermite_root(g(&y), side * y[3], g(&y1), side * y1[3], rem);
                ya = path(f * rem);
                for _ in 0..8 {
                    let (ga, rate) = (g(&ya), side * ya[3]);
                    if rate.is_nan() || rate <= 0.0 || ga.abs() <= 1e-15 * stop.angle_rad {
                        break;
                    }
                    let next = (f - ga / (rate * rem)).clamp(0.0, 1.0);
                    if next == f {
                        break;
                    }
                    f = next;
                    ya = path(f * rem);
                }
                tau = f * rem;
            } else {
                let first = (1..=8)
                    .map(|k| rem * k as f64 / 8.0)
                    .find(|&tk| g(&path(tk)) > 0.0)
                    .unwrap_or(rem);
                let (mut lo, mut hi) = ((first - rem / 8.0).max(0.0), first);
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    if g(&path(mid)) > 0.0 {
                        hi = mid;
                    } else {
                        lo = mid;
                    }
                    if hi - lo <= 1e-13 * h {
                        break;
                    }
                }
                tau = lo;
                ya = if tau > 0.0 { path(tau) } else { y };
            }
            if !tau.is_finite() {
                tau = 0.0;
                ya = y;
            }
            t += tau;
            ya[1] = stop.stop_theta_rad(rest, side);
            // The strike's impulse stops the pitch: the node is taken on both sides.
            nodes.push((t, ya, true));
            y = self.strike(&ya, &reheld(t, &ya));
            nodes.push((t, y, false));
        }
        if t < end {
            return Err(Error::Analysis(format!(
                "the wing met its inelastic hinge stops more than {MAX_STOP_EVENTS} times in one sub-step of {h:e} s (at t = {t:e} s): shorten the step"
            )));
        }
        Ok(y)
    }

    /// The end of a segment from (t, y) to `end`: the state its path reaches there with the
    /// loads `base` (its start's) held, one Runge-Kutta step (`k1`: the accelerations at
    /// its start), and the loads `reheld` takes there. Held loads put an O(h^2) error in
    /// the rates, so the end's loads are second-order accurate; the segment's loads at its
    /// later stages are then taken linear in time between its start's and these
    /// ([`lerp_loads`]): two evaluations per segment where loads at every stage take four.
    /// Under the split scheme ([`DynamicWing::split_scheme`]) the path is
    /// the midpoint rule's (second order, one solution of the equations where the
    /// Runge-Kutta step takes three): its own O(h^3) error in the rates is below the held
    /// loads' O(h^2).
    pub(super) fn segment_end(
        &self,
        t: f64,
        y: &[f64; 4],
        end: f64,
        base: &Held,
        k1: [f64; 2],
        reheld: Reheld,
    ) -> ([f64; 4], Held) {
        let h = end - t;
        let yp = match self.split_scheme() {
            true => {
                let half = 0.5 * h;
                let ym = [
                    y[0] + half * y[2],
                    y[1] + half * y[3],
                    y[2] + half * k1[0],
                    y[3] + half * k1[1],
                ];
                let km = self.stage_accelerations(t + half, &ym, base);
                [
                    y[0] + h * ym[2],
                    y[1] + h * ym[3],
                    y[2] + h * km[0],
                    y[3] + h * km[1],
                ]
            }
            false => self.rk4(t, y, h, base, Some(k1), None).0,
        };
        (yp, reheld(end, &yp))
    }

    /// The state just after a perfectly inelastic strike of the wing at `y` (on the stop):
    /// the impulse that takes the pitch rate to zero, and with the stroke free the stroke
    /// rate it moves with it (first row of M dq_dot = (0, Lambda)).
    fn strike(&self, y: &[f64; 4], held: &Held) -> [f64; 4] {
        let mut out = *y;
        if let Stroke::Driven { .. } = self.model().stroke {
            let m = self.mass_matrix(y[1], &held.added);
            out[2] += y[3] * m[0][1] / m[0][0];
        }
        out[3] = 0.0;
        out
    }

    /// The nearer stop's unclamped push k_c delta + c delta_dot at state `y` (positive: the
    /// stop pushes the wing out), N m.
    fn stop_push(&self, stop: &StopContact, y: &[f64; 4], held: &Held) -> f64 {
        let dev = y[1] - self.model().hinge.rest_rad;
        let (delta, s) = stop.penetration(dev);
        let m_eff = self.pitch_inertia_effective(&self.mass_matrix(y[1], &held.added));
        let c = 2.0 * stop.damping_ratio * (stop.stiffness_nm_rad * m_eff).sqrt();
        stop.stiffness_nm_rad * delta + c * s * y[3]
    }
}

/// The loads at time `ts` of a segment whose loads are `l_a` at `t_a` and `l_b` at `end`,
/// linear in time between them ([`DynamicWing::segment_end`]); the flags are `l_a`'s.
pub(super) fn lerp_loads(
    t_a: f64,
    l_a: Held,
    end: f64,
    l_b: Held,
) -> impl Fn(f64, &[f64; 4]) -> Held {
    let rem = end - t_a;
    move |ts: f64, _: &[f64; 4]| l_a.lerp(&l_b, if rem > 0.0 { (ts - t_a) / rem } else { 1.0 })
}
