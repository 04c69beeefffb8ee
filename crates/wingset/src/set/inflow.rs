//! The wing set's dynamic inflow: each pair's wake, stepped with the set (issue #38).
//!
//! Wings whose [`wingforce::InducedInflow`] is dynamic are grouped into pairs in the set's
//! order ((0, 1), (2, 3), ...; a last wing alone is a disc of its own sector). Each pair
//! sweeps a disc ([`wingforce::inflow::InflowDisc`], from its stroke amplitude and tip
//! radius) centred between its hinges in the stroke plane, and carries three inflow states
//! ([`wingforce::inflow::dynamic`]). Every step:
//!
//! 1. [`PairInflows::apply`] sets each wing's inflow field from its pair's states: the
//!    states at the step's start ([`LoadSampling::StepStart`]), or at its midpoint
//!    ([`LoadSampling::Midpoint`]), extrapolated by half the last step's change (as the
//!    set predicts the body's midpoint velocity);
//! 2. the wings' loads are taken;
//! 3. [`PairInflows::advance`] steps the states over the step with the pair's loads of that
//!    step held: its aerodynamic force along the stroke-plane normal and that force's first
//!    moments over the plane about the disc's centre, and the disc's velocity through the air.
//!
//! **Actuated wings** sweep the disc their dynamics make, not a prescribed one: a pair built
//! with [`DiscAmplitude::Measured`] sizes its disc from the stroke its wings actually swept
//! over the last wingbeat (the mean of its last two half-stroke excursions, each wing's
//! extremes found where its stroke rate changes sign, interpolated within the step; the pair
//! the mean of its wings). Until a wing has swept a whole wingbeat the disc is its
//! kinematics' nominal amplitude (the model file's `[kinematics]`, which for an actuated
//! vehicle is its nominal motion), so a run from rest starts from that disc.
//!
//! **Several pairs** (a four-winged flier) overlap: each pair's disc also receives the share
//! of every other pair's wake that crosses it ([`wingforce::inflow::interference`]: the
//! other pair's linear field at the overlap's centroid, times the overlap's share of the
//! disc), in its momentum balance (as a flow through it) and on its wings (uniformly, on top
//! of their own field). The shares follow the discs as their amplitudes change.

use nalgebra::{Matrix3, Vector2, Vector3};
use wingforce::inflow::{
    DynamicInflow, InflowDisc, InflowForcing, InflowState, PlacedDisc, WakeShare, wake_share,
};
use wingforce::{BodyMotion, Wing, WingForces};

use crate::error::{Error, Result};
use crate::sampling::LoadSampling;

/// Where a pair's disc takes its stroke amplitude from (module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DiscAmplitude {
    /// The wings' kinematics (prescribed wings: a controller changes it between wingbeats).
    Kinematics,
    /// The stroke the wings swept over their last wingbeat (actuated wings, whose stroke is
    /// an output of their dynamics).
    Measured,
}

/// One wing's stroke extremes as its dynamics sweep them: the last stroke angle and rate
/// seen, and the last reversals' angles.
#[derive(Debug, Clone, Copy, Default)]
struct StrokeTracker {
    /// The last sample's stroke angle (rad) and rate (rad/s), if any.
    last: Option<(f64, f64)>,
    /// The stroke angles of the last three reversals, newest last (rad).
    reversals: [Option<f64>; 3],
}

impl StrokeTracker {
    /// Takes the stroke angle and rate of a step `dt_s` after the last one.
    fn push(&mut self, phi: f64, phi_dot: f64, dt_s: f64) {
        if let Some((phi0, rate0)) = self.last
            && rate0 != 0.0
            && (rate0 > 0.0) != (phi_dot > 0.0)
        {
            // The rate taken linear over the step: it vanishes s after the last sample,
            // where the angle has moved by the trapezoid rate0 s / 2.
            let s = dt_s * rate0 / (rate0 - phi_dot);
            self.reversals = [
                self.reversals[1],
                self.reversals[2],
                Some(phi0 + 0.5 * rate0 * s),
            ];
        }
        self.last = Some((phi, phi_dot));
    }

    /// The stroke swept over the last wingbeat (the mean of the last two half-stroke
    /// excursions), rad; `None` before three reversals.
    fn amplitude_rad(&self) -> Option<f64> {
        match self.reversals {
            [Some(a), Some(b), Some(c)] => Some(0.5 * ((b - a).abs() + (c - b).abs())),
            _ => None,
        }
    }
}

