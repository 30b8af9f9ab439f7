//! One pass of an identification (paper §4): the base set at its start
//! (structural, then what the data excite), the problem on it, the descent
//! and the reweighted phase, an elastic robot's loads followed, and the
//! summary.

use super::{branch, coarse, hayati, loads, repeatability, repeats, scale, statistics, tied};

use gecaro_core::Robot;

use crate::Error;
use crate::identifiability::{Excitation, RankReport, structural_parameters_at};
use crate::progress::{Observer, Progress, report};
use crate::study::{Study, StudyStates};

use super::evaluation::errors_at;
use super::options::IdentificationOptions;
use super::passes::significantly_lower;
use super::prior_rows::{extra_prior_rows, prior_rows};
use super::result::{ErrorSummary, Identification, Route};
use super::routes::descend;
use super::solver::{Iterate, Problem};
use super::summary::{Begun, summarise};
use super::warnings::Warning;
use super::warnings::correlation_warning;
use super::weighting::{Weighting, second_pass_prior};

use crate::progress::IterationRecord;
use crate::robust::Loss;

/// Seed of the random data of the structural analysis: fixed, so that an
/// identification is a pure function of its inputs.
pub(super) const STRUCTURAL_SEED: u64 = 0x6ECA20;

/// A pass's identification, and what the passes after it need.
pub(super) struct Passed {
    pub(super) result: Identification,
    /// The data's sum of squares at the pass's solution with the loads it
    /// was given, before they followed it ([`loads`]): what an F test
    /// against the pass before, with the same loads, reads.
    pub(super) given_loads_cost: f64,
    /// The study with an elastic robot's loads at the pass's solution,
    /// when they moved.
    pub(super) loaded: Option<Study>,
}

impl Passed {
    /// Whether this pass (with `added` more unknowns) explains the data
    /// significantly better than `before` ([`significantly_lower`]), both
    /// with the loads this pass was given.
    pub(super) fn better_than(&self, before: &Identification, added: usize) -> bool {
        significantly_lower(
            before.data_cost,
            self.given_loads_cost,
            added,
            self.result.degrees_of_freedom,
        )
    }
}

