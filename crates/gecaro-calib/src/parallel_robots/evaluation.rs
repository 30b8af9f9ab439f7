//! A parallel robot judged where its user judges it: the poses its direct
//! model predicts for the actuator values of measured configurations,
//! against the measured ones.

use gecaro_core::parallel_model::ParallelModel;
use gecaro_data::sample::Sample;

use super::leg::{MeasuringLeg, leg_reading};
use super::measure::{PlatformMeasure, check_pairs};
use super::observation::actuator_values;
use crate::Error;

/// The errors of a parallel robot's direct model at measured configurations.
#[derive(Clone, Debug, PartialEq)]
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
    /// Each observation's position error (m), in order: a configuration's
    /// (a pose's origin, a point), a pair's distance error.
    pub observations: Vec<f64>,
    /// Each measured pose's orientation error (rad), in order; empty for
    /// points and distances.
    pub observation_angles: Vec<f64>,
}

impl PlatformErrors {
    /// The summary of each observation's position error and, for measured
    /// poses, its orientation error.
    fn of(observations: Vec<f64>, angles: Option<&[f64]>) -> Self {
        let rms = |values: &[f64]| {
            (values.iter().map(|value| value * value).sum::<f64>() / values.len().max(1) as f64)
                .sqrt()
        };
        let largest = |values: &[f64]| values.iter().copied().fold(0.0, f64::max);
        Self {
            position_rms: rms(&observations),
            position_max: largest(&observations),
            angle_rms: angles.map(rms),
            angle_max: angles.map(largest),
            observations,
            observation_angles: angles.map(<[f64]>::to_vec).unwrap_or_default(),
        }
    }
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
    match measure {
        PlatformMeasure::Distance => return distance_errors(model, samples),
        PlatformMeasure::Leg => {
            return Err(Error::InvalidOption {
                setting: crate::Setting::Method,
                message: "a measuring leg's errors are its readings' (leg_errors)".into(),
            });
        }
        PlatformMeasure::Pose | PlatformMeasure::Point => {}
    }
    let poses = measure == PlatformMeasure::Pose;
    let mut observations = Vec::with_capacity(samples.len());
    let mut angles = Vec::with_capacity(if poses { samples.len() } else { 0 });
    for sample in samples {
        let actuators = actuator_values(model, sample)?;
        let measured = measure.measured(sample)?;
        let pose = solved(model, sample, actuators)?;
        let predicted = if poses {
            pose.translation.vector
        } else {
            model.tool_point(&pose)
        };
        observations.push((predicted - measured.translation.vector).norm());
        if poses {
            angles.push((pose.rotation.inverse() * measured.rotation).angle());
        }
    }
    Ok(PlatformErrors::of(
        observations,
        poses.then_some(&angles[..]),
    ))
}

/// The errors of `model` carrying the measuring leg `leg` at `samples`
/// read by it: for each configuration, the direct model from the home pose,
/// and the leg's predicted length against `l + K·s` (m).
///
/// # Errors
/// Samples without the model's number of actuator values or a reading, or
/// actuator values with no pose (naming the sample's line).
pub fn leg_errors<M: ParallelModel>(
    model: &M,
    leg: &MeasuringLeg,
    samples: &[Sample],
) -> Result<PlatformErrors, Error> {
    let observations = samples
        .iter()
        .map(|sample| {
            let actuators = actuator_values(model, sample)?;
            let reading = leg_reading(sample)?;
            let pose = solved(model, sample, actuators)?;
            Ok((leg.length_at(&pose) - leg.length - leg.gain * reading).abs())
        })
        .collect::<Result<Vec<f64>, Error>>()?;
    Ok(PlatformErrors::of(observations, None))
}

/// Whether `samples` are what `measure` reads of `model`, a sample that is
/// not named by its line: the measure's columns, a distance's pairs whole,
/// actuator values whose pose the direct model finds from the home pose —
/// what a fit would otherwise meet mid-way, when it can no longer say in
/// which of several files.
///
/// # Errors
/// As [`platform_errors`] (and [`leg_errors`] for a leg's readings).
pub fn check_platform_samples<M: ParallelModel>(
    model: &M,
    samples: &[Sample],
    measure: PlatformMeasure,
) -> Result<(), Error> {
    measure.check_for(model)?;
    if measure == PlatformMeasure::Distance {
        check_pairs(samples)?;
    }
    for sample in samples {
        let actuators = actuator_values(model, sample)?;
        match measure {
            PlatformMeasure::Pose | PlatformMeasure::Point => {
                measure.measured(sample)?;
            }
            PlatformMeasure::Leg => {
                leg_reading(sample)?;
            }
            PlatformMeasure::Distance => {}
        }
        solved(model, sample, actuators)?;
    }
    Ok(())
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
    let mut observations = Vec::with_capacity(measured.len());
    for (pair, distance) in samples.chunks_exact(2).zip(&measured) {
        let mut points = Vec::with_capacity(2);
        for sample in pair {
            let actuators = actuator_values(model, sample)?;
            points.push(model.tool_point(&solved(model, sample, actuators)?));
        }
        observations.push(((points[1] - points[0]).norm() - distance).abs());
    }
    Ok(PlatformErrors::of(observations, None))
}
