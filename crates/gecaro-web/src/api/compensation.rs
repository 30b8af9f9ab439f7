//! The "Compensate" function: a program written for the nominal robot (the
//! table's), corrected for the calibrated one, target by target.

use axum::extract::State;
use gecaro_app::CompensateRequest;
use gecaro_app::documents::CompensationJson;
use serde::Serialize;

use super::Json;
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

/// The name a corrected copy of `program` (a file name or an upload's) goes
/// by: `weld.csv` → `weld-compensated.csv`.
fn corrected_name(program: &str) -> String {
    let file = std::path::Path::new(program)
        .file_stem()
        .and_then(|stem| stem.to_str())
        .unwrap_or("program");
    format!("{file}-compensated.csv")
}

/// Compensation of a program (see the module docs); a client that leaves
/// stops it at its next target, and nothing is written.
pub(crate) async fn compensate(
    State(state): State<AppState>,
    Json(request): Json<CompensateRequest>,
) -> Result<Json<CompensatedProgramJson>, ApiError> {
    let name = match &request.program {
        gecaro_app::ProgramSource::File(name) => Some(name.clone()),
        gecaro_app::ProgramSource::Csv { name, .. } => {
            Some(name.clone().unwrap_or_else(|| "program.csv".into()))
        }
        gecaro_app::ProgramSource::Points(_) => None,
    };
    let save_as = request.save_as.clone();
    state
        .compute_abandonable(move |state, observer| {
            let compensated = request.run(state.workspace(), observer)?;
            // The saved file by its name in the folder, not the server's path.
            let mut document = compensated.document();
            if document.output.is_some() {
                document.output = save_as;
            }
            let csv = compensated
                .program
                .as_ref()
                .map(|program| program.format_corrected(&compensated.results));
            Ok(Json(CompensatedProgramJson {
                document,
                file_name: csv.as_ref().and(name.as_deref()).map(corrected_name),
                csv,
            }))
        })
        .await
}

#[cfg(test)]
mod tests {
    use super::corrected_name;

    #[test]
    fn a_corrected_program_is_named_after_the_program() {
        assert_eq!(corrected_name("weld.csv"), "weld-compensated.csv");
        assert_eq!(corrected_name("cell/path.csv"), "path-compensated.csv");
        assert_eq!(corrected_name(""), "program-compensated.csv");
    }
}
