//! The routes to a pass's solution (see the parent module docs): the
//! paper's plain steps, the minimum-norm route when they do not converge,
//! and Levenberg–Marquardt from the start when neither does.

use super::options::Solver;
use super::result::Route;
use super::solver::{Damping, Iterate, Problem, Run};
use super::verdict::StopReason;
use crate::Error;
use crate::identifiability::{ParameterStatus, RankReport};
use crate::progress::{IterationRecord, Observer, Progress, report};
use crate::study::StudyStates;

/// The descent from `start` by the options' solver: the paper's plain steps,
/// the minimum-norm route when they do not converge, and Levenberg–Marquardt
/// from the start when neither does (module docs); the converged run, else
/// the one with the lowest cost.
pub(super) fn descend(
    problem: &Problem<'_>,
    start: Iterate,
    rank: &RankReport,
    initial_auxiliary: &[f64],
    first: &IterationRecord,
    states: &mut StudyStates,
    observer: &mut dyn Observer,
) -> Result<(Run, Route), Error> {
    let options = problem.options;
    if options.solver == Solver::LevenbergMarquardt {
        let run = levenberg_marquardt(problem, start, states, observer)?;
        return Ok((run, Route::LevenbergMarquardt));
    }
    // The start's parameters (its system, megabytes for large data, is
    // written again only if the last resort needs it).
    let (start_robot, start_auxiliary) = (start.robot.clone(), start.auxiliary.clone());
    let plain = problem.descend(
        start,
        Damping::Never,
        options.max_iterations,
        states,
        observer,
    )?;
    if plain.stop == StopReason::Converged {
        return Ok((plain, Route::GaussNewton));
    }
    let effective: Vec<usize> = rank
        .parameters
        .iter()
        .enumerate()
        .filter(|(_, p)| {
            matches!(
                p.status,
                ParameterStatus::Identifiable | ParameterStatus::Regrouped
            )
        })
        .map(|(index, _)| index)
        .collect();
    report(observer, Progress::Iteration(first))?;
    let robust = problem.minimum_norm_route(
        (problem.nominal, initial_auxiliary),
        &effective,
        states,
        observer,
    )?;
    if robust.stop == StopReason::Converged {
        return Ok((robust, Route::MinimumNorm));
    }
    // Neither converged: Levenberg–Marquardt from the start, the damping
    // holding the steps where the linearisation does not (a far start).
    report(observer, Progress::Iteration(first))?;
    let start = problem.assemble(&start_robot, &start_auxiliary, &problem.layout, states)?;
    let damped = levenberg_marquardt(problem, start, states, observer)?;
    if damped.stop == StopReason::Converged {
        return Ok((damped, Route::LevenbergMarquardt));
    }
    // None converged: the lowest cost, named by its own stop.
    let lowest = |a: (Run, Route), b: (Run, Route)| {
        if b.0.best.cost < a.0.best.cost { b } else { a }
    };
    Ok(lowest(
        lowest((plain, Route::GaussNewton), (robust, Route::MinimumNorm)),
        (damped, Route::LevenbergMarquardt),
    ))
}

/// Levenberg–Marquardt on the base set from `start`, up to the options'
/// iteration limit.
fn levenberg_marquardt(
    problem: &Problem<'_>,
    start: Iterate,
    states: &mut StudyStates,
    observer: &mut dyn Observer,
) -> Result<Run, Error> {
    problem.descend(
        start,
        Damping::Always,
        problem.options.max_iterations,
        states,
        observer,
    )
}
