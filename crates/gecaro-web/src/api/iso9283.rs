//! ISO 9283's acceptance test (issue 78): the test planned
//! (`/api/iso9283/plan`, as `gecaro iso9283 plan --json`, with the
//! program's CSV text) and evaluated (`/api/iso9283/evaluate`, as `gecaro
//! iso9283 evaluate --json`).

use axum::extract::State;
use gecaro_app::{Iso9283EvaluateRequest, Iso9283PlanRequest, TestEvaluationJson, TestPlanJson};
use serde::Serialize;

use super::json::Json;
use crate::error::ApiError;
use crate::state::AppState;

/// A planned test and its program.
#[derive(Serialize)]
pub(crate) struct PlannedTestJson {
    /// As the command line's JSON.
    #[serde(flatten)]
    plan: TestPlanJson,
    /// The program (CSV), to download or run.
    program: String,
}

/// The test planned (see the module docs); the program written into the
/// folder when named.
pub(crate) async fn plan(
    State(state): State<AppState>,
    Json(request): Json<Iso9283PlanRequest>,
) -> Result<Json<PlannedTestJson>, ApiError> {
    state
        .compute(move |state| {
            let planned = request.run(state.workspace())?;
            Ok(Json(PlannedTestJson {
                plan: planned.document(),
                program: planned.program,
            }))
        })
        .await
}

/// An evaluated test and its report.
#[derive(Serialize)]
pub(crate) struct EvaluatedTestJson {
    /// As the command line's JSON.
    #[serde(flatten)]
    evaluation: TestEvaluationJson,
    /// The self-contained HTML report, to download.
    report: String,
}

/// The test evaluated (see the module docs), with its report.
pub(crate) async fn evaluate(
    State(state): State<AppState>,
    Json(request): Json<Iso9283EvaluateRequest>,
) -> Result<Json<EvaluatedTestJson>, ApiError> {
    state
        .compute(move |state| {
            let evaluated = request.run(state.workspace())?;
            Ok(Json(EvaluatedTestJson {
                evaluation: evaluated.document(),
                report: evaluated.report("the page's acceptance test")?,
            }))
        })
        .await
}
