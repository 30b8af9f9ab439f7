//! The identification at the end of its reweighted phase, summarised
//! (paper §4): the identified parameters with their precision (eq. 11),
//! the errors before and after, outliers, the warnings and the verdict's
//! evidence.

use super::{curvature, disagreement, gauge, outliers, plausibility, repeatability, tested, tied};

use gecaro_core::Robot;

use crate::Error;
use crate::frames::FRAME_UNKNOWNS;
use crate::identifiability::{Excitation, RankReport};
use crate::linalg::{LeastSquaresRows, NormalEquations, precision, sandwich_diagonal};

use super::coverage::{Coverage, UnobservedScale};
use super::parameter::IdentifiedParameter;
use super::repeatability::PoseGroups;
use super::repeats::Repeats;
use super::result::{ErrorSummary, Identification, Route};
use super::reweighting::Reweighted;
use super::solver::{Problem, Run};
use super::verdict::Evidence;
use super::verdict::Verdict;
use super::warnings::Warning;
use super::warnings::{correlation_warning, strongly_correlated, warnings_of};
use super::weighting::second_pass_prior;

use crate::observation::ObservationErrors;
use crate::progress::IterationRecord;

/// The state at the nominal robot, before any step.
pub(super) struct Begun {
    /// The starting point of the history.
    pub(super) first: IterationRecord,
    pub(super) before: ErrorSummary,
    pub(super) errors_before: ObservationErrors,
}

