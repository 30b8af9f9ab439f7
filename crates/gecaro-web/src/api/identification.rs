//! The "Identification" function of a method menu, as a background job
//! ([`background`]): the page submits, polls the residual of every
//! iteration, then shows the result, its plots, and offers the calibrated
//! robot, the report and the residuals.

use axum::extract::State;
use axum::http::StatusCode;
use gecaro_app::documents::IdentificationJson;
use gecaro_app::{Identified, IdentifyRequest, Plots};
use gecaro_io::RobotDocument;
use serde::Serialize;

use super::background::{self, Submitted};
use super::json::Json;
use crate::error::ApiError;
use crate::jobs::JobOutcome;
use crate::state::AppState;

/// Checks the request, reads the data, and starts the job: 202 with its number.
pub(crate) async fn submit(
    State(state): State<AppState>,
    Json(request): Json<IdentifyRequest>,
) -> Result<(StatusCode, Json<Submitted>), ApiError> {
    // Read and check the data now, so that a bad file is an answer, not a failed job.
    let prepared = state
        .compute(move |state| Ok(request.prepare(state.workspace())?))
        .await?;
    let need = prepared.memory_need();
    background::start(state, need, move |_, observer| {
        outcome(&prepared.run(observer)?)
    })
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
        result: background::encoded(&value)?,
        report: Some(report),
        residuals: Some(identified.residuals_csv()?),
    })
}
