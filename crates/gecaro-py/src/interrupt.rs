//! Long calls run without the GIL and stop on Ctrl-C.
//!
//! The work runs inside `Python::detach`, so other Python threads go on. Its
//! progress hooks call [`Watch::poll`], which at most every
//! [`POLL_PERIOD`] takes the GIL back for `PyErr_CheckSignals`: a pending
//! Ctrl-C makes the hook answer `Break`, the library stops with
//! `Error::Interrupted`, and the `KeyboardInterrupt` is raised in Python.

use std::ops::ControlFlow;
use std::time::{Duration, Instant};

use pyo3::prelude::*;

use crate::errors::{IntoPyResult, ToPyErr};

/// How often a long call looks for a pending signal.
const POLL_PERIOD: Duration = Duration::from_millis(20);

/// The signal check of one long call, and why it stopped.
pub(crate) struct Watch {
    last: Instant,
    /// The exception that stopped the work (Ctrl-C, or a progress callback's).
    stopped: Option<PyErr>,
}

impl Watch {
    /// A watch starting now.
    pub(crate) fn new() -> Self {
        Watch {
            last: Instant::now(),
            stopped: None,
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
    pub(crate) fn stop(&mut self, error: PyErr) -> ControlFlow<()> {
        self.stopped = Some(error);
        ControlFlow::Break(())
    }

    /// The result of the work: the exception that stopped it, if any,
    /// otherwise `result` with the library's error converted.
    pub(crate) fn finish<T, E: ToPyErr>(self, result: Result<T, E>) -> PyResult<T> {
        match self.stopped {
            Some(error) => Err(error),
            None => result.py(),
        }
    }
}
