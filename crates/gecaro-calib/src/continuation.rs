//! The calibrated robot's inverse model where the direct solve from a
//! program's joints stalls: near a singularity a small change of pose asks a
//! large change of the joints, and damped least squares crawls. Two ways
//! keep the program's branch, tried in this order:
//!
//! 1. **Continuation** ([`continue_from_nominal`]): the robot is moved from
//!    the nominal parameters to the calibrated ones in small steps, the
//!    target held, and each step solved from the solution of the one before
//!    (Newton steps: it is a step or two away).
//!    The compensation follows it where the calibrated robot meets the
//!    target from the program's joints with the limits lifted; elsewhere
//!    the target nearly always leaves the branch's reach on the way.
//! 2. **Nearby starts** ([`closest_from_nearby_starts`]): where the path is
//!    cut (a wrist that must pass through q5 = 0 turns q4 and q6 by up to π
//!    at once), starts drawn around the program's joints at growing
//!    distances; of the solutions found, the one closest to the program's
//!    joints. Most starts fall into the basin of one minimum short of the
//!    target, beside the program's joints: once one start has settled
//!    there, the others give up on the way ([`KnownMinima`]).
//!
//! With η₀ the nominal and η₁ the calibrated parameters (angles compared
//! modulo 2π), the robot of step t ∈ [0, 1] has η(t) = η₁ − (1 − t)(η₁ − η₀)
//! and the calibrated robot's couplings. At t = 0 the program's joints
//! solve the target (it is the nominal model's pose of them); the solution
//! follows t continuously, so the program's branch (elbow, wrist, shoulder)
//! is kept, and a step that fails is halved. The path may cross a joint
//! limit: limits are left to the caller.

use gecaro_core::{
    InverseOptions, InverseSolution, InverseSolver, KinematicModel, KnownMinima, ParameterKind,
    Robot, Target,
};

use crate::Error;
use crate::sampler::Sampler;

/// Starts drawn around the program's joints, per spread.
const STARTS_PER_SPREAD: usize = 10;
/// The spreads (standard deviations, in the joint variables' units) of
/// the nearby starts.
const SPREADS: [f64; 4] = [0.1, 0.5, 1.5, 3.0];

/// How near (per joint, rad or m) a known minimum short of the target a
/// nearby start's solve is given up ([`KnownMinima`]): most starts fall
/// into the basin of one minimum beside the program's joints. Measured on
/// the first 10⁵ targets of a 10⁶-target Stanford program (CPU time 8.9 s
/// without): 0.01 cut it by 27 % and changed no row; 0.02 by 30 % and
/// 0.05 by 35 %, each changing one row: a target with q2 at ±π, reached
/// at the other end of its range (the same configuration a turn away),
/// so `reconfigured` rather than `ok`.
const KNOWN_MINIMUM_RADIUS: f64 = 0.05;

/// The longest step from the nominal to the calibrated robot (in t).
const LONGEST_STEP: f64 = 1.0 / 8.0;
/// The shortest step: a path that needs less is cut (the target leaves the
/// calibrated robot's reach on the way). Measured on 20,000 targets over
/// the Stanford arm's joint space: of 630 paths followed to the end, 4 had
/// a step halved, none more than twice; the 1,268 cut were cut where the
/// target left the reach, after 12.7 failed steps on average when the
/// shortest step was 1/256 of the longest, 5.3 at 1/8 of it, with the
/// same results (2 of 10⁵ targets then reached within the limits, beyond
/// them before).
const SHORTEST_STEP: f64 = LONGEST_STEP / 8.0;
/// Failed steps before the path is given up, whatever their length.
const MAX_FAILED_STEPS: usize = 64;

/// The path of robots from a nominal robot to its calibrated one (see the
/// module docs): the parameters' change, and the robots at every whole
/// step (t = k·[`LONGEST_STEP`]) compiled once for a whole program — nearly
/// every path is followed by them alone (a step is seldom halved).
pub(crate) struct NominalPath {
    calibrated: Robot,
    change: Vec<f64>,
    /// The robot at t = (k + 1)·`LONGEST_STEP` and its compiled model.
    stations: Vec<(Robot, KinematicModel)>,
}

