//! The "Identification" function of a method menu, as a background job: the
//! page submits, polls the residual of every iteration, then shows the
//! result, its plots, and offers the calibrated robot and the report.

use std::sync::Arc;

use axum::extract::{Path as UrlPath, State};
use axum::http::header;
use axum::response::{IntoResponse, Response};
use gecaro_app::documents::IdentificationJson;
use gecaro_app::{Identified, IdentifyRequest, Plots};
use gecaro_calib::Progress;
use gecaro_io::RobotDocument;
use serde::Serialize;
use std::ops::ControlFlow;

use super::json::Json;
use crate::error::ApiError;
use crate::jobs::{Job, JobOutcome, JobView};
use crate::state::AppState;

#[derive(Serialize)]
pub(crate) struct Submitted {
    job: u64,
}

/// Checks the request, reads the data, and starts the job: 202 with its number.
pub(crate) async fn submit(
    State(state): State<AppState>,
    Json(request): Json<IdentifyRequest>,
) -> Result<(axum::http::StatusCode, Json<Submitted>), ApiError> {
    // Read and check the data now, so that a bad file is an answer, not a failed job.
    let prepared = state
        .compute(move |state| Ok(request.prepare(state.workspace())?))
        .await?;
    let job = state.jobs().create(prepared.memory_need())?;
    let id = job.id();
    tokio::spawn(async move {
        let running = Arc::clone(&job);
        let outcome = state
            .run_job(move |_| {
                running.start();
                // Records every iteration; stops the work once cancelled.
                let mut observer = |progress: Progress<'_>| {
                    if let Progress::Iteration(record) = progress {
                        running.record(record.rms);
                    }
                    if running.is_cancelled() {
                        ControlFlow::Break(())
                    } else {
                        ControlFlow::Continue(())
                    }
                };
                let identified = prepared.run(&mut observer)?;
                outcome(&identified)
            })
            .await;
        match outcome {
            Ok(outcome) => job.finish(outcome),
            Err(error) => job.fail(error.to_string()),
        }
    });
    Ok((
        axum::http::StatusCode::ACCEPTED,
        Json(Submitted { job: id }),
    ))
}

#[derive(Serialize)]
struct IdentifyResult {
    identification: IdentificationJson,
    plots: Plots,
    /// The calibrated robot, to save.
    calibrated: RobotDocument,
    /// A file name to save it as.
    calibrated_name: String,
    /// What the user should know about the data (unused columns, joints
    /// outside their limits).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    notes: Vec<String>,
}

/// The result and the report of a finished identification.
fn outcome(identified: &Identified) -> Result<JobOutcome, ApiError> {
    let stem = identified
        .loaded
        .robot
        .robot
        .name()
        .to_lowercase()
        .replace(|c: char| !c.is_alphanumeric(), "-");
    let value = IdentifyResult {
        identification: identified.document(),
        plots: identified.plots()?,
        calibrated: RobotDocument::from_robot_file(&identified.calibrated()),
        calibrated_name: format!("{stem}-calibrated.toml"),
        notes: identified
            .loaded
            .notes
            .iter()
            .map(|note| note.text(gecaro_app::Dialect::Web))
            .collect(),
    };
    let report = identified.report(&format!(
        "gecaro serve: {} method on {}",
        identified.loaded.study.method_names(),
        identified.loaded.label
    ))?;
    Ok(JobOutcome {
        result: serde_json::value::to_raw_value(&value)
            .map_err(|error| ApiError::Internal(format!("cannot encode the result: {error}")))?,
        report,
        residuals: identified.residuals_csv()?,
    })
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

/// A finished job's HTML report.
pub(crate) async fn report(
    State(state): State<AppState>,
    UrlPath(id): UrlPath<String>,
) -> Result<Response, ApiError> {
    download(&state, &id, "report", |outcome| {
        (
            "text/html; charset=utf-8",
            format!("gecaro-report-{id}.html"),
            outcome.report.clone(),
        )
    })
}

/// A finished job's residuals, observation by observation (CSV).
pub(crate) async fn residuals(
    State(state): State<AppState>,
    UrlPath(id): UrlPath<String>,
) -> Result<Response, ApiError> {
    download(&state, &id, "residuals", |outcome| {
        (
            "text/csv; charset=utf-8",
            format!("gecaro-residuals-{id}.csv"),
            outcome.residuals.clone(),
        )
    })
}

/// A file of finished job `id`'s outcome (`what` it is, for the error),
/// as an attachment: its type, file name and text from `file`.
fn download(
    state: &AppState,
    id: &str,
    what: &str,
    file: impl FnOnce(&JobOutcome) -> (&'static str, String, String),
) -> Result<Response, ApiError> {
    let job = find(state, id)?;
    let outcome = job.outcome().ok_or_else(|| {
        ApiError::Conflict(format!(
            "job {id} has no {what}: it has not finished, or failed"
        ))
    })?;
    let (kind, name, text) = file(&outcome);
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
