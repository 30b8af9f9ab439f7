//! A parallel robot judged where its user judges it: the poses its direct
//! model predicts for the actuator values of measured configurations,
//! against the measured ones.

use gecaro_core::parallel_model::ParallelModel;
use gecaro_data::sample::Sample;

use super::measure::{PlatformMeasure, check_pairs};
use super::observation::actuator_values;
use crate::Error;

/// The errors of a parallel robot's direct model at measured configurations.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlatformErrors {
    /// RMS of the position errors' lengths (m): the platform frame's origin
    /// for poses, the tool point for points, the distance for distances.
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
    if measure == PlatformMeasure::Distance {
        return distance_errors(model, samples);
    }
    let (mut squares, mut largest) = (0.0, 0.0f64);
    let (mut angle_squares, mut angle_largest) = (0.0, 0.0f64);
    let poses = measure == PlatformMeasure::Pose;
    for sample in samples {
        let actuators = actuator_values(model, sample)?;
        let measured = measure.measured(sample)?;
        let pose = solved(model, sample, actuators)?;
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

/// The direct model's pose at a sample's actuator values, from home.
fn solved<M: ParallelModel>(
    model: &M,
    sample: &Sample,
    actuators: &[f64],
) -> Result<nalgebra::Isometry3<f64>, Error> {
    model
        .direct(actuators, &model.home())
        .map_err(|cause| Error::InvalidData {
            line: sample.line,
            message: cause.to_string(),
        })
}

/// [`platform_errors`] of measured distances: each pair's predicted
/// distance between its tool points against the measured one.
fn distance_errors<M: ParallelModel>(
    model: &M,
    samples: &[Sample],
) -> Result<PlatformErrors, Error> {
    let measured = check_pairs(samples)?;
    let (mut squares, mut largest) = (0.0, 0.0f64);
    for (pair, distance) in samples.chunks_exact(2).zip(&measured) {
        let mut points = Vec::with_capacity(2);
        for sample in pair {
            let actuators = actuator_values(model, sample)?;
            points.push(model.tool_point(&solved(model, sample, actuators)?));
        }
        let error = ((points[1] - points[0]).norm() - distance).abs();
        squares += error * error;
        largest = largest.max(error);
    }
    Ok(PlatformErrors {
        position_rms: (squares / measured.len().max(1) as f64).sqrt(),
        position_max: largest,
        angle_rms: None,
        angle_max: None,
    })
}
