//! Progress of long library calls (studies, `predict`, calibration), reported through one
//! trait so that the library prints nothing and depends on no terminal crate.
//!
//! A long call takes a [`ProgressHandle`] in its options and sends it [`Event`]s: a task
//! starts (with its number of steps, when known), steps advance (from any thread), a note says
//! what is being done, the task finishes. A handle is off by default ([`ProgressHandle::none`]);
//! anything implementing [`Progress`] — any `Fn(Event)` closure that is `Send + Sync` among
//! them — turns it on. The command line adapts it to a terminal progress bar.
//!
//! ```
//! use ccrkit::progress::{Event, ProgressHandle};
//! use std::sync::atomic::{AtomicU64, Ordering};
//! use std::sync::Arc;
//!
//! let done = Arc::new(AtomicU64::new(0));
//! let seen = Arc::clone(&done);
//! let progress = ProgressHandle::new(move |e: Event<'_>| {
//!     if let Event::Advance(n) = e {
//!         seen.fetch_add(n, Ordering::Relaxed);
//!     }
//! });
//! progress.start("demo", Some(3));
//! for _ in 0..3 {
//!     progress.advance(1);
//! }
//! progress.finish();
//! assert_eq!(done.load(Ordering::Relaxed), 3);
//! ```

use std::fmt;
use std::sync::Arc;

/// One report of a long call's progress.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum Event<'a> {
    /// A task begins: its name and how many steps it takes (`None`: not counted).
    Start {
        /// What the task is (e.g. `predict`, `stability`, a method's name).
        task: &'a str,
        /// Its steps, when known.
        total: Option<u64>,
    },
    /// This many more steps are done (sent from any thread, in any order).
    Advance(u64),
    /// What is being done now (e.g. the calibration's current error).
    Note(&'a str),
    /// The task ended, whether it succeeded or not.
    Finish,
}

/// Receives the [`Event`]s of a long call. Implemented by every `Fn(Event) + Send + Sync`
/// closure; events may come from several threads at once.
pub trait Progress: Send + Sync {
    /// One event.
    fn event(&self, event: Event<'_>);
}

impl<F: Fn(Event<'_>) + Send + Sync> Progress for F {
    fn event(&self, event: Event<'_>) {
        self(event)
    }
}

/// Where a long call reports its progress: nowhere ([`ProgressHandle::none`], the default) or
/// to a shared [`Progress`] receiver. Cheap to clone; what options structs hold.
#[derive(Clone, Default)]
pub struct ProgressHandle(Option<Arc<dyn Progress>>);

impl ProgressHandle {
    /// Report nothing.
    pub fn none() -> Self {
        ProgressHandle(None)
    }

    /// Report to `receiver`.
    pub fn new(receiver: impl Progress + 'static) -> Self {
        ProgressHandle(Some(Arc::new(receiver)))
    }

    /// Report to a receiver already shared.
    pub fn shared(receiver: Arc<dyn Progress>) -> Self {
        ProgressHandle(Some(receiver))
    }

    /// True when events go somewhere.
    pub fn is_on(&self) -> bool {
        self.0.is_some()
    }

    /// Send one event (nothing when off).
    pub fn send(&self, event: Event<'_>) {
        if let Some(p) = &self.0 {
            p.event(event);
        }
    }

    /// [`Event::Start`].
    pub fn start(&self, task: &str, total: Option<u64>) {
        self.send(Event::Start { task, total });
    }

    /// [`Event::Advance`].
    pub fn advance(&self, steps: u64) {
        self.send(Event::Advance(steps));
    }

    /// [`Event::Note`]; `note` is only called when the handle is on, so building the text
    /// costs nothing otherwise.
    pub fn note(&self, note: impl FnOnce() -> String) {
        if self.is_on() {
            self.send(Event::Note(&note()));
        }
    }

    /// [`Event::Finish`].
    pub fn finish(&self) {
        self.send(Event::Finish);
    }
}

impl fmt::Debug for ProgressHandle {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(if self.is_on() {
            "ProgressHandle(on)"
        } else {
            "ProgressHandle(off)"
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex;

    #[test]
    fn events_reach_the_receiver_in_order_and_none_sends_nothing() {
        let log = Arc::new(Mutex::new(Vec::<String>::new()));
        let l = Arc::clone(&log);
        let h = ProgressHandle::new(move |e: Event<'_>| {
            l.lock().expect("log").push(format!("{e:?}"));
        });
        h.start("t", Some(2));
        h.advance(2);
        h.note(|| "n".into());
        h.finish();
        let got = log.lock().expect("log").clone();
        assert_eq!(
            got,
            [
                "Start { task: \"t\", total: Some(2) }",
                "Advance(2)",
                "Note(\"n\")",
                "Finish"
            ]
        );
        let off = ProgressHandle::none();
        off.note(|| unreachable!("a handle that is off builds no note"));
        assert!(!off.is_on());
        assert_eq!(format!("{off:?}"), "ProgressHandle(off)");
    }
}