impl NominalPath {
    /// The path from `nominal` to `calibrated`; `None` when their
    /// parameters differ (no path between them).
    ///
    /// # Errors
    /// Configuration errors of the robots (never for robots of the same
    /// joints).
    pub(crate) fn new(nominal: &Robot, calibrated: &Robot) -> Result<Option<Self>, Error> {
        if nominal.parameters() != calibrated.parameters() {
            return Ok(None);
        }
        let change: Vec<f64> = calibrated
            .parameters()
            .ids()
            .iter()
            .map(|id| {
                let delta = calibrated.parameter(*id) - nominal.parameter(*id);
                match id.kind {
                    ParameterKind::Alpha | ParameterKind::Theta | ParameterKind::Beta => {
                        // The shortest way round: a wrapped angle is not a turn of change.
                        delta - std::f64::consts::TAU * (delta / std::f64::consts::TAU).round()
                    }
                    _ => delta,
                }
            })
            .collect();
        let mut path = NominalPath {
            calibrated: calibrated.clone(),
            change,
            stations: Vec::new(),
        };
        let whole_steps = (1.0 / LONGEST_STEP).round() as usize;
        path.stations = (1..=whole_steps)
            .map(|k| {
                let robot = path.robot_at(k as f64 * LONGEST_STEP)?;
                let model = KinematicModel::new(&robot);
                Ok((robot, model))
            })
            .collect::<Result<_, Error>>()?;
        Ok(Some(path))
    }

    /// The robot at `t` ∈ [0, 1]: η(t) = η₁ − (1 − t)(η₁ − η₀).
    fn robot_at(&self, t: f64) -> Result<Robot, Error> {
        let mut robot = self.calibrated.clone();
        let back: Vec<f64> = self.change.iter().map(|delta| -(1.0 - t) * delta).collect();
        robot.apply_deltas(&back)?;
        Ok(robot)
    }

    /// The compiled robot at `t` when it is a whole step.
    fn station(&self, t: f64) -> Option<&(Robot, KinematicModel)> {
        let steps = t / LONGEST_STEP;
        (steps.fract() == 0.0 && steps >= 1.0)
            .then(|| self.stations.get(steps as usize - 1))
            .flatten()
    }
}

/// The calibrated robot's solution for `target`, continued along `path`
/// from `start_motor_positions` (which solve it on the nominal robot);
/// `None` when the path cannot be followed (the target leaves the
/// calibrated robot's reach on the way).
///
/// # Errors
/// Configuration errors of the robots (never for robots of the same joints).
pub(crate) fn continue_from_nominal(
    path: &NominalPath,
    target: &Target,
    start_motor_positions: &[f64],
    options: &InverseOptions,
) -> Result<Option<InverseSolution>, Error> {
    let unlimited = InverseOptions {
        respect_limits: false,
        ..*options
    };
    // Each step's solution is near the one before: Newton steps from it,
    // the damped solver where they do not converge; where several
    // configurations meet the target (a point for six joints), the damped
    // solver's, whose moves stay near the start.
    let redundant = path.calibrated.joint_count() > target.rows();
    let solve = |t: f64, start: &[f64]| -> Result<_, Error> {
        let built;
        let solver = match path.station(t) {
            Some((robot, model)) => InverseSolver::bound(robot, model)?,
            None => {
                built = path.robot_at(t)?;
                InverseSolver::new(&built)
            }
        };
        Ok(if redundant {
            solver.solve(target, start, &unlimited)
        } else {
            solver.solve_near(target, start, &unlimited)
        })
    };
    let mut current = start_motor_positions.to_vec();
    let mut reached = 0.0;
    let mut step = LONGEST_STEP;
    let mut failures = 0;
    let mut last = None;
    while reached < 1.0 {
        let next = (reached + step).min(1.0);
        match solve(next, &current)? {
            Ok(solution) => {
                current.clone_from(&solution.motor_positions);
                reached = next;
                last = Some(solution);
                // A step that went through may grow again.
                step = (step * 2.0).min(LONGEST_STEP);
            }
            Err(gecaro_core::Error::Unreachable { .. }) => {
                failures += 1;
                step /= 2.0;
                if step < SHORTEST_STEP || failures > MAX_FAILED_STEPS {
                    return Ok(None);
                }
            }
            Err(other) => return Err(other.into()),
        }
    }
    Ok(last)
}

