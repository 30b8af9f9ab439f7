//! The prior's pseudo-observation rows of a pass (see
//! [`super::weighting::PriorRow`]): a user's prior on the base set, and the
//! weak prior that holds the second pass's added parameters.

use gecaro_core::Robot;

use super::solver::Problem;
use super::weighting::PriorRow;
use crate::identifiability::Relation;
use crate::prior::Prior;

/// The prior's rows for the base parameters of `problem` (weights set by the
/// reweighted phase), with the regrouped priors of [`Prior::base_sigma`].
pub(super) fn prior_rows(
    prior: &Prior,
    robot: &Robot,
    problem: &Problem<'_>,
    relations: &[Relation],
) -> Vec<PriorRow> {
    let offset = problem.base_auxiliary.len();
    problem
        .base
        .iter()
        .enumerate()
        .map(|(position, &index)| PriorRow {
            column: offset + position,
            sigma: prior.base_sigma(robot, robot.parameters().id(index), relations),
            index,
            weight: 0.0,
        })
        .collect()
}

/// Prior rows for the second pass's added parameters (`extras`, vocabulary
/// indices) that the data excite, centred on the pass's start.
pub(super) fn extra_prior_rows(
    prior: &Prior,
    problem: &Problem<'_>,
    extras: &[usize],
) -> Vec<PriorRow> {
    let offset = problem.base_auxiliary.len();
    extras
        .iter()
        .filter_map(|index| {
            let position = problem.base.iter().position(|base| base == index)?;
            let id = problem.nominal.parameters().id(*index);
            Some(PriorRow {
                column: offset + position,
                sigma: prior.sigma(id, problem.nominal.parameter(id)),
                index: *index,
                weight: 0.0,
            })
        })
        .collect()
}
