//! Property tests (issue 7): every bad vehicle file gets a clear error and nothing panics.
//!
//! `flapsim::Vehicle::from_toml` is fed mutated versions of the real vehicle files
//! (`models/drosophila.toml`, `robobee.toml`, `bumblebee.toml`) and of a "full" drosophila that
//! spells out every optional field (gravity, Ixz, overrides, left harmonic and right tabulated
//! kinematics, controls, aero, sim, initial), random tabulated kinematics, garbage and truncated
//! text. Loading must never panic and must either succeed or return an error whose Display
//! starts with `<origin>: `; value errors must name the field and say "not allowed". Targeted
//! properties check that out-of-range values of each documented field are rejected naming
//! exactly that field. A vehicle that loads must also start simulating without a panic.
//!
//! Generated inputs per property (proptest `cases`; the file runs in a few seconds in release):
//!
//! | property                                        | cases |
//! |-------------------------------------------------|-------|
//! | `structural_mutations_never_panic`              |  1500 |
//! | `out_of_range_values_name_their_field`          |   600 |
//! | `out_of_range_integers_name_their_field`        |   200 |
//! | `unknown_fields_are_named`                      |   300 |
//! | `type_errors_are_parse_errors`                  |   400 |
//! | `text_mutations_never_panic`                    |  1500 |
//! | `tabulated_kinematics_tables`                   |   400 |
//! | `moderate_values_load_and_simulate_or_fail_cleanly` | 400 |
//! | `controls_that_break_the_kinematics_name_controls` | 200 |
//! | `loaded_vehicles_simulate` (exhaustive, not proptest) | ~1500 |
//!
//! `FLAPWING_PROP_SCALE=N` multiplies every proptest case count (for long local soak runs).
//!
//! The TOML-tree walkers, the mutation, text-mutation, table and range generators and
//! `config` are shared with `wingforce/tests/prop_model.rs`, in
//! `crates/wingforce/tests/support/toml_mutation/` (included here with `#[path]`).
//!
//! The properties by family: `mutations.rs` (structural and text mutations never panic),
//! `ranges.rs` (out-of-range values name their field), `tables.rs` (tabulated kinematics),
//! `loaded.rs` (a vehicle that loads simulates) and `controls.rs` (controls that break the
//! kinematics), on the base models of `bases.rs` and the loading and error contract of
//! `checks.rs`.

#[path = "../../../wingforce/tests/support/prop_config.rs"]
mod prop_config;
#[path = "../../../wingforce/tests/support/toml_mutation/mod.rs"]
mod toml_mutation;

mod bases;
mod checks;
mod controls;
mod loaded;
mod mutations;
mod ranges;
mod tables;
