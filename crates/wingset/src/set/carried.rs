//! What a host carries from one run of the set to another, or sets by hand: the step
//! memory of the midpoint prediction, each pair's dynamic inflow states, and the actuated
//! wings' dynamics and drives (a restart from a logged state, a start on a periodic motion,
//! a Floquet perturbation).

use wingforce::Wing;

use super::{PairInflows, StepMemory, WingSet};
use crate::actuated::{Drive, DynamicWing, StrikeShare};
use crate::error::{Error, Result};

impl WingSet {
    /// The memory the next step's midpoint prediction uses: the last step's body state
    /// ([`StepMemory`]); `None` for the step-start sampling and after a restart.
    pub fn step_memory(&self) -> Option<StepMemory> {
        self.previous()
    }

    /// Gives the set the memory of the step before the next one (a restart from a logged
    /// state that logged it too): an error unless the memory is of the step just before.
    pub fn set_step_memory(&mut self, memory: StepMemory) -> Result<()> {
        if memory.step + 1 != self.step {
            return Err(Error::Input(format!(
                "wing set: a step memory of step {} does not precede step {}",
                memory.step, self.step
            )));
        }
        self.prev_body = Some(memory);
        Ok(())
    }

    /// Forgets the body states of earlier steps: the host moved the body other than by
    /// integrating the set's loads (a reset, a disturbance set by hand), so the next step
    /// takes the body's state at its start ([`LoadSampling::Midpoint`] predicts the
    /// midpoint from the last two states otherwise).
    pub fn restart_motion(&mut self) {
        self.prev_body = None;
        if let Some(i) = &mut self.inflow {
            i.restart();
        }
    }

    /// Each wing pair's dynamic inflow states now (empty unless the wake answers:
    /// `wingforce::inflow::dynamic`).
    pub fn inflow_states(&self) -> Vec<wingforce::inflow::InflowState> {
        self.inflow
            .as_ref()
            .map_or_else(Vec::new, PairInflows::states)
    }

    /// Replaces each pair's dynamic inflow states (a start at a periodic inflow, a Floquet
    /// perturbation); an error for a set whose wake does not answer or a wrong count.
    pub fn set_inflow_states(&mut self, states: &[wingforce::inflow::InflowState]) -> Result<()> {
        match &mut self.inflow {
            Some(i) => i.set_states(states),
            None => Err(Error::Input(
                "wing set: no dynamic inflow to set (its wings' inflow is frozen or off)".into(),
            )),
        }
    }

    /// The dynamic inflow of the set's pairs, if its wake answers.
    pub fn pair_inflows(&self) -> Option<&PairInflows> {
        self.inflow.as_ref()
    }

    /// The actuated wings' dynamics (`None` for prescribed kinematics).
    pub fn dynamic_wings(&self) -> Option<&[DynamicWing]> {
        self.dynamic.as_deref()
    }

    /// Continues the actuated wings from given dynamics and wings (a periodic motion found
    /// at a frozen body state); does nothing for prescribed kinematics.
    ///
    /// `inflow`: the pair's dynamic inflow that went with them (its states and the stroke its
    /// disc was measured from), when the set's wake answers; `None` keeps the set's own.
    pub fn start_dynamic_from(
        &mut self,
        dynamic: &[DynamicWing],
        wings: &[Wing],
        inflow: Option<&PairInflows>,
    ) {
        if let (Some(mine), Some(given)) = (&mut self.inflow, inflow) {
            mine.clone_from(given);
            mine.restart();
        }
        if let Some(d) = &mut self.dynamic {
            // The set's own ways of taking the stops' loads and sharing strikes stay.
            let own = d.first().map(|w| (w.stage_loads(), w.strike_share_rule()));
            d.clone_from_slice(dynamic);
            for w in d.iter_mut() {
                w.set_load_sampling(self.sampling);
                if let Some((stage_loads, share)) = own {
                    if w.stage_loads() != stage_loads {
                        w.set_stage_loads(stage_loads);
                    }
                    w.set_strike_share(share);
                }
            }
            for (w, settled) in self.wings.iter_mut().zip(wings) {
                w.set_stroke_reference(settled.stroke_reference().cloned());
            }
        }
    }

    /// Overwrites the actuated wings' states (Floquet perturbations).
    pub fn set_wing_states(&mut self, states: &[crate::actuated::WingState]) {
        if let Some(d) = &mut self.dynamic {
            for (w, s) in d.iter_mut().zip(states) {
                w.set_state(*s);
            }
        }
        self.restart_motion();
    }

    /// How the actuated wings share a stop strike's impulse between the body's steps: by the
    /// host's pose ([`StrikeShare`]; a host that moves the body by the trapezoidal rule, as
    /// flapsim's do under a second-order sampling, sets [`StrikeShare::TrapezoidalPose`]).
    /// Nothing for prescribed kinematics.
    pub fn set_strike_share(&mut self, share: StrikeShare) {
        for w in self.dynamic.iter_mut().flatten() {
            w.set_strike_share(share);
        }
    }

    /// The drives of the actuated wings now.
    pub fn drives(&self) -> Option<Vec<Drive>> {
        self.dynamic
            .as_ref()
            .map(|d| d.iter().map(|w| *w.drive()).collect())
    }
}
