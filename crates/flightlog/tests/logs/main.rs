//! flightlog's integration tests, one binary: each module is one idea (its own module doc),
//! linked once against the logging stack (Rerun's and Foxglove's crates) instead of once a
//! file. The property tests are `prop_replay/`.

mod check;
mod common;
mod foreign;
mod four_wings;
mod json_logs;
mod mcap_format;
// Not `rerun`: the module would shadow the `rerun` crate its tests use.
#[path = "rerun.rs"]
mod rerun_output;
mod roundtrip;
mod scene_forces;
mod truncation;
mod wind_estimate;
