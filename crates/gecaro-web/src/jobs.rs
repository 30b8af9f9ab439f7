//! Background jobs: an identification or a plan runs in the background
//! while the page polls its progress (the residual RMS of every iteration
//! so far; the part of the work under way and its steps done of all) and
//! finally its result.

use std::collections::VecDeque;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant};

use std::ops::ControlFlow;

use gecaro_calib::Progress as WorkProgress;
use serde::Serialize;

use crate::error::ApiError;
use crate::limits::{MAX_JOBS_ACTIVE, MAX_JOBS_KEPT, MAX_JOBS_MEMORY};

/// Where a job is.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum JobState {
    /// Waiting for a computing slot.
    Queued,
    /// Working (iterating, planning).
    Running,
    /// Finished with a result (converged or not: see the result).
    Done,
    /// Stopped by an error (bad data, too few equations, …).
    Failed,
    /// Stopped at the user's request (`POST /api/jobs/{id}/cancel`).
    Cancelled,
}

/// What a finished job produced.
#[derive(Debug)]
pub struct JobOutcome {
    /// The result as the API answers it, encoded once: every poll of the
    /// job sends these bytes (64 polls at once each cloned a JSON tree of
    /// tens of MB before).
    pub result: Box<serde_json::value::RawValue>,
    /// The HTML report of an identification.
    pub report: Option<String>,
    /// An identification's every observation's error before and after,
    /// located in its file (CSV).
    pub residuals: Option<String>,
}

/// `done` of `total` units of the part of the work under way.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Steps {
    /// Units done.
    pub done: usize,
    /// Units in all.
    pub total: usize,
}

/// One job's progress.
#[derive(Debug)]
struct Progress {
    state: JobState,
    history: Vec<f64>,
    phase: Option<String>,
    steps: Option<Steps>,
    outcome: Option<Arc<JobOutcome>>,
    error: Option<String>,
    /// When it finished (done, failed or cancelled).
    finished: Option<Instant>,
    /// When a client first saw it finished.
    read: Option<Instant>,
}

/// How long a finished job is kept after a client first saw it finished:
/// its report and residuals are fetched right after.
pub(crate) const READ_GRACE: Duration = Duration::from_secs(2);

/// How long a finished job nobody has seen finished is kept: a client that
/// polls every few seconds finds its result (issue 75: 802 of 1,000 jobs
/// were dropped before their clients saw them finish).
pub(crate) const UNREAD_KEEP: Duration = Duration::from_secs(600);

/// One job.
#[derive(Debug)]
pub struct Job {
    id: u64,
    progress: Mutex<Progress>,
    /// Set by [`Job::cancel`]; the job's observer stops the work at its next
    /// iteration or step.
    cancelled: std::sync::atomic::AtomicBool,
    /// The bytes it needs while active.
    need: usize,
}

/// A job as the API shows it.
#[derive(Debug, Serialize)]
pub struct JobView {
    /// The job's number.
    pub id: u64,
    /// Where it is.
    pub state: JobState,
    /// Residual RMS of every iterate so far, from the nominal robot on.
    pub history: Vec<f64>,
    /// The part of the work under way (`"choosing the configurations"`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub phase: Option<String>,
    /// How far that part is.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub steps: Option<Steps>,
    /// The error of a failed job.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// The result of a finished job (shared with the job, written as it was
    /// encoded).
    #[serde(
        rename = "result",
        skip_serializing_if = "Option::is_none",
        serialize_with = "encoded_result"
    )]
    pub outcome: Option<Arc<JobOutcome>>,
}

/// A finished job's result, as it was encoded.
fn encoded_result<S: serde::Serializer>(
    outcome: &Option<Arc<JobOutcome>>,
    serializer: S,
) -> Result<S::Ok, S::Error> {
    match outcome {
        Some(outcome) => outcome.result.serialize(serializer),
        None => serializer.serialize_none(),
    }
}

impl Job {
    fn progress(&self) -> std::sync::MutexGuard<'_, Progress> {
        self.progress.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// The job's number.
    pub fn id(&self) -> u64 {
        self.id
    }

    /// Marks the job as running.
    pub fn start(&self) {
        self.progress().state = JobState::Running;
    }

    /// Records the residual RMS of one more iterate.
    pub fn record(&self, rms: f64) {
        self.progress().history.push(rms);
    }

