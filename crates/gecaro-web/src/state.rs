//! What every request shares: the folder, the jobs, and the right to compute.
//!
//! Work never runs on the request path: file work (listing, saving) runs on
//! blocking threads at once ([`AppState::files`]); computations a request
//! waits for (generation, planning, identifiability) take one of a slot per
//! core ([`AppState::compute`]); identification jobs take one of their own
//! slots ([`AppState::run_job`]), so that jobs running or queued never delay
//! a listing or a table check.
//!
//! A computation can be abandoned: [`AppState::compute_abandonable`] hands
//! its work an [`Observer`] that stops it once the request is dropped (the
//! page aborted it, the client went away), so that a long plan or generation
//! stops instead of holding its core, and writes nothing.

use std::ops::ControlFlow;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use gecaro_calib::{Observer, Progress};

use tokio::sync::Semaphore;

use crate::error::ApiError;
use crate::jobs::Jobs;
use crate::workspace::Workspace;

/// The shared state of the server (cheap to clone).
#[derive(Clone, Debug)]
pub struct AppState {
    inner: Arc<Inner>,
}

#[derive(Debug)]
struct Inner {
    workspace: Workspace,
    jobs: Jobs,
    /// Computations of requests at once: one per core.
    computing: Arc<Semaphore>,
    /// Identification jobs running at once: one per core, apart from the
    /// requests' computations.
    jobs_running: Arc<Semaphore>,
    /// `Host` headers accepted (`127.0.0.1:8080`, `localhost:8080`); empty = any.
    allowed_hosts: Vec<String>,
    /// The longest a request may take.
    request_timeout: std::time::Duration,
}

impl AppState {
    /// The state of a server working in `workspace` and answering requests
    /// addressed to one of `allowed_hosts` (all when empty, for tests).
    pub fn new(workspace: Workspace, allowed_hosts: Vec<String>) -> Self {
        let cores = std::thread::available_parallelism().map_or(2, std::num::NonZero::get);
        AppState {
            inner: Arc::new(Inner {
                workspace,
                jobs: Jobs::default(),
                computing: Arc::new(Semaphore::new(cores.max(1))),
                jobs_running: Arc::new(Semaphore::new(cores.max(1))),
                allowed_hosts,
                request_timeout: crate::limits::REQUEST_TIMEOUT,
            }),
        }
    }

    /// The same state with another request timeout (the default is
    /// [`REQUEST_TIMEOUT`](crate::limits::REQUEST_TIMEOUT)). Only for a state
    /// not yet shared with a router.
    ///
    /// # Panics
    /// When the state has been cloned already.
    #[must_use]
    pub fn with_request_timeout(mut self, timeout: std::time::Duration) -> Self {
        Arc::get_mut(&mut self.inner)
            .expect("the timeout is set before the state is shared")
            .request_timeout = timeout;
        self
    }

    /// The longest a request may take.
    pub fn request_timeout(&self) -> std::time::Duration {
        self.inner.request_timeout
    }

    /// The sandboxed folder.
    pub fn workspace(&self) -> &Workspace {
        &self.inner.workspace
    }

    /// The identification jobs.
    pub fn jobs(&self) -> &Jobs {
        &self.inner.jobs
    }

    /// The accepted `Host` headers.
    pub fn allowed_hosts(&self) -> &[String] {
        &self.inner.allowed_hosts
    }

    /// Runs `work` on a blocking thread once a computing slot is free. A
    /// panic in `work` becomes an [`ApiError::Internal`]; the server lives on.
    pub async fn compute<T, F>(&self, work: F) -> Result<T, ApiError>
    where
        T: Send + 'static,
        F: FnOnce(&AppState) -> Result<T, ApiError> + Send + 'static,
    {
        self.blocking(Some(&self.inner.computing), work).await
    }

