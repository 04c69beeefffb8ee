//! Going back: a host that sets its body back to an earlier step and steps again (MuJoCo's
//! `mjd_transitionFD` and `mj_setState`, a finite-difference linearisation of any host) needs
//! the wings back at that step too. [`WingSet::save_state`] copies a set's state into a
//! copy of it (a [`Clone`] of the set made once), [`WingSet::restore_state`] puts it back: the
//! steps that follow repeat bit for bit.
//!
//! What is copied is everything a step reads or writes (time and phase, controls, the
//! actuated wings' dynamics, each pair's dynamic inflow, the midpoint prediction's memory,
//! wind and host settings, the last output) except the wingbeat's table of kinematic loads.
//! That table is a cache: an entry holds the loads of one step of the wingbeat under one
//! generation of the kinematics, tagged with it, and is used only when its tag is the set's
//! generation now. Generations are drawn from one counter for the whole process
//! ([`fresh_tag`]), so a tag names one kinematics everywhere: a set restored to an earlier
//! generation finds the entries computed under it valid (they are the same loads) and those
//! of the kinematics it went on to, in the branch it left, stale. Not copying the table is
//! what makes a save cheap (it is most of a clone: about 500 B per wing and step of the
//! wingbeat).

use std::sync::atomic::{AtomicU64, Ordering};

use super::WingSet;
use crate::error::{Error, Result};

/// A number no earlier call returned (in this process): the sets' identities and the
/// generations of their kinematics.
pub(super) fn fresh_tag() -> u64 {
    static NEXT: AtomicU64 = AtomicU64::new(1);
    NEXT.fetch_add(1, Ordering::Relaxed)
}

impl WingSet {
    /// Copies this set's state into `saved`, a copy of it ([`Clone`], made once): an error,
    /// and `saved` unchanged, if `saved` is not a copy of this set (or of a copy of it).
    pub fn save_state(&self, saved: &mut WingSet) -> Result<()> {
        same_origin(self, saved, "save_state")?;
        copy_state(saved, self);
        Ok(())
    }

    /// Puts back the state saved in `saved` ([`WingSet::save_state`]): the steps that follow
    /// repeat those that followed the save, bit for bit. An error, and this set unchanged, if
    /// `saved` is not a copy of this set.
    pub fn restore_state(&mut self, saved: &WingSet) -> Result<()> {
        same_origin(self, saved, "restore_state")?;
        copy_state(self, saved);
        Ok(())
    }
}

/// Sets built apart have different tables' tags and different wings: only copies of one
/// build share a state.
fn same_origin(a: &WingSet, b: &WingSet, what: &str) -> Result<()> {
    if a.origin == b.origin {
        Ok(())
    } else {
        Err(Error::Input(format!(
            "wing set: {what}: the other set is not a copy of this one (built apart); allowed: \
             a clone of this set or of a clone of it"
        )))
    }
}

/// `to` takes `from`'s state, the kinematic-loads table excepted (module documentation),
/// reusing `to`'s allocations where the types allow. Every field is named, so that a field
/// added to the set must be placed here.
fn copy_state(to: &mut WingSet, from: &WingSet) {
    let WingSet {
        origin: _,
        wings,
        dynamic,
        control_map,
        wing_mass_kg,
        centroid_r_m,
        dt_s,
        step,
        base_phase,
        base_step,
        phase_per_step,
        steps_per_wingbeat,
        periodic,
        sized_for_hz,
        table: _,
        table_gen: _,
        generation,
        pending,
        controls,
        last_cycle,
        wind_world_m_s,
        wing_winds_world_m_s,
        wing_motions,
        body_drag_area_m2,
        sampling,
        held,
        prev_body,
        sampled,
        rate_damping,
        inflow,
        still,
        out,
    } = from;
    // The wings' kinematics and the control map change only with a new generation of the
    // kinematics (`restart_phase` follows every change): within one, a prescribed wing
    // changes from step to step only in its dynamic inflow's field, and copying that alone
    // is most of what keeps a save cheap (a whole wing is its strips, several allocations).
    // Actuated wings carry their measured stroke too: copied whole.
    if to.generation == *generation && dynamic.is_none() {
        for (t, f) in to.wings.iter_mut().zip(wings) {
            t.copy_inflow_field_from(f);
        }
    } else {
        to.wings.clone_from(wings);
    }
    if to.generation != *generation {
        to.control_map.clone_from(control_map);
    }
    to.dynamic.clone_from(dynamic);
    to.wing_mass_kg = *wing_mass_kg;
    to.centroid_r_m.clone_from(centroid_r_m);
    to.dt_s = *dt_s;
    to.step = *step;
    to.base_phase = *base_phase;
    to.base_step = *base_step;
    to.phase_per_step = *phase_per_step;
    to.steps_per_wingbeat = *steps_per_wingbeat;
    to.periodic = *periodic;
    to.sized_for_hz = *sized_for_hz;
    to.generation = *generation;
    to.pending = *pending;
    to.controls = *controls;
    to.last_cycle = *last_cycle;
    to.wind_world_m_s = *wind_world_m_s;
    to.wing_winds_world_m_s.clone_from(wing_winds_world_m_s);
    to.wing_motions.clone_from(wing_motions);
    to.body_drag_area_m2 = *body_drag_area_m2;
    to.sampling = *sampling;
    // The held correction's base wings and their table never change after the build (only
    // whether steps take it), so copies of one build share them.
    match (&mut to.held, held) {
        (Some(t), Some(f)) => t.enabled = f.enabled,
        (t, f) => t.clone_from(f),
    }
    to.prev_body = *prev_body;
    to.sampled = *sampled;
    to.rate_damping = *rate_damping;
    to.inflow.clone_from(inflow);
    to.still = *still;
    to.out.clone_from(out);
}
