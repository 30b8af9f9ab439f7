//! The JSON API of the page (documented in `docs/api.md`).
//!
//! Every request that computes carries the robot as a [`RobotDocument`](gecaro_io::RobotDocument): the
//! page holds the table being edited, and the server keeps no robot between
//! requests. Values are in the document's own units (its `angle_unit`);
//! everything the server computes is in metres and radians.

mod background;
mod calibration;
mod compensation;
mod frames;
mod identification;
mod iso9283;
mod json;
mod parallel;
mod planning;
mod robot;
mod study;

use axum::Router;
use axum::routing::{get, post};

use crate::state::AppState;

/// Every POST route of the API (full paths), each taking a JSON body: for
/// clients, tests and the fuzz targets. `routes` registers them (a test
/// checks that each one answers).
pub const POST_ROUTES: [&str; 23] = [
    "/api/robots/check",
    "/api/robots/new",
    "/api/robots/upload",
    "/api/robots/save",
    "/api/robots/pose",
    "/api/identifiable",
    "/api/generate",
    "/api/plan",
    "/api/identify",
    "/api/evaluate",
    "/api/compensate",
    "/api/iso9283/plan",
    "/api/iso9283/evaluate",
    "/api/parallel/generate",
    "/api/parallel/plan",
    "/api/parallel/predict",
    "/api/parallel/identifiable",
    "/api/parallel/identify",
    "/api/parallel/evaluate",
    "/api/parallel/compensate",
    "/api/studies/save",
    "/api/studies/plan",
    "/api/studies/predict",
];

/// The routes under `/api`.
pub(crate) fn routes() -> Router<AppState> {
    Router::new()
        .route("/info", get(robot::info))
        .route("/files", get(robot::files))
        .route("/robots/ready/{name}", get(robot::ready))
        .route("/robots/file", get(robot::open_file))
        .route("/robots/check", post(robot::check))
        .route("/robots/new", post(robot::new))
        .route("/robots/upload", post(robot::upload))
        .route("/robots/save", post(robot::save))
        .route("/robots/pose", post(robot::pose))
        .route("/identifiable", post(calibration::identifiable))
        .route("/generate", post(calibration::generate))
        .route("/plan", post(planning::plan))
        .route("/identify", post(identification::submit))
        .route("/evaluate", post(calibration::evaluate))
        .route("/compensate", post(compensation::compensate))
        .route("/tcp", post(frames::tool_point))
        .route("/frame", post(frames::user_frame))
        .route("/join", post(frames::join))
        .route("/iso9283/plan", post(iso9283::plan))
        .route("/iso9283/evaluate", post(iso9283::evaluate))
        .route("/parallel/generate", post(parallel::generate))
        .route("/parallel/plan", post(parallel::plan))
        .route("/parallel/predict", post(parallel::predict))
        .route("/parallel/identifiable", post(parallel::identifiable))
        .route("/parallel/identify", post(parallel::identify))
        .route("/parallel/evaluate", post(parallel::evaluate))
        .route("/parallel/compensate", post(parallel::compensate))
        .route("/studies/file", get(study::open))
        .route("/studies/save", post(study::save))
        .route("/studies/plan", post(planning::plan_study))
        .route("/studies/predict", post(planning::predict_study))
        .route("/jobs/{id}", get(background::status))
        .route("/jobs/{id}/cancel", post(background::cancel))
        .route("/jobs/{id}/report", get(background::report))
        .route("/jobs/{id}/residuals.csv", get(background::residuals))
}
