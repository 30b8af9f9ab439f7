//! Errors of the API, as HTTP answers: a status code and a JSON body
//! `{"error": "...", "problems": [...]}` (see `docs/api.md`).

use axum::Json;
use axum::extract::rejection::{JsonRejection, QueryRejection};
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use gecaro_io::DocumentError;
use serde::Serialize;

/// A request that cannot be served, and why.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ApiError {
    /// The request is malformed (bad JSON, a missing field, a bad name): 400.
    #[error("{0}")]
    BadRequest(String),
    /// The robot document breaks rules of the model: 422 with every problem.
    #[error("the robot is not valid: {}", .0.first().map_or("", |p| p.message.as_str()))]
    InvalidRobot(Vec<DocumentError>),
    /// The request is well-formed but its content cannot be used (data that
    /// do not fit the method, too few equations, …): 422.
    #[error("{0}")]
    Unprocessable(String),
    /// No such file, job or robot: 404.
    #[error("{0}")]
    NotFound(String),
    /// The file exists and overwriting was not asked for: 409.
    #[error("{0}")]
    Conflict(String),
    /// Outside the folder, or from another site: 403.
    #[error("{0}")]
    Forbidden(String),
    /// The body is larger than the server accepts: 413.
    #[error("{0}")]
    TooLarge(String),
    /// The request took too long: 408.
    #[error("{0}")]
    Timeout(String),
    /// Too many jobs at once: 503.
    #[error("{0}")]
    Busy(String),
    /// A failure of the server itself (a file that cannot be written): 500.
    #[error("{0}")]
    Internal(String),
}

#[derive(Serialize)]
struct ErrorBody<'a> {
    error: String,
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    problems: &'a [DocumentError],
}

impl ApiError {
    /// The HTTP status of this error.
    pub fn status(&self) -> StatusCode {
        match self {
            ApiError::BadRequest(_) => StatusCode::BAD_REQUEST,
            ApiError::InvalidRobot(_) | ApiError::Unprocessable(_) => {
                StatusCode::UNPROCESSABLE_ENTITY
            }
            ApiError::NotFound(_) => StatusCode::NOT_FOUND,
            ApiError::Conflict(_) => StatusCode::CONFLICT,
            ApiError::Forbidden(_) => StatusCode::FORBIDDEN,
            ApiError::TooLarge(_) => StatusCode::PAYLOAD_TOO_LARGE,
            ApiError::Timeout(_) => StatusCode::REQUEST_TIMEOUT,
            ApiError::Busy(_) => StatusCode::SERVICE_UNAVAILABLE,
            ApiError::Internal(_) => StatusCode::INTERNAL_SERVER_ERROR,
        }
    }
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        let problems = match &self {
            ApiError::InvalidRobot(problems) => problems.as_slice(),
            _ => &[],
        };
        let body = ErrorBody {
            error: self.to_string(),
            problems,
        };
        (self.status(), Json(body)).into_response()
    }
}

impl From<JsonRejection> for ApiError {
    fn from(rejection: JsonRejection) -> Self {
        let message = rejection.body_text();
        if rejection.status() == StatusCode::PAYLOAD_TOO_LARGE {
            ApiError::TooLarge(format!(
                "the request body is larger than the server accepts ({} MiB)",
                crate::limits::MAX_BODY_BYTES >> 20
            ))
        } else if rejection.status() == StatusCode::UNSUPPORTED_MEDIA_TYPE {
            ApiError::BadRequest("send JSON with `Content-Type: application/json`".into())
        } else {
            ApiError::BadRequest(message)
        }
    }
}

impl From<QueryRejection> for ApiError {
    fn from(rejection: QueryRejection) -> Self {
        ApiError::BadRequest(rejection.body_text())
    }
}

impl From<gecaro_app::AppError> for ApiError {
    fn from(error: gecaro_app::AppError) -> Self {
        use gecaro_app::ErrorKind;
        let dialect = gecaro_app::Dialect::Web;
        let message = match error.help(dialect) {
            Some(help) => format!("{}; {help}", error.message(dialect)),
            None => error.message(dialect),
        };
        match error.kind() {
            ErrorKind::Usage => ApiError::BadRequest(message),
            ErrorKind::InvalidRobot => ApiError::InvalidRobot(error.problems().to_vec()),
            ErrorKind::NotFound => ApiError::NotFound(message),
            ErrorKind::Exists => ApiError::Conflict(message),
            ErrorKind::Forbidden => ApiError::Forbidden(message),
            ErrorKind::TooLarge => ApiError::TooLarge(message),
            ErrorKind::Output | ErrorKind::Internal => ApiError::Internal(message),
            _ => ApiError::Unprocessable(message),
        }
    }
}

impl From<gecaro_calib::Error> for ApiError {
    fn from(error: gecaro_calib::Error) -> Self {
        gecaro_app::AppError::from(error).into()
    }
}

impl From<gecaro_core::Error> for ApiError {
    fn from(error: gecaro_core::Error) -> Self {
        gecaro_app::AppError::from(error).into()
    }
}

impl From<gecaro_report::Error> for ApiError {
    fn from(error: gecaro_report::Error) -> Self {
        gecaro_app::AppError::from(error).into()
    }
}

impl From<gecaro_io::Error> for ApiError {
    fn from(error: gecaro_io::Error) -> Self {
        gecaro_app::AppError::from(error).into()
    }
}