/// Of the solutions found from starts around `start_motor_positions`
/// ([`SPREADS`], seeded by `seed`) on `robot` (compiled as `model`), the
/// one closest to it (largest joint difference) of those `preferred`
/// says yes to, else of all; `None` when no start reaches the target. A
/// start heading for a minimum short of the target that an earlier one
/// settled at is given up on the way ([`KNOWN_MINIMUM_RADIUS`]).
///
/// # Errors
/// Configuration errors of the robot.
pub(crate) fn closest_from_nearby_starts(
    solver: &InverseSolver<'_>,
    target: &Target,
    start_motor_positions: &[f64],
    options: &InverseOptions,
    preferred: &dyn Fn(&InverseSolution) -> bool,
    seed: u64,
) -> Result<Option<InverseSolution>, Error> {
    let mut sampler = Sampler::new(seed);
    // Preferred first, then the closest.
    let rank = |solution: &InverseSolution| {
        let distance = solution
            .motor_positions
            .iter()
            .zip(start_motor_positions)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        (!preferred(solution), distance)
    };
    let mut best: Option<(InverseSolution, (bool, f64))> = None;
    let mut known = KnownMinima::new(KNOWN_MINIMUM_RADIUS);
    for spread in SPREADS {
        for _ in 0..STARTS_PER_SPREAD {
            let start: Vec<f64> = start_motor_positions
                .iter()
                .map(|value| value + sampler.gaussian(spread))
                .collect();
            match solver.solve_avoiding(target, &start, options, &mut known) {
                Ok(solution) => {
                    let ranked = rank(&solution);
                    if best.as_ref().is_none_or(|(_, kept)| ranked < *kept) {
                        best = Some((solution, ranked));
                    }
                }
                Err(gecaro_core::Error::Unreachable { .. }) => {}
                Err(other) => return Err(other.into()),
            }
        }
        // The nearest spread that finds a solution keeps the branch best.
        if best.is_some() {
            break;
        }
    }
    Ok(best.map(|(solution, _)| solution))
}

#[cfg(test)]
mod tests {
    use gecaro_core::{Frame, FrameType, Joint, RobotSpec, terminal_pose};

    use super::*;

    /// A planar arm of two revolute joints (links 0.5 and 0.4 m): each point
    /// of its annulus has two solutions, elbow one way and the other.
    fn planar_arm() -> Robot {
        let frame = |frame_type, d| Frame {
            d,
            ..Frame::new(frame_type)
        };
        Robot::new(RobotSpec {
            name: "planar".into(),
            frames: vec![
                frame(FrameType::Fixed, 0.0),
                frame(FrameType::Revolute, 0.0),
                frame(FrameType::Revolute, 0.5),
                frame(FrameType::Fixed, 0.4),
            ],
            joints: vec![Joint::default_for(FrameType::Revolute); 2],
            motor_coupling: None,
            joint_coupling: None,
            priority: None,
            compliances: None,
        })
        .expect("valid")
    }

    /// From the arm nearly stretched, the nearest starts find both
    /// solutions: without a preference the closer one is taken (elbow up,
    /// 1.15 rad away), with one the solution it prefers (elbow down, 1.25
    /// rad away).
    #[test]
    fn a_preferred_solution_comes_before_a_closer_one() {
        let robot = planar_arm();
        let solver = InverseSolver::new(&robot);
        let elbow_up = [0.3, 1.2];
        let pose = terminal_pose(&robot, &elbow_up).expect("pose");
        let target = Target::Position(pose.translation.vector);
        let options = InverseOptions::default();
        let start = [0.35, 0.05];
        let any = |_: &InverseSolution| true;
        let elbow_down = |solution: &InverseSolution| solution.joint_positions[1] < 0.0;
        let closest = closest_from_nearby_starts(&solver, &target, &start, &options, &any, 5)
            .expect("runs")
            .expect("reached");
        assert!(
            (closest.joint_positions[1] - 1.2).abs() < 1e-9,
            "{closest:?}"
        );
        let preferred =
            closest_from_nearby_starts(&solver, &target, &start, &options, &elbow_down, 5)
                .expect("runs")
                .expect("reached");
        assert!(
            (preferred.joint_positions[1] + 1.2).abs() < 1e-9,
            "{preferred:?}"
        );
    }
}
