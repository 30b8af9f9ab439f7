//! Identification (paper §3.1, eq. 9–10): iterative linearised least squares.
//!
//! The identifiable parameters are the structural base set of the study
//! (Appendix III on random data of the same kind) that these data excite
//! ([`crate::identifiability::structural_parameters`], [`crate::identifiability::excitation`]). From the nominal
//! parameters, each iteration rebuilds W_b and Δy at the updated parameters and
//! solves `W_b Δη_b = Δy` in the least-squares sense (eq. 10, QR of W_b); the
//! base parameters and the methods' auxiliary unknowns are updated. The
//! non-base parameters keep their nominal values: their effect is carried by
//! the base parameters that absorb them.
//!
//! ## Routes to the solution
//!
//! 1. **The paper's scheme** (default): plain Gauss–Newton steps, a step
//!    that would increase the residual being shortened along its direction
//!    (backtracking). It converges in about five iterations for position,
//!    frame and distance measure even from errors of half a metre.
//! 2. **Minimum-norm route**, taken automatically when a plain step would
//!    increase the residual or the plain scheme does not converge. Methods
//!    without an external length (link, plane) cannot observe the robot's
//!    scale, which the base set pins through a non-base length (the Stanford's
//!    r7 for point link). With errors of a few centimetres on that length the
//!    base-set solution is the real robot rescaled by tens of percent, and from
//!    the nominal robot the linearisation mistakes shrinking the robot for
//!    progress. So the route first iterates minimum-norm Gauss–Newton steps
//!    over *all* parameters with an effect (truncated SVD at the structural
//!    rank): they reach a robot that reproduces the data close to the nominal
//!    one. It then walks the non-base parameters back to their nominal values
//!    in continuation stages, re-converging the base parameters after each (a
//!    stage is halved when it fails), which ends at the paper's base-parameter
//!    solution. The base set is chosen at the nominal geometry, where its
//!    regrouping relations hold to first order: with errors of degrees and
//!    centimetres an exact solution may not exist with every non-base
//!    parameter at nominal. The continuation then stops where one still does,
//!    and the moved non-base parameters are reported
//!    ([`Identification::moved`]) rather than leaving a residual of model error.
//! 3. **Levenberg–Marquardt** (`Solver::LevenbergMarquardt`): damped steps on
//!    the base set from the start, `min ‖W Δ − Δy‖² + λ‖D Δ‖²` with D the
//!    column norms of W; also the fallback of the continuation steps, and
//!    the last resort of the default when neither route above converges.
//!
//! Joints placed by Hayati's rule within 10° of their previous axis hold
//! their offset r_j; a study that does not observe the robot's scale keeps
//! the most likely one (docs/methods.md, "Scale").
//!
//! An iteration stops when the correction the data ask for is negligible,
//! `‖Δη_b‖ ≤ tol·(1 + ‖η_b‖)` with tol = 1e-8 (converged; that last
//! correction is applied — with quadratic convergence it lands on the
//! solution to rounding — but not counted as an update), when no step lowers
//! the residual (diverged), or at the limit.
//! The best iterate is always returned, with the reason it stopped.
//!
//! Precision: `σ² = ‖r‖²/(equations − b)`, `cov(Δη_b) = σ² (W_bᵀW_b)⁻¹` at the
//! solution; where `W_bᵀW_b` is nearly singular, the noise's part uses the
//! Hessian with the residuals' curvature instead (`curvature`).
//!
//! ## Measurements as they are
//!
//! With a robust [`Loss`] or a [`Prior`] ([`IdentificationOptions`]), the
//! least-squares solution is the start of a reweighted phase (see
//! the reweighted phase): iteratively reweighted least squares for the loss, and
//! the prior as pseudo-observations, maximum a posteriori. Every
//! identification reports the observations whose standardised residual
//! exceeds [`IdentificationOptions::outlier_threshold`]
//! ([`Identification::outliers`]); with [`IdentificationOptions::reject`] they
//! are dropped and the identification runs again on the rest, once.

