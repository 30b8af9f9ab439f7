//! Watching long work: every function that may run for long (identification,
//! cross-validation, planning, simulated calibrations, compensation) reports
//! its [`Progress`] to an [`Observer`], which may stop it.
//!
//! ```
//! use std::ops::ControlFlow;
//! use gecaro_calib::{Observer, Progress};
//!
//! let mut iterations = 0;
//! let mut count = |progress: Progress<'_>| {
//!     if let Progress::Iteration(_) = progress {
//!         iterations += 1;
//!     }
//!     ControlFlow::Continue(())
//! };
//! let observer: &mut dyn Observer = &mut count;
//! # let _ = observer;
//! ```
//!
//! An observer that answers [`ControlFlow::Break`] stops the work, which then
//! returns [`Error::Interrupted`] (a user's Ctrl-C, a closed page). Pass
//! [`Quiet`] to watch nothing.

use std::ops::ControlFlow;

use crate::error::Error;

/// One iteration: the residual after it and the step that led there.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct IterationRecord {
    /// RMS of the (weighted) residual vector after the update.
    pub rms: f64,
    /// Norm of the update (0 for the starting point).
    pub step: f64,
    /// The damping λ of the update (0 for an undamped step).
    pub damping: f64,
}

/// What long work reports as it goes.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum Progress<'a> {
    /// An iterate of an identification: its starting point, then every
    /// accepted update.
    Iteration(&'a IterationRecord),
    /// `done` of `total` units of work (folds, exchanges, runs, targets).
    Step {
        /// Units done.
        done: usize,
        /// Units in all (may grow as the work learns how much remains).
        total: usize,
    },
    /// The work enters a part of its own (`"drawing the candidates"`,
    /// `"choosing the configurations"`): the [`Step`](Progress::Step)s that
    /// follow count that part's units, from zero.
    Phase(&'a str),
}

/// Watches long work and may stop it; see the module docs. Any
/// `FnMut(Progress) -> ControlFlow<()>` closure is an observer.
pub trait Observer: Send {
    /// Called as the work goes on; [`ControlFlow::Break`] stops it.
    fn observe(&mut self, progress: Progress<'_>) -> ControlFlow<()>;
}

impl<F: FnMut(Progress<'_>) -> ControlFlow<()> + Send> Observer for F {
    fn observe(&mut self, progress: Progress<'_>) -> ControlFlow<()> {
        self(progress)
    }
}

/// The observer that watches nothing: work runs to its end.
#[derive(Copy, Clone, Debug, Default)]
pub struct Quiet;

impl Observer for Quiet {
    fn observe(&mut self, _: Progress<'_>) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }
}

/// An observer that calls `f` with every iterate of an identification
/// ([`Progress::Iteration`]) and lets the work run to its end.
pub fn each_iteration(mut f: impl FnMut(&IterationRecord) + Send) -> impl Observer {
    move |progress: Progress<'_>| {
        if let Progress::Iteration(record) = progress {
            f(record);
        }
        ControlFlow::Continue(())
    }
}

/// An observer that calls `f(done, total)` with every step of the work
/// ([`Progress::Step`]) and lets it run to its end.
pub fn each_step(mut f: impl FnMut(usize, usize) + Send) -> impl Observer {
    move |progress: Progress<'_>| {
        if let Progress::Step { done, total } = progress {
            f(done, total);
        }
        ControlFlow::Continue(())
    }
}

/// Reports `progress`; [`Error::Interrupted`] when the observer stops the work.
pub(crate) fn report(observer: &mut dyn Observer, progress: Progress<'_>) -> Result<(), Error> {
    match observer.observe(progress) {
        ControlFlow::Continue(()) => Ok(()),
        ControlFlow::Break(()) => Err(Error::Interrupted),
    }
}

/// Reports that the work enters the part `name` ([`Progress::Phase`]);
/// [`Error::Interrupted`] when the observer stops the work.
///
/// # Errors
/// [`Error::Interrupted`], as said.
pub fn report_phase(observer: &mut dyn Observer, name: &str) -> Result<(), Error> {
    report(observer, Progress::Phase(name))
}

/// Reports `done` of `total` units of work ([`Progress::Step`]);
/// [`Error::Interrupted`] when the observer stops the work.
///
/// # Errors
/// [`Error::Interrupted`], as said.
pub fn report_step(observer: &mut dyn Observer, done: usize, total: usize) -> Result<(), Error> {
    report(observer, Progress::Step { done, total })
}
