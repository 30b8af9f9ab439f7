//! Parallel robots (issue 79) on the page: a Gough–Stewart platform of the
//! folder (or the ready `hexapod`) generated, analysed, identified and
//! evaluated, and a program of its poses compensated:
//! `/api/parallel/{generate, plan, predict, identifiable, identify,
//! evaluate, compensate}`,
//! each as the command line's `--json`.

use axum::extract::State;
use gecaro_app::parallel::{
    ParallelCompensateRequest, ParallelCompensated, ParallelEvaluateRequest, ParallelEvaluated,
    ParallelGenerateRequest, ParallelIdentifiableRequest, ParallelIdentifyRequest,
    ParallelPlanRequest, ParallelPlanned, ParallelPredictRequest, ParallelPredicted,
    PlatformIdentificationDocument, PlatformRankDocument,
};
use serde::Serialize;

use super::json::Json;
use crate::error::ApiError;
use crate::state::AppState;

/// A generation: how many poses, and the files written.
#[derive(Serialize)]
pub(crate) struct ParallelGeneratedJson {
    configurations: usize,
    written: Vec<String>,
}

/// Measurements of a simulated real platform, written into the folder.
pub(crate) async fn generate(
    State(state): State<AppState>,
    Json(request): Json<ParallelGenerateRequest>,
) -> Result<Json<ParallelGeneratedJson>, ApiError> {
    state
        .compute(move |state| {
            let generated = request.run(state.workspace())?;
            Ok(Json(ParallelGeneratedJson {
                configurations: generated.samples.len(),
                written: generated
                    .written
                    .iter()
                    .map(|path| path.display().to_string())
                    .collect(),
            }))
        })
        .await
}

/// The identifiable parameters.
pub(crate) async fn identifiable(
    State(state): State<AppState>,
    Json(request): Json<ParallelIdentifiableRequest>,
) -> Result<Json<PlatformRankDocument>, ApiError> {
    state
        .compute(move |state| Ok(Json(request.run(state.workspace())?)))
        .await
}

/// An identification (the calibrated platform written when named), with
/// whether its verdict trusts it, its report and its residuals.
#[derive(Serialize)]
pub(crate) struct ParallelIdentifiedJson {
    #[serde(flatten)]
    document: PlatformIdentificationDocument,
    trusted: bool,
    /// The self-contained HTML report, to download.
    report: String,
    /// Every measurement's errors and residual (CSV), to download.
    residuals: String,
}

/// An identification.
pub(crate) async fn identify(
    State(state): State<AppState>,
    Json(request): Json<ParallelIdentifyRequest>,
) -> Result<Json<ParallelIdentifiedJson>, ApiError> {
    state
        .compute(move |state| {
            let identified = request.run(state.workspace())?;
            Ok(Json(ParallelIdentifiedJson {
                trusted: identified.failure().is_none(),
                report: identified.report("the page's parallel identification")?,
                residuals: identified.residuals_csv()?,
                document: identified.document,
            }))
        })
        .await
}

/// An evaluation on measured poses.
pub(crate) async fn evaluate(
    State(state): State<AppState>,
    Json(request): Json<ParallelEvaluateRequest>,
) -> Result<Json<ParallelEvaluated>, ApiError> {
    state
        .compute(move |state| Ok(Json(request.run(state.workspace())?)))
        .await
}

/// A compensated program (written into the folder when named), with its
/// CSV text.
#[derive(Serialize)]
pub(crate) struct ParallelCompensatedJson {
    #[serde(flatten)]
    compensated: ParallelCompensated,
    program: String,
}

/// A program of platform poses turned into the calibrated platform's
/// actuator values.
pub(crate) async fn compensate(
    State(state): State<AppState>,
    Json(request): Json<ParallelCompensateRequest>,
) -> Result<Json<ParallelCompensatedJson>, ApiError> {
    state
        .compute(move |state| {
            let compensated = request.run(state.workspace())?;
            Ok(Json(ParallelCompensatedJson {
                program: compensated.text.clone(),
                compensated,
            }))
        })
        .await
}

/// The precision of a calibration from a file's configurations, before
/// measuring.
pub(crate) async fn predict(
    State(state): State<AppState>,
    Json(request): Json<ParallelPredictRequest>,
) -> Result<Json<ParallelPredicted>, ApiError> {
    state
        .compute(move |state| Ok(Json(request.run(state.workspace())?)))
        .await
}

/// The poses to measure, written into the folder when named.
pub(crate) async fn plan(
    State(state): State<AppState>,
    Json(request): Json<ParallelPlanRequest>,
) -> Result<Json<ParallelPlanned>, ApiError> {
    state
        .compute(move |state| Ok(Json(request.run(state.workspace())?)))
        .await
}
