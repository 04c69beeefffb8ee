//! flapsim's integration tests, one binary: each module below was a test file of its own and
//! keeps its module doc (the physics it checks). One link against rapier and the physics
//! stack instead of one a file (Cargo.toml sets `autotests = false`; the property tests are
//! `prop_vehicle/`). `every_test_file_is_a_module` fails when a file in tests/ is left out.

mod actuated;
mod actuated_hover;
mod actuated_vehicle;
mod added_mass_actuated;
mod bad_models;
mod dragonfly_cases;
mod estimator;
mod estimator_rates;
mod forward_flight;
mod four_wings;
mod hinge_stop;
mod hover_start;
mod pair_controls;
mod phase;
mod physics;
mod randomize;
mod rapier_host;
mod second_order;
mod sensors;
mod strike_loads;
mod task;
mod wind;
mod wing_inertia;

#[path = "../../../tests/support/test_files.rs"]
mod test_files;

/// Every file in this folder runs: see [`test_files::assert_every_test_file_runs`].
#[test]
fn every_test_file_is_a_module() {
    test_files::assert_every_test_file_runs(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests"),
        "vehicle.rs",
        include_str!("vehicle.rs"),
        Some(include_str!("../Cargo.toml")),
    );
}
