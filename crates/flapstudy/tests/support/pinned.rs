//! The RoboBee model as the failure-handling cases of a study were written against, shared by
//! flapstudy's and the CLI's tests (the CLI's include this file by path).

/// `model` with the sampling and step count these failure-handling cases were written
/// against (the step-start sampling at 100 steps per wingbeat, the RoboBee's default before
/// its step mean): which designs settle within a few drive periods depends on them.
pub fn pinned(model: &str) -> String {
    let pinned: String = model
        .lines()
        .map(|l| {
            if l.starts_with("steps_per_wingbeat = ") {
                "steps_per_wingbeat = 100\n".to_owned()
            } else if l.starts_with("load_sampling = ") {
                "load_sampling = \"step_start\"\n".to_owned()
            } else {
                format!("{l}\n")
            }
        })
        .collect();
    assert!(pinned.contains("\nload_sampling = \"step_start\"\n"));
    pinned
}