/// One pair's disc and states.
#[derive(Debug, Clone)]
struct Pair {
    /// The wings' indices in the set.
    wings: Vec<usize>,
    inflow: DynamicInflow,
    /// The disc's centre (between the hinges) in the stroke frame, m.
    centre_s: Vector3<f64>,
    /// The disc's centre in the body frame, m.
    centre_body_m: Vector3<f64>,
    stroke_from_body: Matrix3<f64>,
    /// The states the wings' loads were last taken at.
    used: InflowState,
    /// The states at the last step's start (the midpoint prediction extrapolates from
    /// them), or `None` after a restart.
    last: Option<InflowState>,
    /// The amplitude the disc was last sized for, rad.
    amplitude_rad: f64,
    /// Each wing's swept stroke, for a disc of [`DiscAmplitude::Measured`].
    trackers: Option<Vec<StrokeTracker>>,
    /// The other pairs' downwash through this disc that its wings met in the last step
    /// (several pairs), m/s.
    external_m_s: f64,
}

/// Every pair's dynamic inflow (see the module documentation).
#[derive(Debug, Clone)]
pub struct PairInflows {
    pairs: Vec<Pair>,
    /// shares[p][q]: the share of pair q's wake that crosses pair p's disc (zero for p = q).
    shares: Vec<Vec<WakeShare>>,
}

impl PairInflows {
    /// The pairs of `wings` when their inflow is dynamic; `None` when no wing's is. Every
    /// wing must then have one, and one pair at most (module documentation). Each disc's
    /// amplitude comes from `amplitude` (the kinematics' for prescribed wings, the swept
    /// stroke for actuated ones).
    pub fn of(wings: &[Wing], amplitude: DiscAmplitude) -> Result<Option<Self>> {
        let dynamic = |w: &Wing| w.options().induced_inflow.is_some_and(|i| i.dynamic);
        let n_dynamic = wings.iter().filter(|w| dynamic(w)).count();
        if n_dynamic == 0 {
            return Ok(None);
        }
        if n_dynamic != wings.len() {
            return Err(Error::Input(format!(
                "{n_dynamic} of the set's {} wings have a dynamic inflow: the pairs' wakes are the set's, so all its wings or none must (aero inflow = \"dynamic\")",
                wings.len()
            )));
        }
        let mut pairs = Vec::new();
        for start in (0..wings.len()).step_by(2) {
            let idx: Vec<usize> = (start..(start + 2).min(wings.len())).collect();
            pairs.push(Pair::new(wings, idx, amplitude));
        }
        let mut set = Self {
            pairs,
            shares: Vec::new(),
        };
        set.place();
        Ok(Some(set))
    }

    /// The shares of each pair's wake on every other pair's disc, at the discs' sizes now.
    fn place(&mut self) {
        let placed: Vec<PlacedDisc> = self.pairs.iter().map(Pair::placed).collect();
        self.shares = placed
            .iter()
            .enumerate()
            .map(|(p, to)| {
                placed
                    .iter()
                    .enumerate()
                    .map(|(q, from)| {
                        if p == q {
                            WakeShare::default()
                        } else {
                            wake_share(to, from)
                        }
                    })
                    .collect()
            })
            .collect();
    }

    /// The other pairs' downwash through pair `p`'s disc at their states `states`, m/s.
    fn external_m_s(&self, p: usize, states: impl Iterator<Item = InflowState>) -> f64 {
        states
            .zip(&self.shares[p])
            .map(|(s, share)| share.downwash_m_s(&s))
            .sum()
    }

    /// Sets each wing's inflow field from its pair's states for the coming step (module
    /// documentation, 1).
    pub fn apply(&mut self, wings: &mut [Wing], sampling: LoadSampling) {
        let mut resized = false;
        for p in &mut self.pairs {
            resized |= p.refresh_disc(wings);
        }
        if resized && self.pairs.len() > 1 {
            self.place();
        }
        for p in &mut self.pairs {
            p.used = match (sampling, &p.last) {
                (s, Some(last)) if s.is_second_order() => {
                    let now = p.inflow.state;
                    InflowState {
                        mean_m_s: now.mean_m_s + 0.5 * (now.mean_m_s - last.mean_m_s),
                        gradient_m_s: now.gradient_m_s
                            + 0.5 * (now.gradient_m_s - last.gradient_m_s),
                    }
                }
                _ => p.inflow.state,
            };
        }
        for k in 0..self.pairs.len() {
            let external = if self.pairs.len() > 1 {
                self.external_m_s(k, self.pairs.iter().map(|p| p.used))
            } else {
                0.0
            };
            let p = &mut self.pairs[k];
            p.external_m_s = external;
            let r = p.inflow.disc.radius_m();
            for &i in &p.wings {
                let hinge = wings[i].hinge_in_stroke_m() - p.centre_s;
                let at_hinge = p.used.at(&hinge.xy(), r) + external;
                wings[i].set_inflow_field(at_hinge, p.used.gradient_m_s / r);
            }
        }
    }

