//! What every parallel robot is to the calibration ([`ParallelModel`]): k
//! actuators, k closure equations `F(x, qm, ξ) = 0` that tie the platform's
//! pose x to the actuator values qm and the parameters ξ, their
//! derivatives, the explicit inverse model, and the direct model solved by
//! Newton's method on the closure equations — Khalil's approach for closed
//! chains, for the Gough–Stewart platform ([`crate::gough_stewart`]) and the
//! Delta robot ([`crate::delta`]) alike.
//!
//! A pose change is `[δp; ω]` with `R ← exp(ω)·R` (base frame) for a
//! platform that turns, `δp` alone for one that only translates (a Delta's);
//! [`ParallelModel::pose_freedom`] says which (6 or 3).

use nalgebra::{DMatrix, DVector, Isometry3, Translation3, UnitQuaternion, Vector3};

use crate::error::{Error, Field};
use crate::stated::{MIN_GAIN, check_magnitude};

/// Newton iterations at most: from a start a stroke away, convergence
/// takes 4–6.
const MAX_ITERATIONS: usize = 50;

/// The closure equations' residual below which the pose is solved (m).
const TOLERANCE: f64 = 1e-12;

/// A parallel robot; see the module docs.
pub trait ParallelModel: Clone + std::fmt::Debug + Send + Sync {
    /// Its name.
    fn name(&self) -> &str;

    /// The same robot under another name.
    #[must_use]
    fn renamed(&self, name: &str) -> Self;

    /// k: actuators, and closure equations.
    fn actuator_count(&self) -> usize;

    /// 6 for a platform that turns, 3 for one that only translates.
    fn pose_freedom(&self) -> usize;

    /// The parameter vector ξ.
    fn parameters(&self) -> Vec<f64>;

    /// The names of [`parameters`](Self::parameters).
    fn parameter_names(&self) -> Vec<String>;

    /// Whether parameter `index` is a gain (dimensionless; the others are
    /// lengths, or angles for a Delta's).
    fn parameter_unit(&self, index: usize) -> ParameterUnit;

    /// The indices of the tool point's three parameters.
    fn tool_parameters(&self) -> std::ops::Range<usize>;

    /// The same robot with other parameter values (name, ranges and home
    /// kept).
    ///
    /// # Errors
    /// [`Error::Invalid`] for values no such robot has.
    fn with_parameters(&self, values: &[f64]) -> Result<Self, Error>;

    /// The home pose: the direct model's default start, which fixes the
    /// assembly mode.
    fn home(&self) -> Isometry3<f64>;

    /// The tool point, in the platform frame (m).
    fn tool(&self) -> Vector3<f64>;

    /// The tool point at a pose, in the base frame.
    fn tool_point(&self, pose: &Isometry3<f64>) -> Vector3<f64> {
        pose.transform_point(&nalgebra::Point3::from(self.tool()))
            .coords
    }

    /// `F(x, qm)`: one residual per actuator (m).
    fn closure(&self, pose: &Isometry3<f64>, actuators: &[f64]) -> DVector<f64>;

    /// `∂F/∂x` (k × [`pose_freedom`](Self::pose_freedom)).
    fn pose_jacobian(&self, pose: &Isometry3<f64>, actuators: &[f64]) -> DMatrix<f64>;

    /// `∂F/∂ξ` (k × parameters).
    fn parameter_jacobian(&self, pose: &Isometry3<f64>, actuators: &[f64]) -> DMatrix<f64>;

    /// `F`, `∂F/∂x` and `∂F/∂ξ` at once, for a structure to compute what
    /// they share once (a calibration linearises every measured pose).
    fn linearised(&self, pose: &Isometry3<f64>, actuators: &[f64]) -> Linearised {
        Linearised {
            closure: self.closure(pose, actuators),
            by_pose: self.pose_jacobian(pose, actuators),
            by_parameter: self.parameter_jacobian(pose, actuators),
        }
    }

    /// The parameters closure equation `equation` can involve (a leg's
    /// own eight): the columns of `∂F/∂ξ` outside are zero. All of them by
    /// default.
    fn equation_parameters(&self, equation: usize) -> std::ops::Range<usize> {
        let _ = equation;
        0..self.parameters().len()
    }

    /// The inverse model: the actuator values that put the platform at
    /// `pose`.
    ///
    /// # Errors
    /// [`Error::Unreachable`] for a pose no leg or arm reaches.
    fn actuator_values(&self, pose: &Isometry3<f64>) -> Result<Vec<f64>, Error>;

    /// Actuator `index`'s range `(min, max)` (0-based).
    fn actuator_range(&self, index: usize) -> (f64, f64);

