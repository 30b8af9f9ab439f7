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
//! the residual (diverged), or at the limit. A plain step that is not
//! negligible but ends the descent all the same — at most a tenth of the
//! step before it, `ρ = ‖Δ_k‖/‖Δ_(k−1)‖ ≤ 0.1`, so that the steps still to
//! come, at most `ρ/(1 − ρ)·‖Δ_k‖` together, are — is applied and counted
//! without W evaluated at its end: the residuals are the linear model's
//! `r − W·Δ` (exact to O(‖Δ‖²)), a folded system's measured ones evaluated
//! at the new parameters, and the precision reads W at the step's start
//! (every σ within a relative 1e-4 of W at its end's, tested on the
//! Stanford arm's 2,000 positions).
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
mod pass;
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
mod summary;
mod tested;
mod tied;
mod verdict;
mod warnings;
mod weighting;
mod words;

use std::borrow::Cow;

use gecaro_core::Robot;

use crate::Error;
use crate::identifiability::{ParameterStatus, structural_parameters_at};
use crate::progress::{Observer, Progress, Quiet, report};
use crate::study::{Study, StudyStates};

pub(crate) use change::change_among;
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
use pass::{Passed, STRUCTURAL_SEED, fit_pass, parameter_change};
pub use passes::SECOND_PASS_LEVEL;
use passes::{ScoreTests, score_tests, significantly_lower};
pub use region::{FLOOR_FACTOR, REGION_FACTOR, REGION_POSES, WORK_POSES};
pub use repeatability::{MIN_FREEDOM, Repeatability, SAME_POSE};
pub use result::{ErrorSummary, Identification, Route};
pub use reweighting::MAX_REWEIGHTINGS;
pub use split::{SPLIT_CORRELATION, UNDETERMINED_ANGLE, UNDETERMINED_LENGTH};
pub(crate) use verdict::noise_test;
pub use verdict::{
    Implausible, NOISE_TEST_LEVEL, NoiseTest, Outcome, SIGMA_MARGIN, StopReason, Verdict,
};
pub use warnings::{POOR_CONDITIONING, STRONG_CORRELATION, Warning};
pub use weighting::SECOND_PASS_PRIOR;
use weighting::second_pass_prior;

pub use crate::observation::ObservationErrors;
pub use crate::prior::{COMPLIANCE_PRIOR, Prior, PriorError};
pub use crate::progress::IterationRecord;
pub use crate::robust::{Loss, LossKind, robust_sigma};

/// Passes at most: the paper's, and the second pass repeated while the
/// structure at the calibrated robot keeps adding parameters.
const MAX_PASSES: usize = 3;

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
            &WholeModel {
                added: &added,
                every: &every,
                gauge,
                rank,
            },
            observer,
        ),
        _ => Ok(current),
    }
}

/// What the last phase ([`full_model_phase`]) descends over.
struct WholeModel<'a> {
    /// The parameters the passes added to the base set.
    added: &'a [usize],
    /// Every parameter the priority matrix allows.
    every: &'a [usize],
    /// The prior that fixes the descent's gauge, if any.
    gauge: Option<&'a Prior>,
    /// How many parameters the score test says the base set lacks.
    rank: usize,
}

/// The last phase, when parameters outside the base set still matter after
/// the passes (the score test says they add `rank`): the damped descent over
/// every parameter the priority matrix allows (`every`; [`full_model`]), then a pass
/// on the base set from there (its parameters' precision; the others stay
/// where the descent put them and are listed as moved). Kept when an F test
/// says it explains the data better.
fn full_model_phase(
    robot: &Robot,
    study: &Study,
    options: &IdentificationOptions,
    priority: &gecaro_core::PriorityMatrix,
    mut current: Identification,
    whole: &WholeModel<'_>,
    observer: &mut dyn Observer,
) -> Result<Identification, Error> {
    let &WholeModel {
        added,
        every,
        gauge,
        rank,
    } = whole;
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
        prior: second_pass_prior(),
    });
    second
}