/// The identification at the end of the reweighted phase (reached by
/// `route`, with the data's `repeats` and its repeated poses): parameters
/// with their precision, errors, outliers and warnings.
pub(super) fn summarise(
    problem: &Problem<'_>,
    nominal: &Robot,
    begun: Begun,
    (reweighted, route, scale, (repeats, repeated_poses)): (
        Reweighted,
        Route,
        Option<UnobservedScale>,
        (Repeats, PoseGroups),
    ),
    rank: RankReport,
    excited: Excitation,
    initial_auxiliary: &[f64],
) -> Result<Identification, Error> {
    let Reweighted {
        run: Run {
            mut best,
            history: updates,
            stop,
        },
        weighting,
        statistics,
        reweightings,
    } = reweighted;
    // Whole turns are the same robot: every angle within ±π of its nominal
    // value (a joint zero 90° off was written 2250° off, the long way round).
    best.robot.wrap_angles_near(nominal);
    let (robot, study, options) = (nominal, problem.study, problem.options);
    let prior_std = |column: usize| {
        weighting
            .prior_rows
            .iter()
            .find(|row| row.column == column)
            .map(|row| row.sigma)
    };
    let mut history = vec![begun.first];
    history.extend(updates);
    let columns = problem.layout.columns();
    // The errors after the fit, its outliers and the test of its residuals
    // on another core, while this one takes the precision and what is read
    // from it (each about a tenth of a millisecond at 5,000 configurations).
    let (fitted, estimated) = crate::parallel::beside_if_free(
        || fit_errors(study, &best.system, &statistics, options, columns),
        || -> Result<_, Error> {
            // Precision at the solution: σ² (W_bᵀ W_b)⁻¹, and the condition
            // number of W_b (of the data's rows: prior rows would hide a
            // poor excitation).
            let system = &best.system;
            let all_rows = system.solver_rows(false);
            let (solved, mut condition_number) =
                precision(all_rows.matrix(), &best.normal, problem.condition)?;
            drop(all_rows);
            // The residuals' curvature, where G is nearly singular ([`curvature`]).
            let hessian = curvature::newton_hessian(problem, &weighting, &best)?;
            // The data's rows (or their stand-in, for a folded system).
            let data_rows = (hessian.is_some() || system.rows() > system.measured_rows())
                .then(|| system.solver_rows(true));
            if let Some(data_rows) = data_rows
                .as_ref()
                .filter(|_| !weighting.prior_rows.is_empty())
            {
                // The data's rows over the columns the data must determine (the
                // joined ones last, held by their prior).
                let data = data_rows.matrix().subcols(0, columns - problem.joined);
                let normal = NormalEquations::of(data, data_rows.right());
                condition_number = precision(data, &normal, problem.condition)?.1;
            }
            // σ² = Σ w e²/(n_eff − b): ‖r‖²/(equations − b) in least squares.
            let variance = statistics.variance;
            let std = |column: usize| (variance * solved.inverse_normal_diagonal[column]).sqrt();
            // The noise's part of it, where a prior's rows (or the gauge that holds
            // an unmeasured scale) hold a parameter: σ² diag(G⁻¹ DᵀD G⁻¹), D the
            // measured rows; with H for G where the curvature matters.
            let data_part = data_rows.as_ref().and_then(|data_rows| match &hessian {
                Some(hessian) => sandwich_diagonal(hessian, data_rows.matrix()),
                None => best.normal.data_part_diagonal(data_rows.matrix()),
            });
            let noise_std = |column: usize| {
                let part = data_part
                    .as_ref()
                    .map_or(solved.inverse_normal_diagonal[column], |diagonal| {
                        diagonal[column]
                    });
                (variance * part).sqrt()
            };
            let auxiliary_names = study.auxiliary_names();
            let relations = rank.relations();
            // The parameters joined to the structural base set ([`tied`]), the last
            // columns: what a base parameter stands for leaves them out, since they
            // are estimated beside it.
            let joined: Vec<String> = problem.base[problem.base.len() - problem.joined..]
                .iter()
                .map(|index| robot.parameters().id(*index).to_string())
                .collect();
            let absorbed = |name: &str| -> Vec<(String, f64)> {
                relations
                    .iter()
                    .find(|relation| relation.base == name)
                    .map(|relation| {
                        let mut absorbed = relation.absorbed.clone();
                        absorbed.retain(|(other, _)| !joined.contains(other));
                        absorbed
                    })
                    .unwrap_or_default()
            };
            let auxiliary_columns = problem.base_auxiliary.len();
            let auxiliary: Vec<IdentifiedParameter> = problem
                .base_auxiliary
                .iter()
                .enumerate()
                .map(|(column, &index)| IdentifiedParameter {
                    name: auxiliary_names[index].clone(),
                    parameter: None,
                    nominal: initial_auxiliary[index],
                    identified: best.auxiliary[index],
                    std: std(column),
                    noise_std: noise_std(column),
                    prior_std: None,
                    absorbs: absorbed(&auxiliary_names[index]),
                })
                .collect();
            let parameters: Vec<IdentifiedParameter> = problem
                .base
                .iter()
                .enumerate()
                .map(|(position, &index)| {
                    let id = robot.parameters().id(index);
                    IdentifiedParameter {
                        name: id.to_string(),
                        parameter: Some(id),
                        nominal: robot.parameter(id),
                        identified: best.robot.parameter(id),
                        std: std(auxiliary_columns + position),
                        noise_std: noise_std(auxiliary_columns + position),
                        prior_std: prior_std(auxiliary_columns + position),
                        absorbs: absorbed(&id.to_string()),
                    }
                })
                .collect();
            // A scale the data do not measure is uncertain to its own σ: every
            // length carries it (the σ of the data hold it at one length).
            let mut parameters = parameters;
            if let Some(relative) = scale.map(|scale| scale.std).filter(|std| std.is_finite()) {
                for p in &mut parameters {
                    if p.parameter.is_some_and(|id| gauge::scales(robot, id)) {
                        p.std = p.std.hypot(p.identified * relative);
                    }
                }
            }
            let moved = moved_outside_base(robot, &best.robot, &problem.base);
            let names: Vec<&str> = auxiliary
                .iter()
                .chain(&parameters)
                .map(|p| p.name.as_str())
                .collect();
            let correlated = strongly_correlated(&best.normal, &names);
            let mut warnings: Vec<Warning> = rank
                .set_up_warnings(robot)
                .into_iter()
                .map(Warning::SetUp)
                .collect();
            warnings.extend(correlation_warning(&correlated));
            warnings.extend(warnings_of(
                &excited.not_excited,
                condition_number,
                &parameters,
                &moved,
            ));
            Ok(Estimates {
                condition_number,
                variance,
                joined,
                auxiliary,
                parameters,
                moved,
                correlated,
                warnings,
            })
        },
    );
    let Estimates {
        condition_number,
        variance,
        joined,
        auxiliary,
        parameters,
        moved,
        correlated,
        mut warnings,
    } = estimated?;
    let FitErrors {
        errors_after,
        outliers,
        data_cost,
        degrees_of_freedom,
        tested,
    } = fitted;
    warnings.extend(
        tested::loss_scale_warning(&options.loss, &statistics.weights).map(Warning::LossScale),
    );
    // The posterior covariance of the unknowns (eq. 11: σ² (W_bᵀW_b)⁻¹,
    // with the prior's rows), for predictions away from the data; σ² of the
    // residuals as measured (with a robust loss, the loss-weighted sum
    // keeps part of every gross error).
    let tested_variance = tested.cost / tested.freedom.max(1) as f64;
    let covariance = best
        .normal
        .inverse()
        .map(|inverse| inverse * tested_variance);
    let implausible = plausibility::implausible(&plausibility::Written {
        nominal: robot,
        calibrated: &best.robot,
        parameters: &parameters,
        moved: &moved,
        prior: options.prior.as_ref(),
        expansion: options.prior.as_ref().unwrap_or(&second_pass_prior()),
    });
    if let Some(scale) = scale.filter(|scale| scale.std.is_finite()) {
        warnings.push(Warning::ScaleNotMeasured {
            base_set_scale: scale.base_set_scale,
            std: scale.std,
        });
    }
    let coverage = Coverage::of(
        robot,
        study,
        &rank,
        &excited.not_excited,
        columns - problem.joined,
        scale,
    );
    if !coverage.base_observed {
        warnings.push(Warning::BaseNotObserved);
    }
    let verdict = Verdict::of(
        study,
        Evidence {
            stop,
            iterations: history.len() - 1,
            system: &best.system,
            observation_weights: &tested.weights,
            data_cost: tested.cost,
            degrees_of_freedom: tested.freedom,
            unknowns: columns - problem.joined,
            repeatability: repeatability::repeatability(
                &repeated_poses,
                &best.system,
                tested.cost,
                tested.freedom,
            ),
            sets: if study.sets.len() > 1 {
                disagreement::set_fits(study, &best.system, tested.freedom)
            } else {
                Vec::new()
            },
            implausible,
            coverage,
            repeats,
        },
    );
    Ok(Identification {
        correlated,
        covariance,
        verdict,
        second_pass: Vec::new(),
        joined,
        data_cost,
        degrees_of_freedom,
        loss: options.loss,
        prior: options.prior.clone(),
        reweightings,
        robust_sigma: statistics.robust_sigma,
        observation_weights: statistics.weights,
        standardized: statistics.standardized,
        outlier_threshold: options.outlier_threshold,
        outliers,
        rejected: Vec::new(),
        excitation: excited.report,
        moved,
        warnings,
        condition_number,
        after: ErrorSummary::of_errors(&errors_after),
        errors_after,
        errors_before: begun.errors_before,
        before: begun.before,
        calibrated: best.robot,
        rank,
        history,
        route,
        parameters,
        auxiliary,
        frames: study
            .frames
            .iter()
            .enumerate()
            .map(|(index, frame)| {
                let first = index * FRAME_UNKNOWNS;
                frame.at(&best.auxiliary[first..first + FRAME_UNKNOWNS])
            })
            .collect(),
        residual_sigma: variance.sqrt(),
        stop_reason: stop,
        not_excited: excited.not_excited,
    })
}

