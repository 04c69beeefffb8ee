//! Property-test machinery for TOML model files, shared by `wingforce/tests/prop_model.rs`
//! (wing models) and `flapsim/tests/prop_vehicle/` (vehicles, which include this file with
//! `#[path]`): walking and editing a parsed TOML tree by path, structural mutations of it
//! (replace a value, delete a value or a section, add an unknown field), text-level
//! mutations of a file, random tabulated kinematics, documented ranges of fields and values
//! outside them, and the proptest configuration (`FLAPWING_PROP_SCALE`).
//!
//! Every item here is used by both test files.
//!
//! By idea: `tree.rs` (parsing, paths into the tree, walking and editing it),
//! `structural.rs` (replacement values, structural mutations, the exhaustive special-value
//! test), `ranges.rs` (documented ranges and values outside them), `text.rs` (text-level
//! mutations) and `tabulated.rs` (tabulated kinematics tables); here, the loader guard and
//! the proptest configuration.

mod ranges;
mod structural;
mod tabulated;
mod text;
mod tree;

use std::panic::{AssertUnwindSafe, catch_unwind};

use proptest::prelude::*;

pub use ranges::*;
pub use structural::*;
pub use tabulated::*;
pub use text::*;
pub use tree::*;

/// A panic's payload as text (empty if it is neither a `String` nor a `&str`).
pub fn panic_message(p: Box<dyn std::any::Any + Send>) -> String {
    p.downcast_ref::<String>()
        .cloned()
        .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_default()
}

/// `load(text)`, a panic turned into a test failure that shows the input (proptest reports
/// panics too; this names the input).
pub fn guarded<T>(text: &str, load: impl FnOnce(&str) -> T) -> Result<T, TestCaseError> {
    catch_unwind(AssertUnwindSafe(|| load(text))).map_err(|p| {
        TestCaseError::fail(format!(
            "loader panicked ({}) on:\n{text}",
            panic_message(p)
        ))
    })
}

/// The property tests' configuration (see `prop_config.rs`).
pub fn config(cases: u32) -> ProptestConfig {
    super::prop_config::scaled_config(cases, 2000)
}
