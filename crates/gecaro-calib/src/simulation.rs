//! Points generation (paper §4): a simulated "real" robot and what sensors
//! would measure on it.
//!
//! The real robot is the nominal one with every parameter that has a non-zero
//! priority moved by a uniform error of ±L units at error level L: lengths
//! ±L cm, angles ±L°, gains ±L % (level 10 moves the Stanford's terminal point
//! by 0.3–0.8 m). The method then generates configurations that satisfy its
//! constraint *for the real robot*, with Gaussian sensor noise.

use gecaro_core::{ParameterKind, Robot, terminal_pose};

use crate::Error;
use crate::error::Setting;
use crate::method::CalibrationMethod;
use crate::progress::Observer;
use crate::sample::Sample;
use crate::samples::SampleSlice;

pub use crate::sampler::{CELL_DRAWS, DEFAULT_SEED, RANDOM_STARTS, Sampler, solve_from_starts};

/// Largest error level: ±50 cm on lengths, ±50° on angles, ±50 % on gains.
/// Beyond it a simulated robot is no longer a perturbation of the nominal one
/// (gains could reach zero, lengths overflow).
pub const MAX_ERROR_LEVEL: f64 = 50.0;

/// The error level of a simulated real robot when none is asked for: ±1 cm,
/// ±1°, ±1 % (a parallel robot's: ±1 mm, ±1 mrad, ±0.1 %).
pub const DEFAULT_ERROR_LEVEL: f64 = 1.0;

/// Largest sensor noise: 1 m (1 rad for orientations). Beyond it no
/// measurement carries information, and simulated values lose their digits.
pub const MAX_NOISE: f64 = 1.0;

/// Size of one error unit (the unit of `--error-level`): 0.01 m for lengths,
/// 1° (in radians) for angles, 1 % (a fraction of the value) for gains, and
/// 1e-6 rad/(N·m) (m/N) for compliances, about a tenth of a soft joint's,
/// 1° for gravity's tilts.
pub fn error_unit(kind: ParameterKind) -> f64 {
    match kind {
        ParameterKind::D | ParameterKind::R => 0.01,
        ParameterKind::Alpha
        | ParameterKind::Theta
        | ParameterKind::Beta
        | ParameterKind::GravityTilt => 1f64.to_radians(),
        ParameterKind::Gain => 0.01,
        ParameterKind::Compliance => 1e-6,
    }
}

/// The nominal robot with uniform errors of ±`level` units on every parameter
/// of non-zero priority (see the module docs).
///
/// # Errors
/// [`Error::InvalidOption`] for a level that is not a number in
/// 0..=[`MAX_ERROR_LEVEL`].
pub fn perturbed_robot(nominal: &Robot, level: f64, sampler: &mut Sampler) -> Result<Robot, Error> {
    if !(0.0..=MAX_ERROR_LEVEL).contains(&level) {
        return Err(Error::InvalidOption {
            setting: Setting::ErrorLevel,
            message: format!(
                "must be a number from 0 to {MAX_ERROR_LEVEL} (±{MAX_ERROR_LEVEL} cm, °, %), \
                 not {level:e}"
            ),
        });
    }
    let priority = nominal.priority();
    let mut real = nominal.clone();
    for id in nominal.parameters().ids() {
        if priority.get(*id) == 0 {
            continue;
        }
        let error = sampler.uniform(-level, level) * error_unit(id.kind);
        let value = nominal.parameter(*id);
        let moved = match id.kind {
            ParameterKind::Gain => value * (1.0 + error),
            _ => value + error,
        };
        real.set_parameter(*id, moved)?;
    }
    real.set_name(format!(
        "{} (simulated real, error level {level})",
        nominal.name()
    ));
    Ok(real)
}

/// `real` with its joint limits narrowed to the configurations whose motor
/// readings the nominal robot places within its own limits, as a controller
/// holds them (its software limits are in the nominal model's joint values):
/// the robot to draw simulated measurements on. The gains of the real robot
/// differ, so the same motor reading is another joint value for each robot,
/// and configurations drawn near a limit of the real robot would read as
/// beyond the nominal limit (every `identify` would warn of them). The
/// geometry is the real robot's; only the limits differ.
///
/// With `M` the motor-to-joint map (eq. 4) of each robot and the offsets
/// shared, `q_nominal − Offset = T · (q_real − Offset)`, `T = M_nominal ·
/// M_real⁻¹`. Each limit moves inwards by `δ_j = Σ_k |T − I|_jk · max|q_k −
/// Offset_k|`, the largest change of row j over the joint box (at most a
/// quarter of the range on each side).
///
/// # Errors
/// Never for robots of the same joints (the narrowed limits stay ordered).
pub fn within_nominal_limits(nominal: &Robot, real: &Robot) -> Result<Robot, Error> {
    let real = real.clone();
    if real.joint_count() != nominal.joint_count() {
        return Ok(real);
    }
    let Some(inverse) = real.motor_to_joint().clone().try_inverse() else {
        return Ok(real);
    };
    let change = nominal.motor_to_joint() * inverse
        - nalgebra::DMatrix::identity(real.joint_count(), real.joint_count());
    let reach: Vec<f64> = real
        .joints()
        .iter()
        .map(|joint| {
            (joint.qmin - joint.offset)
                .abs()
                .max((joint.qmax - joint.offset).abs())
        })
        .collect();
    let mut spec = real.to_spec();
    for (row, joint) in spec.joints.iter_mut().enumerate() {
        let shift: f64 = (0..reach.len())
            .map(|k| change[(row, k)].abs() * reach[k])
            .sum();
        let shift = shift.min(0.25 * (joint.qmax - joint.qmin));
        joint.qmin += shift;
        joint.qmax -= shift;
    }
    Ok(Robot::new(spec)?)
}