mod angle_unit;
mod branch;
mod change;
mod coarse;
mod coverage;
mod curvature;
mod data_scale;
mod disagreement;
mod evaluation;
mod findings;
mod full_model;
mod gauge;
mod hayati;
mod join;
mod loads;
mod observations;
mod options;
mod outliers;
mod parameter;
mod passes;
mod plausibility;
mod prior_rows;
mod region;
mod repeatability;
mod repeats;
mod result;
mod reweighting;
mod routes;
mod scale;
mod solver;
mod split;
mod start;
mod statistics;
mod subsample;
mod tested;
mod tied;
mod verdict;
mod warnings;
mod weighting;
mod words;

use std::borrow::Cow;

use gecaro_core::Robot;

use crate::Error;
use crate::frames::FRAME_UNKNOWNS;
use crate::identifiability::{Excitation, ParameterStatus, RankReport, structural_parameters_at};
use crate::linalg::{LeastSquaresRows, NormalEquations, precision, sandwich_diagonal};
use crate::progress::{Observer, Progress, Quiet, report};
use crate::study::{Study, StudyStates};

pub use change::{CHANGE_LEVEL, CellChange, MIN_CHANGED};
pub use coarse::COARSE_FRACTION;
pub use coverage::{Coverage, MIN_REDUNDANCY, STILL_RANGE, UnobservedScale};
pub use disagreement::{MAX_CONFIGURATIONS, MAX_SETS, MIN_SETS};
use evaluation::errors_at;
pub use evaluation::{evaluate, evaluate_errors};
pub use findings::{Disagreement, NARROW_FRACTION, RegionPrediction, SetFit, ShiftedJoin};
pub use join::{FAR_BEYOND, MAX_SHIFT};
pub use observations::{ObservationLocation, locate_observations};
pub use options::{
    DEFAULT_COARSE_FROM, DEFAULT_MAX_ITERATIONS, DEFAULT_STREAMED_ROWS, IdentificationOptions,
    Solver,
};
pub use outliers::{DEFAULT_OUTLIER_THRESHOLD, Outlier};
pub use parameter::IdentifiedParameter;
pub use passes::SECOND_PASS_LEVEL;
use passes::{ScoreTests, score_tests, significantly_lower};
use prior_rows::{extra_prior_rows, prior_rows};
pub use region::{FLOOR_FACTOR, REGION_FACTOR, REGION_POSES, WORK_POSES};
pub use repeatability::{MIN_FREEDOM, Repeatability, SAME_POSE};
use repeats::Repeats;
pub use result::{ErrorSummary, Identification, Route};
pub use reweighting::MAX_REWEIGHTINGS;
use reweighting::Reweighted;
use routes::descend;
use solver::{Iterate, Problem, Run};
pub use split::{SPLIT_CORRELATION, UNDETERMINED_ANGLE, UNDETERMINED_LENGTH};
use verdict::Evidence;
pub use verdict::{
    Implausible, NOISE_TEST_LEVEL, NoiseTest, Outcome, SIGMA_MARGIN, StopReason, Verdict,
};
pub use warnings::{POOR_CONDITIONING, STRONG_CORRELATION, Warning};
use warnings::{correlation_warning, strongly_correlated, warnings_of};
pub use weighting::SECOND_PASS_PRIOR;
use weighting::{Weighting, second_pass_prior};

pub use crate::observation::ObservationErrors;
pub use crate::prior::{COMPLIANCE_PRIOR, Prior, PriorError};
pub use crate::progress::IterationRecord;
pub use crate::robust::{Loss, LossKind, robust_sigma};

/// Passes at most: the paper's, and the second pass repeated while the
/// structure at the calibrated robot keeps adding parameters.
const MAX_PASSES: usize = 3;

/// Seed of the random data of the structural analysis: fixed, so that an
/// identification is a pure function of its inputs.
const STRUCTURAL_SEED: u64 = 0x6ECA20;

