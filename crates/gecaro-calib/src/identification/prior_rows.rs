//! The prior's pseudo-observation rows of a pass (see
//! [`super::weighting::PriorRow`]): a user's prior on the base set, and the
//! weak prior that holds the second pass's added parameters.

use gecaro_core::Robot;

use super::solver::Problem;
use super::weighting::{PriorRow, second_pass_prior};
use crate::identifiability::Relation;
use crate::prior::Prior;

/// The prior's rows for the base parameters of `problem` (weights set by the
/// reweighted phase), with the regrouped priors of [`crate::prior::base_sigma`].
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
            centre: robot.parameter(robot.parameters().id(index)),
            sigma: crate::prior::base_sigma(prior, robot, robot.parameters().id(index), relations),
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
                centre: problem.nominal.parameter(id),
                sigma: prior.sigma(id, problem.nominal.parameter(id)),
                index: *index,
                weight: 0.0,
            })
        })
        .collect()
}

/// Rows of the second pass's weak prior ([`second_pass_prior`], centred on
/// their values in `nominal`) for `parameters` (vocabulary indices) in the
/// columns from `first_column` on, weighted for data of standard deviation
/// `data_sigma` (the damped descent's parameters, the joined ones).
pub(super) fn weak_prior_rows(
    nominal: &Robot,
    parameters: &[usize],
    first_column: usize,
    data_sigma: f64,
) -> Vec<PriorRow> {
    let prior = second_pass_prior();
    parameters
        .iter()
        .enumerate()
        .map(|(position, &index)| {
            let id = nominal.parameters().id(index);
            let sigma = prior.sigma(id, nominal.parameter(id));
            PriorRow {
                column: first_column + position,
                centre: nominal.parameter(id),
                sigma,
                index,
                weight: data_sigma / sigma,
            }
        })
        .collect()
}