/// How far the terminal point of `real` is from that of `nominal` over the
/// configurations of `samples`: (RMS, largest) distance in metres. It tells
/// how large the simulated errors are in the units a user feels.
///
/// # Errors
/// When a configuration does not fit the robots.
pub fn terminal_displacement(
    nominal: &Robot,
    real: &Robot,
    samples: SampleSlice<'_>,
) -> Result<(f64, f64), Error> {
    let mut squares = 0.0;
    let mut largest: f64 = 0.0;
    for sample in samples {
        let a = terminal_pose(nominal, sample.motor_positions())?
            .translation
            .vector;
        let b = terminal_pose(real, sample.motor_positions())?
            .translation
            .vector;
        let distance = (a - b).norm();
        squares += distance * distance;
        largest = largest.max(distance);
    }
    Ok(((squares / samples.len().max(1) as f64).sqrt(), largest))
}

/// Data a method's sensor would give on `real`: `count` configurations that
/// satisfy its constraint, with Gaussian noise of `noise` (metres, radians).
/// `observer` hears of the configurations done and may stop the work.
///
/// # Errors
/// [`Error::Generation`] when the constraint cannot be met,
/// [`Error::Interrupted`] when the observer stops the work.
pub fn simulate_measurements(
    real: &Robot,
    method: &dyn CalibrationMethod,
    count: usize,
    noise: f64,
    sampler: &mut Sampler,
    observer: &mut dyn Observer,
) -> Result<Vec<Sample>, Error> {
    check_noise(noise)?;
    if count == 0 {
        return Err(Error::InvalidOption {
            setting: Setting::Count,
            message: "must be at least 1".into(),
        });
    }
    method
        .sensor()
        .generate(real, count, noise, sampler, observer)
}

/// Simulated measurements of `real` at planned configurations (see
/// [`Sensor::measure_at`](crate::methods::Sensor::measure_at)).
///
/// `observer` hears of the configurations done and may stop the work.
///
/// # Errors
/// A negative or non-finite `noise`, no configurations, and the method's
/// own; [`Error::Interrupted`] when the observer stops the work.
pub fn simulate_at(
    real: &Robot,
    method: &dyn CalibrationMethod,
    planned: SampleSlice<'_>,
    noise: f64,
    sampler: &mut Sampler,
    observer: &mut dyn Observer,
) -> Result<Vec<Sample>, Error> {
    check_noise(noise)?;
    if planned.is_empty() {
        return Err(Error::InvalidData {
            line: None,
            message: "no configurations to measure at".into(),
        });
    }
    for sample in planned {
        real.check_configuration(sample.motor_positions())?;
    }
    method
        .sensor()
        .measure_at(real, planned, noise, sampler, observer)
}

/// A sensor's standard deviation must be a number in 0..=[`MAX_NOISE`].
fn check_noise(noise: f64) -> Result<(), Error> {
    if (0.0..=MAX_NOISE).contains(&noise) {
        Ok(())
    } else {
        Err(Error::InvalidOption {
            setting: Setting::Noise,
            message: format!(
                "must be a standard deviation from 0 to {MAX_NOISE} (metres; radians for \
                 orientations), not {noise:e}"
            ),
        })
    }
}

/// A robot judged against the real one where its user will: on held-out
/// configurations, by the tool points it predicts, after the rigid
/// registration that best maps them onto the real robot's ([`judge`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Judgement {
    /// RMS distance (metres) between the registered predicted tool points
    /// and the real ones: what is left once the base frame, which link and
    /// plane methods do not observe, is fitted.
    pub rms: f64,
    /// The largest of those distances (metres).
    pub max: f64,
    /// The scale of the similarity that best maps the predicted points onto
    /// the real ones: above 1, the robot is too small (1.0 for a robot of
    /// the right size).
    pub scale: f64,
}

/// `robot` judged against `real` at `configurations` (motor positions; see
/// [`Judgement`]). The registration is rigid, so a robot of the wrong size
/// shows its error here however well it fits its own data.
///
/// # Errors
/// A configuration that does not fit the robots, or fewer than three.
pub fn judge(robot: &Robot, real: &Robot, configurations: &[Vec<f64>]) -> Result<Judgement, Error> {
    use crate::registration::{rigid_fit, similarity_fit};
    if configurations.len() < 3 {
        return Err(Error::InvalidData {
            line: None,
            message: format!(
                "a judgement needs three configurations at least, not {}",
                configurations.len()
            ),
        });
    }
    let points = |robot: &Robot| -> Result<Vec<nalgebra::Vector3<f64>>, Error> {
        configurations
            .iter()
            .map(|motors| Ok(terminal_pose(robot, motors)?.translation.vector))
            .collect()
    };
    let (predicted, truth) = (points(robot)?, points(real)?);
    let registration = rigid_fit(&predicted, &truth);
    let distances: Vec<f64> = predicted
        .iter()
        .zip(&truth)
        .map(|(p, t)| ((registration * nalgebra::Point3::from(*p)).coords - t).norm())
        .collect();
    Ok(Judgement {
        rms: (distances.iter().map(|d| d * d).sum::<f64>() / distances.len() as f64).sqrt(),
        max: distances.iter().copied().fold(0.0, f64::max),
        scale: similarity_fit(&predicted, &truth).scale,
    })
}

/// `count` configurations of `robot` drawn at random within its joint
/// limits: held-out configurations for [`judge`].
pub fn held_out_configurations(
    robot: &Robot,
    count: usize,
    sampler: &mut Sampler,
) -> Vec<Vec<f64>> {
    (0..count).map(|_| sampler.configuration(robot)).collect()
}