/// Identifies the base parameters of `robot` from `study` (see the module
/// docs), reporting the starting point and every accepted update to
/// `observer` ([`Progress::Iteration`]); pass [`Quiet`] to
/// watch nothing.
///
/// # Errors
/// Invalid data (points that cannot be this robot's in their stated length
/// unit among them, named before any fitting); [`Error::TooFewEquations`] when there
/// are no more equations than identifiable unknowns; [`Error::Numerical`] when nothing is
/// identifiable or the data produce non-finite values;
/// [`Error::Interrupted`] when the observer stops the work.
///
/// # Example
///
/// Simulated position measurements of a Stanford arm with errors, identified
/// back to the noise:
///
/// ```
/// use gecaro_calib::prelude::*;
///
/// let nominal = gecaro_io::load_robot("stanford")?.robot;
/// let position = method("position", &MethodOptions::default())?;
/// let mut sampler = Sampler::new(1);
/// let real = perturbed_robot(&nominal, 0.3, &mut sampler)?;
/// let samples = simulate_measurements(&real, position.as_ref(), 50, 1e-5, &mut sampler, &mut Quiet)?;
/// let study = Study::single(position, samples, "simulated");
///
/// let result = identify(&nominal, &study, &IdentificationOptions::default(), &mut Quiet)?;
/// assert_eq!(result.stop_reason, StopReason::Converged);
/// assert!(result.after.rms < 1e-4 && result.before.rms > 1e-3);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn identify(
    robot: &Robot,
    study: &Study,
    options: &IdentificationOptions,
    observer: &mut dyn Observer,
) -> Result<Identification, Error> {
    identify_as(robot, study, options, observer, true)
}

/// [`identify`] without looking beyond the fit (a change of the cell, the
/// set that disagrees, a shifted join, where the result holds): what a
/// cross-validation's fold or a Monte Carlo run needs of it, the robot.
///
/// # Errors
/// As [`identify`].
pub(crate) fn identify_fit(
    robot: &Robot,
    study: &Study,
    options: &IdentificationOptions,
    observer: &mut dyn Observer,
) -> Result<Identification, Error> {
    identify_as(robot, study, options, observer, false)
}

/// [`identify`], looking beyond the fit when `further`.
fn identify_as(
    robot: &Robot,
    study: &Study,
    options: &IdentificationOptions,
    observer: &mut dyn Observer,
    further: bool,
) -> Result<Identification, Error> {
    options::check_options(robot, options)?;
    angle_unit::check_angle_unit(robot, study)?;
    data_scale::check_data_scale(robot, study)?;
    let first = fit(robot, study, options, observer)?;
    if !further && (!options.reject || first.outliers.is_empty()) {
        return Ok(first);
    }
    let found = if further {
        look_further(robot, study, options, &first, observer)?
    } else {
        Found::default()
    };
    if !options.reject || first.outliers.is_empty() {
        return Ok(judged(first, study, found, options));
    }
    let kept = outliers::inliers(study, &first.outliers);
    let mut refit = fit(robot, &kept, options, observer).map_err(|error| Error::Numerical {
        message: format!(
            "after rejecting {} outliers the rest cannot be identified: {error}",
            first.outliers.len()
        ),
    })?;
    refit.warnings.insert(
        0,
        Warning::OutliersRejected {
            count: first.outliers.len(),
            threshold: options.outlier_threshold,
        },
    );
    refit.rejected = first.outliers;
    Ok(judged(refit, &kept, found, options))
}

