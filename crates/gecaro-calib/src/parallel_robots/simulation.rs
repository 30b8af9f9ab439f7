//! A simulated "real" parallel robot, the poses it reaches and what a
//! sensor measures there (the paper's points generation, for a parallel
//! robot).

use gecaro_core::parallel_model::{ParallelModel, ParameterUnit, moved};
use gecaro_data::sample::Sample;
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

use super::leg::MeasuringLeg;
use super::measure::{PlatformMeasure, PlatformNoise};
use crate::Error;
use crate::simulation::{MAX_ERROR_LEVEL, Sampler};

/// Draws per pose kept, at most, before the workspace is said to hold too
/// few reachable poses.
const DRAWS_PER_POSE: usize = 200;

/// Where poses are drawn: about the home pose, within ±`translation` (m)
/// along each axis and ±`rotation` (rad) about each (for a platform that
/// turns).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlatformWorkspace {
    /// Half the side of the box of positions (m).
    pub translation: f64,
    /// The largest turn about each axis (rad).
    pub rotation: f64,
}

impl PlatformWorkspace {
    /// The share of [`whole`](Self::whole) that [`of`](Self::of) takes.
    pub const GENERATED_SHARE: f64 = 0.6;

    /// The workspace a robot's ranges allow about its home pose, as points
    /// generation draws it: [`GENERATED_SHARE`](Self::GENERATED_SHARE) of
    /// [`whole`](Self::whole).
    pub fn of(model: &impl ParallelModel) -> Self {
        Self::whole(model).scaled(Self::GENERATED_SHARE)
    }

    /// The box of the twelve moves (±x, ±y, ±z; ±turns) a robot can make
    /// alone from its home pose before an actuator leaves its range, found
    /// by bisection: its whole work region (a pose drawn in it is kept when
    /// every actuator is within its range).
    pub fn whole(model: &impl ParallelModel) -> Self {
        let home = model.home();
        let reach = |axis: usize, sign: f64| {
            let inside = |size: f64| {
                let mut step = vec![0.0; model.pose_freedom()];
                step[axis] = sign * size;
                let pose = moved(&home, &step);
                model
                    .actuator_values(&pose)
                    .is_ok_and(|values| model.out_of_range(&values).is_empty())
            };
            let (mut low, mut high) = (0.0, 1.0);
            for _ in 0..50 {
                let middle = 0.5 * (low + high);
                if inside(middle) {
                    low = middle;
                } else {
                    high = middle;
                }
            }
            low
        };
        let shortest = |axes: std::ops::Range<usize>| {
            axes.flat_map(|axis| [reach(axis, 1.0), reach(axis, -1.0)])
                .fold(f64::INFINITY, f64::min)
        };
        Self {
            translation: shortest(0..3),
            rotation: if model.pose_freedom() == 6 {
                shortest(3..6)
            } else {
                0.0
            },
        }
    }

    /// This workspace with its sides and turns multiplied by `share`.
    pub fn scaled(self, share: f64) -> Self {
        Self {
            translation: self.translation * share,
            rotation: self.rotation * share,
        }
    }
}

/// A "real" robot drawn about `nominal`: every length moved uniformly within
/// ±`level` mm, every angle within ±`level` mrad, every gain within
/// ±`level`·10⁻³ of its value.
///
/// # Errors
/// [`Error::InvalidOption`] for a level that is not a number in
/// 0..=[`MAX_ERROR_LEVEL`] (the serial robots' bound).
pub fn perturbed_platform<M: ParallelModel>(
    nominal: &M,
    level: f64,
    sampler: &mut Sampler,
) -> Result<M, Error> {
    if !(0.0..=MAX_ERROR_LEVEL).contains(&level) {
        return Err(Error::InvalidOption {
            setting: crate::Setting::ErrorLevel,
            message: format!(
                "must be a number from 0 to {MAX_ERROR_LEVEL} (±{MAX_ERROR_LEVEL} mm and mrad, \
                 ±{} % on gains for a parallel robot), not {level:e}",
                MAX_ERROR_LEVEL / 10.0
            ),
        });
    }
    let mut values = nominal.parameters();
    for (index, value) in values.iter_mut().enumerate() {
        let spread = match nominal.parameter_unit(index) {
            ParameterUnit::Gain => level * 1e-3 * value.abs(),
            ParameterUnit::Length | ParameterUnit::Angle => level * 1e-3,
        };
        *value += sampler.uniform(-spread, spread);
    }
    Ok(nominal.with_parameters(&values)?)
}

