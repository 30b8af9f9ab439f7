//! Numerical inverse geometric model (paper §3.2: "a general numerical method
//! based on the differential model of the robot").
//!
//! Damped least squares (Levenberg–Marquardt) on the joint variables q, from a
//! chosen start configuration, on the compiled direct model
//! ([`KinematicModel`]). Each step solves `J Δq ≈ Δx` with
//! `Δq = (JᵀJ + λI)⁻¹JᵀΔx = Jᵀ(JJᵀ + λI)⁻¹Δx` (k×n task Jacobian; the
//! smaller of the two products, formed once per iterate and factorised by
//! Cholesky per damping tried, so redundant, position-only and plane
//! problems need nothing special), leaves out of it the joints held at a
//! limit that it would push beyond (their columns of J zeroed, the step
//! taken again: an active set), clamps q to the joint limits, and keeps the
//! step only if it lowers ‖Δx‖; λ shrinks after a kept step and grows after
//! a refused one (or a product that does not factorise). Close to the
//! solution λ → 0 and the iteration is Newton's, so targets are met to
//! ~1e-13 m.
//!
//! Failure is an error, never a silently wrong configuration: when the target
//! is out of reach within the joint limits, or the iteration stalls from this
//! start, [`Error::Unreachable`] reports the remaining error. A solve gives up
//! at a least-squares minimum short of the target (the projected gradient
//! `Jᵀ Δx` vanishing against `‖J‖ ‖Δx‖`), after five iterations that lower
//! ‖Δx‖ by rounding's worth, or after 25 that do not halve it.

use nalgebra::{
    DMatrix, DVector, IsometryMatrix3, Matrix3, Matrix6, Matrix6xX, SMatrix, SVector, Vector3,
    Vector6,
};

use super::known_minima::KnownMinima;
use super::model::{ChainBuffer, KinematicModel};
use super::pose_difference::{OrientationDifference, orientation_difference};
use crate::Error;
use crate::frame::Joint;
use crate::robot::Robot;

/// What the end-effector frame n+1 must reach, in the world frame.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum Target {
    /// The origin of frame n+1 at this point (metres); orientation free.
    Position(Vector3<f64>),
    /// Frame n+1 at this pose.
    Frame(IsometryMatrix3<f64>),
    /// The origin of frame n+1 anywhere on the plane `normal · x = offset`
    /// (`normal` of unit length); the solution is close to the start.
    Plane {
        /// Unit normal of the plane.
        normal: Vector3<f64>,
        /// Signed distance of the plane from the world origin (metres).
        offset: f64,
    },
}

impl Target {
    /// The rows of the task it sets: 3 for a point, 6 for a frame, 1 for a plane.
    pub fn rows(&self) -> usize {
        match self {
            Target::Position(_) => 3,
            Target::Frame(_) => 6,
            Target::Plane { .. } => 1,
        }
    }

    fn name(&self) -> &'static str {
        match self {
            Target::Position(_) => "position",
            Target::Frame(_) => "frame",
            Target::Plane { .. } => "plane",
        }
    }
}

/// Settings of [`inverse_kinematics`].
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct InverseOptions {
    /// Iteration limit.
    pub max_iterations: usize,
    /// Success when ‖Δx‖ (metres and radians) falls below this.
    pub tolerance: f64,
    /// Keep q within the joint limits (clamped after every step). Without
    /// it, a solution beyond a limit is found and returned as it is.
    pub respect_limits: bool,
}

impl Default for InverseOptions {
    fn default() -> Self {
        InverseOptions {
            max_iterations: 200,
            tolerance: 1e-12,
            respect_limits: true,
        }
    }
}

/// A configuration that reaches the target.
#[derive(Clone, Debug, PartialEq)]
pub struct InverseSolution {
    /// Motor variables qm (eq. 4).
    pub motor_positions: Vec<f64>,
    /// Joint variables q, within the joint limits.
    pub joint_positions: Vec<f64>,
    /// Iterations used.
    pub iterations: usize,
    /// Final ‖Δx‖.
    pub residual: f64,
    /// The pose of frame n+1 there (world frame).
    pub pose: IsometryMatrix3<f64>,
}