/// What `first`, the fit of `study`, leaves for the data to say: a block
/// of outliers in a set's row order ([`change`]), the set that disagrees
/// with the rest ([`disagreement`]), a join off by a few rows ([`join`]).
/// The last two identify the study again; `observer` may stop them (it
/// hears of them as one part of the work).
///
/// # Errors
/// [`Error::Interrupted`] when the observer stops the work.
fn look_further(
    robot: &Robot,
    study: &Study,
    options: &IdentificationOptions,
    first: &Identification,
    observer: &mut dyn Observer,
) -> Result<Found, Error> {
    // A block of outliers is a change of the cell, whatever the loss or a
    // rejection makes of them.
    let changes = change::cell_changes(study, &first.outliers);
    let mut checking =
        |_: Progress<'_>| observer.observe(Progress::Phase("looking for a mistake in the data"));
    // A study that exceeds the noise: the set that disagrees with the rest.
    let disagreement = disagreement::disagreeing_set(study, first, |without| {
        fit(robot, without, options, &mut checking)
    })?;
    // A fit that fails far from the noise: a join off by a few rows?
    let join = join::shifted_join(study, first, |shifted| {
        fit(robot, shifted, options, &mut checking)
    })?;
    Ok(Found {
        changes,
        disagreement,
        join,
    })
}

/// What the data say beyond the first fit, for the verdict.
#[derive(Default)]
struct Found {
    /// Blocks of outliers in a set's row order.
    changes: Vec<change::CellChange>,
    /// The set that disagrees with the rest.
    disagreement: Option<Disagreement>,
    /// A set joined a few rows off.
    join: Option<ShiftedJoin>,
}

/// `result` (of `study`) with the verdict on what the data say beyond its
/// fit: the cell's `changes` during the measurement ([`change`]), the set
/// that disagrees with the rest ([`disagreement`]), a join off by a few
/// rows ([`join`]), and where
/// the result holds ([`region`]), its predicted error in the measured
/// region and over the work region.
fn judged(
    mut result: Identification,
    study: &Study,
    found: Found,
    options: &IdentificationOptions,
) -> Identification {
    result.verdict.changes = found.changes;
    result.verdict.disagreement = found.disagreement;
    result.verdict.shifted_join = found.join;
    result.verdict.outlier_threshold = options.outlier_threshold;
    result.verdict.region = region::where_it_holds(study, &result, options.work_region.as_ref());
    result.warnings.extend(
        result
            .verdict
            .region
            .as_ref()
            .and_then(RegionPrediction::warning)
            .map(Warning::Region),
    );
    let (iterations, unknowns) = (result.iterations(), result.unknowns());
    result.verdict.reconsider(iterations, unknowns);
    result
}

/// One identification of `study` (see the module docs): the paper's pass on
/// the base set chosen at the nominal robot, then, where the structure at the
/// calibrated robot differs, the second pass ([`second_pass`]); a split of
/// two parameters the data cannot tell apart held ([`split`]).
fn fit(
    robot: &Robot,
    study: &Study,
    options: &IdentificationOptions,
    observer: &mut dyn Observer,
) -> Result<Identification, Error> {
    let result = fit_once(robot, study, options, observer)?;
    let Some((held, words)) = split::undetermined_split(&result) else {
        return Ok(result);
    };
    let mut priority = options.priority.clone().unwrap_or_else(|| robot.priority());
    priority.set(held, 0);
    let holding = IdentificationOptions {
        priority: Some(priority),
        ..options.clone()
    };
    let Ok(mut refit) = fit_once(robot, study, &holding, &mut Quiet) else {
        return Ok(result);
    };
    let as_well = refit.stop_reason == StopReason::Converged
        && !significantly_lower(
            refit.data_cost,
            result.data_cost,
            1,
            result.degrees_of_freedom,
        );
    if !as_well {
        return Ok(result);
    }
    refit.warnings.push(Warning::SplitHeld(words));
    Ok(refit)
}

