//! The study editor's files: a study file of the folder opened as its
//! statement (a study file's keys as JSON, what `/api/identify` takes as
//! `study`), and a statement saved as a study file.

use axum::extract::{Query, State};
use gecaro_app::StudySpec;
use gecaro_app::{SaveStudyRequest, open_study};
use serde::{Deserialize, Serialize};

use super::json::Json;
use crate::error::ApiError;
use crate::state::AppState;

/// `?name=` of a study file of the folder.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct StudyQuery {
    name: String,
}

/// A study file's statement.
#[derive(Serialize)]
pub(crate) struct StudyView {
    name: String,
    study: StudySpec,
}

/// Opens a study file of the folder (its keys checked; the files it names
/// are read when it runs).
pub(crate) async fn open(
    State(state): State<AppState>,
    query: Result<Query<StudyQuery>, axum::extract::rejection::QueryRejection>,
) -> Result<Json<StudyView>, ApiError> {
    let Query(StudyQuery { name }) = query?;
    state
        .files(move |state| {
            let study = open_study(state.workspace(), &name)?;
            Ok(Json(StudyView { name, study }))
        })
        .await
}

/// A saved study file, by its name in the folder.
#[derive(Serialize)]
pub(crate) struct SavedStudy {
    saved: String,
}

/// Saves a statement as a study file of the folder (never over a file
/// unless `overwrite`; read back before it is written).
pub(crate) async fn save(
    State(state): State<AppState>,
    Json(request): Json<SaveStudyRequest>,
) -> Result<Json<SavedStudy>, ApiError> {
    state
        .files(move |state| {
            request.run(state.workspace())?;
            Ok(Json(SavedStudy {
                saved: request.name,
            }))
        })
        .await
}