/// The Euclidean norm of the change of every parameter from `from` to `to`
/// (the step of an iteration that jumps to a start).
pub(super) fn parameter_change(from: &Robot, to: &Robot) -> f64 {
    from.parameters()
        .ids()
        .iter()
        .map(|id| (to.parameter(*id) - from.parameter(*id)).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// One pass of an identification of `study`: the base set at `start` and
/// the start, the descent, then the reweighted phase, an elastic robot's
/// loads followed ([`loads`]), and the summary (values reported against
/// `nominal`). `extras` (vocabulary indices) are the second pass's added
/// parameters, held by [`second_pass_prior`].
pub(super) fn fit_pass(
    nominal: &Robot,
    start: &Robot,
    study: &Study,
    options: &IdentificationOptions,
    priority: &gecaro_core::PriorityMatrix,
    extras: &[usize],
    observer: &mut dyn Observer,
) -> Result<Passed, Error> {
    let Setup {
        problem,
        rank,
        excited,
        initial_auxiliary,
        mut states,
        start,
        coarse,
        begun,
    } = set_up(start, study, options, priority, extras.is_empty())?;
    // A study that does not observe the scale: the second pass's added
    // parameters are held by their prior from the first step. Nearly
    // regrouped with the length that pins the scale, they would let plain
    // steps shrink the robot, along which its residuals in metres shrink.
    let (problem, start) = if extras.is_empty() || study.observes_scale() {
        (problem, start)
    } else {
        let statistics = statistics::ResidualStatistics::of(
            &start.system,
            &Loss::default(),
            study.equation_count(),
            problem.layout.columns(),
        );
        let mut rows = extra_prior_rows(&second_pass_prior(), &problem, extras);
        for row in &mut rows {
            row.weight = statistics.variance.sqrt() / row.sigma;
        }
        let held = problem.with_weighting(Weighting {
            prior_rows: rows,
            ..Weighting::default()
        });
        let start = held.assemble(&start.robot, &start.auxiliary, &held.layout, &mut states)?;
        (held, start)
    };
    let begun = begun.unwrap_or_else(|| {
        let errors_before = start.system.observation_errors();
        Begun {
            first: problem.record(&start, &[], 0.0),
            before: ErrorSummary::of_errors(&errors_before),
            errors_before,
        }
    });
    report(observer, Progress::Iteration(&begun.first))?;
    // Iteration 1 of a coarse start is the jump to its solution.
    let jump = coarse.as_ref().map(|coarse| IterationRecord {
        step: parameter_change(problem.nominal, &coarse.robot),
        ..problem.record(&start, &[], 0.0)
    });
    if let Some(jump) = &jump {
        report(observer, Progress::Iteration(jump))?;
    }
    let (mut run, route) = descend(
        &problem,
        start,
        &rank,
        &initial_auxiliary,
        &begun.first,
        &mut states,
        observer,
    )?;
    // The minimum-norm route starts from the pass's robot, not the jump.
    if let Some(jump) = jump.filter(|_| route != Route::MinimumNorm) {
        run.history.insert(0, jump);
    }
    // What repeats in the data is counted, and its repeated poses grouped,
    // on another core while the pass goes on on this one (the reweighting,
    // the scale, the loads): a tenth of a second at 10⁶ configurations, a
    // fifth of a millisecond at 5,000. Loads do not change them.
    let (counted, ended) = gecaro_data::parallel::beside(
        || {
            (
                repeats::repeats(study),
                repeatability::repeated_poses(study),
            )
        },
        || -> Result<_, Error> {
            let prior_rows = if extras.is_empty() {
                options
                    .prior
                    .as_ref()
                    .map(|prior| prior_rows(prior, problem.nominal, &problem, rank.relations()))
                    .unwrap_or_default()
            } else {
                extra_prior_rows(&second_pass_prior(), &problem, extras)
            };
            let reweighted =
                problem.reweighted(run, options.loss, prior_rows, &mut states, observer)?;
            // Moved parameters a base parameter absorbs join the base set ([`tied`]).
            let (problem, mut reweighted) = if study.observes_scale() {
                tied::joined(problem, nominal, &rank, reweighted, &mut states)?
            } else {
                (problem, reweighted)
            };
            let scale = if study.observes_scale() {
                None
            } else {
                // The final weights and prior rows, at the scaled robot: its
                // residuals are the same multiplied by the factor.
                let weighted = problem.with_weighting(reweighted.weighting.clone());
                let (moved, scale) =
                    scale::rescaled(&weighted, nominal, &rank, &reweighted.run.best, &mut states)?;
                if let Some(moved) = moved {
                    reweighted.statistics = statistics::ResidualStatistics::of(
                        &moved.system,
                        &options.loss,
                        study.equation_count(),
                        problem.layout.columns(),
                    );
                    reweighted.run.best = moved;
                }
                Some(scale)
            };
            let given_loads_cost = reweighted.run.best.system.measured_cost();
            let (mut reweighted, loaded) =
                loads::follow_the_loads(&problem, reweighted, &mut states)?;
            // The same fit written the way nearest to the nominal ([`branch`]).
            if let Some(nearer) = branch::nearest_branch(nominal, &reweighted.run.best.robot) {
                let problem = problem.with_study(loaded.as_ref().unwrap_or(study));
                let weighted = problem.with_weighting(reweighted.weighting.clone());
                let auxiliary = reweighted.run.best.auxiliary.clone();
                reweighted.run.best =
                    weighted.assemble(&nearer, &auxiliary, &weighted.layout, &mut states)?;
            }
            Ok((problem, reweighted, scale, given_loads_cost, loaded))
        },
    );
    let (problem, reweighted, scale, given_loads_cost, loaded) = ended?;
    let problem = problem.with_study(loaded.as_ref().unwrap_or(study));
    let mut result = summarise(
        &problem,
        nominal,
        begun,
        (reweighted, route, scale, counted),
        rank,
        excited,
        &initial_auxiliary,
    )?;
    if let Some(coarse) = &coarse {
        result.warnings.push(Warning::CoarseStart(coarse.note()));
    }
    result.second_pass = extras
        .iter()
        .map(|index| nominal.parameters().id(*index).to_string())
        .collect();
    if !result.joined.is_empty() {
        result.warnings.push(Warning::Joined {
            parameters: result.joined.clone(),
            prior: second_pass_prior(),
        });
    }
    if !extras.is_empty() || !result.joined.is_empty() {
        // The added and joined parameters are held by their prior, and
        // correlate with the base parameters they nearly regroup with by
        // construction.
        let added: Vec<String> = result
            .second_pass
            .iter()
            .chain(&result.joined)
            .cloned()
            .collect();
        result
            .correlated
            .retain(|(a, b, _)| !added.contains(a) && !added.contains(b));
        result
            .warnings
            .retain(|w| !matches!(w, Warning::Correlated(_)));
        result
            .warnings
            .extend(correlation_warning(&result.correlated));
    }
    drop(problem);
    Ok(Passed {
        result,
        given_loads_cost,
        loaded,
    })
}

/// What the descent starts from.
struct Setup<'a> {
    problem: Problem<'a>,
    /// The structural base set (random data like these, Appendix III).
    rank: RankReport,
    /// What these data excite of it, where the descent starts.
    excited: Excitation,
    initial_auxiliary: Vec<f64>,
    states: StudyStates,
    /// The iterate the descent starts from: at the nominal robot, or at
    /// the coarse start.
    start: Iterate,
    /// The coarse start of large data, when there was one.
    coarse: Option<coarse::CoarseStart>,
    /// The state at the robot, evaluated apart when the descent starts at
    /// a coarse start (before the start's system is made: the two are not
    /// held together).
    begun: Option<Begun>,
}

/// The base set of `study` at `robot` (structural, then what the data
/// excite: paper §3.1, §4), the problem on it, and the starting iterate:
/// at `robot`, or, for a `first_pass` on large data, at a coarse start's
/// solution ([`coarse`]).
fn set_up<'a>(
    robot: &'a Robot,
    study: &'a Study,
    options: &'a IdentificationOptions,
    priority: &gecaro_core::PriorityMatrix,
    first_pass: bool,
) -> Result<Setup<'a>, Error> {
    study.check(robot)?;
    let mut states = StudyStates::default();
    study.evaluate_poses(robot, &mut states)?;
    let initial_auxiliary = study.initial_auxiliary(&states)?;
    // Nearly parallel axes hold their offset (Hayati; see `hayati`).
    let priority = &hayati::hayati_priority(robot, priority);
    let rank = structural_parameters_at(robot, study, &states, priority, STRUCTURAL_SEED)?;
    // A first pass on data that observe the scale (the others' plain steps
    // may shrink the robot: they take the minimum-norm route from it).
    let coarse = if first_pass && study.observes_scale() {
        coarse::coarse_start(robot, study, options, &rank)?
    } else {
        None
    };
    let from_auxiliary = match &coarse {
        Some(coarse) => {
            study.evaluate_poses(&coarse.robot, &mut states)?;
            study.initial_auxiliary(&states)?
        }
        None => initial_auxiliary.clone(),
    };
    let from = coarse.as_ref().map_or(robot, |coarse| &coarse.robot);
    let begun = match &coarse {
        Some(_) => {
            let (before, errors_before, rms) = errors_at(robot, study)?;
            Some(Begun {
                first: IterationRecord {
                    rms,
                    step: 0.0,
                    damping: 0.0,
                },
                before,
                errors_before,
            })
        }
        None => None,
    };
    let (problem, excited, start) = Problem::excited(
        robot,
        study,
        options,
        &rank,
        (from, &from_auxiliary),
        &mut states,
    )?;
    Ok(Setup {
        problem,
        rank,
        excited,
        initial_auxiliary,
        states,
        start,
        coarse,
        begun,
    })
}