/// [`fit`] without the split held.
fn fit_once(
    robot: &Robot,
    study: &Study,
    options: &IdentificationOptions,
    observer: &mut dyn Observer,
) -> Result<Identification, Error> {
    let priority = options.priority.clone().unwrap_or_else(|| robot.priority());
    priority.validate(robot.parameters())?;
    // Stations and tools stated far from where the data put them start
    // where a closed-form fit does (the errors before are the stated ones).
    let registered = start::registered_frames(robot, study)?;
    let fitted = registered.as_ref().map_or(study, |found| &found.study);
    // The robot where the registration puts it in the data's world frame,
    // else where the closed-form start of the sets without named frames does.
    let start = match registered.as_ref().and_then(|found| found.base) {
        Some(base) => Some(robot.reframed(&base, &nalgebra::IsometryMatrix3::identity())?),
        None => start::closed_form_start(robot, fitted, &priority)?,
    };
    let first = match (start, &registered) {
        (Some(start), _) => first_from(robot, &start, fitted, study, options, &priority, observer)?,
        (None, Some(_)) => first_from(robot, robot, fitted, study, options, &priority, observer)?,
        (None, None) => fit_pass(robot, robot, study, options, &priority, &[], observer)?,
    };
    // An elastic robot's loads, followed by the paper's pass, are at its
    // geometry when the second pass looks for structure (the nominal
    // loads' error would pass for some).
    let loaded = first.loaded.as_ref().unwrap_or(fitted);
    second_pass(robot, loaded, options, &priority, first.result, observer)
}

/// A pass's identification, and what the passes after it need.
struct Passed {
    result: Identification,
    /// The data's sum of squares at the pass's solution with the loads it
    /// was given, before they followed it ([`loads`]): what an F test
    /// against the pass before, with the same loads, reads.
    given_loads_cost: f64,
    /// The study with an elastic robot's loads at the pass's solution,
    /// when they moved.
    loaded: Option<Study>,
}

impl Passed {
    /// Whether this pass (with `added` more unknowns) explains the data
    /// significantly better than `before` ([`significantly_lower`]), both
    /// with the loads this pass was given.
    fn better_than(&self, before: &Identification, added: usize) -> bool {
        significantly_lower(
            before.data_cost,
            self.given_loads_cost,
            added,
            self.result.degrees_of_freedom,
        )
    }
}

/// The paper's pass from the closed-form start (see [`start`]) on `study`
/// (its named frames perhaps re-stated there), reported against `nominal`
/// and `stated`, the study as given: the errors before and iteration 0 are
/// the nominal robot's with the stated frames, iteration 1 is the start.
fn first_from(
    nominal: &Robot,
    start: &Robot,
    study: &Study,
    stated: &Study,
    options: &IdentificationOptions,
    priority: &gecaro_core::PriorityMatrix,
    observer: &mut dyn Observer,
) -> Result<Passed, Error> {
    let (before, errors_before, rms) = errors_at(nominal, stated)?;
    let first = IterationRecord {
        rms,
        step: 0.0,
        damping: 0.0,
    };
    report(observer, Progress::Iteration(&first))?;
    let mut passed = fit_pass(nominal, start, study, options, priority, &[], observer)?;
    let result = &mut passed.result;
    result.before = before;
    result.errors_before = errors_before;
    // Iteration 1 is the jump to the start: its step, the parameters' change.
    if let Some(record) = result.history.first_mut() {
        record.step = parameter_change(nominal, start);
    }
    result.history.insert(0, first);
    result.verdict.summary = result
        .verdict
        .sentence(result.iterations(), result.unknowns());
    result.warnings.push(Warning::ClosedFormStart {
        named_frames: study.frames != stated.frames,
    });
    Ok(passed)
}