/// `count` poses of `model` drawn uniformly in `workspace` about its home
/// pose, each reached with every actuator value within its range.
///
/// # Errors
/// [`Error::Generation`] when fewer than one draw in 200 is reachable (a
/// workspace larger than the ranges allow).
pub fn random_platform_poses(
    model: &impl ParallelModel,
    count: usize,
    workspace: PlatformWorkspace,
    sampler: &mut Sampler,
) -> Result<Vec<Isometry3<f64>>, Error> {
    let home = model.home();
    let mut poses = Vec::with_capacity(count);
    let mut draws = 0;
    while poses.len() < count {
        if draws >= DRAWS_PER_POSE * count.max(1) {
            return Err(Error::Generation {
                message: format!(
                    "only {} of {draws} poses drawn within ±{:.1} mm and ±{:.2}° of the home \
                     pose are within the actuators' ranges: a smaller workspace is needed",
                    poses.len(),
                    workspace.translation * 1e3,
                    workspace.rotation.to_degrees(),
                ),
            });
        }
        draws += 1;
        let mut axis = || sampler.uniform(-1.0, 1.0);
        let offset = Vector3::new(axis(), axis(), axis()) * workspace.translation;
        let turn = Vector3::new(axis(), axis(), axis()) * workspace.rotation;
        let pose = Isometry3::from_parts(
            Translation3::from(home.translation.vector + offset),
            UnitQuaternion::from_scaled_axis(turn) * home.rotation,
        );
        if model
            .actuator_values(&pose)
            .is_ok_and(|values| model.out_of_range(&values).is_empty())
        {
            poses.push(pose);
        }
    }
    Ok(poses)
}

/// What a sensor measures of the `real` robot at `poses`: the actuator
/// values that put it there (its inverse model) and the measured pose or
/// tool point with Gaussian noise (σ `noise.length` a coordinate,
/// `noise.angle` about each axis); for a distance, consecutive poses are
/// pairs (`pair` 1, 2, …) and both rows carry the distance between their
/// tool points, its noise σ `noise.length`.
///
/// # Errors
/// A measure the structure cannot take, a pose the real robot does not
/// reach, an odd number of poses for a distance.
pub fn simulate_platform<M: ParallelModel>(
    real: &M,
    measure: PlatformMeasure,
    poses: &[Isometry3<f64>],
    noise: PlatformNoise,
    sampler: &mut Sampler,
) -> Result<Vec<Sample>, Error> {
    measure.check_for(real)?;
    match measure {
        PlatformMeasure::Distance => return simulate_distances(real, poses, noise, sampler),
        PlatformMeasure::Leg => {
            return Err(Error::InvalidOption {
                setting: crate::Setting::Method,
                message: "a measuring leg's readings are simulated with its mount \
                          (simulate_leg)"
                    .into(),
            });
        }
        PlatformMeasure::Pose | PlatformMeasure::Point => {}
    }
    poses
        .iter()
        .map(|pose| {
            let actuators = real.actuator_values(pose)?;
            let read = match measure {
                PlatformMeasure::Pose => Isometry3::from_parts(
                    Translation3::from(
                        pose.translation.vector + sampler.gaussian_vector(noise.length),
                    ),
                    UnitQuaternion::from_rotation_matrix(&sampler.gaussian_rotation(noise.angle))
                        * pose.rotation,
                ),
                PlatformMeasure::Point | PlatformMeasure::Distance | PlatformMeasure::Leg => *pose,
            };
            let mut sample = measure.reading(real, &read, &actuators);
            if measure == PlatformMeasure::Point {
                sample.position = sample
                    .position
                    .map(|point| point + sampler.gaussian_vector(noise.length));
            }
            Ok(sample)
        })
        .collect()
}

/// What a measuring leg `leg` on the `real` robot reads at `poses`: the
/// actuator values that put it there and the leg's reading
/// `(‖p + R·b − a‖ − l)/K` with Gaussian noise of σ `noise.length` on its
/// length, in the `distance` column.
///
/// # Errors
/// A structure a measuring leg cannot calibrate, a pose the real robot
/// does not reach.
pub fn simulate_leg<M: ParallelModel>(
    real: &M,
    leg: &MeasuringLeg,
    poses: &[Isometry3<f64>],
    noise: PlatformNoise,
    sampler: &mut Sampler,
) -> Result<Vec<Sample>, Error> {
    PlatformMeasure::Leg.check_for(real)?;
    poses
        .iter()
        .map(|pose| {
            let mut sample = Sample::new(real.actuator_values(pose)?);
            sample.distance = Some(
                (leg.length_at(pose) + sampler.gaussian(noise.length) - leg.length) / leg.gain,
            );
            Ok(sample)
        })
        .collect()
}

/// [`simulate_platform`] of distances.
fn simulate_distances<M: ParallelModel>(
    real: &M,
    poses: &[Isometry3<f64>],
    noise: PlatformNoise,
    sampler: &mut Sampler,
) -> Result<Vec<Sample>, Error> {
    if !poses.len().is_multiple_of(2) {
        return Err(Error::InvalidOption {
            setting: crate::Setting::Count,
            message: format!(
                "a distance is measured between two poses: {} poses are not whole pairs",
                poses.len()
            ),
        });
    }
    let mut samples = Vec::with_capacity(poses.len());
    for (index, pair) in poses.chunks_exact(2).enumerate() {
        let first = real.actuator_values(&pair[0])?;
        let second = real.actuator_values(&pair[1])?;
        let distance = (real.tool_point(&pair[1]) - real.tool_point(&pair[0])).norm()
            + sampler.gaussian(noise.length);
        for actuators in [first, second] {
            let mut sample = Sample::new(actuators);
            sample.group = Some(index as u64 + 1);
            sample.distance = Some(distance);
            samples.push(sample);
        }
    }
    Ok(samples)
}
