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
//! ~1e-13 m. The steps are [`joint_step`](super::joint_step)'s; a solve
//! works in buffers its thread keeps for the next one, so an iteration for
//! a point or a frame allocates nothing.
//!
//! Failure is an error, never a silently wrong configuration: when the target
//! is out of reach within the joint limits, or the iteration stalls from this
//! start, [`Error::Unreachable`] reports the remaining error, and whether a
//! joint met a limit on the way (if not, the same solve without the limits
//! would take the same steps). A solve gives up
//! at a least-squares minimum short of the target (the projected gradient
//! `Jᵀ Δx` vanishing against `‖J‖ ‖Δx‖`), after five iterations that lower
//! ‖Δx‖ by rounding's worth, or after 25 that do not halve it.

use std::cell::Cell;

use nalgebra::{DMatrix, DVector, IsometryMatrix3, Matrix6xX, Vector3};

use super::joint_step::{DampedSystem, bounded_step, newton_step, pushes_beyond};
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
pub(super) fn inverse_kinematics_on(
    robot: &Robot,
    model: &KinematicModel,
    target: &Target,
    start_motor_positions: &[f64],
    options: &InverseOptions,
) -> Result<InverseSolution, Error> {
    check_target(target)?;
    let start = robot.joint_positions(start_motor_positions)?;
    damped_descent((robot, model, options), target, &start, None)
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
pub(super) fn inverse_kinematics_avoiding(
    robot: &Robot,
    model: &KinematicModel,
    target: &Target,
    start_motor_positions: &[f64],
    options: &InverseOptions,
    known: &mut KnownMinima,
) -> Result<InverseSolution, Error> {
    check_target(target)?;
    let start = robot.joint_positions(start_motor_positions)?;
    damped_descent((robot, model, options), target, &start, Some(known))
}

/// The buffers of one solve, reused from iteration to iteration: an
/// iteration for a point or a frame target allocates nothing.
struct Workspace {
    /// The iterate, and the candidate a step leads to.
    current: Iterate,
    candidate: Iterate,
    /// The 6×n joint Jacobian, and the target's rows of it at the iterate.
    full: Matrix6xX<f64>,
    jacobian: DMatrix<f64>,
    /// J with the columns of the joints held at a limit zeroed.
    held: DMatrix<f64>,
    /// The step from the iterate to the candidate.
    step: DVector<f64>,
    /// Whether an iterate of this solve had a joint at or beyond a limit
    /// (see [`Error::Unreachable`]'s `met_limit`).
    met_limit: bool,
}

/// Joint positions, the direct model there and the task error.
struct Iterate {
    joint_positions: DVector<f64>,
    chain: ChainBuffer,
    error: DVector<f64>,
}

thread_local! {
    /// The buffers of this thread's last solve, for its next: a
    /// compensation solves a million targets one after another, each in a
    /// few iterations.
    static SPARE_WORKSPACE: Cell<Option<Workspace>> = const { Cell::new(None) };
}

/// `solve` in buffers for `target` on a robot of `joints` joints: this
/// thread's spare ones when they have that shape.
fn in_workspace<R>(target: &Target, joints: usize, solve: impl FnOnce(&mut Workspace) -> R) -> R {
    let shape = (target.rows(), joints);
    let mut work = SPARE_WORKSPACE
        .take()
        .filter(|work| work.jacobian.shape() == shape)
        .unwrap_or_else(|| Workspace::new(shape));
    let result = solve(&mut work);
    SPARE_WORKSPACE.set(Some(work));
    result
}

impl Workspace {
    /// The buffers for a target of `rows` rows on a robot of `joints` joints.
    fn new((rows, joints): (usize, usize)) -> Self {
        let iterate = || Iterate {
            joint_positions: DVector::zeros(joints),
            chain: ChainBuffer::default(),
            error: DVector::zeros(rows),
        };
        Workspace {
            current: iterate(),
            candidate: iterate(),
            full: Matrix6xX::zeros(joints),
            jacobian: DMatrix::zeros(rows, joints),
            held: DMatrix::zeros(rows, joints),
            step: DVector::zeros(joints),
            met_limit: false,
        }
    }

    /// The target's rows of the joint Jacobian at the iterate.
    fn linearise(&mut self, model: &KinematicModel, target: &Target) {
        model.joint_jacobian(&self.current.chain, &mut self.full);
        task_rows(target, &self.full, &mut self.jacobian);
    }
}

/// The robot, its compiled model and the options of a solve.
type Solver<'a> = (&'a Robot, &'a KinematicModel, &'a InverseOptions);

