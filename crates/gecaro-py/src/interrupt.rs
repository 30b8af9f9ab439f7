//! Long calls run without the GIL and stop on Ctrl-C.
//!
//! The work runs inside `Python::detach`, so other Python threads go on. A
//! [`Watch`] is the work's [`Observer`]: at most every [`POLL_PERIOD`] it
//! takes the GIL back for `PyErr_CheckSignals`, and it calls the user's
//! progress callback, if any, with every iterate of an identification. A
//! pending Ctrl-C (or an exception in the callback) stops the work, the
//! library returns `Error::Interrupted`, and that exception is raised in
//! Python.

use std::ops::ControlFlow;
use std::time::{Duration, Instant};

use gecaro_calib::{Observer, Progress};
use pyo3::prelude::*;

use crate::errors::IntoPyResult;

/// How often a long call looks for a pending signal.
const POLL_PERIOD: Duration = Duration::from_millis(20);

/// The signal check of one long call, and why it stopped.
pub(crate) struct Watch {
    last: Instant,
    /// Called with (iteration, residual RMS) for every iterate.
    callback: Option<Py<PyAny>>,
    iteration: usize,
    /// The exception that stopped the work (Ctrl-C, or the callback's).
    stopped: Option<PyErr>,
}

impl Watch {
    /// A watch starting now.
    pub(crate) fn new() -> Self {
        Watch {
            last: Instant::now(),
            callback: None,
            iteration: 0,
            stopped: None,
        }
    }

    /// A watch that also calls `callback(iteration, rms)` for every iterate.
    pub(crate) fn with_callback(callback: Option<Py<PyAny>>) -> Self {
        Watch {
            callback,
            ..Watch::new()
        }
    }

    /// `Break` when a signal handler raised (Ctrl-C), checked at most every
    /// [`POLL_PERIOD`].
    pub(crate) fn poll(&mut self) -> ControlFlow<()> {
        if self.last.elapsed() < POLL_PERIOD {
            return ControlFlow::Continue(());
        }
        self.last = Instant::now();
        match Python::attach(|py| py.check_signals()) {
            Ok(()) => ControlFlow::Continue(()),
            Err(error) => self.stop(error),
        }
    }

    /// Stops the work with `error` (raised when the call returns).
    fn stop(&mut self, error: PyErr) -> ControlFlow<()> {
        self.stopped = Some(error);
        ControlFlow::Break(())
    }

    /// The result of the work: the exception that stopped it, if any,
    /// otherwise `result` with its error converted.
    pub(crate) fn finish<T, E: Into<gecaro_app::AppError>>(
        self,
        result: Result<T, E>,
    ) -> PyResult<T> {
        match self.stopped {
            Some(error) => Err(error),
            None => result.py(),
        }
    }
}

/// Runs `work` without the GIL, watched by a [`Watch`]: Ctrl-C stops it,
/// and its error (or the signal's exception) is raised in Python.
pub(crate) fn watched<T, E>(
    py: Python<'_>,
    work: impl FnOnce(&mut dyn Observer) -> Result<T, E> + Send,
) -> PyResult<T>
where
    T: Send,
    E: Into<gecaro_app::AppError> + Send,
{
    py.detach(|| {
        let mut watch = Watch::new();
        let result = work(&mut watch);
        watch.finish(result)
    })
}

impl Observer for Watch {
    fn observe(&mut self, progress: Progress<'_>) -> ControlFlow<()> {
        if let (Progress::Iteration(record), Some(callback)) = (progress, &self.callback) {
            let iteration = self.iteration;
            let called =
                Python::attach(|py| callback.call1(py, (iteration, record.rms)).map(|_| ()));
            self.iteration += 1;
            if let Err(error) = called {
                return self.stop(error);
            }
        }
        self.poll()
    }
}
