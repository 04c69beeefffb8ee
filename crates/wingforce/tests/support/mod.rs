//! Helpers shared by the wingforce integration tests.

pub mod toml_mutation;