impl Iterate {
    /// This iterate at `from` plus `step`, evaluated; its ‖Δx‖.
    fn step_from(
        &mut self,
        (from, step): (&Iterate, &DVector<f64>),
        solver: Solver<'_>,
        (target, met_limit): (&Target, &mut bool),
    ) -> f64 {
        self.joint_positions.copy_from(&from.joint_positions);
        self.joint_positions += step;
        self.evaluate(solver, (target, met_limit))
    }

    /// Clamps the joint positions to the limits (when the options keep
    /// them; `met_limit` set when a joint is at or beyond one) and
    /// evaluates the model and the task error there; ‖Δx‖.
    fn evaluate(
        &mut self,
        (robot, model, options): Solver<'_>,
        (target, met_limit): (&Target, &mut bool),
    ) -> f64 {
        if options.respect_limits {
            *met_limit |= clamp_to_limits(robot, &mut self.joint_positions);
        }
        model.forward_joints(self.joint_positions.as_slice(), &mut self.chain);
        task_error(target, self.chain.world_from_tool(), &mut self.error);
        self.error.norm()
    }
}

/// The damped least-squares descent of [`inverse_kinematics`] from the
/// joint positions `start`, on the compiled `model` of `robot`; given up
/// near a minimum of `known`, and its own recorded there when it fails.
fn damped_descent(
    solver: Solver<'_>,
    target: &Target,
    start: &DVector<f64>,
    known: Option<&mut KnownMinima>,
) -> Result<InverseSolution, Error> {
    in_workspace(target, solver.0.joint_count(), |work| {
        work.met_limit = false;
        descend_from(work, solver, target, start, known)
    })
}

