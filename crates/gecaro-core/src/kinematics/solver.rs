//! The inverse geometric model of one robot ([`InverseSolver`]): the robot
//! and its compiled model bound together — compiled here, or checked when
//! given ([`KinematicModel::is_of`]) — and the three ways a solve starts:
//! damped least squares from a start ([`solve`](InverseSolver::solve)),
//! Newton steps first from a start near the solution
//! ([`solve_near`](InverseSolver::solve_near)), and one of many starts on
//! one target, given up near a minimum an earlier start settled at
//! ([`solve_avoiding`](InverseSolver::solve_avoiding)). The mathematics and
//! the settings ([`InverseOptions`]) are [`super::inverse`]'s.

use std::borrow::Cow;

use super::inverse::{
    InverseOptions, InverseSolution, Target, inverse_kinematics_avoiding, inverse_kinematics_near,
    inverse_kinematics_newton, inverse_kinematics_on,
};
use super::known_minima::KnownMinima;
use super::model::KinematicModel;
use crate::Error;
use crate::robot::Robot;

/// A robot and its compiled model, bound (see the module docs).
///
/// A planar arm of links 0.5 and 0.4 m asked for a point 1 m away: every
/// start settles with the arm stretched towards it, 0.1 m short. The
/// second start, given up near the first one's minimum, takes fewer
/// iterations:
///
/// ```
/// use gecaro_core::{
///     Frame, FrameType, InverseOptions, InverseSolver, Joint, KnownMinima, Robot, RobotSpec,
///     Target,
/// };
/// use nalgebra::Vector3;
///
/// let frame = |frame_type, d| Frame { d, ..Frame::new(frame_type) };
/// let robot = Robot::new(RobotSpec::rigid(
///     "planar",
///     vec![
///         frame(FrameType::Fixed, 0.0),
///         frame(FrameType::Revolute, 0.0),
///         frame(FrameType::Revolute, 0.5),
///         frame(FrameType::Fixed, 0.4),
///     ],
///     vec![Joint::default_for(FrameType::Revolute); 2],
/// ))?;
/// let solver = InverseSolver::new(&robot);
/// let far = Target::Position(Vector3::new(1.0, 0.0, 0.0));
/// let mut known = KnownMinima::new(0.01);
/// let options = InverseOptions::default();
///
/// let mut solve = |start: &[f64]| solver.solve_avoiding(&far, start, &options, &mut known);
/// let first = solve(&[0.3, 0.4]);
/// let second = solve(&[0.3, 0.5]);
/// let iterations = |result: Result<_, gecaro_core::Error>| match result {
///     Err(gecaro_core::Error::Unreachable { iterations, .. }) => iterations,
///     other => panic!("{other:?}"),
/// };
/// assert_eq!(known.len(), 1);
/// assert!(iterations(second) < iterations(first));
///
/// // A model compiled from another robot is refused, not used.
/// let mut longer = robot.clone();
/// longer.set_parameter(gecaro_core::ParameterId::new(gecaro_core::ParameterKind::D, 2), 0.6)?;
/// let model = gecaro_core::KinematicModel::new(&longer);
/// assert!(InverseSolver::bound(&robot, &model).is_err());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct InverseSolver<'a> {
    robot: &'a Robot,
    model: Cow<'a, KinematicModel>,
}

impl<'a> InverseSolver<'a> {
    /// The solver of `robot`, its model compiled.
    pub fn new(robot: &'a Robot) -> Self {
        InverseSolver {
            robot,
            model: Cow::Owned(KinematicModel::new(robot)),
        }
    }

    /// The solver of `robot` on `model`, compiled from it before.
    ///
    /// # Errors
    /// [`Error::ModelMismatch`] when `model` is not `robot`'s as it is now.
    pub fn bound(robot: &'a Robot, model: &'a KinematicModel) -> Result<Self, Error> {
        if !model.is_of(robot) {
            return Err(Error::ModelMismatch {
                robot: robot.name().to_owned(),
            });
        }
        Ok(InverseSolver {
            robot,
            model: Cow::Borrowed(model),
        })
    }

    /// The robot.
    pub fn robot(&self) -> &'a Robot {
        self.robot
    }

    /// Its compiled model.
    pub fn model(&self) -> &KinematicModel {
        &self.model
    }

    /// Damped least squares from `start` (motor values).
    ///
    /// # Errors
    /// [`Error::Unreachable`] when the target is not met within the
    /// tolerance; a start that is not n finite values.
    pub fn solve(
        &self,
        target: &Target,
        start: &[f64],
        options: &InverseOptions,
    ) -> Result<InverseSolution, Error> {
        inverse_kinematics_on(self.robot, &self.model, target, start, options)
    }

    /// From a start near the solution (a program's joints on a calibrated
    /// robot): Newton steps first, the damped solver where they do not
    /// converge.
    ///
    /// # Errors
    /// As [`solve`](Self::solve).
    pub fn solve_near(
        &self,
        target: &Target,
        start: &[f64],
        options: &InverseOptions,
    ) -> Result<InverseSolution, Error> {
        inverse_kinematics_near(self.robot, &self.model, target, start, options)
    }

    /// From a start a step or two from a solution (a configuration of a
    /// nearby robot in closed form): Newton steps alone, and
    /// [`Error::Unreachable`] at once where they do not converge.
    ///
    /// # Errors
    /// As [`solve`](Self::solve).
    pub fn solve_newton(
        &self,
        target: &Target,
        start: &[f64],
        options: &InverseOptions,
    ) -> Result<InverseSolution, Error> {
        inverse_kinematics_newton(self.robot, &self.model, target, start, options)
    }

    /// One of many starts on one target: given up as soon as its joints come
    /// near a minimum short of the target an earlier solve settled at; the
    /// minimum this one settles at, when it fails, recorded in `known`.
    ///
    /// # Errors
    /// As [`solve`](Self::solve), and [`Error::Unreachable`] for a solve
    /// given up near a known minimum.
    pub fn solve_avoiding(
        &self,
        target: &Target,
        start: &[f64],
        options: &InverseOptions,
        known: &mut KnownMinima,
    ) -> Result<InverseSolution, Error> {
        inverse_kinematics_avoiding(self.robot, &self.model, target, start, options, known)
    }
}
