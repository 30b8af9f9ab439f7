//! A platform judged where its user judges it: the poses its direct model
//! predicts for the actuator values of measured configurations, against the
//! measured ones.

use gecaro_core::gough_stewart::{GoughStewart, LEGS};
use gecaro_data::sample::Sample;

use super::measure::PlatformMeasure;
use crate::Error;

/// The errors of a platform's direct model at measured configurations.
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

/// The errors of `platform` at `samples` measured by `measure`: for each,
/// the direct model from the platform's home pose (the assembly mode of a
/// platform above its base) against the measured pose or point.
///
/// # Errors
/// Samples without six actuator values or the measure's columns, or
/// actuator values with no pose (naming the sample's line).
pub fn platform_errors(
    platform: &GoughStewart,
    samples: &[Sample],
    measure: PlatformMeasure,
) -> Result<PlatformErrors, Error> {
    let (mut squares, mut largest) = (0.0, 0.0f64);
    let (mut angle_squares, mut angle_largest) = (0.0, 0.0f64);
    for sample in samples {
        let actuators: [f64; LEGS] =
            sample
                .motor_positions
                .as_slice()
                .try_into()
                .map_err(|_| Error::InvalidData {
                    line: sample.line,
                    message: format!("a Gough–Stewart platform has {LEGS} actuator values qm1…qm6"),
                })?;
        let measured = measure.measured(sample)?;
        let pose = platform
            .direct(&actuators, &platform.home())
            .map_err(|cause| Error::InvalidData {
                line: sample.line,
                message: cause.to_string(),
            })?;
        let (predicted, read) = match measure {
            PlatformMeasure::Pose => (pose.translation.vector, measured.translation.vector),
            PlatformMeasure::Point => (platform.tool_point(&pose), measured.translation.vector),
        };
        let error = (predicted - read).norm();
        squares += error * error;
        largest = largest.max(error);
        if measure == PlatformMeasure::Pose {
            let angle = (pose.rotation.inverse() * measured.rotation).angle();
            angle_squares += angle * angle;
            angle_largest = angle_largest.max(angle);
        }
    }
    let count = samples.len().max(1) as f64;
    let poses = measure == PlatformMeasure::Pose;
    Ok(PlatformErrors {
        position_rms: (squares / count).sqrt(),
        position_max: largest,
        angle_rms: poses.then(|| (angle_squares / count).sqrt()),
        angle_max: poses.then_some(angle_largest),
    })
}
