//! Progress bars for long work, drawn on stderr (indicatif hides them when stderr is not a
//! terminal, so pipes and tests see nothing).

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// A bar of `len` items called `unit` (e.g. "steps", "cases") with a message.
pub fn progress_bar(len: u64, message: impl Into<String>, unit: &str) -> ProgressBar {
    let bar = ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::stderr());
    if let Ok(style) = ProgressStyle::with_template(&format!(
        "{{msg}} {{bar:40}} {{pos}}/{{len}} {unit} ({{elapsed}}, eta {{eta}})"
    )) {
        bar.set_style(style);
    }
    bar.set_message(message.into());
    bar
}
