//! The JSON API of the page (documented in `docs/api.md`).
//!
//! Every request that computes carries the robot as a [`RobotDocument`]: the
//! page holds the table being edited, and the server keeps no robot between
//! requests. Values are in the document's own units (its `angle_unit`);
//! everything the server computes is in metres and radians.

mod calibration;
mod identification;
mod planning;
mod robot;

use std::path::Path;

use axum::Router;
use axum::extract::FromRequest;
use axum::routing::{get, post};
use gecaro_calib::{
    methods::{CalibrationMethod, MethodOptions, Plane},
    study::Sample,
};
use gecaro_core::OrientationDifference;
use gecaro_io::{DocumentError, Location, RobotDocument, RobotFile};
use nalgebra::Vector3;
use serde::Deserialize;

use crate::error::ApiError;
use crate::limits::{MAX_JOINTS, MAX_SAMPLES};
use crate::state::AppState;

/// A JSON body whose rejections are [`ApiError`]s (JSON bodies of their own).
#[derive(FromRequest)]
#[from_request(via(axum::Json), rejection(ApiError))]
pub(crate) struct Json<T>(pub(crate) T);

impl<T: serde::Serialize> axum::response::IntoResponse for Json<T> {
    fn into_response(self) -> axum::response::Response {
        axum::Json(self.0).into_response()
    }
}

/// Every POST route of the API (full paths), each taking a JSON body: for
/// clients, tests and the fuzz targets. [`routes`] registers them (a test
/// checks that each one answers).
pub const POST_ROUTES: [&str; 8] = [
    "/api/robots/check",
    "/api/robots/new",
    "/api/robots/save",
    "/api/robots/pose",
    "/api/identifiable",
    "/api/generate",
    "/api/plan",
    "/api/identify",
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
        .route("/robots/save", post(robot::save))
        .route("/robots/pose", post(robot::pose))
        .route("/identifiable", post(calibration::identifiable))
        .route("/generate", post(calibration::generate))
        .route("/plan", post(planning::plan))
        .route("/identify", post(identification::submit))
        .route("/jobs/{id}", get(identification::status))
        .route("/jobs/{id}/report", get(identification::report))
}

/// The validated robot of a document.
///
/// # Errors
/// [`ApiError::InvalidRobot`] with every problem of the document.
pub(crate) fn robot_file(document: &RobotDocument) -> Result<RobotFile, ApiError> {
    if document.frame.len() > MAX_JOINTS + 2 {
        return Err(ApiError::InvalidRobot(vec![DocumentError {
            location: Location::Document,
            message: format!(
                "{} frames: the server takes robots of up to {MAX_JOINTS} joints",
                document.frame.len()
            ),
        }]));
    }
    let problems = document.problems();
    if !problems.is_empty() {
        return Err(ApiError::InvalidRobot(problems));
    }
    document
        .to_robot_file("robot")
        .map_err(|problem| ApiError::InvalidRobot(vec![problem]))
}

/// Writes `csv` into the folder as `save_as`, when one is given; the name
/// written.
///
/// # Errors
/// As the folder's `write` (a name outside the folder, an
/// existing file without `overwrite`, ...).
pub(crate) fn save_csv(
    state: &AppState,
    save_as: Option<&str>,
    csv: &str,
    overwrite: bool,
) -> Result<Option<String>, ApiError> {
    let Some(name) = save_as else {
        return Ok(None);
    };
    state
        .workspace()
        .write(name, "csv", csv.as_bytes(), overwrite)?;
    Ok(Some(name.to_owned()))
}

/// The name a data file of `robot` for `what` (a method name, ...) with
/// `count` configurations downloads as: `stanford-position-50.csv`.
pub(crate) fn data_file_name(robot: &gecaro_core::Robot, what: &str, count: usize) -> String {
    let slug = robot
        .name()
        .to_lowercase()
        .replace(|c: char| !c.is_alphanumeric(), "-");
    format!("{slug}-{what}-{count}.csv")
}

