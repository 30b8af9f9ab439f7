//! The frame of data an instrument took elsewhere — a laser tracker metres
//! from the platform, levelled its own way — registered in closed form
//! before the identification, so that the parameters are found in the
//! robot's base frame and not as joint centres metres away.
//!
//! The nominal robot's direct model gives, at each measured
//! configuration, the platform's pose in the base frame; the measured one
//! is in the instrument's. When the two differ, RMS over the measured
//! positions, by more than any platform's error
//! ([`PLAUSIBLE_LENGTH`]), the data are taken to be in another frame and
//! the rigid transform `T` (the base frame in the instrument's) that best
//! maps the one onto the other (Horn/Kabsch, [`crate::registration`]) is
//! found — from four points of each measured pose (its origin and a
//! decimetre along each axis), or from the measured points, of at most
//! [`FRAME_SAMPLES`] configurations spread over the data — and every
//! measurement is brought into the base frame by `T⁻¹`. The
//! identification then finds the rest: the base frame is the nominal
//! robot's best fit to the data, the frame a vendor's drawing states.
//! Distances and a measuring leg's readings have no frame and are never
//! registered.

use gecaro_core::parallel_model::ParallelModel;
use gecaro_data::sample::Sample;
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};

use super::measure::PlatformMeasure;
use super::observation::actuator_values;
use super::plausible::PLAUSIBLE_LENGTH;
use crate::registration::rigid_fit;
use crate::sampler::spread_indices;

/// The arm of the points a measured pose gives the fit, along each of its
/// axes (m).
const AXIS_POINT: f64 = 0.1;

/// Configurations the frame is found from at most, spread over the data:
/// six unknowns need few, and the direct model of 10⁵ would cost more than
/// the fit.
const FRAME_SAMPLES: usize = 2000;

/// The base frame in the instrument's frame, when `samples` measured by
/// `measure` are in another frame than `model`'s base (module docs);
/// `None` when they are in it (or give no frame: distances, or fewer than
/// three configurations the nominal robot reaches).
pub fn measurement_frame<M: ParallelModel>(
    model: &M,
    samples: &[Sample],
    measure: PlatformMeasure,
) -> Option<Isometry3<f64>> {
    if !measure.has_frame() {
        return None;
    }
    let home = model.home();
    let (mut nominal, mut measured) = (Vec::new(), Vec::new());
    for sample in spread_indices(samples.len(), FRAME_SAMPLES)
        .into_iter()
        .map(|index| &samples[index])
    {
        let (Ok(actuators), Ok(read)) = (actuator_values(model, sample), measure.measured(sample))
        else {
            continue;
        };
        let Ok(pose) = model.direct(actuators, &home) else {
            continue;
        };
        match measure {
            PlatformMeasure::Pose => {
                for axis in [Vector3::zeros(), Vector3::x(), Vector3::y(), Vector3::z()] {
                    let arm = Point3::from(axis * AXIS_POINT);
                    nominal.push((pose * arm).coords);
                    measured.push((read * arm).coords);
                }
            }
            _ => {
                nominal.push(model.tool_point(&pose));
                measured.push(read.translation.vector);
            }
        }
    }
    if nominal.len() < 3 {
        return None;
    }
    let rms = |transform: &dyn Fn(&Vector3<f64>) -> Vector3<f64>| {
        let squares: f64 = nominal
            .iter()
            .zip(&measured)
            .map(|(from, to)| (transform(from) - to).norm_squared())
            .sum();
        (squares / nominal.len() as f64).sqrt()
    };
    if rms(&|point| *point) <= PLAUSIBLE_LENGTH {
        return None;
    }
    let fit = rigid_fit(&nominal, &measured);
    let frame = Isometry3::from_parts(
        Translation3::from(fit.translation.vector),
        UnitQuaternion::from_rotation_matrix(&fit.rotation),
    );
    (rms(&|point| (frame * Point3::from(*point)).coords) < rms(&|point| *point)).then_some(frame)
}

/// `samples` brought from the instrument's frame into the base frame
/// (`frame` the base frame in the instrument's): measured positions and
/// orientations by `frame⁻¹`.
pub fn in_base_frame(samples: &[Sample], frame: &Isometry3<f64>) -> Vec<Sample> {
    let inverse = frame.inverse();
    samples
        .iter()
        .map(|sample| {
            let mut moved = sample.clone();
            moved.position = sample
                .position
                .map(|position| (inverse * Point3::from(position)).coords);
            moved.orientation = sample
                .orientation
                .map(|orientation| inverse.rotation * orientation);
            moved
        })
        .collect()
}
