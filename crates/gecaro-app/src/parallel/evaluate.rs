//! A parallel robot judged on measured configurations: its direct model's
//! pose (or tool point) at each one's actuator values, against the
//! measured one. Data an instrument took in its own frame (the platform
//! more than 50 mm off them) are registered on all their rows first, and
//! the result says so.

use gecaro_calib::parallel_robots::{in_base_frame, measurement_frame, platform_errors};
use gecaro_core::parallel_model::ParallelModel;
use serde::Deserialize;

use super::documents::{PlatformErrorsDocument, pose_document};
use super::{actuator_types, load_parallel_robot, measure_without_leg};
use crate::documents::PoseJson;
use crate::error::AppError;
use crate::files::Files;
use crate::sources::{DataFormatSpec, DataSource};

/// An evaluation of a parallel robot.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParallelEvaluateRequest {
    /// The platform (a calibrated one's file, typically).
    pub robot: String,
    /// `frame`, `position` or `distance`.
    pub method: String,
    /// The held-out measurements.
    pub data: DataSource,
    /// Units and columns of the data file.
    #[serde(default)]
    pub format: DataFormatSpec,
}

/// An evaluated platform.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ParallelEvaluated {
    /// The platform's name.
    pub robot: String,
    /// `frame`, `position` or `distance`.
    pub method: &'static str,
    /// The data's label.
    pub data: String,
    /// Configurations evaluated.
    pub configurations: usize,
    /// The errors.
    pub errors: PlatformErrorsDocument,
    /// The base frame in the instrument's frame, when the data were in
    /// another frame (the platform more than 50 mm off them) and were
    /// registered on all their rows before they were judged: the errors are
    /// then the platform's up to its base frame's pose.
    pub registered: Option<PoseJson>,
}

impl ParallelEvaluateRequest {
    /// Runs the evaluation.
    ///
    /// # Errors
    /// A robot or data file that cannot be read, actuator values with no
    /// pose (naming the line).
    pub fn run(&self, files: &dyn Files) -> Result<ParallelEvaluated, AppError> {
        let file = load_parallel_robot(&self.robot, files)?;
        let measure = measure_without_leg(&self.method, &file.robot, "evaluate")?;
        let read = self.data.read(
            files,
            &actuator_types(&file.robot),
            measure.columns(),
            &self.format.format()?,
        )?;
        let mut samples = read.samples.to_rows();
        let registered = measurement_frame(&file.robot, &samples, measure);
        if let Some(frame) = &registered {
            samples = in_base_frame(&samples, frame);
        }
        let errors = platform_errors(&file.robot, &samples, measure)?;
        Ok(ParallelEvaluated {
            robot: file.robot.name().to_owned(),
            method: measure.name(),
            data: read.label,
            configurations: samples.len(),
            errors: (&errors).into(),
            registered: registered.as_ref().map(pose_document),
        })
    }
}
