//! The flapsim error type: the wing set's (`wingset::Error`), one enum for the element and
//! its rapier host. `Model` names a malformed model file's field and value; `Diverged` a run
//! that left the physically meaningful region; `Input` something a host or caller gave that
//! cannot be used; `Analysis` an analysis (trim, stability) that could not find what it
//! looked for, or controls the wings cannot follow.

pub use wingset::{Error, Result};
