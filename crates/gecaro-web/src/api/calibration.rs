//! The "Identifiable parameters" and "Points generation" functions of a
//! method menu.

use axum::extract::State;
use gecaro_app::documents::{ComparisonJson, IdentifiableJson, SummaryJson};
use gecaro_app::{EvaluateRequest, EvaluationPlots, GenerateRequest, IdentifiableRequest};
use gecaro_io::RobotDocument;
use serde::Serialize;

use super::json::Json;
use crate::error::ApiError;
use crate::state::AppState;

/// Identifiable parameters of a method (Appendix III).
pub(crate) async fn identifiable(
    State(state): State<AppState>,
    Json(request): Json<IdentifiableRequest>,
) -> Result<Json<IdentifiableJson>, ApiError> {
    state
        .compute_abandonable(move |state, observer| {
            Ok(Json(request.run(state.workspace(), observer)?.document()))
        })
        .await
}

#[derive(Serialize)]
pub(crate) struct GeneratedJson {
    /// The measured (terminal) points of the real robot, world frame (m),
    /// for the 3D view; the first [`MAX_VIEW_POINTS`](crate::limits::MAX_VIEW_POINTS).
    points: Vec<[f64; 3]>,
    /// The data file's text.
    csv: String,
    configurations: usize,
    /// A file name to download it as.
    file_name: String,
    /// The file of the folder it was saved to.
    #[serde(skip_serializing_if = "Option::is_none")]
    saved: Option<String>,
    /// The simulated real robot (to compare with what identification finds).
    real: RobotDocument,
    /// RMS and largest distance between the nominal and real terminal points (m).
    displacement_rms: f64,
    displacement_max: f64,
}

/// Points generation: measurements of a simulated real robot.
pub(crate) async fn generate(
    State(state): State<AppState>,
    Json(request): Json<GenerateRequest>,
) -> Result<Json<GeneratedJson>, ApiError> {
    let saved = request.output.save_as.clone();
    state
        .compute_abandonable(move |state, observer| {
            // A client that leaves stops the generation: nothing is written.
            let generated = request.run(state.workspace(), observer)?;
            // The terminal points of the simulated real robot, for the 3D view
            // (plane and link data hold configurations only).
            let points = generated
                .samples
                .iter()
                .take(crate::limits::MAX_VIEW_POINTS)
                .filter_map(|sample| {
                    gecaro_core::terminal_pose(&generated.real.robot, sample.motor_positions())
                        .ok()
                        .map(|pose| pose.translation.vector.into())
                })
                .collect();
            Ok(Json(GeneratedJson {
                points,
                configurations: generated.samples.len(),
                file_name: generated.file_name(),
                saved: generated.saved.as_ref().and(saved),
                real: RobotDocument::from_robot_file(&generated.real),
                displacement_rms: generated.displacement.0,
                displacement_max: generated.displacement.1,
                csv: generated.csv,
            }))
        })
        .await
}

#[derive(Serialize)]
pub(crate) struct EvaluatedJson {
    /// The robot's errors on the data.
    errors: SummaryJson,
    /// The compared robot's, when one was sent.
    compared: Option<SummaryJson>,
    /// The compared robot against the robot: better, worse or the same.
    comparison: Option<ComparisonJson>,
    plots: EvaluationPlots,
    /// What the user should know about the data (unused columns, joints
    /// outside their limits).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    notes: Vec<String>,
}

/// The "Evaluate" function: the errors of the table's robot (and of a
/// compared one, the calibrated robot) on held-out measurements.
pub(crate) async fn evaluate(
    State(state): State<AppState>,
    Json(request): Json<EvaluateRequest>,
) -> Result<Json<EvaluatedJson>, ApiError> {
    state
        .compute(move |state| {
            let evaluation = request.run(state.workspace())?;
            Ok(Json(EvaluatedJson {
                errors: (&evaluation.summary).into(),
                compared: evaluation
                    .compared
                    .as_ref()
                    .map(|(summary, _)| summary.into()),
                comparison: evaluation.comparison(),
                plots: evaluation.plots()?,
                notes: evaluation
                    .loaded
                    .notes
                    .iter()
                    .map(|note| note.text(gecaro_app::Dialect::Web))
                    .collect(),
            }))
        })
        .await
}
