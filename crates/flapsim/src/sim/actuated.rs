//! An actuated vehicle in the [`Simulation`]: its wings' dynamics stepped with the body,
//! their loads and inertial reaction, and the wing states the analyses set and read.

use wingforce::{BodyMotion, Term, Wing};

use super::{BodyLoad, Simulation, State, StepOutput};
use crate::actuated::{ActuatedWingOutput, DynamicWing};
use crate::error::{Error, Result};
use crate::model::Controls;

impl Simulation {
    /// Continues an actuated vehicle's wings from a periodic motion found at a frozen body
    /// state ([`crate::actuated::periodic::settle`] on this vehicle), instead of from rest.
    /// The motion spans whole drive periods, so it joins the simulation's phase 0; call it
    /// before the first step. Does nothing for prescribed kinematics.
    pub fn start_wings_from(&mut self, p: &crate::actuated::PeriodicWings) {
        if self.dynamic.is_some() {
            self.dynamic = Some(Box::new(p.dynamic.clone()));
            for (w, settled) in self.vehicle.wings.iter_mut().zip(&p.wings) {
                w.set_stroke_reference(settled.stroke_reference().cloned());
            }
        }
    }

    /// The wings' dynamic states (left, right) of an actuated vehicle.
    pub fn wing_states(&self) -> Option<[crate::actuated::WingState; 2]> {
        self.dynamic.as_ref().map(|d| [d[0].state(), d[1].state()])
    }

    /// Overwrites the wings' dynamic states of an actuated vehicle (Floquet perturbations);
    /// does nothing for prescribed kinematics.
    pub fn set_wing_states(&mut self, states: [crate::actuated::WingState; 2]) {
        if let Some(d) = &mut self.dynamic {
            for (w, s) in d.iter_mut().zip(states) {
                w.set_state(s);
            }
        }
    }

    /// What an actuated step needs to know of the simulation.
    pub(super) fn actuated_ctx(&self) -> ActuatedCtx {
        let state = self.state();
        let body_from_world = state.world_from_body.inverse();
        ActuatedCtx {
            motion: BodyMotion {
                velocity_m_s: body_from_world * (state.velocity_m_s - self.wind_world_m_s),
                angular_velocity_rad_s: state.angular_velocity_body_rad_s,
            },
            state,
            dt_s: self.dt_s,
            t_s: self.time_s(),
            step: self.step,
            freq_hz: self.vehicle.freq_hz(),
            controls: self.vehicle.controls,
            wings_still: self.wings_still,
        }
    }
}

/// See [`Simulation::actuated_ctx`].
#[derive(Debug, Clone, Copy)]
pub(super) struct ActuatedCtx {
    state: State,
    motion: BodyMotion,
    dt_s: f64,
    t_s: f64,
    step: u64,
    freq_hz: f64,
    controls: Controls,
    wings_still: bool,
}

/// The loads of an actuated vehicle's wings, advancing their dynamics by one step. The
/// inertial reaction of the wings and actuators is reported in `wing_inertia`, apart from
/// the aerodynamic terms, and both enter `total`.
pub(super) fn actuated_loads_into(
    ctx: &ActuatedCtx,
    dynamic: &mut [DynamicWing; 2],
    wings: &mut [Wing; 2],
    out: &mut StepOutput,
) -> Result<()> {
    let mut terms = [BodyLoad::default(); 4];
    let mut total = BodyLoad::default();
    let mut wing_inertia = BodyLoad::default();
    let mut actuated = [ActuatedWingOutput::default(); 2];
    for i in 0..2 {
        let s = dynamic[i]
            .step(&mut wings[i], &ctx.motion, ctx.dt_s)
            .map_err(|e| match e {
                Error::Diverged { reason, .. } => Error::Diverged {
                    t_s: ctx.t_s,
                    step: ctx.step,
                    reason,
                },
                e => e,
            })?;
        let hinge = wings[i].mount().hinge_in_body_m;
        if !ctx.wings_still {
            for term in Term::ALL {
                let t = s.forces.term(term);
                let m = t.moment_about_com_nm(&hinge);
                terms[term as usize].add(t.force_n, m);
                total.add(t.force_n, m);
            }
            let m = s.inertial_moment_hinge_nm + hinge.cross(&s.inertial_force_n);
            wing_inertia.add(s.inertial_force_n, m);
            total.add(s.inertial_force_n, m);
        }
        out.wings[i] = s.forces;
        actuated[i] = s.output();
    }
    out.step = ctx.step;
    out.t_s = ctx.t_s;
    out.phase = ctx.t_s * ctx.freq_hz;
    out.state = ctx.state;
    out.terms = terms;
    out.wing_inertia = wing_inertia;
    out.total = total;
    out.controls = ctx.controls;
    out.actuated = Some(actuated);
    Ok(())
}