    /// Records what the work reports (an iterate's residual, a part
    /// begun, a step done) and answers whether it goes on: it stops at its
    /// next iteration or step once the job is cancelled.
    pub fn observe(&self, progress: WorkProgress<'_>) -> ControlFlow<()> {
        match progress {
            WorkProgress::Iteration(record) => self.record(record.rms),
            WorkProgress::Step { done, total } => {
                self.progress().steps = Some(Steps { done, total });
            }
            WorkProgress::Phase(part) => {
                let mut progress = self.progress();
                progress.phase = Some(part.to_owned());
                progress.steps = None;
            }
        }
        if self.is_cancelled() {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    }

    /// Finishes the job with its outcome.
    pub fn finish(&self, outcome: JobOutcome) {
        let mut progress = self.progress();
        progress.state = JobState::Done;
        progress.outcome = Some(Arc::new(outcome));
        progress.finished = Some(Instant::now());
    }

    /// Ends the job with an error.
    pub fn fail(&self, error: String) {
        let mut progress = self.progress();
        progress.finished = Some(Instant::now());
        if self.is_cancelled() {
            progress.state = JobState::Cancelled;
            progress.error = Some("cancelled".into());
        } else {
            progress.state = JobState::Failed;
            progress.error = Some(error);
        }
    }

    /// Asks the job to stop (its observer breaks off at the next iteration
    /// or step); a finished job is left as it is. Returns whether the job
    /// was still active.
    pub fn cancel(&self) -> bool {
        let active = self.active();
        if active {
            self.cancelled.store(true, Ordering::Relaxed);
        }
        active
    }

    /// Whether [`cancel`](Self::cancel) was called on the active job.
    pub fn is_cancelled(&self) -> bool {
        self.cancelled.load(Ordering::Relaxed)
    }

    /// The job as the API shows it; a finished job shown is read.
    pub fn view(&self) -> JobView {
        let mut progress = self.progress();
        if progress.finished.is_some() && progress.read.is_none() {
            progress.read = Some(Instant::now());
        }
        JobView {
            id: self.id,
            state: progress.state,
            history: progress.history.clone(),
            phase: progress.phase.clone(),
            steps: progress.steps,
            error: progress.error.clone(),
            outcome: progress.outcome.clone(),
        }
    }

    /// The outcome of a finished job.
    pub fn outcome(&self) -> Option<Arc<JobOutcome>> {
        self.progress().outcome.clone()
    }

    fn active(&self) -> bool {
        matches!(self.progress().state, JobState::Queued | JobState::Running)
    }

    /// Whether the job may be forgotten: finished, and seen finished
    /// `read_grace` ago, or never seen and finished [`UNREAD_KEEP`] ago.
    fn forgettable(&self, read_grace: Duration) -> bool {
        let progress = self.progress();
        match (progress.finished, progress.read) {
            (Some(_), Some(read)) => read.elapsed() >= read_grace,
            (Some(finished), None) => finished.elapsed() >= UNREAD_KEEP,
            (None, _) => false,
        }
    }
}

/// The jobs of the server: at most [`MAX_JOBS_ACTIVE`] queued or running, and
/// [`MAX_JOBS_KEPT`] kept for their results. A finished job is kept until
/// its client has seen it finished (and [`READ_GRACE`] more, for its
/// report), or [`UNREAD_KEEP`]; when every kept job is still owed to its
/// client, a new one waits (503) rather than a result be dropped unread.
///
/// Job numbers are unique across the server's restarts: a page reloaded
/// after a restart still holds the numbers of the last server's jobs, and
/// must not get another job's report under one. They count on from the
/// server's start time in milliseconds × 1000 (below 2⁵³ until the year
/// 2255, so exact as JavaScript numbers), and from past the last server's
/// numbers for servers started in one process.
#[derive(Debug)]
pub struct Jobs {
    next: AtomicU64,
    jobs: Mutex<VecDeque<Arc<Job>>>,
    /// [`READ_GRACE`], shorter in tests.
    read_grace: Duration,
}

impl Default for Jobs {
    fn default() -> Self {
        /// Where the last `Jobs` of this process started numbering.
        static LAST_START: AtomicU64 = AtomicU64::new(0);
        let now = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |since| since.as_millis() as u64);
        let clock = now.saturating_mul(1000);
        let after = |last: u64| clock.max(last.saturating_add(1_000_000));
        // The update always succeeds: `Ok` and `Err` both hold the last start.
        let last = LAST_START
            .fetch_update(Ordering::Relaxed, Ordering::Relaxed, |last| {
                Some(after(last))
            })
            .unwrap_or_else(|last| last);
        let start = after(last);
        Jobs {
            next: AtomicU64::new(start),
            jobs: Mutex::new(VecDeque::new()),
            read_grace: READ_GRACE,
        }
    }
}

