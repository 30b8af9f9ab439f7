//! The "Identification" function of a method menu, as a background job: the
//! page submits, polls the residual of every iteration, then shows the
//! result, its plots, and offers the calibrated robot and the report.

use std::sync::Arc;

use axum::extract::{Path as UrlPath, State};
use axum::http::header;
use axum::response::IntoResponse;
use gecaro_calib::{
    Quiet, each_iteration,
    identification::{Identification, IdentificationOptions, Loss, LossKind, Solver, identify},
    study::Study,
    validation::cross_validate,
};
use gecaro_io::{RobotDocument, RobotFile};
use gecaro_report::json::{CrossValidationJson, IdentificationJson};
use gecaro_report::{
    ReportInput, calibrated_robot_file, convergence_svg, error_histograms_svg,
    errors_per_configuration_svg, html_report,
};
use serde::{Deserialize, Serialize};

use super::{DataRequest, Json, MethodRequest, robot_file};
use crate::error::ApiError;
use crate::jobs::{Job, JobOutcome, JobView};
use crate::limits::{MAX_FOLDS, MAX_ITERATIONS};
use crate::state::AppState;

/// The step rule.
#[derive(Copy, Clone, Debug, Default, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub(crate) enum SolverChoice {
    /// Plain Gauss–Newton (the paper), damped only when needed.
    #[default]
    GaussNewton,
    /// Levenberg–Marquardt from the first step.
    Lm,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct IdentifyRequest {
    robot: RobotDocument,
    method: MethodRequest,
    data: DataRequest,
    #[serde(default)]
    solver: SolverChoice,
    #[serde(default)]
    max_iterations: Option<usize>,
    /// `l2` (default), `huber`, `cauchy` or `tukey`.
    #[serde(default)]
    loss: Option<String>,
    /// The robust loss's scale, in robust σ (default per loss).
    #[serde(default)]
    loss_scale: Option<f64>,
    /// A Gaussian prior, `5mm,0.5deg,1%`.
    #[serde(default)]
    prior: Option<String>,
    /// Outliers beyond this many robust σ (default 3).
    #[serde(default)]
    outlier_threshold: Option<f64>,
    /// Drop the outliers and identify again.
    #[serde(default)]
    reject: bool,
    /// K-fold cross-validation after the identification.
    #[serde(default)]
    cv: Option<usize>,
    /// Seed of the folds (default 1).
    #[serde(default)]
    seed: Option<u64>,
}

impl IdentifyRequest {
    /// The loss, prior and outlier options of the request.
    fn robust_options(&self) -> Result<IdentificationOptions, ApiError> {
        let kind: LossKind = self.loss.as_deref().unwrap_or("l2").parse()?;
        let loss = Loss::from_parts(kind, self.loss_scale)?;
        let prior = match self.prior.as_deref().map(str::trim) {
            None | Some("") => None,
            Some(text) => Some(
                gecaro_io::parse_prior(text)
                    .map_err(|message| ApiError::BadRequest(format!("prior: {message}")))?,
            ),
        };
        if let Some(folds) = self.cv
            && !(2..=MAX_FOLDS).contains(&folds)
        {
            return Err(ApiError::BadRequest(format!(
                "cv {folds}: between 2 and {MAX_FOLDS} folds"
            )));
        }
        Ok(IdentificationOptions {
            loss,
            prior,
            outlier_threshold: self
                .outlier_threshold
                .unwrap_or(gecaro_calib::identification::DEFAULT_OUTLIER_THRESHOLD),
            reject: self.reject,
            ..IdentificationOptions::default()
        })
    }
}

#[derive(Serialize)]
pub(crate) struct Submitted {
    job: u64,
}

