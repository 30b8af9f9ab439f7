//! A simulated "real" platform, the poses it reaches and what a sensor
//! measures there (the paper's points generation, for a parallel robot).

use gecaro_core::gough_stewart::{GoughStewart, LEGS, PARAMETER_COUNT, PARAMETERS_PER_LEG};
use gecaro_data::sample::Sample;
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

use super::measure::PlatformMeasure;
use crate::{Error, simulation::Sampler};

/// Draws per pose kept, at most, before the workspace is said to hold too
/// few reachable poses.
const DRAWS_PER_POSE: usize = 200;

/// Where poses are drawn: about the platform's home pose, within ±`translation`
/// (m) along each axis and ±`rotation` (rad) about each.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlatformWorkspace {
    /// Half the side of the box of positions (m).
    pub translation: f64,
    /// The largest turn about each axis (rad).
    pub rotation: f64,
}

impl PlatformWorkspace {
    /// The workspace a platform's strokes allow: 40 % of the shortest
    /// half-stroke in translation, and the turn that moves the platform's
    /// joints by as much.
    pub fn of(platform: &GoughStewart) -> Self {
        let stroke = platform
            .legs()
            .iter()
            .map(|leg| 0.5 * (leg.max - leg.min) * leg.gain.abs())
            .fold(f64::INFINITY, f64::min);
        let radius = platform
            .legs()
            .iter()
            .map(|leg| leg.platform.norm())
            .sum::<f64>()
            / LEGS as f64;
        Self {
            translation: 0.4 * stroke,
            rotation: (0.4 * stroke / radius.max(1e-3)).min(0.5),
        }
    }
}

/// A "real" platform drawn about `nominal`: every joint centre, length at
/// actuator zero and tool coordinate moved uniformly within ±`level` mm,
/// every gain within ±`level`·10⁻³ of its value.
///
/// # Errors
/// When the drawn platform is not one (an error level of metres).
pub fn perturbed_platform(
    nominal: &GoughStewart,
    level: f64,
    sampler: &mut Sampler,
) -> Result<GoughStewart, Error> {
    let mut values = nominal.parameters();
    for (index, value) in values.iter_mut().enumerate() {
        let gain = index < LEGS * PARAMETERS_PER_LEG && index % PARAMETERS_PER_LEG == 7;
        let spread = if gain {
            level * 1e-3 * value.abs()
        } else {
            level * 1e-3
        };
        *value += sampler.uniform(-spread, spread);
    }
    debug_assert_eq!(values.len(), PARAMETER_COUNT);
    Ok(nominal.with_parameters(&values)?)
}

/// `count` poses of `platform` drawn uniformly in `workspace` about its home
/// pose, each with every actuator value within its range.
///
/// # Errors
/// [`Error::Generation`] when fewer than one draw in [`DRAWS_PER_POSE`]
/// is reachable (a workspace larger than the strokes allow).
pub fn random_platform_poses(
    platform: &GoughStewart,
    count: usize,
    workspace: PlatformWorkspace,
    sampler: &mut Sampler,
) -> Result<Vec<Isometry3<f64>>, Error> {
    let home = platform.home();
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
        if platform
            .legs_out_of_range(&platform.actuator_values(&pose))
            .is_empty()
        {
            poses.push(pose);
        }
    }
    Ok(poses)
}

/// What a sensor measures of the `real` platform at `poses`: the actuator
/// values that put it there (its inverse model) and the measured pose or
/// tool point with Gaussian noise (σ `noise.length` a coordinate,
/// `noise.angle` about each axis).
pub fn simulate_platform(
    real: &GoughStewart,
    measure: PlatformMeasure,
    poses: &[Isometry3<f64>],
    noise: super::PlatformNoise,
    sampler: &mut Sampler,
) -> Vec<Sample> {
    poses
        .iter()
        .map(|pose| {
            let actuators = real.actuator_values(pose);
            let read = match measure {
                PlatformMeasure::Pose => Isometry3::from_parts(
                    Translation3::from(
                        pose.translation.vector + sampler.gaussian_vector(noise.length),
                    ),
                    UnitQuaternion::from_rotation_matrix(&sampler.gaussian_rotation(noise.angle))
                        * pose.rotation,
                ),
                PlatformMeasure::Point => *pose,
            };
            let mut sample = measure.reading(real, &read, &actuators);
            if measure == PlatformMeasure::Point {
                sample.position = sample
                    .position
                    .map(|point| point + sampler.gaussian_vector(noise.length));
            }
            sample
        })
        .collect()
}