    /// As [`compute`](Self::compute), and `work` gets an observer that
    /// stops it at its next step once the request has been dropped.
    pub async fn compute_abandonable<T, F>(&self, work: F) -> Result<T, ApiError>
    where
        T: Send + 'static,
        F: FnOnce(&AppState, &mut dyn Observer) -> Result<T, ApiError> + Send + 'static,
    {
        /// Marks the computation abandoned when the request's future is
        /// dropped before the computation ended.
        struct Abandon(Arc<AtomicBool>);
        impl Drop for Abandon {
            fn drop(&mut self) {
                self.0.store(true, Ordering::Relaxed);
            }
        }
        let abandoned = Arc::new(AtomicBool::new(false));
        let guard = Abandon(Arc::clone(&abandoned));
        let result = self
            .compute(move |state| {
                let mut until_abandoned = |_: Progress<'_>| {
                    if abandoned.load(Ordering::Relaxed) {
                        ControlFlow::Break(())
                    } else {
                        ControlFlow::Continue(())
                    }
                };
                work(state, &mut until_abandoned)
            })
            .await;
        // Ended (with an answer): nothing to abandon.
        std::mem::forget(guard);
        result
    }

    /// Runs an identification job's `work` once one of the jobs' slots is
    /// free; as [`compute`](Self::compute) otherwise.
    pub async fn run_job<T, F>(&self, work: F) -> Result<T, ApiError>
    where
        T: Send + 'static,
        F: FnOnce(&AppState) -> Result<T, ApiError> + Send + 'static,
    {
        self.blocking(Some(&self.inner.jobs_running), work).await
    }

    /// Runs quick file work (a listing, a save) on a blocking thread at once.
    pub async fn files<T, F>(&self, work: F) -> Result<T, ApiError>
    where
        T: Send + 'static,
        F: FnOnce(&AppState) -> Result<T, ApiError> + Send + 'static,
    {
        self.blocking(None, work).await
    }

    async fn blocking<T, F>(&self, slots: Option<&Arc<Semaphore>>, work: F) -> Result<T, ApiError>
    where
        T: Send + 'static,
        F: FnOnce(&AppState) -> Result<T, ApiError> + Send + 'static,
    {
        let permit = match slots {
            Some(slots) => Some(
                Arc::clone(slots)
                    .acquire_owned()
                    .await
                    .map_err(|_| ApiError::Internal("the server is shutting down".into()))?,
            ),
            None => None,
        };
        let state = self.clone();
        let result = tokio::task::spawn_blocking(move || {
            let _permit = permit;
            work(&state)
        })
        .await;
        match result {
            Ok(outcome) => outcome,
            Err(error) => Err(ApiError::Internal(format!(
                "the computation failed unexpectedly ({error}); please report this with the request"
            ))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    /// A computation whose request is dropped is stopped by its observer;
    /// without that it would spin until the test's timeout.
    #[tokio::test]
    async fn a_dropped_request_abandons_its_computation() {
        let folder = tempfile::tempdir().expect("folder");
        let state = AppState::new(
            Workspace::new(folder.path()).expect("workspace"),
            Vec::new(),
        );
        let (ended, ending) = tokio::sync::oneshot::channel();
        let step = Progress::Step { done: 0, total: 1 };
        let request = state.compute_abandonable(move |_, observer| {
            let started = std::time::Instant::now();
            while observer.observe(step).is_continue() {
                assert!(
                    started.elapsed() < Duration::from_secs(20),
                    "never abandoned"
                );
                std::thread::sleep(Duration::from_millis(5));
            }
            let _ = ended.send(());
            Ok(())
        });
        // The client goes away after 100 ms: the request's future is dropped.
        assert!(
            tokio::time::timeout(Duration::from_millis(100), request)
                .await
                .is_err()
        );
        tokio::time::timeout(Duration::from_secs(10), ending)
            .await
            .expect("the computation ended")
            .expect("it said so");
        // A request that ends normally is not abandoned.
        let answer = state
            .compute_abandonable(move |_, observer| Ok(observer.observe(step).is_break()))
            .await
            .expect("answer");
        assert!(!answer);
    }
}
