//! Progress of long work on stderr (hidden when stderr is not a terminal).

use std::ops::ControlFlow;

use gecaro_calib::{Observer, Progress};

/// A progress bar labelled `what`; its length is set by its user, and its
/// message (after the label) names the part of the work under way.
pub(crate) fn progress_bar(what: &str) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new(1);
    bar.set_style(
        indicatif::ProgressStyle::with_template(&format!(
            "{what}{{msg}} {{bar:30}} {{pos}}/{{len}} [{{elapsed}}]"
        ))
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar
}

/// Runs `work` with an observer that shows its steps on a progress bar
/// labelled `what` (and the part under way, `planning: choosing the
/// configurations`), cleared when the work ends.
pub(crate) fn with_steps<T>(what: &str, work: impl FnOnce(&mut dyn Observer) -> T) -> T {
    let bar = progress_bar(what);
    let result = work(&mut |progress: Progress<'_>| {
        match progress {
            Progress::Step { done, total } => {
                bar.set_length(total as u64);
                bar.set_position(done as u64);
            }
            Progress::Phase(part) => {
                bar.set_message(format!(": {part}"));
                bar.set_position(0);
            }
            Progress::Iteration(_) => {}
        }
        ControlFlow::Continue(())
    });
    bar.finish_and_clear();
    result
}
