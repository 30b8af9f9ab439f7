//! Parallel robots (issue 79) on the page: a Gough–Stewart platform of the
//! folder (or the ready `hexapod`) generated, analysed, identified and
//! evaluated: `/api/parallel/{generate, identifiable, identify, evaluate}`,
//! each as the command line's `--json`.

use axum::extract::State;
use gecaro_app::parallel::{
    ParallelEvaluateRequest, ParallelEvaluated, ParallelGenerateRequest,
    ParallelIdentifiableRequest, ParallelIdentifyRequest, PlatformIdentificationDocument,
    PlatformRankDocument,
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
/// whether its verdict trusts it.
#[derive(Serialize)]
pub(crate) struct ParallelIdentifiedJson {
    #[serde(flatten)]
    document: PlatformIdentificationDocument,
    trusted: bool,
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
