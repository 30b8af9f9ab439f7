//! A coarse start for large data: the first pass's first iterations on a
//! spread subsample.
//!
//! Far from the solution a Gauss–Newton step needs few observations: its
//! error is the linearisation's, centimetres at the nominal robot, beside
//! which the noise of a subsample's estimate (σ/√m) is nothing. A million
//! tracker points give the same first steps as twenty thousand of them, at
//! fifty times the cost. So a study of more than
//! [`IdentificationOptions::coarse_from`] configurations first runs the
//! plain descent of the pass (the same base set, structural at the pass's
//! robot, on the units the subsample excites) on a subsample of a fifth as
//! many units ([`spread_subsample`]: spread over the sets and over each set,
//! drawn at random in equal stretches so that no cycle of the data aligns
//! with them). Its solution is within the subsample's noise of the whole
//! data's, where the linearisation is exact to far below it; the pass then
//! starts there on all the data, and its last iterations, its stopping test,
//! its statistics and its verdict are all the data's, as they were. Only
//! base parameters move, so the pass ends at the solution it reaches from
//! its own robot, to its stopping tolerance.
//!
//! It takes two evaluations of every configuration with its Jacobian
//! instead of four at 10⁶ tracker points (Stanford, position, errors of a
//! centimetre and a degree), and one of the residuals alone at the robot
//! the pass starts from, for its errors before. A subsample whose descent
//! does not converge by plain steps is no start: the pass starts from its
//! robot as without one.

use gecaro_core::Robot;

use super::options::{IdentificationOptions, Solver};
use super::solver::{Damping, Problem};
use super::subsample::spread_subsample;
use super::verdict::StopReason;
use crate::Error;
use crate::identifiability::RankReport;
use crate::progress::Quiet;
use crate::study::{Study, StudyStates};

/// The subsample of a coarse start holds this fraction of the
/// [`IdentificationOptions::coarse_from`] configurations that call for one.
pub const COARSE_FRACTION: usize = 5;

/// Where a coarse start put the robot, and what it read.
#[derive(Clone, Debug)]
pub(super) struct CoarseStart {
    /// The robot at the subsample's solution (only base parameters moved).
    pub(super) robot: Robot,
    /// Configurations of the subsample.
    pub(super) configurations: usize,
    /// Configurations of the whole study.
    pub(super) of: usize,
}

impl CoarseStart {
    /// The note on the identification that says what iteration 1 is.
    pub(super) fn note(&self) -> String {
        format!(
            "large data: the first iterations read a spread subsample of {} of the {} \
             configurations and the descent on all of them started at its solution (iteration \
             1); every later iteration, the precision and the verdict read all the data",
            self.configurations, self.of
        )
    }
}

/// The coarse start of a pass of `robot` on `study` with the structural base
/// set `rank` (see the module docs), or `None` when the study is not large
/// enough for one or its subsample's descent does not converge.
///
/// # Errors
/// A configuration that does not fit the robot, or auxiliary unknowns the
/// subsample cannot initialise. A subsample that excites nothing or has
/// too few equations gives no start rather than an error.
pub(super) fn coarse_start(
    robot: &Robot,
    study: &Study,
    options: &IdentificationOptions,
    rank: &RankReport,
) -> Result<Option<CoarseStart>, Error> {
    let of: usize = study.sets.iter().map(|set| set.samples.len()).sum();
    if of <= options.coarse_from {
        return Ok(None);
    }
    let subsample = spread_subsample(study, &[], options.coarse_from / COARSE_FRACTION);
    let subsample: &Study = &subsample;
    let configurations = subsample.sets.iter().map(|set| set.samples.len()).sum();
    let mut states = StudyStates::default();
    subsample.evaluate_poses(robot, &mut states)?;
    let auxiliary = subsample.initial_auxiliary(&states)?;
    let Ok((problem, _, start)) = Problem::excited(
        robot,
        subsample,
        options,
        rank,
        (robot, &auxiliary),
        &mut states,
    ) else {
        return Ok(None);
    };
    let damping = match options.solver {
        Solver::GaussNewton => Damping::Never,
        Solver::LevenbergMarquardt => Damping::Always,
    };
    let run = problem.descend(
        start,
        damping,
        options.max_iterations,
        &mut states,
        &mut Quiet,
    )?;
    Ok((run.stop == StopReason::Converged).then_some(CoarseStart {
        robot: run.best.robot,
        configurations,
        of,
    }))
}
