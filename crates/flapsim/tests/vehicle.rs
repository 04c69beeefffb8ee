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

/// Every `.rs` file in tests/ is a module above, and every folder with a `main.rs` is a test
/// target in Cargo.toml: with `autotests = false` cargo would not find a new file by itself.
#[test]
fn every_test_file_is_a_module() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests");
    let root = include_str!("vehicle.rs");
    let manifest = include_str!("../Cargo.toml");
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_str().unwrap().to_owned();
        if let Some(stem) = name.strip_suffix(".rs") {
            if stem != "vehicle" {
                let declared = format!("\nmod {stem};\n");
                assert!(
                    root.contains(&declared),
                    "tests/{name} is not a module of tests/vehicle.rs"
                );
            }
        } else if path.join("main.rs").is_file() {
            let target = format!("path = \"tests/{name}/main.rs\"");
            assert!(
                manifest.contains(&target),
                "tests/{name}/main.rs is not a [[test]] in Cargo.toml"
            );
        }
    }
}
