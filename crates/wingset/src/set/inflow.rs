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
//! Several pairs: a hind pair meets only its own wake here; the fore pair's wake on it is
//! not modelled (issue #38 leaves it open), and a set of several pairs says so by refusing
//! the dynamic inflow until it is.

use nalgebra::{Matrix3, Vector2, Vector3};
use wingforce::inflow::{DynamicInflow, InflowDisc, InflowForcing, InflowState};
use wingforce::{BodyMotion, Wing, WingForces};

use crate::error::{Error, Result};
use crate::sampling::LoadSampling;

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
}

/// Every pair's dynamic inflow (see the module documentation).
#[derive(Debug, Clone)]
pub struct PairInflows {
    pairs: Vec<Pair>,
}

impl PairInflows {
    /// The pairs of `wings` when their inflow is dynamic; `None` when no wing's is. Every
    /// wing must then have one, and one pair at most (module documentation).
    pub fn of(wings: &[Wing]) -> Result<Option<Self>> {
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
        if wings.len() > 2 {
            return Err(Error::Input(format!(
                "a dynamic inflow on {} wings: the hind pair's interference with the fore pair's wake is not modelled yet (issue #38); allowed: one pair, or inflow = \"frozen\" or \"off\"",
                wings.len()
            )));
        }
        let mut pairs = Vec::new();
        for start in (0..wings.len()).step_by(2) {
            let idx: Vec<usize> = (start..(start + 2).min(wings.len())).collect();
            pairs.push(Pair::new(wings, idx));
        }
        Ok(Some(Self { pairs }))
    }

    /// Sets each wing's inflow field from its pair's states for the coming step (module
    /// documentation, 1).
    pub fn apply(&mut self, wings: &mut [Wing], sampling: LoadSampling) {
        for p in &mut self.pairs {
            p.refresh_disc(wings);
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
            let r = p.inflow.disc.radius_m();
            for &i in &p.wings {
                let hinge = wings[i].hinge_in_stroke_m() - p.centre_s;
                let at_hinge = p.used.at(&hinge.xy(), r);
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

    /// The states each pair's wings took their last loads at.
    pub fn used(&self) -> Vec<InflowState> {
        self.pairs.iter().map(|p| p.used).collect()
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
    fn new(wings: &[Wing], idx: Vec<usize>) -> Self {
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
        let disc = Self::disc_of(wings, &idx);
        let inflow = DynamicInflow::hover(disc, thrust);
        Self {
            centre_s: stroke_from_body * centre_body_m,
            centre_body_m,
            stroke_from_body,
            used: inflow.state,
            inflow,
            wings: idx,
            last: None,
            amplitude_rad: first.kinematics().amplitude_rad,
        }
    }

    fn disc_of(wings: &[Wing], idx: &[usize]) -> InflowDisc {
        let w = &wings[idx[0]];
        InflowDisc::swept(
            w.fluid().density_kg_m3,
            w.kinematics().amplitude_rad,
            w.geometry().r_tip_m,
            idx.len(),
        )
    }

    /// The disc follows the amplitude the kinematics now have (a controller changes it).
    fn refresh_disc(&mut self, wings: &[Wing]) {
        let amplitude_rad = wings[self.wings[0]].kinematics().amplitude_rad;
        if amplitude_rad != self.amplitude_rad {
            self.amplitude_rad = amplitude_rad;
            self.inflow.disc = Self::disc_of(wings, &self.wings);
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
        let v_body = motion.velocity_m_s + motion.angular_velocity_rad_s.cross(&self.centre_body_m);
        InflowForcing {
            thrust_n,
            load_moment_nm,
            disc_velocity_m_s: self.stroke_from_body * v_body,
        }
    }
}
