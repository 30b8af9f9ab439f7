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

use nalgebra::{
    DMatrix, DVector, Isometry3, Matrix6, Translation3, UnitQuaternion, Vector3, Vector6,
};

use smallvec::SmallVec;

use crate::error::{Error, Field};
use crate::stated::{MIN_GAIN, check_magnitude};

/// Newton iterations at most: from a start a stroke away, convergence
/// takes 4–6.
const MAX_ITERATIONS: usize = 50;

/// The closure equations' residual below which the pose is solved (m).
const TOLERANCE: f64 = 1e-12;

/// What [`ParallelModel::visit_equations`] calls for each closure equation:
/// its index, its residual `Fᵢ`, its row of `∂F/∂x` and its coefficients on
/// its own parameters.
pub type EquationVisitor<'a> = dyn FnMut(usize, f64, &[f64], &[f64]) + 'a;

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

    /// How many parameters there are ([`parameters`](Self::parameters)'s
    /// length, without forming them).
    fn parameter_count(&self) -> usize {
        self.parameters().len()
    }

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

    /// `∂F/∂ξ` (k × parameters): each equation's own coefficients
    /// ([`visit_equations`](Self::visit_equations)) in its own columns.
    fn parameter_jacobian(&self, pose: &Isometry3<f64>, actuators: &[f64]) -> DMatrix<f64> {
        self.linearised(pose, actuators).by_parameter
    }

    /// `F`, `∂F/∂x` and `∂F/∂ξ` at once, as
    /// [`visit_equations`](Self::visit_equations) gives them row by row.
    fn linearised(&self, pose: &Isometry3<f64>, actuators: &[f64]) -> Linearised {
        let equations = self.actuator_count();
        let mut linearised = Linearised {
            closure: DVector::zeros(equations),
            by_pose: DMatrix::zeros(equations, self.pose_freedom()),
            by_parameter: DMatrix::zeros(equations, self.parameter_count()),
        };
        self.visit_equations(pose, actuators, &mut |equation, closure, row, own| {
            linearised.closure[equation] = closure;
            for (column, value) in row.iter().enumerate() {
                linearised.by_pose[(equation, column)] = *value;
            }
            for (column, value) in self.equation_parameters(equation).zip(own) {
                linearised.by_parameter[(equation, column)] = *value;
            }
        });
        linearised
    }

    /// Each closure equation at `pose` in order, given to `visit` as its
    /// index, its residual `Fᵢ`, its row of `∂F/∂x` and its coefficients on
    /// its own parameters ([`equation_parameters`](Self::equation_parameters)),
    /// without forming the k × parameters matrix: a calibration of 10⁵
    /// measured poses linearises each once an iteration. The structure's
    /// equations are written here once; [`linearised`](Self::linearised) and
    /// [`parameter_jacobian`](Self::parameter_jacobian) gather them.
    fn visit_equations(
        &self,
        pose: &Isometry3<f64>,
        actuators: &[f64],
        visit: &mut EquationVisitor<'_>,
    );

    /// The parameters that define the base and the platform frames when
    /// nothing outside the robot measures them (a measuring leg's
    /// self-calibration): held at their stated values, the frames are the
    /// drawing's. Empty (the default) for a structure without such a
    /// convention, which is then calibrated only by an instrument that sees
    /// its frames.
    fn frame_parameters(&self) -> Vec<usize> {
        Vec::new()
    }

    /// The parameters closure equation `equation` can involve (a leg's
    /// own eight): the columns of `∂F/∂ξ` outside are zero. All of them by
    /// default.
    fn equation_parameters(&self, equation: usize) -> std::ops::Range<usize> {
        let _ = equation;
        0..self.parameter_count()
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
        solve_direct(self, actuators, start).map(|solved| solved.pose)
    }
}