const INITIAL_DAMPING: f64 = 1e-3;
const MAX_DAMPING: f64 = 1e8;
/// A solve that has not halved its error in this many iterations has stalled
/// (a local minimum or a joint limit in the way) and is given up.
const STALL_ITERATIONS: usize = 25;
/// A solve whose error fell by less than [`STATIONARY_DECREASE`] of itself
/// in each of this many iterations in a row has settled at a least-squares
/// minimum short of the target (a target out of reach): given up without
/// waiting for [`STALL_ITERATIONS`].
const STATIONARY_ITERATIONS: usize = 5;
/// See [`STATIONARY_ITERATIONS`].
const STATIONARY_DECREASE: f64 = 1e-9;
/// A solve whose error is orthogonal, to this cosine, to every direction
/// the free joints can move the task (`‖Jᵀ_free Δx‖ ≤ this · ‖J‖_F ‖Δx‖`:
/// the gradient of ‖Δx‖² vanishes) is at a least-squares minimum short of
/// the target, and given up: it can only creep closer to that minimum. At
/// a solution J has full rank and the cosine stays above
/// σ_min(J)/‖J‖_F. Measured on the solves of the compensation's fallbacks
/// for Stanford targets reached only on another branch, beyond a limit or
/// not at all (2,000 targets of each): of 28,428 solves that met their
/// target, one went below 1e-5 on the way (7.8e-7; the next lowest
/// 1.0e-5); the 321,759 that failed were cut by 21 % of their iterations.
const STATIONARY_COSINE: f64 = 1e-5;

/// Solves the inverse geometric model for `target`, starting from the motor
/// configuration `start_motor_positions`.
///
/// # Errors
/// [`Error::Unreachable`] when the target is not met within the tolerance;
/// configuration errors when the start is not n finite values.
pub fn inverse_kinematics(
    robot: &Robot,
    target: &Target,
    start_motor_positions: &[f64],
    options: &InverseOptions,
) -> Result<InverseSolution, Error> {
    inverse_kinematics_on(
        robot,
        &KinematicModel::new(robot),
        target,
        start_motor_positions,
        options,
    )
}

/// [`inverse_kinematics`] on the compiled `model` of `robot`, for callers
/// that solve many targets or starts on one robot (the model is compiled
/// once rather than per solve).
///
/// # Errors
/// As [`inverse_kinematics`].
pub fn inverse_kinematics_on(
    robot: &Robot,
    model: &KinematicModel,
    target: &Target,
    start_motor_positions: &[f64],
    options: &InverseOptions,
) -> Result<InverseSolution, Error> {
    check_target(target)?;
    let start = robot.joint_positions(start_motor_positions)?;
    damped_descent(robot, model, target, start, options, None)
}

/// [`inverse_kinematics_on`] for one of many starts on one target: the
/// solve is given up as soon as its joint positions come near a minimum
/// short of the target that an earlier solve settled at (see
/// [`KnownMinima`]), and the minimum this one settles at, when it fails,
/// is recorded in `known`.
///
/// # Errors
/// As [`inverse_kinematics`]; [`Error::Unreachable`] also for a solve given
/// up near a known minimum.
///
/// # Example
///
/// A planar arm of links 0.5 and 0.4 m asked for a point 1 m away: every
/// start settles with the arm stretched towards it, 0.1 m short. The
/// second start, given up near the first one's minimum, takes fewer
/// iterations:
///
/// ```
/// use gecaro_core::{
///     Frame, FrameType, InverseOptions, Joint, KinematicModel, KnownMinima, Robot, RobotSpec,
///     Target, inverse_kinematics_avoiding,
/// };
/// use nalgebra::Vector3;
///
/// let frame = |frame_type, d| Frame { d, ..Frame::new(frame_type) };
/// let robot = Robot::new(RobotSpec {
///     name: "planar".into(),
///     frames: vec![
///         frame(FrameType::Fixed, 0.0),
///         frame(FrameType::Revolute, 0.0),
///         frame(FrameType::Revolute, 0.5),
///         frame(FrameType::Fixed, 0.4),
///     ],
///     joints: vec![Joint::default_for(FrameType::Revolute); 2],
///     motor_coupling: None,
///     joint_coupling: None,
///     priority: None,
///     compliances: None,
/// })?;
/// let model = KinematicModel::new(&robot);
/// let far = Target::Position(Vector3::new(1.0, 0.0, 0.0));
/// let mut known = KnownMinima::new(0.01);
/// let options = InverseOptions::default();
///
/// let mut solve = |start: &[f64]| {
///     inverse_kinematics_avoiding(&robot, &model, &far, start, &options, &mut known)
/// };
/// let first = solve(&[0.3, 0.4]);
/// let second = solve(&[0.3, 0.5]);
/// let iterations = |result: Result<_, gecaro_core::Error>| match result {
///     Err(gecaro_core::Error::Unreachable { iterations, .. }) => iterations,
///     other => panic!("{other:?}"),
/// };
/// assert_eq!(known.len(), 1);
/// assert!(iterations(second) < iterations(first));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn inverse_kinematics_avoiding(
    robot: &Robot,
    model: &KinematicModel,
    target: &Target,
    start_motor_positions: &[f64],
    options: &InverseOptions,
    known: &mut KnownMinima,
) -> Result<InverseSolution, Error> {
    check_target(target)?;
    let start = robot.joint_positions(start_motor_positions)?;
    damped_descent(robot, model, target, start, options, Some(known))
}