impl Jobs {
    /// A new queued job that needs `need` bytes while it runs.
    ///
    /// # Errors
    /// [`ApiError::Busy`] when [`MAX_JOBS_ACTIVE`] jobs are queued or
    /// running, or when they and this one would need more than
    /// [`MAX_JOBS_MEMORY`]; [`ApiError::TooLarge`] when this one alone would.
    pub fn create(&self, need: usize) -> Result<Arc<Job>, ApiError> {
        let megabytes = |bytes: usize| bytes >> 20;
        if need > MAX_JOBS_MEMORY {
            return Err(ApiError::TooLarge(format!(
                "this job needs about {} MB, more than the {} MB the server gives its jobs: use \
                 fewer configurations, or the command line",
                megabytes(need),
                megabytes(MAX_JOBS_MEMORY)
            )));
        }
        let mut jobs = self.jobs.lock().unwrap_or_else(PoisonError::into_inner);
        if jobs.iter().filter(|job| job.active()).count() >= MAX_JOBS_ACTIVE {
            return Err(ApiError::Busy(format!(
                "{MAX_JOBS_ACTIVE} jobs (identifications, plans) are already queued or running; try \
                 again when one has finished"
            )));
        }
        let held: usize = jobs
            .iter()
            .filter(|job| job.active())
            .map(|job| job.need)
            .sum();
        if held + need > MAX_JOBS_MEMORY {
            return Err(ApiError::Busy(format!(
                "this job needs about {} MB and the jobs under way hold {} of the server's {} \
                 MB; try again when one has finished",
                megabytes(need),
                megabytes(held),
                megabytes(MAX_JOBS_MEMORY)
            )));
        }
        while jobs.len() >= MAX_JOBS_KEPT {
            match jobs.iter().position(|job| job.forgettable(self.read_grace)) {
                Some(oldest_read) => {
                    jobs.remove(oldest_read);
                }
                None => {
                    return Err(ApiError::Busy(format!(
                        "the server keeps {MAX_JOBS_KEPT} jobs and each is running or finished \
                         and not yet seen by its client; try again in a moment"
                    )));
                }
            }
        }
        let job = Arc::new(Job {
            id: self.next.fetch_add(1, Ordering::Relaxed) + 1,
            progress: Mutex::new(Progress {
                state: JobState::Queued,
                history: Vec::new(),
                phase: None,
                steps: None,
                outcome: None,
                error: None,
                finished: None,
                read: None,
            }),
            cancelled: std::sync::atomic::AtomicBool::new(false),
            need,
        });
        jobs.push_back(Arc::clone(&job));
        Ok(job)
    }