/// A pose the direct model solved, with the linearisation of its last
/// visit there ([`ParallelModel::visit_equations`] at the pose returned):
/// what the calibration's derivative of the tool point needs, without
/// visiting the equations again.
#[derive(Clone, Debug, PartialEq)]
pub struct SolvedPose {
    /// The platform's pose.
    pub pose: Isometry3<f64>,
    /// `∂F/∂x` there, padded as [`linearised_at`]'s.
    pub jacobian: Matrix6<f64>,
    /// Each equation's own coefficients ([`ParallelModel::equation_parameters`]),
    /// one after the other (on the stack for a hexapod's 48 or a Delta's 33).
    pub coefficients: SmallVec<[f64; 48]>,
    /// Where each equation's coefficients end in
    /// [`coefficients`](Self::coefficients).
    pub ends: [usize; 6],
}

/// The direct model ([`ParallelModel::direct`]) with its last
/// linearisation: Newton's method on the closure equations from `start`,
/// each step halved while it does not lower the residual.
///
/// # Errors
/// As [`ParallelModel::direct`].
pub fn solve_direct<M: ParallelModel>(
    model: &M,
    actuators: &[f64],
    start: &Isometry3<f64>,
) -> Result<SolvedPose, Error> {
    if actuators.len() != model.actuator_count() {
        return Err(Error::ConfigurationLength {
            expected: model.actuator_count(),
            found: actuators.len(),
        });
    }
    if let Some((index, value)) = actuators.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(Error::NonFiniteConfiguration {
            joint: index + 1,
            value: *value,
        });
    }
    let freedom = model.pose_freedom();
    // Two linearisations, the current pose's and a trial's, visited in
    // place (a trial accepted becomes the current one by its index).
    let blank = || SolvedPose {
        pose: *start,
        jacobian: Matrix6::identity(),
        coefficients: SmallVec::new(),
        ends: [0; 6],
    };
    let mut solved = [blank(), blank()];
    let mut current = 0;
    let mut residual = visit_into(model, start, actuators, &mut solved[current]);
    for _ in 0..MAX_ITERATIONS {
        if residual.amax() < TOLERANCE {
            let [first, second] = solved;
            return Ok(if current == 0 { first } else { second });
        }
        let Some(step) = solve_padded(&solved[current].jacobian, &residual, freedom) else {
            break;
        };
        let trial = 1 - current;
        let mut lowered = false;
        for halvings in 0..30 {
            let next = moved(
                &solved[current].pose,
                &(step * 0.5f64.powi(halvings)).as_slice()[..freedom],
            );
            let next_residual = visit_into(model, &next, actuators, &mut solved[trial]);
            if next_residual.norm() < residual.norm() {
                (residual, current, lowered) = (next_residual, trial, true);
                break;
            }
        }
        if !lowered {
            break;
        }
    }
    Err(Error::NoAssembly {
        residual: residual.amax(),
    })
}

/// One visit of the equations at `pose` into `solved` (its pose, padded
/// `∂F/∂x` and coefficients replaced): the closure residuals, padded.
fn visit_into<M: ParallelModel>(
    model: &M,
    pose: &Isometry3<f64>,
    actuators: &[f64],
    solved: &mut SolvedPose,
) -> Vector6<f64> {
    let mut residual = Vector6::zeros();
    solved.pose = *pose;
    solved.jacobian.fill_with_identity();
    solved.coefficients.clear();
    model.visit_equations(pose, actuators, &mut |equation, closure, by_pose, own| {
        residual[equation] = closure;
        for (column, value) in by_pose.iter().enumerate() {
            solved.jacobian[(equation, column)] = *value;
        }
        solved.coefficients.extend_from_slice(own);
        solved.ends[equation] = solved.coefficients.len();
    });
    residual
}