/// The damped least-squares descent of [`inverse_kinematics`] from the
/// joint positions `start`, on the compiled `model` of `robot`; given up
/// near a minimum of `known`, and its own recorded there when it fails.
fn damped_descent(
    robot: &Robot,
    model: &KinematicModel,
    target: &Target,
    start: DVector<f64>,
    options: &InverseOptions,
    known: Option<&mut KnownMinima>,
) -> Result<InverseSolution, Error> {
    let limit = |q: DVector<f64>| limited(robot, options, q);
    let evaluate = |joint_positions: &DVector<f64>, chain: &mut ChainBuffer| {
        model.forward_joints(joint_positions.as_slice(), chain);
        task_error(target, chain.world_from_tool())
    };
    let mut joint_positions = limit(start);
    let (mut chain, mut candidate_chain) = (ChainBuffer::default(), ChainBuffer::default());
    let mut error = evaluate(&joint_positions, &mut chain);
    // ‖Δx‖ of `error`, kept beside it.
    let mut residual = error.norm();
    let mut full = Matrix6xX::zeros(robot.joint_count());
    let mut damping = INITIAL_DAMPING;
    let mut iterations = 0;
    let (mut checkpoint_error, mut checkpoint_iteration) = (residual, 0);
    let mut stationary = 0;
    while residual > options.tolerance && iterations < options.max_iterations {
        // Given up near a known minimum (where it would settle again).
        if known
            .as_deref()
            .is_some_and(|known| known.is_near(joint_positions.as_slice()))
        {
            break;
        }
        iterations += 1;
        model.joint_jacobian(&chain, &mut full);
        let jacobian = task_rows(target, &full);
        if at_stationary_point(
            robot,
            options,
            &joint_positions,
            &jacobian,
            &error,
            residual,
        ) {
            break;
        }
        let system = DampedSystem::new(&jacobian);
        let mut improved = false;
        while damping < MAX_DAMPING {
            let Some(step) =
                bounded_step(robot, options, &joint_positions, &system, &error, damping)
            else {
                damping *= 10.0;
                continue;
            };
            let candidate = limit(&joint_positions + step);
            let candidate_error = evaluate(&candidate, &mut candidate_chain);
            let candidate_residual = candidate_error.norm();
            if candidate_residual < residual {
                let decrease = residual - candidate_residual;
                stationary = if decrease <= STATIONARY_DECREASE * residual {
                    stationary + 1
                } else {
                    0
                };
                joint_positions = candidate;
                std::mem::swap(&mut chain, &mut candidate_chain);
                (error, residual) = (candidate_error, candidate_residual);
                damping = (damping / 3.0).max(1e-15);
                improved = true;
                break;
            }
            damping *= 10.0;
        }
        if !improved || stationary >= STATIONARY_ITERATIONS {
            break;
        }
        if residual < 0.5 * checkpoint_error {
            (checkpoint_error, checkpoint_iteration) = (residual, iterations);
        } else if iterations - checkpoint_iteration > STALL_ITERATIONS {
            break;
        }
    }
    if residual > options.tolerance {
        if let Some(known) = known {
            known.record(joint_positions.as_slice());
        }
        return Err(Error::Unreachable {
            iterations,
            residual,
            tolerance: options.tolerance,
        });
    }
    solution(robot, (&joint_positions, &chain), iterations, residual)
}

/// Whether `error` (of norm `residual`) is orthogonal to what the free
/// joints can do at `joint_positions` (see [`STATIONARY_COSINE`]): the
/// gradient `Jᵀ Δx` with the components of the joints held at a limit
/// that it would push beyond left out (a projected gradient).
fn at_stationary_point(
    robot: &Robot,
    options: &InverseOptions,
    joint_positions: &DVector<f64>,
    jacobian: &DMatrix<f64>,
    error: &DVector<f64>,
    residual: f64,
) -> bool {
    let held = |index: usize, change: f64| {
        options.respect_limits
            && pushes_beyond(&robot.joints()[index], joint_positions[index], change)
    };
    let gradient_squared: f64 = jacobian
        .column_iter()
        .map(|column| column.dot(error))
        .enumerate()
        .filter(|(index, change)| !held(*index, *change))
        .map(|(_, change)| change * change)
        .sum();
    gradient_squared.sqrt() <= STATIONARY_COSINE * jacobian.norm() * residual
}