/// How orientation differences are computed (Appendix I).
#[derive(Copy, Clone, Debug, Default, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub(crate) enum OrientationChoice {
    /// Method 2 (exact).
    #[default]
    AxisAngle,
    /// Method 1 (first order).
    CrossProducts,
}

/// The method of a request and its options.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct MethodRequest {
    /// `position`, `frame`, `point-link`, `frame-link`, `plane1`, `plane2`, `distance`.
    pub(crate) name: String,
    /// Normal of the plane (plane methods), world frame.
    #[serde(default)]
    pub(crate) plane_normal: Option<[f64; 3]>,
    /// A point of the plane, world frame, metres.
    #[serde(default)]
    pub(crate) plane_point: Option<[f64; 3]>,
    /// Whether the plane (or its normal) is identified too.
    #[serde(default)]
    pub(crate) plane_unknown: Option<bool>,
    /// Orientation difference of the frame methods.
    #[serde(default)]
    pub(crate) orientation: OrientationChoice,
    /// Configurations per set when generating link data.
    #[serde(default)]
    pub(crate) set_size: Option<usize>,
}

impl MethodRequest {
    /// The method with its options.
    ///
    /// # Errors
    /// [`ApiError::BadRequest`] for an unknown method or impossible options.
    pub(crate) fn build(&self) -> Result<Box<dyn CalibrationMethod>, ApiError> {
        let plane = match (self.plane_normal, self.plane_point) {
            (None, None) => None,
            (Some(normal), Some(point)) => {
                Some(Plane::new(Vector3::from(normal), Vector3::from(point))?)
            }
            _ => {
                return Err(ApiError::BadRequest(
                    "a plane needs both plane_normal and plane_point".into(),
                ));
            }
        };
        let (plane, plane_unknown) = MethodOptions::plane_choice(plane, self.plane_unknown)?;
        let options = MethodOptions {
            plane,
            plane_unknown,
            orientation: match self.orientation {
                OrientationChoice::AxisAngle => OrientationDifference::AxisAngle,
                OrientationChoice::CrossProducts => OrientationDifference::CrossProducts,
            },
            set_size: MethodOptions::check_set_size(self.set_size)?,
        };
        Ok(gecaro_calib::methods::method(&self.name, &options)?)
    }
}

/// Where measurements come from: a file of the folder, or CSV text (an upload).
#[derive(Clone, Debug, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub(crate) enum DataRequest {
    /// A `.csv` file of the folder.
    File(String),
    /// CSV text, with a name for messages.
    Csv {
        /// The file's content.
        text: String,
        /// Its name (for messages).
        #[serde(default)]
        name: Option<String>,
    },
}

impl DataRequest {
    /// The samples, checked against the robot and method; and their label.
    ///
    /// # Errors
    /// [`ApiError::Unprocessable`] naming the line at fault, or
    /// [`ApiError::NotFound`]/[`ApiError::Forbidden`] for the file.
    pub(crate) fn samples(
        &self,
        state: &AppState,
        robot: &RobotFile,
        method: &dyn CalibrationMethod,
    ) -> Result<(Vec<Sample>, String), ApiError> {
        let (label, text) = match self {
            DataRequest::File(name) => {
                (name.clone(), state.workspace().read_text(name, &["csv"])?.1)
            }
            DataRequest::Csv { text, name } => (
                name.clone().unwrap_or_else(|| "uploaded data".into()),
                text.clone(),
            ),
        };
        let samples = gecaro_io::parse_samples(
            text.as_bytes(),
            Path::new(&label),
            &gecaro_io::joint_types(&robot.robot),
            method.data_columns(),
            &gecaro_io::DataFormat::default(),
        )?
        .samples;
        if samples.len() > MAX_SAMPLES {
            return Err(ApiError::Unprocessable(format!(
                "{label} has {} configurations; the server takes up to {MAX_SAMPLES}",
                samples.len()
            )));
        }
        Ok((samples, label))
    }
}
