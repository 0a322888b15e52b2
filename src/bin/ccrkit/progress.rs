//! The library's progress events ([`ccrkit::progress`]) drawn as terminal progress bars on
//! standard error (hidden when standard error is not a terminal).

use ccrkit::progress::{Event, ProgressHandle};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;

/// A bar that draws on standard error when it is a terminal, else nothing.
fn terminal_bar(len: Option<u64>) -> ProgressBar {
    if std::io::stderr().is_terminal() {
        ProgressBar::with_draw_target(len, ProgressDrawTarget::stderr())
    } else {
        ProgressBar::hidden()
    }
}

/// A counted bar: `{msg} [=====>   ] pos/len (rate, eta)`.
pub fn bar(len: u64, msg: &str) -> ProgressBar {
    let bar = terminal_bar(Some(len));
    if let Ok(style) =
        ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} ({per_sec}, eta {eta})")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_message(msg.to_string());
    bar
}

/// A spinner with the elapsed time for one long step whose progress cannot be counted (a
/// single solve), ticking on its own thread. `finish_and_clear` it when the step ends.
pub fn spinner(msg: &str) -> ProgressBar {
    let bar = terminal_bar(None);
    if let Ok(style) = ProgressStyle::with_template("{spinner} {msg} ({elapsed})") {
        bar.set_style(style);
    }
    bar.set_message(msg.to_string());
    if !bar.is_hidden() {
        bar.enable_steady_tick(std::time::Duration::from_millis(120));
    }
    bar
}

/// A library progress handle drawn as a bar: a counted task gets a bar, an uncounted one a
/// spinner; a note replaces the bar's message; the bar is cleared when the task finishes.
pub fn handle() -> ProgressHandle {
    let bar = bar(0, "");
    ProgressHandle::new(move |e: Event<'_>| match e {
        Event::Start { task, total } => {
            match total {
                Some(n) => bar.set_length(n),
                None => bar.unset_length(),
            }
            bar.set_position(0);
            bar.set_message(task.to_string());
            bar.reset_elapsed();
        }
        Event::Advance(n) => bar.inc(n),
        Event::Note(msg) => bar.set_message(msg.to_string()),
        Event::Finish => bar.finish_and_clear(),
        _ => {}
    })
}
