//! The last phase of an identification (see [`super::second_pass`]): a
//! damped descent over *every* parameter the priority matrix lets be
//! identified, from the solution of the passes on a base set.
//!
//! A base set holds parameters at fixed values: the paper's at their nominal
//! values, the minimum-norm route's at where its continuation stopped. With
//! errors of centimetres and degrees, what the nominal structure regroups or
//! ignores matters at the order of (error)², and the fixed values leave a
//! residual above the noise (PUMA 560 position data at ±2 cm, ±2°: 3× the
//! noise floor on held-out data after the second pass). Levenberg–Marquardt
//! over all parameters, `min ‖W Δ − Δy‖² + λ‖D Δ‖²` with D the column norms
//! of W, needs no base set: directions the data do not determine are held by
//! the damping instead of being removed, so the descent reaches the least
//! squares optimum of the whole model (pybotics fits this way). Measured on
//! the cases of docs/methods.md it converges in one or two steps from the
//! base set's solution, to 1.02–1.03× the floor.

use gecaro_core::Robot;

use super::gauge::Gauge;
use super::options::IdentificationOptions;
use super::prior_rows::weak_prior_rows;
use super::solver::{Damping, Problem, Run};
use super::statistics::ResidualStatistics;
use super::verdict::StopReason;
use super::weighting::Weighting;
use crate::Error;
use crate::prior::Prior;
use crate::progress::Quiet;
use crate::rows::ColumnLayout;
use crate::study::{Study, StudyStates};

/// Iterations allowed to the damped descent (it needs one or two).
const ITERATIONS: usize = 20;

/// The damped descent over `parameters` (vocabulary indices) and every
/// auxiliary unknown of `study`, from `start`; `None` when it diverges or
/// lowers nothing. Least squares with a weak prior about the nominal
/// values (this phase runs only without a user's prior or robust weights).
/// A study that does not observe the scale has it held by a [`Gauge`] row
/// (with the σ of `gauge`).
///
/// # Errors
/// Only if the data cannot be evaluated at `start`.
pub(super) fn damped_descent(
    nominal: &Robot,
    study: &Study,
    options: &IdentificationOptions,
    parameters: &[usize],
    start: &Robot,
    gauge: Option<&Prior>,
) -> Result<Option<Run>, Error> {
    let mut states = StudyStates::default();
    study.evaluate_poses(start, &mut states)?;
    let auxiliary = study.initial_auxiliary(&states)?;
    let every_auxiliary: Vec<usize> = (0..auxiliary.len()).collect();
    let layout = ColumnLayout::with_auxiliary(
        nominal.parameters().len(),
        parameters,
        auxiliary.len(),
        &every_auxiliary,
    );
    let layout_for_gauge = layout.clone();
    let problem = Problem {
        study,
        nominal,
        options,
        base: parameters.to_vec(),
        base_auxiliary: every_auxiliary,
        layout,
        rows: study.row_count(),
        // W is rank deficient by design: steps and decreases row by row.
        condition: f64::INFINITY,
        weighting: Weighting {
            gauge: gauge
                .map(|prior| Gauge::new(start, &layout_for_gauge, prior, study.row_count())),
            ..Weighting::default()
        },
        joined: 0,
    };
    // A weak prior (1 cm, 1°, 1 % about the nominal values) holds what the
    // data do not determine where it is, instead of wherever the path of the
    // damping leaves it (a tool angle the measured point barely sees turned
    // by 60°); parameters the data determine do not feel it.
    let plain = problem.assemble(start, &auxiliary, &problem.layout, &mut states)?;
    let statistics = ResidualStatistics::of(
        &plain.system,
        &crate::robust::Loss::default(),
        study.equation_count(),
        problem.layout.columns(),
    );
    let prior_rows = weak_prior_rows(
        nominal,
        parameters,
        problem.base_auxiliary.len(),
        statistics.variance.sqrt(),
    );
    let problem = problem.with_weighting(Weighting {
        prior_rows,
        ..problem.weighting.clone()
    });
    let first = problem.assemble(start, &auxiliary, &problem.layout, &mut states)?;
    let before = first.cost;
    let run = problem.descend(first, Damping::Always, ITERATIONS, &mut states, &mut Quiet)?;
    // Over a rank-deficient W the last steps crawl along directions the data
    // barely see: a descent that lowered the cost at its iteration limit is
    // kept too (the pass on the base set after it converges, and an F test
    // keeps it or not).
    let lowered = run.best.cost < before && run.stop != StopReason::Diverged;
    Ok(lowered.then_some(run))
}