/// Whether a joint at `q` held at one of its limits would be pushed beyond
/// it by a `change` of that sign (a step, or the descent direction `Jᵀ Δx`).
fn pushes_beyond(joint: &Joint, q: f64, change: f64) -> bool {
    (q <= joint.qmin && change < 0.0) || (q >= joint.qmax && change > 0.0)
}

/// The solution at `joint_positions` (whose chain is `chain`), met to
/// `residual` after `iterations`.
fn solution(
    robot: &Robot,
    (joint_positions, chain): (&DVector<f64>, &ChainBuffer),
    iterations: usize,
    residual: f64,
) -> Result<InverseSolution, Error> {
    let motor_positions = robot.motor_positions(joint_positions.as_slice())?;
    Ok(InverseSolution {
        motor_positions: motor_positions.as_slice().to_vec(),
        joint_positions: joint_positions.as_slice().to_vec(),
        iterations,
        residual,
        pose: *chain.world_from_tool(),
    })
}

/// `joint_positions` clamped to the limits when the options respect them.
fn limited(robot: &Robot, options: &InverseOptions, joint_positions: DVector<f64>) -> DVector<f64> {
    if options.respect_limits {
        clamp_to_limits(robot, joint_positions)
    } else {
        joint_positions
    }
}

fn check_target(target: &Target) -> Result<(), Error> {
    let finite = match target {
        Target::Position(point) => point.iter().all(|v| v.is_finite()),
        Target::Frame(pose) => pose.to_homogeneous().iter().all(|v| v.is_finite()),
        Target::Plane { normal, offset } => {
            normal.iter().all(|v| v.is_finite())
                && offset.is_finite()
                && (normal.norm() - 1.0).abs() < 1e-9
        }
    };
    if finite {
        Ok(())
    } else {
        Err(Error::NonFiniteTarget {
            what: target.name(),
        })
    }
}

/// Newton steps [`inverse_kinematics_near`] tries before the damped solver.
const NEWTON_ITERATIONS: usize = 8;

/// The largest joint step (rad, or m) a Newton step of
/// [`inverse_kinematics_near`] may take: a larger one is a configuration
/// near a singularity (a wrist nearly straight), where the solution the
/// damped solver finds from the start is the one wanted.
const MAX_NEWTON_STEP: f64 = 0.2;

/// [`inverse_kinematics`] from a start near the solution (a program's joints
/// on a calibrated robot, millimetres and a fraction of a degree away):
/// plain Newton steps on the compiled `model` of `robot`, the smallest
/// joint step that meets the linearised target (`Δq = Jᵀ(JJᵀ)⁻¹Δx`, or the
/// least-squares one when the target has more rows than the robot joints),
/// clamped to the limits like the damped solver's. Each step must lower
/// ‖Δx‖ and move no joint by more than `MAX_NEWTON_STEP` (0.2 rad, or m); they converge
/// quadratically, 3–4 of them from a millimetre. When one does not, or
/// they have not converged after a few, the damped solver runs from the
/// start as [`inverse_kinematics`] does: near a singularity, far from the
/// start, the result is the damped solver's. Where several configurations
/// meet the target (a position with six joints) the one found may differ
/// from the damped solver's by the null-space drift of its steps; both
/// meet it to the tolerance.
///
/// # Errors
/// As [`inverse_kinematics`].
pub fn inverse_kinematics_near(
    robot: &Robot,
    model: &KinematicModel,
    target: &Target,
    start_motor_positions: &[f64],
    options: &InverseOptions,
) -> Result<InverseSolution, Error> {
    check_target(target)?;
    let start = robot.joint_positions(start_motor_positions)?;
    let mut joint_positions = limited(robot, options, start.clone());
    let mut chain = ChainBuffer::default();
    model.forward_joints(joint_positions.as_slice(), &mut chain);
    let mut error = task_error(target, chain.world_from_tool());
    let mut full = Matrix6xX::zeros(robot.joint_count());
    for iteration in 0..=NEWTON_ITERATIONS {
        let residual = error.norm();
        if residual <= options.tolerance {
            return solution(robot, (&joint_positions, &chain), iteration, residual);
        }
        if iteration == NEWTON_ITERATIONS {
            break;
        }
        model.joint_jacobian(&chain, &mut full);
        let jacobian = task_rows(target, &full);
        let Some(step) =
            newton_step(&jacobian, &error).filter(|step| step.amax() <= MAX_NEWTON_STEP)
        else {
            break;
        };
        let candidate = limited(robot, options, &joint_positions + step);
        model.forward_joints(candidate.as_slice(), &mut chain);
        let candidate_error = task_error(target, chain.world_from_tool());
        // (A NaN is no improvement either.)
        if candidate_error.norm().is_nan() || candidate_error.norm() >= residual {
            break;
        }
        joint_positions = candidate;
        error = candidate_error;
    }
    damped_descent(robot, model, target, start, options, None)
}

