//! Long work as background jobs (an identification, a plan): started once
//! the request is checked (`202 Accepted` with the job's number), then
//! polled for its progress and result, cancelled, and a finished
//! identification's files downloaded.

use std::sync::Arc;

use axum::extract::{Path as UrlPath, State};
use axum::http::{StatusCode, header};
use axum::response::{IntoResponse, Response};
use gecaro_calib::{Observer, Progress};
use serde::Serialize;

use super::json::Json;
use crate::error::ApiError;
use crate::jobs::{Job, JobOutcome, JobView};
use crate::state::AppState;

/// A started job's number.
#[derive(Serialize)]
pub(crate) struct Submitted {
    job: u64,
}

/// Starts `work` as a job that needs about `need` bytes, once a job slot is
/// free: `202` with its number. `work` gets an observer that records its
/// progress in the job and stops it once the job is cancelled; its outcome
/// (or error) ends the job.
///
/// # Errors
/// [`ApiError::Busy`] or [`ApiError::TooLarge`] when the job cannot be
/// admitted (see [`crate::jobs::Jobs::create`]).
pub(crate) fn start<F>(
    state: AppState,
    need: usize,
    work: F,
) -> Result<(StatusCode, Json<Submitted>), ApiError>
where
    F: FnOnce(&AppState, &mut dyn Observer) -> Result<JobOutcome, ApiError> + Send + 'static,
{
    let job = state.jobs().create(need)?;
    let id = job.id();
    tokio::spawn(async move {
        let running = Arc::clone(&job);
        let outcome = state
            .run_job(move |state| {
                running.start();
                let mut observer = |progress: Progress<'_>| running.observe(progress);
                work(state, &mut observer)
            })
            .await;
        match outcome {
            Ok(outcome) => job.finish(outcome),
            Err(error) => job.fail(error.to_string()),
        }
    });
    Ok((StatusCode::ACCEPTED, Json(Submitted { job: id })))
}

/// The result of a job as the API answers it, encoded once.
///
/// # Errors
/// [`ApiError::Internal`] when it cannot be encoded.
pub(crate) fn encoded<T: Serialize>(
    result: &T,
) -> Result<Box<serde_json::value::RawValue>, ApiError> {
    serde_json::value::to_raw_value(result)
        .map_err(|error| ApiError::Internal(format!("cannot encode the result: {error}")))
}

fn job_id(text: &str) -> Result<u64, ApiError> {
    text.parse()
        .map_err(|_| ApiError::BadRequest(format!("job {text:?}: jobs are numbered 1, 2, …")))
}

fn find(state: &AppState, id: &str) -> Result<Arc<Job>, ApiError> {
    state.jobs().get(job_id(id)?)
}

/// A job's progress, and its result when done.
pub(crate) async fn status(
    State(state): State<AppState>,
    UrlPath(id): UrlPath<String>,
) -> Result<Json<JobView>, ApiError> {
    Ok(Json(find(&state, &id)?.view()))
}

/// Stops a queued or running job: 200 with its state (a finished job is
/// left as it is).
pub(crate) async fn cancel(
    State(state): State<AppState>,
    UrlPath(id): UrlPath<String>,
) -> Result<Json<JobView>, ApiError> {
    let job = find(&state, &id)?;
    job.cancel();
    Ok(Json(job.view()))
}

/// A finished identification's HTML report.
pub(crate) async fn report(
    State(state): State<AppState>,
    UrlPath(id): UrlPath<String>,
) -> Result<Response, ApiError> {
    download(&state, &id, "report", |outcome| {
        outcome.report.as_ref().map(|report| {
            (
                "text/html; charset=utf-8",
                format!("gecaro-report-{id}.html"),
                report.clone(),
            )
        })
    })
}

/// A finished identification's residuals, observation by observation (CSV).
pub(crate) async fn residuals(
    State(state): State<AppState>,
    UrlPath(id): UrlPath<String>,
) -> Result<Response, ApiError> {
    download(&state, &id, "residuals", |outcome| {
        outcome.residuals.as_ref().map(|residuals| {
            (
                "text/csv; charset=utf-8",
                format!("gecaro-residuals-{id}.csv"),
                residuals.clone(),
            )
        })
    })
}

/// A file of finished job `id`'s outcome (`what` it is, for the error),
/// as an attachment: its type, file name and text from `file` (`None`
/// when the job makes no such file).
fn download(
    state: &AppState,
    id: &str,
    what: &str,
    file: impl FnOnce(&JobOutcome) -> Option<(&'static str, String, String)>,
) -> Result<Response, ApiError> {
    let job = find(state, id)?;
    let outcome = job.outcome().ok_or_else(|| {
        ApiError::Conflict(format!(
            "job {id} has no {what}: it has not finished, or failed"
        ))
    })?;
    let (kind, name, text) = file(&outcome).ok_or_else(|| {
        ApiError::NotFound(format!(
            "job {id} has no {what}: only an identification makes one"
        ))
    })?;
    Ok((
        [
            (header::CONTENT_TYPE, kind.to_owned()),
            (
                header::CONTENT_DISPOSITION,
                format!("attachment; filename=\"{name}\""),
            ),
        ],
        text,
    )
        .into_response())
}
