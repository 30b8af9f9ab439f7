//! Parameters outside the base set that the data set, joined to it.
//!
//! A base parameter stands for a combination `Δη_b + Σ β_j Δη_j` of the
//! parameters it absorbs (Appendix III), the `η_j` held where the pass
//! found them. Most stay nominal; but the closed-form start re-frames the
//! tool and the base from the data (a Hayati β7 of a flange parallel to
//! axis 6, a tool point's d7), and the continuation and the damped descent
//! leave parameters where an exact solution still exists
//! ([`super::Identification::moved`]). Such a moved value came from the data
//! and moves with their noise, with coefficients β of hundreds or
//! thousands: the written base parameter then moves with it, and
//! `σ²(W_bᵀW_b)⁻¹`, which holds it fixed, is the spread of neither the
//! written value nor its combination (from 0.01 to 82 times it).
//!
//! So after a pass, the moved parameters that a base parameter absorbs join
//! the base set: a few Gauss–Newton steps from the pass's solution over
//! both, the joined ones held by the weak prior of the second pass
//! ([`super::SECOND_PASS_PRIOR`], centred on their nominal values) where the
//! data barely determine them. The written robot is then the joint
//! estimate, a function of the data alone (not of the route's path), and
//! its precision the usual one with the prior's rows: `σ` the posterior,
//! the noise σ the spread under repeated measurement. It is kept when it
//! converges and explains the data as well (the data's sum of squares
//! within [`COST_SLACK`] of the pass's); otherwise the pass stands as it was.

use gecaro_core::Robot;

use super::prior_rows::weak_prior_rows;
use super::reweighting::Reweighted;
use super::solver::{Damping, Problem, Run};
use super::statistics::ResidualStatistics;
use super::verdict::StopReason;
use crate::Error;
use crate::identifiability::RankReport;
use crate::progress::Quiet;
use crate::rows::ColumnLayout;
use crate::study::StudyStates;

/// Iterations allowed to the joint steps (one or two from a converged pass).
const JOINT_ITERATIONS: usize = 10;

/// How much the data's sum of squares may grow when the joined parameters
/// are pulled towards their prior (relative).
const COST_SLACK: f64 = 1e-3;

/// A parameter differs from its nominal value by more than rounding.
const MOVED_TOLERANCE: f64 = 1e-12;

/// The parameters (vocabulary indices) outside `base` that `robot` moved
/// away from `nominal`.
pub(super) fn moved_outside<'a>(
    nominal: &'a Robot,
    robot: &'a Robot,
    base: &'a [usize],
) -> impl Iterator<Item = usize> + 'a {
    nominal
        .parameters()
        .ids()
        .iter()
        .enumerate()
        .filter(move |(index, id)| {
            !base.contains(index)
                && (robot.parameter(**id) - nominal.parameter(**id)).abs() > MOVED_TOLERANCE
        })
        .map(|(index, _)| index)
}

/// The moved parameters (vocabulary indices) that a base parameter of
/// `rank` absorbs: outside `base`, away from `nominal` at `robot`.
fn tied_to_base(nominal: &Robot, robot: &Robot, base: &[usize], rank: &RankReport) -> Vec<usize> {
    let absorbed = |index: &usize| {
        let name = nominal.parameters().id(*index).to_string();
        rank.relations()
            .iter()
            .any(|relation| relation.absorbed.iter().any(|(other, _)| *other == name))
    };
    moved_outside(nominal, robot, base)
        .filter(absorbed)
        .collect()
}

/// The pass `problem` reached `reweighted` on (its values reported against
/// `nominal`), with the tied moved parameters joined (module docs): the
/// joint problem and its solution ([`Problem::joined`] counts the joined
/// columns, the last ones), or the pass as it was when nothing is tied or
/// the joint estimate is not kept.
///
/// # Errors
/// Errors of the model at the pass's solution (which it evaluated before).
pub(super) fn joined<'a>(
    problem: Problem<'a>,
    nominal: &Robot,
    rank: &RankReport,
    reweighted: Reweighted,
    states: &mut StudyStates,
) -> Result<(Problem<'a>, Reweighted), Error> {
    let best = &reweighted.run.best;
    let tied = tied_to_base(nominal, &best.robot, &problem.base, rank);
    if tied.is_empty() {
        return Ok((problem, reweighted));
    }
    let mut base = problem.base.clone();
    base.extend(&tied);
    let layout = ColumnLayout::with_auxiliary(
        nominal.parameters().len(),
        &base,
        best.auxiliary.len(),
        &problem.base_auxiliary,
    );
    let offset = problem.base_auxiliary.len() + problem.base.len();
    let mut weighting = reweighted.weighting.clone();
    weighting.prior_rows.extend(weak_prior_rows(
        nominal,
        &tied,
        offset,
        reweighted.statistics.variance.sqrt(),
    ));
    let joint = Problem {
        base,
        layout,
        joined: tied.len(),
        ..problem.with_weighting(weighting)
    };
    let start = joint.assemble(&best.robot, &best.auxiliary, &joint.layout, states)?;
    let run = joint.descend(
        start,
        Damping::WhenNeeded,
        JOINT_ITERATIONS,
        states,
        &mut Quiet,
    )?;
    if run.stop != StopReason::Converged
        || run.best.system.measured_cost() > best.system.measured_cost() * (1.0 + COST_SLACK)
    {
        return Ok((problem, reweighted));
    }
    let statistics = ResidualStatistics::of(
        &run.best.system,
        &problem.options.loss,
        problem.study.equation_count(),
        joint.layout.columns(),
    );
    let Reweighted {
        run: pass,
        reweightings,
        ..
    } = reweighted;
    let mut history = pass.history;
    history.extend(run.history);
    let weighting = joint.weighting.clone();
    Ok((
        joint,
        Reweighted {
            run: Run {
                best: run.best,
                history,
                stop: pass.stop,
            },
            weighting,
            statistics,
            reweightings,
        },
    ))
}
