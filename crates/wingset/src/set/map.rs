//! How controls reach the wings: a [`ControlMap`] (a vehicle model) turns [`Controls`] into
//! each wing's kinematics or, for actuated wings, each wing's drive.

use std::any::Any;
use std::fmt::Debug;

use wingforce::Wing;

use crate::actuated::Drive;
use crate::controls::Controls;
use crate::error::Result;

/// Maps controls onto a [`super::WingSet`]'s wings. flapsim's `Vehicle` is one: its control
/// spec moves the base kinematics (or the drives of actuated wings) by the controls. The set
/// keeps its own copy (built with [`super::WingSet::with_control_map`]) and, when controls
/// take effect, calls [`ControlMap::apply`] and then copies [`ControlMap::drives`] (actuated
/// wings) or the kinematics of [`ControlMap::wings`] (prescribed) onto its wings, in order.
/// A host that built the set from a model gets the model back by downcasting
/// ([`super::WingSet::control_map`], then `as &dyn Any`).
pub trait ControlMap: Any + Debug + Send + Sync {
    /// Takes `controls` into force, or says why they do not apply (and changes nothing).
    fn apply(&mut self, controls: &Controls) -> Result<()>;
    /// The wings with the kinematics the controls in force give, in the set's order.
    fn wings(&self) -> &[Wing];
    /// The drives the controls in force give, one per actuated wing in the set's order
    /// (`None` for prescribed kinematics).
    fn drives(&self) -> Option<&[Drive]>;
    /// A boxed copy (the set is `Clone`).
    fn clone_box(&self) -> Box<dyn ControlMap>;
}

impl Clone for Box<dyn ControlMap> {
    fn clone(&self) -> Self {
        self.clone_box()
    }
}