/// The smallest `Δq` with `J Δq = Δx` (J of full row rank), or the
/// least-squares one for a J with more rows than columns; `None` when the
/// product to invert is singular (a singular configuration).
fn newton_step(jacobian: &DMatrix<f64>, error: &DVector<f64>) -> Option<DVector<f64>> {
    if jacobian.is_square() && matches!(jacobian.nrows(), 3 | 6) {
        // A square J (a frame for six joints, a point for three): Δq = J⁻¹Δx
        // by LU, cheaper than the product and with J's own conditioning.
        square_solve(jacobian, error).filter(|step| step.iter().all(|v| v.is_finite()))
    } else {
        DampedSystem::new(jacobian).step(error, 0.0)
    }
}

/// The damped least-squares steps `(JᵀJ + λI)⁻¹JᵀΔx` of one J, computed
/// as `Jᵀ(JJᵀ + λI)⁻¹Δx` when J has no more rows than columns (the smaller
/// product; with λ = 0, the smallest step that meets the linearised
/// target). The product to invert does not change with λ: it is formed
/// once for every damping tried.
struct DampedSystem<'a> {
    jacobian: &'a DMatrix<f64>,
    product: Product,
}

/// The product [`DampedSystem`] inverts.
#[allow(clippy::large_enum_variant)] // one per iterate, on the stack: no allocation
enum Product {
    /// JJᵀ of a frame's rows (six), on the stack.
    Six(Matrix6<f64>),
    /// JJᵀ of a point's rows (three), on the stack.
    Three(Matrix3<f64>),
    /// JJᵀ of other rows (a plane's one).
    Wide(DMatrix<f64>),
    /// JᵀJ of a J with more rows than columns.
    Tall(DMatrix<f64>),
}

impl<'a> DampedSystem<'a> {
    fn new(jacobian: &'a DMatrix<f64>) -> Self {
        let (rows, columns) = jacobian.shape();
        let product = match rows {
            _ if rows > columns => Product::Tall(jacobian.transpose() * jacobian),
            6 => Product::Six(outer_sum(jacobian)),
            3 => Product::Three(outer_sum(jacobian)),
            _ => Product::Wide(jacobian * jacobian.transpose()),
        };
        DampedSystem { jacobian, product }
    }

    /// The step for the damping λ; `None` when the product to invert does
    /// not factorise or the step is not finite.
    fn step(&self, error: &DVector<f64>, damping: f64) -> Option<DVector<f64>> {
        let jacobian = self.jacobian;
        let step = match &self.product {
            Product::Six(product) => jacobian.transpose() * wide_solve(product, error, damping)?,
            Product::Three(product) => jacobian.transpose() * wide_solve(product, error, damping)?,
            Product::Wide(product) => {
                let factor = damped(product.clone(), damping).cholesky()?;
                jacobian.transpose() * factor.solve(error)
            }
            Product::Tall(product) => damped(product.clone(), damping)
                .cholesky()?
                .solve(&(jacobian.transpose() * error)),
        };
        step.iter().all(|v| v.is_finite()).then_some(step)
    }
}

/// JJᵀ for a J of `R` rows, as the sum of its columns' outer products in
/// column order: each entry is the rows' dot product, summed in the same
/// order, read from contiguous columns rather than strided rows.
fn outer_sum<const R: usize>(jacobian: &DMatrix<f64>) -> SMatrix<f64, R, R> {
    let mut product = SMatrix::<f64, R, R>::zeros();
    for column in jacobian.column_iter() {
        for i in 0..R {
            for k in 0..=i {
                product[(i, k)] += column[i] * column[k];
            }
        }
    }
    for i in 0..R {
        for k in 0..i {
            product[(k, i)] = product[(i, k)];
        }
    }
    product
}

/// The damped step of `system` from `joint_positions` with the joints
/// held at a limit it would push beyond taken out of it (an active set):
/// their columns of J are zeroed and the step is taken again by the
/// others, until none pushes beyond. Clamping such a joint instead would
/// cut the step after it is chosen, so the others would not make up for it
/// and the descent would crawl along the limit. Without limits, or with no
/// joint pushing beyond one, the step is the system's.
fn bounded_step(
    robot: &Robot,
    options: &InverseOptions,
    joint_positions: &DVector<f64>,
    system: &DampedSystem<'_>,
    error: &DVector<f64>,
    damping: f64,
) -> Option<DVector<f64>> {
    let mut step = system.step(error, damping)?;
    if !options.respect_limits {
        return Some(step);
    }
    let mut held: Option<DMatrix<f64>> = None;
    loop {
        let mut blocked = false;
        for (index, ((q, joint), change)) in joint_positions
            .iter()
            .zip(robot.joints())
            .zip(step.iter())
            .enumerate()
        {
            if pushes_beyond(joint, *q, *change) {
                held.get_or_insert_with(|| system.jacobian.clone())
                    .column_mut(index)
                    .fill(0.0);
                blocked = true;
            }
        }
        // (A zeroed column gives its joint no step: each round holds a new one.)
        let Some(reduced) = held.as_ref().filter(|_| blocked) else {
            return Some(step);
        };
        step = DampedSystem::new(reduced).step(error, damping)?;
    }
}

