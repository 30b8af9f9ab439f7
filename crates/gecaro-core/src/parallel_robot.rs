//! A parallel robot of any structure gecaro models ([`ParallelRobot`]):
//! what a parallel robot file holds and the jobs take, every
//! [`ParallelModel`] method passed on to the structure's own.

use nalgebra::{DMatrix, DVector, Isometry3, Vector3};

use crate::delta::Delta;
use crate::error::Error;
use crate::gough_stewart::GoughStewart;
use crate::parallel_model::{EquationVisitor, Linearised, ParallelModel, ParameterUnit};

/// A Gough–Stewart platform or a Delta robot.
#[derive(Clone, Debug, PartialEq)]
pub enum ParallelRobot {
    /// Six legs between a base and a platform ([`crate::gough_stewart`]).
    GoughStewart(GoughStewart),
    /// Three arms and parallelograms ([`crate::delta`]).
    Delta(Delta),
}

impl ParallelRobot {
    /// The structure's name in robot files: `gough-stewart` or `delta`.
    pub fn structure(&self) -> &'static str {
        match self {
            ParallelRobot::GoughStewart(_) => "gough-stewart",
            ParallelRobot::Delta(_) => "delta",
        }
    }

    /// Its actuators' name in messages: `leg` or `arm`.
    pub fn actuator_word(&self) -> &'static str {
        match self {
            ParallelRobot::GoughStewart(_) => "leg",
            ParallelRobot::Delta(_) => "arm",
        }
    }
}

/// `$body` with `$robot` bound to the structure's own value.
macro_rules! each {
    ($self:expr, $robot:ident => $body:expr) => {
        match $self {
            ParallelRobot::GoughStewart($robot) => $body,
            ParallelRobot::Delta($robot) => $body,
        }
    };
}

impl ParallelModel for ParallelRobot {
    fn name(&self) -> &str {
        each!(self, robot => robot.name())
    }

    fn renamed(&self, name: &str) -> Self {
        match self {
            ParallelRobot::GoughStewart(robot) => ParallelRobot::GoughStewart(robot.renamed(name)),
            ParallelRobot::Delta(robot) => ParallelRobot::Delta(robot.renamed(name)),
        }
    }

    fn actuator_count(&self) -> usize {
        each!(self, robot => robot.actuator_count())
    }

    fn pose_freedom(&self) -> usize {
        each!(self, robot => robot.pose_freedom())
    }

    fn parameters(&self) -> Vec<f64> {
        each!(self, robot => robot.parameters())
    }

    fn parameter_count(&self) -> usize {
        each!(self, robot => robot.parameter_count())
    }

    fn parameter_names(&self) -> Vec<String> {
        each!(self, robot => robot.parameter_names())
    }

    fn parameter_unit(&self, index: usize) -> ParameterUnit {
        each!(self, robot => robot.parameter_unit(index))
    }

    fn tool_parameters(&self) -> std::ops::Range<usize> {
        each!(self, robot => robot.tool_parameters())
    }

    fn with_parameters(&self, values: &[f64]) -> Result<Self, Error> {
        Ok(match self {
            ParallelRobot::GoughStewart(robot) => {
                ParallelRobot::GoughStewart(robot.with_parameters(values)?)
            }
            ParallelRobot::Delta(robot) => ParallelRobot::Delta(robot.with_parameters(values)?),
        })
    }

    fn home(&self) -> Isometry3<f64> {
        each!(self, robot => robot.home())
    }

    fn tool(&self) -> Vector3<f64> {
        each!(self, robot => robot.tool())
    }

    fn closure(&self, pose: &Isometry3<f64>, actuators: &[f64]) -> DVector<f64> {
        each!(self, robot => robot.closure(pose, actuators))
    }

    fn pose_jacobian(&self, pose: &Isometry3<f64>, actuators: &[f64]) -> DMatrix<f64> {
        each!(self, robot => robot.pose_jacobian(pose, actuators))
    }

    fn parameter_jacobian(&self, pose: &Isometry3<f64>, actuators: &[f64]) -> DMatrix<f64> {
        each!(self, robot => robot.parameter_jacobian(pose, actuators))
    }

    fn linearised(&self, pose: &Isometry3<f64>, actuators: &[f64]) -> Linearised {
        each!(self, robot => robot.linearised(pose, actuators))
    }

    fn frame_parameters(&self) -> Vec<usize> {
        each!(self, robot => robot.frame_parameters())
    }

    fn visit_equations(
        &self,
        pose: &Isometry3<f64>,
        actuators: &[f64],
        visit: &mut EquationVisitor<'_>,
    ) {
        each!(self, robot => robot.visit_equations(pose, actuators, visit))
    }

    fn equation_parameters(&self, equation: usize) -> std::ops::Range<usize> {
        each!(self, robot => robot.equation_parameters(equation))
    }

    fn actuator_values(&self, pose: &Isometry3<f64>) -> Result<Vec<f64>, Error> {
        each!(self, robot => robot.actuator_values(pose))
    }

    fn actuator_range(&self, index: usize) -> (f64, f64) {
        each!(self, robot => robot.actuator_range(index))
    }

    fn actuator_unit(&self) -> ParameterUnit {
        each!(self, robot => robot.actuator_unit())
    }
}
