//! A parallel robot judged where its user judges it: the poses its direct
//! model predicts for the actuator values of measured configurations,
//! against the measured ones.

use gecaro_core::parallel_model::ParallelModel;
use gecaro_data::sample::Sample;

use super::measure::PlatformMeasure;
use super::observation::actuator_values;
use crate::Error;

/// The errors of a parallel robot's direct model at measured configurations.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlatformErrors {
    /// RMS of the position errors' lengths (m): the platform frame's origin
    /// for poses, the tool point for points.
    pub position_rms: f64,
    /// The largest position error (m).
    pub position_max: f64,
    /// RMS of the orientation errors' angles (rad), for measured poses.
    pub angle_rms: Option<f64>,
    /// The largest orientation error (rad), for measured poses.
    pub angle_max: Option<f64>,
}

/// The errors of `model` at `samples` measured by `measure`: for each, the
/// direct model from the home pose (the assembly mode the robot works in)
/// against the measured pose or point.
///
/// # Errors
/// Samples without the model's number of actuator values or the measure's
/// columns, or actuator values with no pose (naming the sample's line).
pub fn platform_errors<M: ParallelModel>(
    model: &M,
    samples: &[Sample],
    measure: PlatformMeasure,
) -> Result<PlatformErrors, Error> {
    let (mut squares, mut largest) = (0.0, 0.0f64);
    let (mut angle_squares, mut angle_largest) = (0.0, 0.0f64);
    let poses = measure == PlatformMeasure::Pose;
    for sample in samples {
        let actuators = actuator_values(model, sample)?;
        let measured = measure.measured(sample)?;
        let pose = model
            .direct(actuators, &model.home())
            .map_err(|cause| Error::InvalidData {
                line: sample.line,
                message: cause.to_string(),
            })?;
        let predicted = if poses {
            pose.translation.vector
        } else {
            model.tool_point(&pose)
        };
        let error = (predicted - measured.translation.vector).norm();
        squares += error * error;
        largest = largest.max(error);
        if poses {
            let angle = (pose.rotation.inverse() * measured.rotation).angle();
            angle_squares += angle * angle;
            angle_largest = angle_largest.max(angle);
        }
    }
    let count = samples.len().max(1) as f64;
    Ok(PlatformErrors {
        position_rms: (squares / count).sqrt(),
        position_max: largest,
        angle_rms: poses.then(|| (angle_squares / count).sqrt()),
        angle_max: poses.then_some(angle_largest),
    })
}