/// `product + λI`.
fn damped(mut product: DMatrix<f64>, damping: f64) -> DMatrix<f64> {
    for i in 0..product.nrows() {
        product[(i, i)] += damping;
    }
    product
}

/// `J⁻¹Δx` for a square J of 6 or 3 rows, by LU; `None` when J is singular.
fn square_solve(jacobian: &DMatrix<f64>, error: &DVector<f64>) -> Option<DVector<f64>> {
    let (values, right) = (jacobian.as_slice(), error.as_slice());
    match jacobian.nrows() {
        6 => Matrix6::from_column_slice(values)
            .lu()
            .solve(&Vector6::from_column_slice(right))
            .map(|step| DVector::from_column_slice(step.as_slice())),
        3 => Matrix3::from_column_slice(values)
            .lu()
            .solve(&Vector3::from_column_slice(right))
            .map(|step| DVector::from_column_slice(step.as_slice())),
        _ => None,
    }
}

/// `(JJᵀ + λI)⁻¹Δx` for a J of `R` rows, from its `product` JJᵀ.
fn wide_solve<const R: usize>(
    product: &SMatrix<f64, R, R>,
    error: &DVector<f64>,
    damping: f64,
) -> Option<DVector<f64>> {
    let mut product = *product;
    for i in 0..R {
        product[(i, i)] += damping;
    }
    let right = SVector::<f64, R>::from_column_slice(error.as_slice());
    let solved = product.cholesky()?.solve(&right);
    Some(DVector::from_column_slice(solved.as_slice()))
}

fn clamp_to_limits(robot: &Robot, mut joint_positions: DVector<f64>) -> DVector<f64> {
    for (q, joint) in joint_positions.iter_mut().zip(robot.joints()) {
        *q = q.clamp(joint.qmin, joint.qmax);
    }
    joint_positions
}

/// The task error `Δx` from frame n+1 at `current` towards the target.
fn task_error(target: &Target, current: &IsometryMatrix3<f64>) -> DVector<f64> {
    match target {
        Target::Position(point) => {
            DVector::from_column_slice((point - current.translation.vector).as_slice())
        }
        Target::Frame(pose) => {
            let position = pose.translation.vector - current.translation.vector;
            let rotation = orientation_difference(
                &pose.rotation,
                &current.rotation,
                OrientationDifference::AxisAngle,
            );
            DVector::from_column_slice(&[
                position.x, position.y, position.z, rotation.x, rotation.y, rotation.z,
            ])
        }
        Target::Plane { normal, offset } => {
            DVector::from_element(1, offset - normal.dot(&current.translation.vector))
        }
    }
}

