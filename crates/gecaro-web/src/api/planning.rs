//! The "Plan" function of a method menu and of the study editor: the
//! configurations to measure, chosen from a generated pool, and how many
//! are enough (docs/planning.md), as background jobs ([`background`]) whose
//! progress names the part under way (drawing the candidates, choosing the
//! configurations, the accuracy curve) and its steps; and a study's
//! predicted precision (eq. 11) before it is measured.

use axum::extract::State;
use axum::http::StatusCode;
use gecaro_app::documents::{CurveJson, PlanJson};
use gecaro_app::{
    PlanRequest, PlanStudyJson, PlanStudyRequest, PredictStudyJson, PredictStudyRequest,
};
use serde::Serialize;

use super::background::{self, Submitted};
use super::json::Json;
use crate::error::ApiError;
use crate::jobs::JobOutcome;
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
    /// The planned configurations' tool points with the table's robot,
    /// world frame (m), for the 3D view.
    points: Vec<[f64; 3]>,
}

/// Checks the request and starts planning a method's configurations (and
/// optionally the accuracy curve) as a job: 202 with its number.
pub(crate) async fn plan(
    State(state): State<AppState>,
    Json(request): Json<PlanRequest>,
) -> Result<(StatusCode, Json<Submitted>), ApiError> {
    if request.count.is_none() {
        return Err(ApiError::BadRequest(
            "count: the number of configurations to plan".into(),
        ));
    }
    let request = state
        .files(move |state| {
            request.check(state.workspace())?;
            Ok(request)
        })
        .await?;
    let need = request.memory_need();
    background::start(state, need, move |state, observer| {
        let saved = request.output.save_as.clone();
        let planning = request.run(state.workspace(), observer)?;
        let (plan, file_name) = planning
            .plan_document()
            .zip(planning.file_name())
            .ok_or_else(|| ApiError::Internal("no plan was made".into()))?;
        let curve = planning
            .curve_document()
            .zip(planning.curve.as_ref())
            .map(|(curve, drawn)| CurveAnswer {
                curve,
                svg: drawn.svg.clone(),
            });
        let points = planning.planned.as_ref().map_or_else(Vec::new, |planned| {
            planned
                .plan
                .samples
                .iter()
                .take(crate::limits::MAX_VIEW_POINTS)
                .filter_map(|sample| {
                    gecaro_core::terminal_pose(&planning.robot.robot, &sample.motor_positions)
                        .ok()
                        .map(|pose| pose.translation.vector.into())
                })
                .collect()
        });
        let planned = planning
            .planned
            .ok_or_else(|| ApiError::Internal("no plan was made".into()))?;
        Ok(JobOutcome {
            result: background::encoded(&Planned {
                plan,
                file_name,
                saved: planned.saved.as_ref().and(saved),
                csv: planned.csv,
                curve,
                points,
            })?,
            report: None,
            residuals: None,
        })
    })
}

/// One set's planned configurations, to download.
#[derive(Serialize)]
struct PlannedSetFile {
    /// A name to save it as.
    file_name: String,
    /// The configurations (metres, radians, gecaro's columns).
    csv: String,
}

#[derive(Serialize)]
struct PlannedStudyAnswer {
    #[serde(flatten)]
    plan: PlanStudyJson,
    /// Every set's configurations, in the study's order.
    files: Vec<PlannedSetFile>,
}

/// Checks the request and starts planning a whole cell (a study's sets
/// chosen together) as a job: 202 with its number. Saved, the planned study
/// and its sets' files are written in the folder.
pub(crate) async fn plan_study(
    State(state): State<AppState>,
    Json(request): Json<PlanStudyRequest>,
) -> Result<(StatusCode, Json<Submitted>), ApiError> {
    // The study and its files read once, before the answer.
    let prepared = state
        .files(move |state| Ok(request.prepare(state.workspace())?))
        .await?;
    let need = prepared.memory_need();
    let save_as = prepared.save_as().map(str::to_owned);
    background::start(state, need, move |state, observer| {
        let planned = prepared.run(state.workspace(), observer)?;
        let stem = save_as
            .as_deref()
            .and_then(|name| std::path::Path::new(name).file_stem())
            .map_or_else(
                || "planned".into(),
                |stem| stem.to_string_lossy().into_owned(),
            );
        let files = planned
            .set_files()
            .into_iter()
            .enumerate()
            .map(|(index, csv)| PlannedSetFile {
                file_name: format!("{stem}_{}.csv", index + 1),
                csv,
            })
            .collect();
        Ok(JobOutcome {
            result: background::encoded(&PlannedStudyAnswer {
                plan: planned.document(),
                files,
            })?,
            report: None,
            residuals: None,
        })
    })
}

/// A study's predicted precision from its sets' configurations (eq. 11),
/// before they are measured.
pub(crate) async fn predict_study(
    State(state): State<AppState>,
    Json(request): Json<PredictStudyRequest>,
) -> Result<Json<PredictStudyJson>, ApiError> {
    state
        .compute(move |state| Ok(Json(request.run(state.workspace())?.document())))
        .await
}
