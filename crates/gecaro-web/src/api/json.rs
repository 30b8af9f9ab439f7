//! The API's JSON body: axum's, with rejections that are [`ApiError`]s (JSON
//! bodies of their own, as every other error of the API).

use axum::extract::FromRequest;

use crate::error::ApiError;

/// A JSON body whose rejections are [`ApiError`]s (JSON bodies of their own).
#[derive(FromRequest)]
#[from_request(via(axum::Json), rejection(ApiError))]
pub(crate) struct Json<T>(pub(crate) T);

impl<T: serde::Serialize> axum::response::IntoResponse for Json<T> {
    fn into_response(self) -> axum::response::Response {
        axum::Json(self.0).into_response()
    }
}
