//! The owner's tool point and user frames (issue 74): a tool point taught
//! by pivoting (`/api/tcp`, as `gecaro tcp --json`), a user frame from
//! measured points (`/api/frame`, as `gecaro frame --json`), and an
//! instrument's export joined with a controller's log (`/api/join`, as
//! `gecaro join`).

use axum::extract::State;
use gecaro_app::{
    JoinRequest, JoinedJson, ToolPointJson, ToolPointRequest, UserFrameJson, UserFrameRequest,
};

use super::json::Json;
use crate::error::ApiError;
use crate::state::AppState;

/// A tool point from the joint values of a pivot (see the module docs).
pub(crate) async fn tool_point(
    State(state): State<AppState>,
    Json(request): Json<ToolPointRequest>,
) -> Result<Json<ToolPointJson>, ApiError> {
    state
        .compute(move |state| Ok(Json(request.run(state.workspace())?.document())))
        .await
}

/// A user frame from measured points (see the module docs).
pub(crate) async fn user_frame(
    State(state): State<AppState>,
    Json(request): Json<UserFrameRequest>,
) -> Result<Json<UserFrameJson>, ApiError> {
    state
        .compute(move |state| Ok(Json(request.run(state.workspace())?.document())))
        .await
}

/// An instrument's export joined with a controller's log (see the module
/// docs): the joined file's text, written into the folder when named.
pub(crate) async fn join(
    State(state): State<AppState>,
    Json(request): Json<JoinRequest>,
) -> Result<Json<JoinedJson>, ApiError> {
    state
        .compute(move |state| {
            let joined = request.run(state.workspace())?;
            Ok(Json(joined.document(request.output.save_as.as_deref())))
        })
        .await
}
