//! The "Compensate" function: a program written for the nominal robot (the
//! table's), corrected for the calibrated one, target by target.

use axum::extract::State;
use gecaro_app::CompensateRequest;
use gecaro_app::documents::CompensationJson;
use serde::Serialize;

use super::json::Json;
use crate::error::ApiError;
use crate::state::AppState;

/// A corrected program, with its file for the page to offer.
#[derive(Serialize)]
pub(crate) struct CompensatedProgramJson {
    /// What `gecaro compensate --json` prints: counts, flagged lines, every
    /// target's status and corrected joints.
    #[serde(flatten)]
    document: CompensationJson,
    /// The corrected program file's text (the program's columns and units,
    /// the joints corrected), when the program came from a file.
    #[serde(skip_serializing_if = "Option::is_none")]
    csv: Option<String>,
    /// A file name to download it as.
    #[serde(skip_serializing_if = "Option::is_none")]
    file_name: Option<String>,
}

/// Compensation of a program (see the module docs); a client that leaves
/// stops it at its next target, and nothing is written.
pub(crate) async fn compensate(
    State(state): State<AppState>,
    Json(request): Json<CompensateRequest>,
) -> Result<Json<CompensatedProgramJson>, ApiError> {
    let save_as = request.output.save_as.clone();
    state
        .compute_abandonable(move |state, observer| {
            let compensated = request.run(state.workspace(), observer)?;
            // The saved file by its name in the folder, not the server's path.
            let mut document = compensated.document();
            if document.output.is_some() {
                document.output = save_as;
            }
            Ok(Json(CompensatedProgramJson {
                document,
                csv: compensated.corrected,
                file_name: compensated.corrected_name,
            }))
        })
        .await
}