/// Checks the request, reads the data, and starts the job: 202 with its number.
pub(crate) async fn submit(
    State(state): State<AppState>,
    Json(request): Json<IdentifyRequest>,
) -> Result<(axum::http::StatusCode, Json<Submitted>), ApiError> {
    let file = robot_file(&request.robot)?;
    let method = request.method.build()?;
    let robust = request.robust_options()?;
    let (folds, seed) = (request.cv, request.seed.unwrap_or(1));
    let max_iterations = request.max_iterations.unwrap_or(30);
    if !(1..=MAX_ITERATIONS).contains(&max_iterations) {
        return Err(ApiError::BadRequest(format!(
            "max_iterations {max_iterations}: between 1 and {MAX_ITERATIONS}"
        )));
    }
    // Read and check the data now, so that a bad file is an answer, not a failed job.
    let data = request.data.clone();
    let (file, study, label) = state
        .compute(move |state| {
            let (samples, label) = data.samples(state, &file, method.as_ref())?;
            let study = Study::single(method, samples, label.clone());
            study.check(&file.robot)?;
            Ok((file, study, label))
        })
        .await?;
    let job = state.jobs().create()?;
    let id = job.id();
    let options = IdentificationOptions {
        solver: match request.solver {
            SolverChoice::GaussNewton => Solver::GaussNewton,
            SolverChoice::Lm => Solver::LevenbergMarquardt,
        },
        max_iterations,
        ..robust
    };
    tokio::spawn(async move {
        let running = Arc::clone(&job);
        let outcome = state
            .compute(move |_| {
                running.start();
                let result = identify(
                    &file.robot,
                    &study,
                    &options,
                    &mut each_iteration(|record| running.record(record.rms)),
                )?;
                let validation = match folds {
                    Some(folds) => Some(CrossValidationJson::new(
                        &cross_validate(&file.robot, &study, &options, folds, seed, &mut Quiet)?,
                        seed,
                    )),
                    None => None,
                };
                outcome(&file, &study, &result, &label, validation)
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
struct Plots {
    convergence: String,
    errors_histogram: String,
    errors_per_configuration: String,
}

#[derive(Serialize)]
struct IdentifyResult {
    identification: IdentificationJson,
    plots: Plots,
    /// The calibrated robot, to save.
    calibrated: RobotDocument,
    /// A file name to save it as.
    calibrated_name: String,
}

/// The result and the report of a finished identification.
fn outcome(
    file: &RobotFile,
    study: &Study,
    result: &Identification,
    label: &str,
    validation: Option<CrossValidationJson>,
) -> Result<JobOutcome, ApiError> {
    let millimetres =
        |errors: &[(f64, f64)]| errors.iter().map(|e| e.0 * 1e3).collect::<Vec<f64>>();
    let (before, after) = (
        millimetres(&result.errors_before),
        millimetres(&result.errors_after),
    );
    let calibrated = calibrated_robot_file(file, study, result, label);
    let stem = file
        .robot
        .name()
        .to_lowercase()
        .replace(|c: char| !c.is_alphanumeric(), "-");
    let mut identification = IdentificationJson::new(study, result);
    identification.cross_validation = validation;
    let value = IdentifyResult {
        identification,
        plots: Plots {
            convergence: convergence_svg(&result.history)?,
            errors_histogram: error_histograms_svg(&before, &after, "mm")?,
            errors_per_configuration: errors_per_configuration_svg(
                &before,
                &after,
                &result.outlier_observations(),
                "mm",
            )?,
        },
        calibrated: RobotDocument::from_robot_file(&calibrated),
        calibrated_name: format!("{stem}-calibrated.toml"),
    };
    let report = html_report(&ReportInput {
        robot: file,
        study,
        identification: result,
        command: &format!("gecaro serve: {} method on {label}", study.method_names()),
    })?;
    Ok(JobOutcome {
        result: serde_json::to_value(value)
            .map_err(|error| ApiError::Internal(format!("cannot encode the result: {error}")))?,
        report,
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

/// The HTML report of a finished job.
pub(crate) async fn report(
    State(state): State<AppState>,
    UrlPath(id): UrlPath<String>,
) -> Result<impl IntoResponse, ApiError> {
    let job = find(&state, &id)?;
    let outcome = job.outcome().ok_or_else(|| {
        ApiError::Conflict(format!(
            "job {id} has no report: it has not finished, or failed"
        ))
    })?;
    Ok((
        [
            (header::CONTENT_TYPE, "text/html; charset=utf-8".to_owned()),
            (
                header::CONTENT_DISPOSITION,
                format!("attachment; filename=\"gecaro-report-{id}.html\""),
            ),
        ],
        outcome.report.clone(),
    ))
}