/// The rows of the 6×n joint Jacobian `full` that the target constrains.
fn task_rows(target: &Target, full: &Matrix6xX<f64>) -> DMatrix<f64> {
    match target {
        Target::Plane { normal, .. } => {
            let row = normal.transpose() * full.fixed_rows::<3>(0);
            DMatrix::from_row_slice(1, row.len(), row.as_slice())
        }
        // (The columns of `full` are contiguous: a frame's rows are all of it.)
        Target::Frame(_) => DMatrix::from_column_slice(6, full.ncols(), full.as_slice()),
        Target::Position(_) => DMatrix::from_fn(3, full.ncols(), |row, column| full[(row, column)]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinematics::jacobian::joint_jacobian;
    use crate::kinematics::terminal_pose;
    use crate::test_robots::{random_configuration, random_robot, stanford};
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The robot of a trial (the Stanford arm, or a random six-axis arm on
    /// odd trials), a random configuration of it and the pose there.
    fn trial_robot(trial: usize, rng: &mut ChaCha8Rng) -> (Robot, Vec<f64>, IsometryMatrix3<f64>) {
        let robot = if trial.is_multiple_of(2) {
            stanford()
        } else {
            random_robot(rng, 6)
        };
        let goal = random_configuration(&robot, rng);
        let pose = terminal_pose(&robot, &goal).expect("valid");
        (robot, goal, pose)
    }

    /// From a near start, Newton steps on the compiled model reach the
    /// damped solver's solution (pose targets: locally unique), in a few
    /// iterations; the compiled joint Jacobian is the reference one.
    #[test]
    fn near_starts_take_newton_steps_to_the_damped_solver_s_solution() {
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let options = InverseOptions::default();
        let mut newton = 0;
        for trial in 0..40 {
            let (robot, goal, pose) = trial_robot(trial, &mut rng);
            let model = KinematicModel::new(&robot);
            let chain = crate::kinematics::forward_kinematics(&robot, &goal).expect("valid");
            let mut buffer = ChainBuffer::default();
            model.forward_joints(chain.joint_positions(), &mut buffer);
            let mut compiled = Matrix6xX::zeros(0);
            model.joint_jacobian(&buffer, &mut compiled);
            let reference = joint_jacobian(&robot, &chain);
            assert!((compiled - &reference).amax() < 1e-12, "trial {trial}");
            let start: Vec<f64> = goal.iter().map(|q| q + 2e-3).collect();
            let target = Target::Frame(pose);
            let damped = inverse_kinematics(&robot, &target, &start, &options);
            let near = inverse_kinematics_near(&robot, &model, &target, &start, &options);
            let (Ok(damped), Ok(near)) = (damped, near) else {
                continue;
            };
            let apart = damped
                .motor_positions
                .iter()
                .zip(&near.motor_positions)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            assert!(apart < 1e-9, "trial {trial}: {apart}");
            newton += usize::from(near.iterations <= 5);
        }
        assert!(newton >= 30, "Newton converged in {newton} of 40");
    }

    #[test]
    fn reaches_reachable_frames_and_points_from_another_start() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let options = InverseOptions::default();
        let mut solved = 0;
        for trial in 0..60 {
            let (robot, goal, pose) = trial_robot(trial, &mut rng);
            let target = if trial % 3 == 0 {
                Target::Position(pose.translation.vector)
            } else {
                Target::Frame(pose)
            };
            // Start near the goal so that most trials must succeed.
            let start: Vec<f64> = goal.iter().map(|q| q + 0.2).collect();
            if let Ok(solution) = inverse_kinematics(&robot, &target, &start, &options) {
                solved += 1;
                let reached = terminal_pose(&robot, &solution.motor_positions).expect("valid");
                assert!((reached.translation.vector - pose.translation.vector).norm() < 1e-11);
                assert!(robot.within_limits(&solution.joint_positions));
            }
        }
        assert!(solved >= 50, "only {solved} of 60 solved");
    }

    #[test]
    fn plane_targets_move_onto_the_plane() {
        let robot = stanford();
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let normal = Vector3::new(0.3, 0.5, 0.81).normalize();
        let offset = normal.dot(&Vector3::new(0.3, 0.2, 0.6));
        let mut solved = 0;
        for _ in 0..20 {
            let start = random_configuration(&robot, &mut rng);
            let target = Target::Plane { normal, offset };
            if let Ok(solution) =
                inverse_kinematics(&robot, &target, &start, &InverseOptions::default())
            {
                let point = terminal_pose(&robot, &solution.motor_positions)
                    .expect("valid")
                    .translation
                    .vector;
                assert!((normal.dot(&point) - offset).abs() < 1e-12);
                solved += 1;
            }
        }
        assert!(solved >= 15, "{solved} of 20");
    }

    /// The iterations and the remaining error of a solve for `pose` from
    /// `start` that must give up (a pose out of reach).
    fn given_up(robot: &Robot, pose: IsometryMatrix3<f64>, start: &[f64]) -> (usize, f64) {
        let result = inverse_kinematics(
            robot,
            &Target::Frame(pose),
            start,
            &InverseOptions::default(),
        );
        let Err(Error::Unreachable {
            iterations,
            residual,
            ..
        }) = result
        else {
            panic!("reached a pose out of reach from {start:?}: {result:?}");
        };
        (iterations, residual)
    }

    /// A pose whose wrist centre lies 2 cm inside the cylinder of radius
    /// r2 about z1 that the Stanford arm's wrist centre never enters: the
    /// solve settles at the least-squares minimum and gives up when its
    /// error is orthogonal to what the joints can do (12 iterations). It
    /// waited before for five iterations of rounding's worth of decrease
    /// (17), and before that for the stall rule's 25.
    #[test]
    fn a_solve_settled_short_of_its_target_stops() {
        let robot = stanford();
        let start = [2.0, 0.01, 0.5, -1.0, 0.6, 1.2];
        let mut pose = terminal_pose(&robot, &start).expect("valid");
        pose.translation.vector.x += 0.02;
        pose.translation.vector.y += 0.02;
        let (iterations, residual) = given_up(&robot, pose, &start);
        assert!(residual > 8e-3, "{residual}");
        assert!(iterations <= 13, "{iterations} iterations");
    }

    /// Poses the Stanford arm would reach with its prismatic joint 5 cm
    /// short of its lower limit (0.2 m): within the limits the best is that
    /// joint held at the limit and the others doing what they can, 3.2 cm
    /// from the pose. The steps are taken with the held joint out of them,
    /// so the solve settles there, and gives up in 7 iterations when the
    /// gradient left to the free joints vanishes (11–12 when it waited for
    /// the error to stop falling). Clamping the held joint after each step
    /// instead cut every step short: the solve crawled along the limit and
    /// gave up after 27, 4.3–4.5 cm from the pose.
    #[test]
    fn a_joint_held_at_its_limit_is_taken_out_of_the_step() {
        let mut spec = stanford().to_spec();
        (spec.joints[2].qmin, spec.joints[2].qmax) = (0.2, 1.0);
        let robot = Robot::new(spec).expect("valid");
        for (index, start) in [
            [0.4, 1.1, 0.45, 0.3, -0.8, 0.2],
            [-1.2, 2.0, 0.6, -0.5, 1.3, 2.2],
            [2.5, -0.9, 0.3, 1.7, 0.4, -1.0],
        ]
        .into_iter()
        .enumerate()
        {
            let mut beyond = start;
            beyond[2] = 0.15;
            beyond[1] += 0.1;
            let pose = terminal_pose(&robot, &beyond).expect("valid");
            let (iterations, residual) = given_up(&robot, pose, &start);
            assert!(
                (0.03..0.034).contains(&residual) && iterations <= 8,
                "start {index}: {iterations} iterations, {residual} from the pose"
            );
        }
    }

    /// The shoulder-void pose of the test above from ten starts 0.1 rad
    /// around the first: each settles where the first did, and given the
    /// first's minimum each gives up on the way there, in a third of the
    /// iterations (32 against 99) and without recording it again. A pose within reach is still met
    /// with that minimum known.
    #[test]
    fn a_solve_heading_for_a_known_minimum_is_given_up() {
        let robot = stanford();
        let model = KinematicModel::new(&robot);
        let options = InverseOptions::default();
        let start = [2.0, 0.01, 0.5, -1.0, 0.6, 1.2];
        let mut pose = terminal_pose(&robot, &start).expect("valid");
        pose.translation.vector.x += 0.02;
        pose.translation.vector.y += 0.02;
        let target = Target::Frame(pose);
        let iterations = |result: Result<InverseSolution, Error>| match result {
            Err(Error::Unreachable { iterations, .. }) => iterations,
            other => panic!("reached a pose out of reach: {other:?}"),
        };
        let mut known = KnownMinima::new(0.01);
        let first =
            inverse_kinematics_avoiding(&robot, &model, &target, &start, &options, &mut known);
        assert_eq!((iterations(first), known.len()), (12, 1));
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let (mut alone, mut avoiding) = (0, 0);
        for _ in 0..10 {
            let nearby: Vec<f64> = start
                .iter()
                .map(|q| q + 0.1 * rng.random_range(-1.0..1.0))
                .collect();
            alone += iterations(inverse_kinematics_on(
                &robot, &model, &target, &nearby, &options,
            ));
            let result =
                inverse_kinematics_avoiding(&robot, &model, &target, &nearby, &options, &mut known);
            avoiding += iterations(result);
        }
        assert_eq!(known.len(), 1);
        assert!(
            2 * avoiding < alone,
            "{avoiding} iterations given up, {alone} settled"
        );
        let within_reach = terminal_pose(&robot, &[1.9, 0.3, 0.55, -0.9, 0.7, 1.1]).expect("valid");
        let reached = inverse_kinematics_avoiding(
            &robot,
            &model,
            &Target::Frame(within_reach),
            &start,
            &options,
            &mut known,
        );
        assert!(reached.is_ok(), "{reached:?}");
    }

    #[test]
    fn far_targets_are_unreachable_errors() {
        let robot = stanford();
        let target = Target::Position(Vector3::new(10.0, 0.0, 0.0));
        let result = inverse_kinematics(
            &robot,
            &target,
            &[0.0, 0.0, 0.5, 0.0, 0.0, 0.0],
            &InverseOptions::default(),
        );
        assert!(
            matches!(result, Err(Error::Unreachable { residual, .. }) if residual > 8.0),
            "{result:?}"
        );
        let nan = Target::Position(Vector3::new(f64::NAN, 0.0, 0.0));
        assert!(matches!(
            inverse_kinematics(&robot, &nan, &[0.0; 6], &InverseOptions::default()),
            Err(Error::NonFiniteTarget { .. })
        ));
    }
}
