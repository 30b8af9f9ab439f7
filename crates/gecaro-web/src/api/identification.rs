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
    /// Every measured point's deviation from the calibrated robot's (point
    /// measures of a rigid robot), the largest [`MAX_DEVIATIONS`] of them
    /// in data order.
    #[serde(skip_serializing_if = "Option::is_none")]
    deviations: Option<Deviations>,
    /// The correlation matrix of the identified unknowns (the page's heatmap).
    #[serde(skip_serializing_if = "Option::is_none")]
    correlation: Option<gecaro_app::Correlation>,
    /// Each named frame's origin covariance (m², row by row): its
    /// uncertainty ellipsoid.
    #[serde(skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    frame_covariances: std::collections::BTreeMap<String, [[f64; 3]; 3]>,
}

/// The most point deviations a result carries to the page (its table and
/// its 3D view); the residuals CSV holds them all.
const MAX_DEVIATIONS: usize = 2000;

/// The points' deviations as the page takes them.
#[derive(Serialize)]
struct Deviations {
    /// The points measured (with a deviation).
    total: usize,
    /// The largest [`MAX_DEVIATIONS`] deviations, in data order.
    points: Vec<gecaro_app::PointDeviation>,
    /// Where the measurement frame lies in the nominal robot's world (the
    /// 3D view's): its origin (m) and the columns of its rotation (its
    /// axes x, y, z), to draw the instrument and its stations.
    measurement_origin: [f64; 3],
    measurement_axes: [[f64; 3]; 3],
}

impl Deviations {
    fn of(
        mut points: Vec<gecaro_app::PointDeviation>,
        view: nalgebra::IsometryMatrix3<f64>,
    ) -> Deviations {
        let total = points.len();
        if total > MAX_DEVIATIONS {
            let length =
                |p: &gecaro_app::PointDeviation| p.deviation.iter().map(|d| d * d).sum::<f64>();
            points.sort_by(|a, b| length(b).total_cmp(&length(a)));
            points.truncate(MAX_DEVIATIONS);
            points.sort_by_key(|p| p.index);
        }
        let axis = |k: usize| {
            let column = view.rotation.matrix().column(k);
            [column[0], column[1], column[2]]
        };
        let origin = view.translation.vector;
        Deviations {
            total,
            points,
            measurement_origin: [origin.x, origin.y, origin.z],
            measurement_axes: [axis(0), axis(1), axis(2)],
        }
    }
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
    // Taken once: for the residuals file and for the page.
    let deviations = identified.point_deviations();
    let residuals = identified.residuals_csv_with(deviations.as_deref())?;
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
        correlation: gecaro_app::correlation(&identified.result),
        frame_covariances: gecaro_app::frame_covariances(&identified.result),
        deviations: deviations.map(|points| {
            let view = identified
                .result
                .calibrated
                .measurement_frame_in(&identified.loaded.robot.robot);
            Deviations::of(points, view)
        }),
    };
    let report = identified.report(&format!(
        "gecaro serve: {} method on {}",
        identified.loaded.study.method_names(),
        identified.loaded.label
    ))?;
    Ok(JobOutcome {
        result: background::encoded(&value)?,
        report: Some(report),
        residuals: Some(residuals),
    })
}