    /// The job numbered `id`.
    ///
    /// # Errors
    /// [`ApiError::NotFound`] for an unknown or forgotten job.
    pub fn get(&self, id: u64) -> Result<Arc<Job>, ApiError> {
        self.jobs
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .iter()
            .find(|job| job.id == id)
            .cloned()
            .ok_or_else(|| {
                ApiError::NotFound(format!(
                    "no job {id} (the server keeps {MAX_JOBS_KEPT} jobs, a finished one until \
                     its client has seen it finished)"
                ))
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Jobs that forget a job read at once (the grace of the tests).
    fn quick() -> Jobs {
        Jobs {
            read_grace: Duration::ZERO,
            ..Jobs::default()
        }
    }

    #[test]
    fn active_jobs_are_bounded_and_read_results_forgotten() {
        let jobs = quick();
        let active: Vec<_> = (0..MAX_JOBS_ACTIVE)
            .map(|_| jobs.create(0).expect("room"))
            .collect();
        assert!(matches!(jobs.create(0), Err(ApiError::Busy(_))));
        for job in &active {
            job.fail("stopped".into());
            job.view();
        }
        let first = active[0].id();
        for _ in 0..MAX_JOBS_KEPT {
            let job = jobs.create(0).expect("room");
            job.fail("stopped".into());
            job.view();
        }
        assert!(matches!(jobs.get(first), Err(ApiError::NotFound(_))));
        let last = jobs.create(0).expect("room");
        last.start();
        last.record(1e-3);
        let view = jobs.get(last.id()).expect("kept").view();
        assert_eq!(view.state, JobState::Running);
        assert_eq!(view.history, [1e-3]);
    }

    /// A finished job nobody has seen finished is never dropped for a new
    /// one (issue 75): the new one waits (503) until a result was read.
    #[test]
    fn a_result_nobody_read_is_kept() {
        let jobs = quick();
        let unread: Vec<_> = (0..MAX_JOBS_KEPT)
            .map(|_| {
                let job = jobs.create(0).expect("room");
                job.fail("finished".into());
                job
            })
            .collect();
        assert!(matches!(jobs.create(0), Err(ApiError::Busy(ref m)) if m.contains("not yet seen")));
        for job in &unread {
            assert!(jobs.get(job.id()).is_ok());
        }
        // One read: its room is taken, the others stay.
        unread[5].view();
        jobs.create(0).expect("room once one was read");
        assert!(matches!(
            jobs.get(unread[5].id()),
            Err(ApiError::NotFound(_))
        ));
        assert!(jobs.get(unread[0].id()).is_ok());
    }

    #[test]
    fn a_job_hears_its_parts_and_steps_and_stops_once_cancelled() {
        let jobs = Jobs::default();
        let job = jobs.create(0).expect("room");
        job.start();
        let step = |done, total| WorkProgress::Step { done, total };
        assert!(
            job.observe(WorkProgress::Phase("drawing the candidates"))
                .is_continue()
        );
        assert!(job.observe(step(150, 150)).is_continue());
        assert_eq!(
            job.view().steps,
            Some(Steps {
                done: 150,
                total: 150
            })
        );
        // A new part counts its own steps, from none.
        assert!(
            job.observe(WorkProgress::Phase("choosing the configurations"))
                .is_continue()
        );
        let view = job.view();
        assert_eq!(view.phase.as_deref(), Some("choosing the configurations"));
        assert_eq!(view.steps, None);
        assert!(job.observe(step(3, 90)).is_continue());
        job.cancel();
        assert!(
            job.observe(step(4, 90)).is_break(),
            "cancelled: the work stops"
        );
        let text = serde_json::to_string(&job.view()).expect("json");
        assert!(text.contains(r#""steps":{"done":4,"total":90}"#), "{text}");
    }

    #[test]
    fn job_numbers_of_two_servers_never_meet() {
        // A page restored after a restart asks the new server for the old
        // numbers: before, both servers counted from 1 and the new one
        // served another job's report under the old number.
        let (first, second) = (Jobs::default(), Jobs::default());
        let old = first.create(0).expect("room").id();
        let new = second.create(0).expect("room").id();
        assert!(new > old, "{new} after {old}");
        assert!(matches!(second.get(old), Err(ApiError::NotFound(_))));
        // Exact as JavaScript numbers.
        assert!(new < 1 << 53);
    }

    #[test]
    fn jobs_are_admitted_by_the_memory_they_need() {
        let jobs = Jobs::default();
        let alone = jobs.create(MAX_JOBS_MEMORY + 1);
        assert!(matches!(alone, Err(ApiError::TooLarge(ref m)) if m.contains("more than the")));
        let big = jobs.create(MAX_JOBS_MEMORY / 3 * 2).expect("room");
        let waiting = jobs.create(MAX_JOBS_MEMORY / 2);
        assert!(matches!(waiting, Err(ApiError::Busy(ref m)) if m.contains("hold")));
        big.fail("done".into());
        jobs.create(MAX_JOBS_MEMORY / 2)
            .expect("room once the first ended");
    }

    #[test]
    fn a_finished_result_is_encoded_once_and_shared() {
        let jobs = Jobs::default();
        let job = jobs.create(0).expect("room");
        job.finish(JobOutcome {
            result: serde_json::value::to_raw_value(&serde_json::json!({"rms": 1e-5}))
                .expect("encoded"),
            report: None,
            residuals: None,
        });
        let first = job.view();
        let second = job.view();
        let (Some(a), Some(b)) = (&first.outcome, &second.outcome) else {
            panic!("finished");
        };
        assert!(Arc::ptr_eq(a, b), "every view shares the one encoding");
        let text = serde_json::to_string(&first).expect("json");
        assert!(text.contains(r#""result":{"rms":0.00001}"#), "{text}");
    }
}
