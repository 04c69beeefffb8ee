//! The proptest configuration of every property test in the workspace (the other crates'
//! tests include this file with `#[path]`).

use proptest::test_runner::Config;

/// `cases` generated inputs, times `FLAPWING_PROP_SCALE` if set (for long local soak runs),
/// shrinking a failure at most `max_shrink_iters` steps. No regression files in the source
/// tree: a failure prints its minimal input.
pub fn scaled_config(cases: u32, max_shrink_iters: u32) -> Config {
    let scale = std::env::var("FLAPWING_PROP_SCALE")
        .ok()
        .and_then(|s| s.parse::<u32>().ok())
        .unwrap_or(1);
    Config {
        cases: cases * scale,
        max_shrink_iters,
        failure_persistence: None,
        ..Config::default()
    }
}