/// The Euclidean norm of the change of every parameter from `from` to `to`
/// (the step of an iteration that jumps to a start).
fn parameter_change(from: &Robot, to: &Robot) -> f64 {
    from.parameters()
        .ids()
        .iter()
        .map(|id| (to.parameter(*id) - from.parameter(*id)).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// The second pass: the base set chosen at the nominal robot is exact only
/// to first order, because the regrouping relations and the parameters
/// without effect of the nominal structure (parallel axes, a tool point on
/// the last axis) hold there and not at the real robot. With errors of a
/// centimetre and a degree the first pass then stops at a residual that
/// grows with their square (15–45× the noise on held-out data). So the
/// structural analysis runs again at the calibrated robot, with the same
/// priority matrix; parameters identifiable there and not at the nominal
/// ([`Identification::second_pass`]) join the base set, and the
/// identification starts again from the first pass's solution, these
/// parameters held by a weak prior ([`SECOND_PASS_PRIOR`], centred on their
/// nominal values) since the data determine them only through the small
/// deviations of the real robot. The second pass is kept when it explains
/// the data significantly better: an F test of the residual sums of squares
/// at [`SECOND_PASS_LEVEL`]; it runs only where a score test at the first
/// pass's solution ([`score_tests`], on the observations that are not
/// outliers: gross errors would pass for structure) says it can, and only
/// after a converged first pass without a prior (centred on the
/// nominal values of the paper's base set). A study that does not observe
/// the scale (links, planes) has it held by a gauge row in the score tests
/// and the descent, and chosen after each pass ([`scale`]). Where
/// parameters outside the base set still matter after the passes, the
/// damped descent over every parameter follows ([`full_model_phase`]).
fn second_pass(
    robot: &Robot,
    study: &Study,
    options: &IdentificationOptions,
    priority: &gecaro_core::PriorityMatrix,
    first: Identification,
    observer: &mut dyn Observer,
) -> Result<Identification, Error> {
    if first.stop_reason != StopReason::Converged || options.prior.is_some() {
        return Ok(first);
    }
    // Data the first pass explains to rounding (noise-free, simulated) leave
    // nothing for parameters outside the base set to explain: the score and
    // F tests would read rounding for structure (a damped descent "took the
    // RMS error from 0.0000 to 0.0000 mm" on a noise-free frame fit).
    if statistics::at_rounding(first.data_cost, study.row_count()) {
        return Ok(first);
    }
    // A study that does not observe the scale: the steps over every
    // parameter hold it with a gauge row (the step that shrinks the robot
    // has the residuals themselves for its column).
    let expansion = second_pass_prior();
    let gauge = (!study.observes_scale()).then_some(&expansion);
    // Every parameter the priority matrix lets be identified, of those
    // with an effect on these data: a column without one (the base frame of
    // a link method, a tool angle about the measured point) is zero only to
    // rounding, and a step over it would be rounding too.
    let has_effect = |index: &usize| {
        first.rank.parameters.get(*index).is_some_and(|p| {
            matches!(
                p.status,
                ParameterStatus::Identifiable | ParameterStatus::Regrouped
            )
        })
    };
    // Gravity's tilts load the joints through their compliances (their
    // columns are `c_j ∂τ_j/∂tilt`): zero at a nominal robot whose
    // compliances are, they have an effect once the first pass has found
    // the compliances.
    let yields = first
        .calibrated
        .compliances()
        .is_some_and(|compliances| compliances.iter().any(|c| *c != 0.0));
    let tilt_seen = |index: &usize| {
        yields && robot.parameters().id(*index).kind == gecaro_core::ParameterKind::GravityTilt
    };
    let every: Vec<usize> = priority
        .ordered_candidates(robot.parameters())
        .into_iter()
        .filter_map(|id| robot.parameters().index_of(id))
        .filter(|index| has_effect(index) || tilt_seen(index))
        .collect();
    let mut current = first;
    let mut added: Vec<usize> = Vec::new();
    // The data with an elastic robot's loads where the last kept pass left
    // them (each pass follows them, [`loads`]).
    let mut loaded = Cow::Borrowed(study);
    // What a step from the current solution could still explain.
    let mut score = ScoreTests::default();
    for pass in 0..MAX_PASSES {
        let study: &Study = &loaded;
        let calibrated = &current.calibrated;
        let outside =
            |index: &usize| !current.rank.base_parameters.contains(index) && !added.contains(index);
        // The score test first, over every parameter the priority matrix
        // lets be identified (cheap, on the data); the structural analysis at
        // the calibrated robot (random data) only when it passes.
        let candidates: Vec<usize> = every.iter().copied().filter(outside).collect();
        if candidates.is_empty() {
            score = ScoreTests::default();
            break;
        }
        // The tests assume Gaussian residuals, and gross errors would pass
        // for structure: they read the observations within the outlier
        // threshold. (A model that misses structure makes outliers of its
        // own; the inliers show that structure still.)
        score = score_tests(&current, study, &candidates, gauge, options.streamed_rows)?;
        if score.outside.is_none() || pass == MAX_PASSES - 1 {
            break;
        }
        let mut states = StudyStates::default();
        study.evaluate_poses(calibrated, &mut states)?;
        let held = hayati::hayati_priority(calibrated, priority);
        let new: Vec<usize> =
            structural_parameters_at(calibrated, study, &states, &held, STRUCTURAL_SEED)?
                .base_parameters
                .into_iter()
                .filter(|index| outside(index))
                .collect();
        if new.is_empty() {
            break;
        }
        let extras: Vec<usize> = added.iter().chain(&new).copied().collect();
        let Ok(next) = fit_pass(
            robot, calibrated, study, options, priority, &extras, &mut Quiet,
        ) else {
            break;
        };
        if next.result.stop_reason != StopReason::Converged
            || !next.better_than(&current, new.len())
        {
            break;
        }
        for record in &next.result.history[1..] {
            report(observer, Progress::Iteration(record))?;
        }
        if let Some(study) = next.loaded {
            loaded = Cow::Owned(study);
        }
        added = extras;
        current = merge_passes(current, next.result);
    }
    match score.whole {
        Some(rank) => full_model_phase(
            robot,
            &loaded,
            options,
            priority,
            current,
            (&added, &every, gauge),
            rank,
            observer,
        ),
        _ => Ok(current),
    }
}

/// The last phase, when parameters outside the base set still matter after
/// the passes (the score test says they add `rank`): the damped descent over
/// every parameter the priority matrix allows (`every`; [`full_model`]), then a pass
/// on the base set from there (its parameters' precision; the others stay
/// where the descent put them and are listed as moved). Kept when an F test
/// says it explains the data better.
#[allow(clippy::too_many_arguments)]
fn full_model_phase(
    robot: &Robot,
    study: &Study,
    options: &IdentificationOptions,
    priority: &gecaro_core::PriorityMatrix,
    mut current: Identification,
    (added, every, gauge): (&[usize], &[usize], Option<&Prior>),
    rank: usize,
    observer: &mut dyn Observer,
) -> Result<Identification, Error> {
    let Some(descent) =
        full_model::damped_descent(robot, study, options, every, &current.calibrated, gauge)?
    else {
        return Ok(current);
    };
    let Ok(passed) = fit_pass(
        robot,
        &descent.best.robot,
        study,
        options,
        priority,
        added,
        &mut Quiet,
    ) else {
        return Ok(current);
    };
    if passed.result.stop_reason != StopReason::Converged || !passed.better_than(&current, rank) {
        return Ok(current);
    }
    let next = passed.result;
    // After a fit with outliers the gain must show on the inliers too: more
    // parameters could chase gross errors (a model that misses structure
    // makes outliers of its own, and there the inliers gain most).
    if !current.outliers.is_empty() {
        let inliers = outliers::inliers(study, &current.outliers);
        let sum_of_squares = |robot: &Robot| -> Result<f64, Error> {
            let rms = errors_at(robot, &inliers)?.2;
            Ok(rms * rms * inliers.row_count() as f64)
        };
        let freedom = inliers
            .row_count()
            .saturating_sub(next.parameters.len() + next.auxiliary.len() + rank);
        let (before, after) = (
            sum_of_squares(&current.calibrated)?,
            sum_of_squares(&next.calibrated)?,
        );
        if !significantly_lower(before, after, rank, freedom) {
            return Ok(current);
        }
    }
    for record in descent.history.iter().chain(&next.history[1..]) {
        report(observer, Progress::Iteration(record))?;
    }
    let from = current.after.rms;
    current.history.extend(descent.history);
    let mut result = merge_passes(current, next);
    result.warnings.push(Warning::FullModelDescent {
        parameters: every.len(),
        from,
        to: result.after.rms,
    });
    Ok(result)
}

/// The second pass as the identification: its parameters and errors, with
/// the first pass's start (errors before, iteration 0), the iterations of
/// both, and the first pass's condition number (the excitation of the
/// nominal base set; the added parameters are held by the prior).
fn merge_passes(first: Identification, mut second: Identification) -> Identification {
    let mut history = first.history;
    history.extend(second.history.drain(1..));
    second.history = history;
    second.verdict.summary = second
        .verdict
        .sentence(second.iterations(), second.unknowns());
    second.before = first.before;
    second.errors_before = first.errors_before;
    second.condition_number = first.condition_number;
    // The first pass's excitation and set-up are the nominal structure's.
    second.warnings.retain(|w| !w.of_nominal_structure());
    let mut warnings: Vec<Warning> = first
        .warnings
        .into_iter()
        .filter(Warning::of_nominal_structure)
        .collect();
    warnings.append(&mut second.warnings);
    second.warnings = warnings;
    second
        .warnings
        .retain(|w| !matches!(w, Warning::SecondPass { .. }));
    if second.second_pass.is_empty() {
        return second;
    }
    second.warnings.push(Warning::SecondPass {
        parameters: second.second_pass.clone(),
        prior: second_pass_prior().to_string(),
    });
    second
}

/// One pass of an identification of `study`: the base set at `start` and
/// the start, the descent, then the reweighted phase, an elastic robot's
/// loads followed ([`loads`]), and the summary (values reported against
/// `nominal`). `extras` (vocabulary indices) are the second pass's added
/// parameters, held by [`second_pass_prior`].
fn fit_pass(
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
    // What repeats in the data is counted on another core while the pass
    // ends on this one (the statistics, the precision, the coverage): a
    // tenth of a second at 10⁶ configurations. Loads do not change it.
    std::thread::scope(|scope| {
        let counting = scope.spawn(|| repeats::repeats(study));
        let counted = move || {
            counting
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
        };
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
        let (mut reweighted, loaded) = loads::follow_the_loads(&problem, reweighted, &mut states)?;
        let problem = problem.with_study(loaded.as_ref().unwrap_or(study));
        // The same fit written the way nearest to the nominal ([`branch`]).
        if let Some(nearer) = branch::nearest_branch(nominal, &reweighted.run.best.robot) {
            let weighted = problem.with_weighting(reweighted.weighting.clone());
            let auxiliary = reweighted.run.best.auxiliary.clone();
            reweighted.run.best =
                weighted.assemble(&nearer, &auxiliary, &weighted.layout, &mut states)?;
        }
        let mut result = summarise(
            &problem,
            nominal,
            begun,
            (reweighted, route, scale, counted()),
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
                prior: second_pass_prior().to_string(),
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
    })
}

/// The state at the nominal robot, before any step.
struct Begun {
    /// The starting point of the history.
    first: IterationRecord,
    before: ErrorSummary,
    errors_before: ObservationErrors,
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

/// The identification at the end of the reweighted phase (reached by
/// `route`, with the data's `repeats`): parameters with their precision,
/// errors, outliers and warnings.
fn summarise(
    problem: &Problem<'_>,
    nominal: &Robot,
    begun: Begun,
    (reweighted, route, scale, repeats): (Reweighted, Route, Option<UnobservedScale>, Repeats),
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
    // Precision at the solution: σ² (W_bᵀ W_b)⁻¹, and the condition number of W_b
    // (of the data's rows: prior rows would hide a poor excitation).
    let system = &best.system;
    let columns = problem.layout.columns();
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
    let errors_after = best.system.observation_errors();
    let outliers =
        outliers::find_outliers(study, &statistics, &errors_after, options.outlier_threshold);
    let data_cost = best.system.measured_cost();
    let degrees_of_freedom = statistics.effective_equations.saturating_sub(columns);
    // The test reads the residuals as measured, not as the loss weighed them.
    let tested = tested::tested(
        &best.system,
        &statistics,
        &options.loss,
        options.outlier_threshold,
        (study.equation_count(), columns),
        (data_cost, degrees_of_freedom),
    );
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
                study,
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