    /// Steps the states over `dt_s` with the loads `forces` (the set's wings, in order) of
    /// the step, for a body moving through the air as `motion` (module documentation, 3).
    pub fn advance(
        &mut self,
        wings: &[Wing],
        forces: &[WingForces],
        motion: &BodyMotion,
        dt_s: f64,
    ) -> Result<()> {
        for p in &mut self.pairs {
            p.track_stroke(forces, dt_s);
            let forcing = p.forcing(wings, forces, motion);
            let before = p.inflow.state;
            p.inflow
                .advance(&forcing, dt_s)
                .map_err(|e| Error::Input(e.to_string()))?;
            p.last = Some(before);
        }
        Ok(())
    }

    /// Forgets the last step's loads (a host restarted the body: the next step takes the
    /// states as they are).
    pub fn restart(&mut self) {
        for p in &mut self.pairs {
            p.last = None;
        }
    }

    /// Each pair's states now.
    pub fn states(&self) -> Vec<InflowState> {
        self.pairs.iter().map(|p| p.inflow.state).collect()
    }

    /// Adds each pair's states now, times `weight`, to `sums` (one per pair; grown to the
    /// pairs' count): the running mean of the states over a wingbeat.
    pub fn add_states_to(&self, sums: &mut Vec<InflowState>, weight: f64) {
        sums.resize(self.pairs.len(), InflowState::default());
        for (sum, p) in sums.iter_mut().zip(&self.pairs) {
            sum.mean_m_s += weight * p.inflow.state.mean_m_s;
            sum.gradient_m_s += weight * p.inflow.state.gradient_m_s;
        }
    }

    /// The states each pair's wings took their last loads at.
    pub fn used(&self) -> Vec<InflowState> {
        self.pairs.iter().map(|p| p.used).collect()
    }

    /// The slowest time constant of any pair's states at the states now, for a body moving
    /// through the air as `motion` (`DynamicInflow::time_constants_s`: in forward flight
    /// and climb the flow through the disc is faster than the induced velocity alone, and
    /// the states settle faster than in hover), s.
    pub fn slowest_time_constant_s(&self, motion: &BodyMotion) -> f64 {
        self.pairs
            .iter()
            .flat_map(|p| {
                let forcing = InflowForcing {
                    disc_velocity_m_s: p.disc_velocity_m_s(motion),
                    ..Default::default()
                };
                p.inflow.time_constants_s(&forcing)
            })
            .fold(0.0, f64::max)
    }

    /// Each pair's disc.
    pub fn discs(&self) -> Vec<InflowDisc> {
        self.pairs.iter().map(|p| p.inflow.disc).collect()
    }

    /// Replaces the states (one per pair), forgetting the last step's loads.
    pub fn set_states(&mut self, states: &[InflowState]) -> Result<()> {
        if states.len() != self.pairs.len() {
            return Err(Error::Input(format!(
                "{} inflow states for a set of {} pair(s); allowed: one per pair",
                states.len(),
                self.pairs.len()
            )));
        }
        if states
            .iter()
            .any(|s| !s.to_array().iter().all(|x| x.is_finite()))
        {
            return Err(Error::Input(format!(
                "inflow states {states:?}: allowed: finite velocities"
            )));
        }
        for (p, s) in self.pairs.iter_mut().zip(states) {
            p.inflow.state = *s;
            p.last = None;
        }
        Ok(())
    }
}

impl Pair {
    fn new(wings: &[Wing], idx: Vec<usize>, amplitude: DiscAmplitude) -> Self {
        let first = &wings[idx[0]];
        let thrust: f64 = idx
            .iter()
            .map(|&i| {
                wings[i]
                    .options()
                    .induced_inflow
                    .map_or(0.0, |f| f.thrust_n)
            })
            .sum();
        let centre_body_m = idx
            .iter()
            .map(|&i| wings[i].mount().hinge_in_body_m)
            .sum::<Vector3<f64>>()
            / idx.len() as f64;
        let stroke_from_body = first.body_from_stroke().transpose();
        let disc = Self::disc_of(wings, &idx, first.kinematics().amplitude_rad);
        let inflow = DynamicInflow::hover(disc, thrust);
        Self {
            centre_s: stroke_from_body * centre_body_m,
            centre_body_m,
            stroke_from_body,
            used: inflow.state,
            inflow,
            last: None,
            amplitude_rad: first.kinematics().amplitude_rad,
            trackers: (amplitude == DiscAmplitude::Measured)
                .then(|| vec![StrokeTracker::default(); idx.len()]),
            external_m_s: 0.0,
            wings: idx,
        }
    }

    fn disc_of(wings: &[Wing], idx: &[usize], amplitude_rad: f64) -> InflowDisc {
        let w = &wings[idx[0]];
        InflowDisc::swept(
            w.fluid().density_kg_m3,
            amplitude_rad,
            w.geometry().r_tip_m,
            idx.len(),
        )
    }

