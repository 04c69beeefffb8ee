//! Helpers shared by the wingforce integration tests.

pub mod prop_config;
pub mod toml_mutation;