/// The unknowns at the solution with their precision, and what the normal
/// equations say of them: [`summarise`]'s part beside [`fit_errors`].
struct Estimates {
    /// The condition number of W_b (of the data's rows).
    condition_number: f64,
    /// σ² of the residuals as the loss weighed them.
    variance: f64,
    /// The parameters joined to the structural base set ([`tied`]).
    joined: Vec<String>,
    /// The auxiliary unknowns (frames, the method's own).
    auxiliary: Vec<IdentifiedParameter>,
    /// The base parameters.
    parameters: Vec<IdentifiedParameter>,
    /// Parameters outside the base set that moved.
    moved: Vec<IdentifiedParameter>,
    /// The strongly correlated pairs.
    correlated: Vec<(String, String, f64)>,
    /// The warnings of the set-up, the correlations and the excitation.
    warnings: Vec<Warning>,
}

/// What the residuals at the solution say ([`fit_errors`]).
struct FitErrors {
    /// Each observation's error.
    errors_after: ObservationErrors,
    /// The observations beyond the outlier threshold.
    outliers: Vec<outliers::Outlier>,
    /// The data's residual sum of squares (prior rows excluded).
    data_cost: f64,
    /// Effective equations less unknowns.
    degrees_of_freedom: usize,
    /// The residuals as measured, tested against the stated noise.
    tested: tested::Tested,
}

/// The errors of `system` (the solution's, of `study`, with `columns`
/// unknowns), its outliers and the test of its residuals as measured (not
/// as the loss weighed them).
fn fit_errors(
    study: &crate::study::Study,
    system: &crate::observation::ObservationSystem,
    statistics: &super::statistics::ResidualStatistics,
    options: &super::options::IdentificationOptions,
    columns: usize,
) -> FitErrors {
    let errors_after = system.observation_errors();
    let outliers =
        outliers::find_outliers(study, statistics, &errors_after, options.outlier_threshold);
    let data_cost = system.measured_cost();
    let degrees_of_freedom = statistics.effective_equations.saturating_sub(columns);
    let tested = tested::tested(
        system,
        statistics,
        &options.loss,
        options.outlier_threshold,
        (study.equation_count(), columns),
        (data_cost, degrees_of_freedom),
    );
    FitErrors {
        errors_after,
        outliers,
        data_cost,
        degrees_of_freedom,
        tested,
    }
}

/// The parameters outside the base set (`base`: vocabulary indices) that
/// differ between `nominal` and `identified` (see [`Identification::moved`]).
fn moved_outside_base(
    nominal: &Robot,
    identified: &Robot,
    base: &[usize],
) -> Vec<IdentifiedParameter> {
    tied::moved_outside(nominal, identified, base)
        .map(|index| nominal.parameters().id(index))
        .map(|id| IdentifiedParameter {
            name: id.to_string(),
            parameter: Some(id),
            nominal: nominal.parameter(id),
            identified: identified.parameter(id),
            std: f64::NAN,
            noise_std: f64::NAN,
            prior_std: None,
            absorbs: Vec::new(),
        })
        .collect()
}
