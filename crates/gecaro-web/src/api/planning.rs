//! The "Plan" function of a method menu: the configurations to measure,
//! chosen from a generated pool, and how many are enough (docs/planning.md).

use axum::extract::State;
use gecaro_app::PlanRequest;
use gecaro_app::documents::{CurveJson, PlanJson};
use serde::Serialize;

use super::json::Json;
use crate::error::ApiError;
use crate::state::AppState;

#[derive(Serialize)]
pub(crate) struct CurveAnswer {
    #[serde(flatten)]
    curve: CurveJson,
    /// The curve as an SVG plot.
    svg: String,
}

#[derive(Serialize)]
pub(crate) struct Planned {
    #[serde(flatten)]
    plan: PlanJson,
    /// The planned data file (configurations, set or pair ids).
    csv: String,
    file_name: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    saved: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    curve: Option<CurveAnswer>,
}

/// Plans the configurations of a method, and optionally the accuracy curve.
pub(crate) async fn plan(
    State(state): State<AppState>,
    Json(request): Json<PlanRequest>,
) -> Result<Json<Planned>, ApiError> {
    if request.count.is_none() {
        return Err(ApiError::BadRequest(
            "count: the number of configurations to plan".into(),
        ));
    }
    let saved = request.save_as.clone();
    // A plan with its curve can take a while: the page's Cancel aborts the
    // request, and the plan stops at its next step.
    state
        .compute_abandonable(move |state, observer| {
            let planning = request.run(state.workspace(), observer)?;
            let (plan, file_name) = planning
                .plan_document()
                .zip(planning.file_name())
                .ok_or_else(|| ApiError::Internal("no plan was made".into()))?;
            let curve =
                planning
                    .curve_document()
                    .zip(planning.curve.as_ref())
                    .map(|(curve, drawn)| CurveAnswer {
                        curve,
                        svg: drawn.svg.clone(),
                    });
            let planned = planning
                .planned
                .ok_or_else(|| ApiError::Internal("no plan was made".into()))?;
            Ok(Json(Planned {
                plan,
                file_name,
                saved: planned.saved.as_ref().and(saved),
                csv: planned.csv,
                curve,
            }))
        })
        .await
}