/// One visit of the equations at `pose`: the closure residuals `F` and the
/// linearisation, `∂F/∂x` padded to six equations of six unknowns (an
/// unused freedom's row and column the identity's, its residual zero):
/// Newton's step of every structure on the stack. The equations are as many
/// as the pose's freedoms (six legs, three arms).
pub fn linearised_at<M: ParallelModel>(
    model: &M,
    pose: &Isometry3<f64>,
    actuators: &[f64],
) -> (Vector6<f64>, SolvedPose) {
    let mut solved = SolvedPose {
        pose: *pose,
        jacobian: Matrix6::identity(),
        coefficients: SmallVec::new(),
        ends: [0; 6],
    };
    let residual = visit_into(model, pose, actuators, &mut solved);
    (residual, solved)
}

/// Newton's step `−J⁻¹·F` of a padded system ([`linearised_at`]) whose first `freedom`
/// rows and columns are the structure's: a 3 × 3 system by its closed-form
/// inverse (a Delta's), else the 6 × 6 by LU; `None` when singular.
fn solve_padded(
    jacobian: &Matrix6<f64>,
    residual: &Vector6<f64>,
    freedom: usize,
) -> Option<Vector6<f64>> {
    if freedom == 3 {
        let inverse = jacobian
            .fixed_view::<3, 3>(0, 0)
            .into_owned()
            .try_inverse()?;
        let step = -(inverse * residual.fixed_rows::<3>(0));
        Some(Vector6::new(step.x, step.y, step.z, 0.0, 0.0, 0.0))
    } else {
        jacobian.lu().solve(&(-residual))
    }
}

/// `J⁻¹` of a padded system ([`linearised_at`]) whose first `freedom` rows
/// and columns are the structure's: a 3 × 3 (a Delta's) inverted as one,
/// in closed form; `None` when singular.
pub fn padded_inverse(jacobian: &Matrix6<f64>, freedom: usize) -> Option<Matrix6<f64>> {
    if freedom == 3 {
        let inverse = jacobian
            .fixed_view::<3, 3>(0, 0)
            .into_owned()
            .try_inverse()?;
        let mut padded = Matrix6::identity();
        padded.fixed_view_mut::<3, 3>(0, 0).copy_from(&inverse);
        Some(padded)
    } else {
        jacobian.try_inverse()
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

/// That `model`'s equations as [`ParallelModel::visit_equations`] gives
/// them are [`ParallelModel::linearised`]'s and, to rounding, the
/// structure's own [`closure`](ParallelModel::closure) and
/// [`pose_jacobian`](ParallelModel::pose_jacobian), written apart (the
/// coefficients are checked by finite differences in each structure's tests).
#[cfg(test)]
pub(crate) fn assert_visits_match_linearised<M: ParallelModel>(
    model: &M,
    pose: &Isometry3<f64>,
    actuators: &[f64],
) {
    let Linearised {
        closure,
        by_pose,
        by_parameter,
    } = model.linearised(pose, actuators);
    let mut visited = 0;
    model.visit_equations(pose, actuators, &mut |equation, value, row, own| {
        visited += 1;
        assert!(
            (value - closure[equation]).abs() < 1e-12,
            "closure {equation}"
        );
        for (column, entry) in row.iter().enumerate() {
            assert!((entry - by_pose[(equation, column)]).abs() < 1e-12);
        }
        let columns = model.equation_parameters(equation);
        assert_eq!(own.len(), columns.len());
        for (entry, column) in own.iter().zip(columns) {
            assert!(
                (entry - by_parameter[(equation, column)]).abs() < 1e-12,
                "equation {equation}, parameter {column}"
            );
        }
        // Outside its own parameters the row is zero.
        for column in 0..by_parameter.ncols() {
            if !model.equation_parameters(equation).contains(&column) {
                assert_eq!(by_parameter[(equation, column)], 0.0);
            }
        }
    });
    assert_eq!(visited, closure.len());
    assert!((closure - model.closure(pose, actuators)).amax() < 1e-12);
    assert!((by_pose - model.pose_jacobian(pose, actuators)).amax() < 1e-12);
}
