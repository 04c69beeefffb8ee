//! Study files: a base vehicle model, factors that change numeric fields of it, a design
//! that picks the cases, and the responses to evaluate.
//!
//! ```toml
//! name = "drosophila_amplitude_aoa"     # optional; the CLI uses the file stem when absent
//! base_model = "drosophila"             # a built-in name, or a vehicle TOML path (relative
//!                                       # to the study file)
//! design = "full_factorial"             # or latin_hypercube, taguchi_l9, taguchi_l18, taguchi_l27
//! responses = ["lift_over_weight", "aero_power_w"]
//! steps_per_wingbeat = 100              # optional; default: the model's sim.steps_per_wingbeat
//!
//! [[factor]]
//! path = "kinematics.amplitude_deg"     # dotted path of a numeric field; `[i]` indexes arrays
//! levels = [120.0, 140.0, 160.0]
//!
//! [[factor]]
//! path = "kinematics.mid_stroke_aoa_deg"
//! range = [30.0, 60.0]                  # with count: evenly spaced levels, ends included
//! count = 4
//! ```
//!
//! `latin_hypercube` takes `samples` and `seed` (default 0) and needs a `range` for every
//! factor. Taguchi designs assign each factor, in order, to the first free column of the
//! array with its number of levels (so three factors of 6, 3 and 3 levels on `taguchi_l18`
//! reproduce the seed paper's Table 2).
//!
//! Factors are applied to the base model after it is parsed and written back out with every
//! default made explicit, so a path may name a field the base file leaves at its default
//! (`aero.strips`, `controls.amplitude_deg`, `initial.attitude_deg[1]`). Integer fields take
//! integral levels only. The fluid's two alternatives exclude each other: setting
//! `fluid.reynolds` removes `fluid.kinematic_viscosity_m2_s` and the other way round.
//!
//! The file's tables are in `file.rs`, factor paths in `path.rs`, the designs' cases in
//! `design.rs`, the checks against the base model in `resolve.rs` and the resolved study
//! in `study.rs`.
mod design;
mod file;
mod path;
mod resolve;
mod study;

pub use design::{SplitMix64, latin_hypercube};
pub use file::{DesignKind, FactorSpec, MAX_CASES, StudySpec};
pub use path::{PathStep, parse_path, set_path};
pub use study::{Factor, Study, shard_range, value_text, vehicle_from_table};