/// [`damped_descent`] in the buffers `work`.
fn descend_from(
    work: &mut Workspace,
    solver: Solver<'_>,
    target: &Target,
    start: &DVector<f64>,
    known: Option<&mut KnownMinima>,
) -> Result<InverseSolution, Error> {
    let (robot, model, options) = solver;
    let joints = options.respect_limits.then(|| robot.joints());
    work.current.joint_positions.copy_from(start);
    // ‖Δx‖ of `work.current.error`, kept beside it.
    let mut residual = work.current.evaluate(solver, (target, &mut work.met_limit));
    let mut damping = INITIAL_DAMPING;
    let mut iterations = 0;
    let (mut checkpoint_error, mut checkpoint_iteration) = (residual, 0);
    let mut stationary = 0;
    while residual > options.tolerance && iterations < options.max_iterations {
        // Given up near a known minimum (where it would settle again).
        if known
            .as_deref()
            .is_some_and(|known| known.is_near(work.current.joint_positions.as_slice()))
        {
            break;
        }
        iterations += 1;
        work.linearise(model, target);
        if at_stationary_point(joints, &work.current, &work.jacobian, residual) {
            break;
        }
        let system = DampedSystem::new(&work.jacobian);
        let mut improved = false;
        while damping < MAX_DAMPING {
            let stepped = bounded_step(
                joints,
                &work.current.joint_positions,
                (&system, &work.current.error, damping),
                &mut work.step,
                &mut work.held,
            );
            if !stepped {
                damping *= 10.0;
                continue;
            }
            let candidate_residual = work.candidate.step_from(
                (&work.current, &work.step),
                solver,
                (target, &mut work.met_limit),
            );
            if candidate_residual < residual {
                let decrease = residual - candidate_residual;
                stationary = if decrease <= STATIONARY_DECREASE * residual {
                    stationary + 1
                } else {
                    0
                };
                std::mem::swap(&mut work.current, &mut work.candidate);
                residual = candidate_residual;
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
            known.record(work.current.joint_positions.as_slice());
        }
        return Err(Error::Unreachable {
            iterations,
            residual,
            tolerance: options.tolerance,
            met_limit: work.met_limit,
        });
    }
    solution(robot, &work.current, iterations, residual)
}

/// Whether the error of `iterate` (of norm `residual`) is orthogonal to
/// what the free joints can do there, J the target's rows of the joint
/// Jacobian (see [`STATIONARY_COSINE`]): the gradient `Jᵀ Δx` with the
/// components of the joints held at a limit that it would push beyond left
/// out (a projected gradient; `joints` the robot's, `None` when the limits
/// are not kept).
fn at_stationary_point(
    joints: Option<&[Joint]>,
    iterate: &Iterate,
    jacobian: &DMatrix<f64>,
    residual: f64,
) -> bool {
    let (joint_positions, error) = (&iterate.joint_positions, &iterate.error);
    let held = |index: usize, change: f64| {
        joints.is_some_and(|joints| pushes_beyond(&joints[index], joint_positions[index], change))
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

/// The solution at `iterate`, met to `residual` after `iterations`.
fn solution(
    robot: &Robot,
    iterate: &Iterate,
    iterations: usize,
    residual: f64,
) -> Result<InverseSolution, Error> {
    let (joint_positions, chain) = (&iterate.joint_positions, &iterate.chain);
    let mut motor_positions = vec![0.0; robot.joint_count()];
    robot.motor_positions_into(joint_positions.as_slice(), &mut motor_positions)?;
    Ok(InverseSolution {
        motor_positions,
        joint_positions: joint_positions.as_slice().to_vec(),
        iterations,
        residual,
        pose: *chain.world_from_tool(),
    })
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
pub(super) fn inverse_kinematics_near(
    robot: &Robot,
    model: &KinematicModel,
    target: &Target,
    start_motor_positions: &[f64],
    options: &InverseOptions,
) -> Result<InverseSolution, Error> {
    newton_then(robot, model, target, start_motor_positions, options, true)
}

/// The Newton steps of [`inverse_kinematics_near`] alone: from a start a
/// step or two from a solution (a configuration of a nearby robot), the
/// solution, else [`Error::Unreachable`] at once, without the damped
/// solver's search.
///
/// # Errors
/// As [`inverse_kinematics`].
pub(super) fn inverse_kinematics_newton(
    robot: &Robot,
    model: &KinematicModel,
    target: &Target,
    start_motor_positions: &[f64],
    options: &InverseOptions,
) -> Result<InverseSolution, Error> {
    newton_then(robot, model, target, start_motor_positions, options, false)
}

/// Newton steps from the start, then (`damped`) the damped solver where
/// they stop short, else [`Error::Unreachable`].
fn newton_then(
    robot: &Robot,
    model: &KinematicModel,
    target: &Target,
    start_motor_positions: &[f64],
    options: &InverseOptions,
    damped: bool,
) -> Result<InverseSolution, Error> {
    check_target(target)?;
    let start = robot.joint_positions(start_motor_positions)?;
    let solver = (robot, model, options);
    in_workspace(target, robot.joint_count(), |work| {
        work.met_limit = false;
        match newton_from(work, solver, target, &start)? {
            Ok(solution) => Ok(solution),
            Err(_) if damped => descend_from(work, solver, target, &start, None),
            Err((iterations, residual)) => Err(Error::Unreachable {
                iterations,
                residual,
                tolerance: options.tolerance,
                met_limit: work.met_limit,
            }),
        }
    })
}

/// Newton steps from `start` (see [`inverse_kinematics_near`]): the
/// solution, or the iterations taken and the error left when they stop
/// short of it.
fn newton_from(
    work: &mut Workspace,
    solver: Solver<'_>,
    target: &Target,
    start: &DVector<f64>,
) -> Result<Result<InverseSolution, (usize, f64)>, Error> {
    let (robot, model, options) = solver;
    work.current.joint_positions.copy_from(start);
    let mut residual = work.current.evaluate(solver, (target, &mut work.met_limit));
    for iteration in 0..=NEWTON_ITERATIONS {
        if residual <= options.tolerance {
            return solution(robot, &work.current, iteration, residual).map(Ok);
        }
        if iteration == NEWTON_ITERATIONS {
            break;
        }
        work.linearise(model, target);
        if !newton_step(&work.jacobian, &work.current.error, &mut work.step)
            || work.step.amax() > MAX_NEWTON_STEP
        {
            return Ok(Err((iteration, residual)));
        }
        let candidate_residual = work.candidate.step_from(
            (&work.current, &work.step),
            solver,
            (target, &mut work.met_limit),
        );
        // (A NaN is no improvement either.)
        if candidate_residual.is_nan() || candidate_residual >= residual {
            return Ok(Err((iteration, residual)));
        }
        std::mem::swap(&mut work.current, &mut work.candidate);
        residual = candidate_residual;
    }
    Ok(Err((NEWTON_ITERATIONS, residual)))
}

/// `joint_positions` clamped to the joint limits; whether one was at or
/// beyond a limit.
fn clamp_to_limits(robot: &Robot, joint_positions: &mut DVector<f64>) -> bool {
    let mut met = false;
    for (q, joint) in joint_positions.iter_mut().zip(robot.joints()) {
        met |= *q <= joint.qmin || *q >= joint.qmax;
        *q = q.clamp(joint.qmin, joint.qmax);
    }
    met
}

/// The task error `Δx` from frame n+1 at `current` towards the target,
/// into `error` (of the target's rows).
fn task_error(target: &Target, current: &IsometryMatrix3<f64>, error: &mut DVector<f64>) {
    match target {
        Target::Position(point) => {
            error.copy_from_slice((point - current.translation.vector).as_slice());
        }
        Target::Frame(pose) => {
            let position = pose.translation.vector - current.translation.vector;
            let rotation = orientation_difference(
                &pose.rotation,
                &current.rotation,
                OrientationDifference::AxisAngle,
            );
            error.copy_from_slice(&[
                position.x, position.y, position.z, rotation.x, rotation.y, rotation.z,
            ]);
        }
        Target::Plane { normal, offset } => {
            error[0] = offset - normal.dot(&current.translation.vector);
        }
    }
}

/// The rows of the 6×n joint Jacobian `full` that the target constrains,
/// into `rows` (of the target's rows, n columns).
fn task_rows(target: &Target, full: &Matrix6xX<f64>, rows: &mut DMatrix<f64>) {
    match target {
        Target::Plane { normal, .. } => {
            rows.copy_from(&(normal.transpose() * full.fixed_rows::<3>(0)))
        }
        // (The columns of `full` are contiguous: a frame's rows are all of it.)
        Target::Frame(_) => rows.copy_from_slice(full.as_slice()),
        Target::Position(_) => rows.copy_from(&full.fixed_rows::<3>(0)),
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

    /// A failed solve says whether a joint met a limit on the way; where
    /// none did, the same solve without the limits takes the same steps to
    /// the same end (the compensation leaves it out). Poses out of the
    /// Stanford arm's reach from starts near them: moved into the cylinder
    /// about the axis of joint 1 that its wrist centre never enters (the
    /// solves settle beside it, mostly within the limits), or three times
    /// as far from the base (the prismatic joint runs to its limit). Both
    /// kinds occur, and every solve that met no limit fails again without
    /// them, bit for bit.
    #[test]
    fn a_failed_solve_says_whether_a_limit_bore_on_it() {
        let robot = stanford();
        let model = KinematicModel::new(&robot);
        let unlimited = InverseOptions {
            respect_limits: false,
            ..InverseOptions::default()
        };
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let (mut met, mut free) = (0, 0);
        for trial in 0..40 {
            let goal = random_configuration(&robot, &mut rng);
            let start: Vec<f64> = goal
                .iter()
                .map(|q| q + rng.random_range(-0.05..0.05))
                .collect();
            let mut pose = terminal_pose(&robot, &goal).expect("valid");
            if trial % 2 == 0 {
                pose.translation.vector.x = rng.random_range(-0.02..0.02);
                pose.translation.vector.y = rng.random_range(-0.02..0.02);
            } else {
                pose.translation.vector *= 3.0;
            }
            let target = Target::Frame(pose);
            for near in [false, true] {
                let solve = |options: &InverseOptions| {
                    if near {
                        inverse_kinematics_near(&robot, &model, &target, &start, options)
                    } else {
                        inverse_kinematics_on(&robot, &model, &target, &start, options)
                    }
                };
                let Err(within @ Error::Unreachable { met_limit, .. }) =
                    solve(&InverseOptions::default())
                else {
                    continue;
                };
                if met_limit {
                    met += 1;
                    continue;
                }
                free += 1;
                let without = solve(&unlimited).expect_err("the same solve");
                assert_eq!(format!("{without:?}"), format!("{within:?}"));
            }
        }
        assert!(met >= 5 && free >= 5, "{met} met a limit, {free} did not");
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

    /// A solve in the buffers of earlier solves of other shapes (points,
    /// frames, planes), robots and outcomes (met, given up) gives what it
    /// gives on a thread of its own, bit for bit.
    #[test]
    fn a_solve_in_reused_buffers_is_the_solve_in_fresh_ones() {
        let mut rng = ChaCha8Rng::seed_from_u64(41);
        let options = InverseOptions::default();
        let mut cases = Vec::new();
        for trial in 0..12 {
            let (robot, goal, pose) = trial_robot(trial, &mut rng);
            let target = match trial % 3 {
                0 => Target::Position(pose.translation.vector),
                1 => Target::Frame(pose),
                _ => Target::Plane {
                    normal: Vector3::z(),
                    offset: pose.translation.vector.z,
                },
            };
            let start: Vec<f64> = goal.iter().map(|q| q + 0.3).collect();
            cases.push((robot, target, start));
        }
        // One far target, given up, between the others.
        cases.insert(
            5,
            (
                stanford(),
                Target::Position(Vector3::new(10.0, 0.0, 0.0)),
                vec![0.0, 0.0, 0.5, 0.0, 0.0, 0.0],
            ),
        );
        let solve = |(robot, target, start): &(Robot, Target, Vec<f64>)| {
            let model = KinematicModel::new(robot);
            let near = inverse_kinematics_near(robot, &model, target, start, &options);
            let damped = inverse_kinematics_on(robot, &model, target, start, &options);
            format!("{near:?} {damped:?}")
        };
        let in_turn: Vec<String> = cases.iter().map(solve).collect();
        for (case, expected) in cases.iter().zip(&in_turn) {
            let alone =
                std::thread::scope(|scope| scope.spawn(|| solve(case)).join().expect("no panic"));
            assert_eq!(&alone, expected);
        }
        assert!(in_turn.iter().any(|result| result.contains("Unreachable")));
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