    /// The amplitude the disc has now: the kinematics' (a controller changes it), or the
    /// mean stroke the wings swept over their last wingbeat once each has swept one.
    fn amplitude_now(&self, wings: &[Wing]) -> f64 {
        let nominal = wings[self.wings[0]].kinematics().amplitude_rad;
        let Some(trackers) = &self.trackers else {
            return nominal;
        };
        let swept: Option<Vec<f64>> = trackers.iter().map(StrokeTracker::amplitude_rad).collect();
        swept.map_or(nominal, |a| a.iter().sum::<f64>() / a.len() as f64)
    }

    /// The disc follows the amplitude its wings now have; true when it changed.
    fn refresh_disc(&mut self, wings: &[Wing]) -> bool {
        let amplitude_rad = self.amplitude_now(wings);
        if amplitude_rad == self.amplitude_rad {
            return false;
        }
        self.amplitude_rad = amplitude_rad;
        self.inflow.disc = Self::disc_of(wings, &self.wings, amplitude_rad);
        true
    }

    /// The disc placed in the body.
    fn placed(&self) -> PlacedDisc {
        let s = &self.stroke_from_body;
        PlacedDisc {
            centre_body_m: self.centre_body_m,
            axes_body: [0, 1, 2].map(|k| s.row(k).transpose()),
            radius_m: self.inflow.disc.radius_m(),
        }
    }

    /// Takes each wing's stroke of the step into its tracker (a measured disc).
    fn track_stroke(&mut self, forces: &[WingForces], dt_s: f64) {
        if let Some(trackers) = &mut self.trackers {
            for (t, &i) in trackers.iter_mut().zip(&self.wings) {
                let a = &forces[i].angles;
                t.push(a.phi, a.phi_dot, dt_s);
            }
        }
    }

    /// The pair's loads on the disc and the disc's motion (module documentation, 3).
    fn forcing(&self, wings: &[Wing], forces: &[WingForces], motion: &BodyMotion) -> InflowForcing {
        let mut thrust_n = 0.0;
        let mut moment_s = Vector3::zeros();
        for &i in &self.wings {
            let t = &forces[i].total;
            let f_s = self.stroke_from_body * t.force_n;
            let arm_s = wings[i].hinge_in_stroke_m() - self.centre_s;
            let m_s = self.stroke_from_body * t.moment_hinge_nm + arm_s.cross(&f_s);
            thrust_n += f_s.z;
            moment_s += m_s;
        }
        // A normal load dT at (x, y) has the moment (y dT, -x dT) about the centre.
        let load_moment_nm = Vector2::new(-moment_s.y, moment_s.x);
        InflowForcing {
            thrust_n,
            load_moment_nm,
            disc_velocity_m_s: self.disc_velocity_m_s(motion),
        }
    }

    /// The disc's velocity through the air, stroke frame, with the other pairs' downwash
    /// its wings met as a climb's flow through it (module documentation), m/s.
    fn disc_velocity_m_s(&self, motion: &BodyMotion) -> Vector3<f64> {
        let v_body = motion.velocity_m_s + motion.angular_velocity_rad_s.cross(&self.centre_body_m);
        self.stroke_from_body * v_body + Vector3::z() * self.external_m_s
    }
}

#[cfg(test)]
mod tests {
    use super::StrokeTracker;

    /// A stroke phi = phi0 + A cos(2 pi f t) sampled at 17 steps a wingbeat (its reversals
    /// fall between samples) reads as 2A swept: the extremes, interpolated on a rate taken
    /// linear over the step, are second order in the step (error about (pi / 17)^2 / 8 of A
    /// here), and nothing before three reversals.
    #[test]
    fn a_sampled_sinusoid_sweeps_twice_its_amplitude() {
        let (amp, f, n) = (1.1_f64, 30.0, 17);
        let dt = 1.0 / (f * n as f64);
        let w = 2.0 * std::f64::consts::PI * f;
        let mut t = StrokeTracker::default();
        let mut seen = Vec::new();
        for k in 0..(3 * n) {
            let s = k as f64 * dt + 0.13 * dt;
            t.push(0.2 + amp * (w * s).cos(), -amp * w * (w * s).sin(), dt);
            seen.push(t.amplitude_rad());
        }
        assert!(seen[..n].iter().all(Option::is_none), "{seen:?}");
        let swept = t.amplitude_rad().unwrap();
        let bound = (std::f64::consts::PI / n as f64).powi(2) / 8.0;
        assert!(
            (swept / (2.0 * amp) - 1.0).abs() < bound,
            "{swept} against {} (bound {bound})",
            2.0 * amp
        );
    }
}