    /// What an actuator value is: a leg's length
    /// ([`Length`](ParameterUnit::Length), m) or a motor's angle
    /// ([`Angle`](ParameterUnit::Angle), rad).
    fn actuator_unit(&self) -> ParameterUnit;

    /// The actuators (1-based) whose value is outside its range.
    fn out_of_range(&self, actuators: &[f64]) -> Vec<usize> {
        actuators
            .iter()
            .enumerate()
            .filter(|(index, value)| {
                let (min, max) = self.actuator_range(*index);
                !(min..=max).contains(*value)
            })
            .map(|(index, _)| index + 1)
            .collect()
    }

    /// The direct model: the pose the actuator values put the platform at,
    /// by Newton's method on the closure equations from `start` (which
    /// fixes the assembly mode), each step halved while it does not lower
    /// the residual.
    ///
    /// # Errors
    /// [`Error::ConfigurationLength`] or [`Error::NonFiniteConfiguration`]
    /// for values that are not k numbers; [`Error::NoAssembly`] when no
    /// pose closes the chains from `start`.
    fn direct(&self, actuators: &[f64], start: &Isometry3<f64>) -> Result<Isometry3<f64>, Error> {
        if actuators.len() != self.actuator_count() {
            return Err(Error::ConfigurationLength {
                expected: self.actuator_count(),
                found: actuators.len(),
            });
        }
        if let Some((index, value)) = actuators.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(Error::NonFiniteConfiguration {
                joint: index + 1,
                value: *value,
            });
        }
        let mut pose = *start;
        let mut residual = self.closure(&pose, actuators);
        for _ in 0..MAX_ITERATIONS {
            if residual.amax() < TOLERANCE {
                return Ok(pose);
            }
            let Some(step) = self
                .pose_jacobian(&pose, actuators)
                .lu()
                .solve(&(-&residual))
            else {
                break;
            };
            let lowered = (0..30)
                .map(|halvings| &step * 0.5f64.powi(halvings))
                .find_map(|step| {
                    let next = moved(&pose, step.as_slice());
                    let next_residual = self.closure(&next, actuators);
                    (next_residual.norm() < residual.norm()).then_some((next, next_residual))
                });
            let Some((next, next_residual)) = lowered else {
                break;
            };
            (pose, residual) = (next, next_residual);
        }
        Err(Error::NoAssembly {
            residual: residual.amax(),
        })
    }
}

/// The closure equations linearised at a pose ([`ParallelModel::linearised`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Linearised {
    /// `F` (k).
    pub closure: DVector<f64>,
    /// `∂F/∂x` (k × pose freedom).
    pub by_pose: DMatrix<f64>,
    /// `∂F/∂ξ` (k × parameters).
    pub by_parameter: DMatrix<f64>,
}

/// What a parameter measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParameterUnit {
    /// A length (m).
    Length,
    /// An angle (rad).
    Angle,
    /// A gain (dimensionless).
    Gain,
}

/// `pose` moved by `step`: `[δp]` or `[δp; ω]` with `R ← exp(ω)·R`.
pub fn moved(pose: &Isometry3<f64>, step: &[f64]) -> Isometry3<f64> {
    let translation = Vector3::new(step[0], step[1], step[2]);
    let rotation = match step.get(3..6) {
        Some(turn) => UnitQuaternion::from_scaled_axis(Vector3::new(turn[0], turn[1], turn[2])),
        None => UnitQuaternion::identity(),
    };
    Isometry3::from_parts(
        Translation3::from(pose.translation.vector + translation),
        rotation * pose.rotation,
    )
}

/// The tool point a file states: finite and within
/// [`MAX_MAGNITUDE`](crate::MAX_MAGNITUDE), as every stated length.
pub(crate) fn check_tool(tool: &Vector3<f64>) -> Result<(), Error> {
    tool.iter()
        .try_for_each(|value| check_magnitude(Field::Key("tool"), *value))
}

/// The rules every actuator of a parallel robot meets as its file states
/// it (a leg, an arm; `field` names one of its keys): every value finite and
/// within [`MAX_MAGNITUDE`](crate::MAX_MAGNITUDE), as a serial robot's, a gain
/// that moves, a range whose ends are in order.
pub(crate) fn check_actuator(
    field: impl Fn(&'static str) -> Field,
    values: &[(&'static str, &[f64])],
    gain: f64,
    min: f64,
    max: f64,
) -> Result<(), Error> {
    for (key, values) in values {
        for value in *values {
            check_magnitude(field(key), *value)?;
        }
    }
    if gain.abs() < MIN_GAIN {
        return Err(Error::invalid(
            field("gain"),
            "a gain of zero moves nothing",
        ));
    }
    if min > max {
        return Err(Error::invalid(
            field("min"),
            format!("the range's ends are reversed (min {min} > max {max})"),
        ));
    }
    Ok(())
}
