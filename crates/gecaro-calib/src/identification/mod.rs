//! Identification (paper §3.1, eq. 9–10): iterative linearised least squares.
//!
//! The identifiable parameters are the structural base set of the study
//! (Appendix III on random data of the same kind) that these data excite
//! ([`crate::structural_parameters`], [`crate::excitation`]). From the nominal
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
//!    column norms of W; also the fallback of the continuation steps.
//!
//! An iteration stops when the correction the data ask for is negligible,
//! `‖Δη_b‖ ≤ tol·(1 + ‖η_b‖)` with tol = 1e-8 (converged; that last
//! correction is applied — with quadratic convergence it lands on the
//! solution to rounding — but not counted as an update), when no step lowers
//! the residual (diverged), or at the limit.
//! The best iterate is always returned, with the reason it stopped.
//!
//! Precision: `σ² = ‖r‖²/(equations − b)`, `cov(Δη_b) = σ² (W_bᵀW_b)⁻¹` at the
//! solution.
//!
//! ## Measurements as they are
//!
//! With a robust [`Loss`] or a [`Prior`] ([`IdentificationOptions`]), the
//! least-squares solution is the start of a reweighted phase (see
//! [`reweighting`]): iteratively reweighted least squares for the loss, and
//! the prior as pseudo-observations, maximum a posteriori. Every
//! identification reports the observations whose standardised residual
//! exceeds [`IdentificationOptions::outlier_threshold`]
//! ([`Identification::outliers`]); with [`IdentificationOptions::reject`] they
//! are dropped and the identification runs again on the rest, once.

mod outliers;
mod reweighting;

use std::ops::ControlFlow;

use gecaro_core::{ParameterId, PriorityMatrix, Robot};

use crate::Error;
use crate::error::Setting;
use crate::identifiability::{
    ParameterStatus, RankReport, excitation_at, structural_parameters_at,
};
use crate::linalg::{
    NormalEquations, damped_step, minimum_norm_step, precision, predicted_decrease, step, view,
};
use crate::observability::Observability;
use crate::observation::ObservationSystem;
use crate::prior::Prior;
use crate::robust::Loss;
use crate::rows::ColumnLayout;
use crate::study::{Study, StudyStates};

pub use outliers::{DEFAULT_OUTLIER_THRESHOLD, Outlier};
pub use reweighting::MAX_REWEIGHTINGS;
use reweighting::{PriorRow, Reweighted, Weighting};

/// How steps are taken.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum Solver {
    /// The paper's plain Gauss–Newton steps, with the minimum-norm route when they fail.
    #[default]
    GaussNewton,
    /// Levenberg–Marquardt damping from the first step.
    LevenbergMarquardt,
}

/// Which route produced the solution (see the module docs).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Route {
    /// Plain Gauss–Newton on the base parameters (the paper).
    GaussNewton,
    /// Minimum-norm steps on all parameters, then continuation to the base set.
    MinimumNorm,
    /// Levenberg–Marquardt on the base parameters.
    LevenbergMarquardt,
}

impl Route {
    /// `gauss-newton`, `minimum-norm` or `levenberg-marquardt`.
    pub fn as_str(self) -> &'static str {
        match self {
            Route::GaussNewton => "gauss-newton",
            Route::MinimumNorm => "minimum-norm",
            Route::LevenbergMarquardt => "levenberg-marquardt",
        }
    }
}

/// Settings of [`identify`].
#[derive(Clone, Debug, PartialEq)]
pub struct IdentificationOptions {
    /// Step rule.
    pub solver: Solver,
    /// Iteration limit (parameter updates) of each route.
    pub max_iterations: usize,
    /// Priority matrix; the robot's when `None`.
    pub priority: Option<PriorityMatrix>,
    /// A step is negligible when `‖Δη_b‖ ≤ step_tolerance · (1 + ‖η_b‖)`.
    pub step_tolerance: f64,
    /// The loss (plain least squares by default).
    pub loss: Loss,
    /// A Gaussian prior on the parameters (none by default).
    pub prior: Option<Prior>,
    /// Observations beyond this many robust σ̂ are reported as outliers.
    pub outlier_threshold: f64,
    /// Drop the outliers and identify again (once).
    pub reject: bool,
}

impl Default for IdentificationOptions {
    fn default() -> Self {
        IdentificationOptions {
            solver: Solver::GaussNewton,
            max_iterations: 30,
            priority: None,
            step_tolerance: 1e-8,
            loss: Loss::default(),
            prior: None,
            outlier_threshold: DEFAULT_OUTLIER_THRESHOLD,
            reject: false,
        }
    }
}

/// Why the iteration stopped.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum StopReason {
    /// The last correction was negligible.
    Converged,
    /// The iteration limit was reached first.
    IterationLimit,
    /// No step lowered the residual: the linearisation does not hold from here.
    Diverged,
}

impl StopReason {
    /// `converged`, `iteration_limit` or `diverged`.
    pub fn as_str(self) -> &'static str {
        match self {
            StopReason::Converged => "converged",
            StopReason::IterationLimit => "iteration_limit",
            StopReason::Diverged => "diverged",
        }
    }
}

/// One iteration: the residual after it and the step that led there.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct IterationRecord {
    /// RMS of the (weighted) residual vector after the update.
    pub rms: f64,
    /// Norm of the update (0 for the starting point).
    pub step: f64,
    /// The damping λ of the update (0 for an undamped step).
    pub damping: f64,
}

/// Statistics of the per-observation errors (configuration, or pair) of a study.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct ErrorSummary {
    /// Number of observations.
    pub count: usize,
    /// RMS of the position-like errors (metres).
    pub rms: f64,
    /// Mean (metres).
    pub mean: f64,
    /// Largest (metres).
    pub max: f64,
    /// RMS of the orientation errors (radians), for data with orientations.
    pub rms_rotation: Option<f64>,
    /// Largest orientation error (radians).
    pub max_rotation: Option<f64>,
}

impl ErrorSummary {
    /// The summary of a system's observation errors.
    pub fn of(system: &ObservationSystem) -> Self {
        let errors = system.observation_errors();
        let count = errors.len();
        let lengths: Vec<f64> = errors.iter().map(|e| e.0).collect();
        let angles: Vec<f64> = errors.iter().map(|e| e.1).collect();
        let has_angles = system.kinds().contains(&crate::RowKind::Angle);
        let rms = |values: &[f64]| {
            (values.iter().map(|v| v * v).sum::<f64>() / values.len().max(1) as f64).sqrt()
        };
        let max = |values: &[f64]| values.iter().copied().fold(0.0, f64::max);
        ErrorSummary {
            count,
            rms: rms(&lengths),
            mean: lengths.iter().sum::<f64>() / count.max(1) as f64,
            max: max(&lengths),
            rms_rotation: has_angles.then(|| rms(&angles)),
            max_rotation: has_angles.then(|| max(&angles)),
        }
    }
}

/// An identified base parameter or auxiliary unknown.
#[derive(Clone, Debug, PartialEq)]
pub struct IdentifiedParameter {
    /// Its name (`theta2`, or an auxiliary name such as `a`).
    pub name: String,
    /// The robot parameter; `None` for an auxiliary unknown.
    pub parameter: Option<ParameterId>,
    /// Value before identification (nominal; initial for auxiliary unknowns).
    pub nominal: f64,
    /// Identified value.
    pub identified: f64,
    /// Standard deviation of the identified value (posterior, with a prior).
    pub std: f64,
    /// Its prior standard deviation, with a prior (regrouping included).
    pub prior_std: Option<f64>,
}

/// The result of [`identify`].
#[derive(Clone, Debug)]
pub struct Identification {
    /// The robot with the identified parameters (the best iterate).
    pub calibrated: Robot,
    /// The structural identifiable parameters (random data like these, Appendix III).
    pub rank: RankReport,
    /// Entry 0 is the starting point; then one entry per accepted update of the route taken.
    pub history: Vec<IterationRecord>,
    /// The route that produced the solution.
    pub route: Route,
    /// Errors of the observations at the nominal parameters.
    pub before: ErrorSummary,
    /// Errors of the observations at the identified parameters.
    pub after: ErrorSummary,
    /// Per observation (configuration or pair): the position-like error (m)
    /// and the orientation error (rad) at the nominal parameters.
    pub errors_before: Vec<(f64, f64)>,
    /// The same at the identified parameters.
    pub errors_after: Vec<(f64, f64)>,
    /// Condition number of W_b at the solution.
    pub condition_number: f64,
    /// Appendix III on the data at the nominal robot (the excitation check):
    /// the base set they excite, and their W_b's condition number and
    /// observability indices, computed when first read.
    pub excitation: RankReport,
    /// The identified base parameters, in column (priority) order.
    pub parameters: Vec<IdentifiedParameter>,
    /// The identified auxiliary unknowns (plane coefficients).
    pub auxiliary: Vec<IdentifiedParameter>,
    /// The a-posteriori residual standard deviation σ (units of the weighted rows).
    pub residual_sigma: f64,
    /// Why the iteration stopped.
    pub stop_reason: StopReason,
    /// Structural base parameters the data do not excite: not identified, left at nominal.
    pub not_excited: Vec<String>,
    /// Parameters outside the base set that the minimum-norm route had to move
    /// (their `std` is NaN): with them at nominal, the base set — chosen at the
    /// nominal geometry, where its regroupings hold to first order — cannot
    /// reproduce these data. Empty on the paper's route.
    pub moved: Vec<IdentifiedParameter>,
    /// Things a user should know about these results, in words.
    pub warnings: Vec<String>,
    /// The loss minimised.
    pub loss: Loss,
    /// The prior, if one was given.
    pub prior: Option<Prior>,
    /// Outer iterations of the reweighted phase (0 in plain least squares).
    pub reweightings: usize,
    /// The robust σ̂ of the residuals at the solution, in units of the
    /// sensors' σ (the rows' weights; metres for an unweighted set).
    pub robust_sigma: f64,
    /// Per observation: its standardised residual at the solution (units of σ̂).
    pub standardized: Vec<f64>,
    /// Per observation: its weight in the final fit (all 1 in least squares).
    pub observation_weights: Vec<f64>,
    /// The outlier threshold used (robust σ̂).
    pub outlier_threshold: f64,
    /// Observations beyond the outlier threshold at the solution, worst first.
    pub outliers: Vec<Outlier>,
    /// Observations dropped before this fit ([`IdentificationOptions::reject`]):
    /// the outliers of the first fit, located in the original data.
    pub rejected: Vec<Outlier>,
}

impl Identification {
    /// The observations beyond the outlier threshold, numbered across sets
    /// as [`Identification::errors_after`] (for plots).
    pub fn outlier_observations(&self) -> Vec<usize> {
        self.standardized
            .iter()
            .enumerate()
            .filter(|(_, u)| **u > self.outlier_threshold)
            .map(|(index, _)| index)
            .collect()
    }

    /// Number of parameter updates of the route taken.
    pub fn iterations(&self) -> usize {
        self.history.len() - 1
    }

    /// Observability indices O1–O5 of the data's W_b at the nominal robot
    /// (see [`crate::Observability`]).
    pub fn observability(&self) -> Observability {
        self.excitation.observability()
    }

    /// RMS of the weighted residual before identification.
    pub fn rms_before(&self) -> f64 {
        self.history[0].rms
    }

    /// RMS of the weighted residual after identification.
    pub fn rms_after(&self) -> f64 {
        self.history
            .iter()
            .map(|h| h.rms)
            .fold(f64::INFINITY, f64::min)
    }

    /// Why the result is not trustworthy, as a sentence, when the iteration
    /// did not converge (`None` when it did).
    pub fn failure(&self) -> Option<String> {
        (self.stop_reason != StopReason::Converged).then(|| {
            format!(
                "the identification did not converge ({}) after {} iterations; best residual RMS {:.3e}",
                self.stop_reason.as_str().replace('_', " "),
                self.iterations(),
                self.rms_after(),
            )
        })
    }
}

/// Above this condition number of W_b the data are called poorly exciting.
pub const POOR_CONDITIONING: f64 = 1e4;

/// Largest damping tried before a step is declared impossible.
const MAX_DAMPING: f64 = 1e12;
const INITIAL_DAMPING: f64 = 1e-3;
/// A step that cannot lower the cost by more than this fraction is negligible.
const COST_TOLERANCE: f64 = 1e-12;
/// Shortest fraction of a step tried when backtracking.
const MIN_FRACTION: f64 = 1.0 / 64.0;
/// Continuation stages tried (the first goes straight to nominal).
const CONTINUATION_ATTEMPTS: usize = 8;
/// Iterations allowed to re-converge the base parameters after a stage.
const CONTINUATION_ITERATIONS: usize = 10;
/// Seed of the random data of the structural analysis: fixed, so that an
/// identification is a pure function of its inputs.
const STRUCTURAL_SEED: u64 = 0x6ECA20;

/// Parameters, auxiliary values and the system they give.
#[derive(Clone)]
struct Iterate {
    robot: Robot,
    auxiliary: Vec<f64>,
    system: ObservationSystem,
    /// The system's normal equations (its step, predicted decrease, precision).
    normal: NormalEquations,
    cost: f64,
}

/// How a descent treats a step that increases the residual.
#[derive(Copy, Clone, PartialEq, Eq)]
enum Damping {
    /// Plain steps only: stop (diverged) at the first increase.
    Never,
    /// Plain steps, damped when one increases the residual.
    WhenNeeded,
    /// Damped from the first step.
    Always,
}

/// The result of one descent.
struct Run {
    best: Iterate,
    history: Vec<IterationRecord>,
    stop: StopReason,
}

/// Everything an identification iterates on.
struct Problem<'a> {
    study: &'a Study,
    nominal: &'a Robot,
    options: &'a IdentificationOptions,
    /// Vocabulary indices of the base parameters (column order).
    base: Vec<usize>,
    /// Indices of the identified auxiliary unknowns.
    base_auxiliary: Vec<usize>,
    /// Columns: identified auxiliary unknowns, then base parameters.
    layout: ColumnLayout,
    rows: usize,
    /// Condition number of W_b on the data at nominal: chooses the solver (see `linalg::solve`).
    condition: f64,
    /// Robust weights and prior rows of the reweighted phase (none in plain least squares).
    weighting: Weighting,
}

impl<'a> Problem<'a> {
    /// This problem with `weighting` (robust weights, prior rows).
    fn with_weighting(&self, weighting: Weighting) -> Problem<'a> {
        Problem {
            study: self.study,
            nominal: self.nominal,
            options: self.options,
            base: self.base.clone(),
            base_auxiliary: self.base_auxiliary.clone(),
            layout: self.layout.clone(),
            rows: self.rows,
            condition: self.condition,
            weighting,
        }
    }

    fn assemble(
        &self,
        robot: &Robot,
        auxiliary: &[f64],
        layout: &ColumnLayout,
        states: &mut StudyStates,
    ) -> Result<Iterate, Error> {
        self.assemble_into(
            robot,
            auxiliary,
            layout,
            states,
            ObservationSystem::default(),
        )
    }

    /// [`assemble`](Self::assemble) reusing the storage of `system`.
    fn assemble_into(
        &self,
        robot: &Robot,
        auxiliary: &[f64],
        layout: &ColumnLayout,
        states: &mut StudyStates,
        mut system: ObservationSystem,
    ) -> Result<Iterate, Error> {
        system.set_observation_weights(self.weighting.observation_weights.clone());
        self.study
            .linearise(robot, auxiliary, layout, states, &mut system)?;
        self.weighting
            .append_prior_rows(&mut system, robot, self.nominal);
        Self::iterate_of(robot, auxiliary, system)
    }

    /// The iterate of a system written at `robot` and `auxiliary`.
    fn iterate_of(
        robot: &Robot,
        auxiliary: &[f64],
        system: ObservationSystem,
    ) -> Result<Iterate, Error> {
        let right = system.weighted_residuals();
        let cost: f64 = right.iter().map(|r| r * r).sum();
        let normal = NormalEquations::of(
            view(system.matrix(), system.rows(), system.columns()),
            &right,
        );
        // Non-finite entries of W or Δy reach the normal equations.
        if !cost.is_finite() || !normal.is_finite() {
            return Err(Error::Numerical {
                message: "the residuals became non-finite".into(),
            });
        }
        Ok(Iterate {
            robot: robot.clone(),
            auxiliary: auxiliary.to_vec(),
            system,
            normal,
            cost,
        })
    }

    fn record(&self, iterate: &Iterate, step: &[f64], damping: f64) -> IterationRecord {
        IterationRecord {
            rms: (iterate.cost / iterate.system.rows().max(1) as f64).sqrt(),
            step: norm(step),
            damping,
        }
    }

    /// Whether a step over `parameters` (vocabulary indices, after the
    /// auxiliary columns) is negligible at `iterate`: small against the
    /// parameters, or unable to lower the cost by more than a relative 1e-12
    /// (a least-squares step lowers ‖r‖² by ‖W·Δ‖² at most). The second test
    /// ends iterations on noisy, ill-conditioned data, where rounding keeps the
    /// computed correction from vanishing at the minimum.
    fn negligible(&self, step: &[f64], iterate: &Iterate, parameters: &[usize]) -> bool {
        let robot = &iterate.robot;
        let scale = norm(
            &parameters
                .iter()
                .map(|i| robot.parameter(robot.parameters().id(*i)))
                .collect::<Vec<_>>(),
        );
        if norm(step) <= self.options.step_tolerance * (1.0 + scale) {
            return true;
        }
        let system = &iterate.system;
        let matrix = view(system.matrix(), system.rows(), system.columns());
        predicted_decrease(matrix, &iterate.normal, step, self.condition)
            <= COST_TOLERANCE * iterate.cost
    }

    /// Adds `step` (auxiliary columns first, then `parameters`) to an iterate.
    fn stepped(
        &self,
        iterate: &Iterate,
        step: &[f64],
        parameters: &[usize],
    ) -> Result<(Robot, Vec<f64>), Error> {
        let mut robot = iterate.robot.clone();
        let mut auxiliary = iterate.auxiliary.clone();
        for (column, index) in self.base_auxiliary.iter().enumerate() {
            auxiliary[*index] += step[column];
        }
        let mut deltas = vec![0.0; robot.parameters().len()];
        for (position, index) in parameters.iter().enumerate() {
            deltas[*index] = step[self.base_auxiliary.len() + position];
        }
        robot.apply_deltas(&deltas)?;
        Ok((robot, auxiliary))
    }

    /// Applies a final, negligible correction to the parameters, and to the
    /// residuals through the linear model `r ← r − W Δ` (exact to O(‖Δ‖²),
    /// below 1e-16 m for a negligible Δ) instead of re-evaluating the model.
    fn polish(&self, mut current: Iterate, step: &[f64], parameters: &[usize]) -> Iterate {
        let Ok((robot, auxiliary)) = self.stepped(&current, step, parameters) else {
            return current;
        };
        current.system.apply_linear_step(step);
        current.normal.apply_step(step);
        current.cost = current
            .system
            .weighted_residuals()
            .iter()
            .map(|r| r * r)
            .sum();
        current.robot = robot;
        current.auxiliary = auxiliary;
        current
    }

    /// Gauss–Newton on the base parameters from `start` (see [`Damping`]).
    ///
    /// A trial iterate is written into the storage of the current one (W is
    /// the largest thing here: 3.7 MB at m = 5000, and fresh memory is slow
    /// to touch); plain steps are nearly always accepted. After the first
    /// refused trial the current system is rebuilt (bit for bit the same) and
    /// a second storage is kept from then on.
    ///
    /// # Errors
    /// Only if rebuilding the current iterate fails, which its first
    /// evaluation did not.
    fn descend(
        &self,
        start: Iterate,
        damping_rule: Damping,
        max_iterations: usize,
        states: &mut StudyStates,
        progress: &mut dyn FnMut(&IterationRecord) -> Result<(), Error>,
    ) -> Result<Run, Error> {
        let mut current = start;
        let mut history = Vec::new();
        let mut damping = if damping_rule == Damping::Always {
            INITIAL_DAMPING
        } else {
            0.0
        };
        let mut stop = StopReason::IterationLimit;
        // The storage of a replaced or refused iterate, reused by the next
        // trial; `None` while trials write into the current iterate's storage.
        let mut spare: Option<ObservationSystem> = None;
        'iterations: while history.len() < max_iterations {
            let right = current.system.weighted_residuals();
            let mut fraction = 1.0;
            loop {
                let system = &current.system;
                let matrix = view(system.matrix(), system.rows(), system.columns());
                let mut step = if damping == 0.0 {
                    step(matrix, &current.normal, &right, self.condition)
                } else {
                    damped_step(matrix, &right, damping)
                };
                if damping <= INITIAL_DAMPING
                    && fraction == 1.0
                    && self.negligible(&step, &current, &self.base)
                {
                    current = self.polish(current, &step, &self.base);
                    stop = StopReason::Converged;
                    break 'iterations;
                }
                step.iter_mut().for_each(|value| *value *= fraction);
                let (storage, shared) = match spare.take() {
                    Some(storage) => (storage, false),
                    None => (std::mem::take(&mut current.system), true),
                };
                let trial =
                    self.stepped(&current, &step, &self.base)
                        .and_then(|(robot, auxiliary)| {
                            self.assemble_into(&robot, &auxiliary, &self.layout, states, storage)
                        });
                match trial {
                    Ok(trial) if trial.cost <= current.cost => {
                        let record = self.record(&trial, &step, damping);
                        progress(&record)?;
                        history.push(record);
                        let previous = std::mem::replace(&mut current, trial).system;
                        spare = (!shared).then_some(previous);
                        damping = match damping_rule {
                            Damping::Always => (damping / 10.0).max(1e-12),
                            _ if damping <= INITIAL_DAMPING => 0.0,
                            _ => damping / 10.0,
                        };
                        break;
                    }
                    refused => {
                        let storage = refused.map(|trial| trial.system).unwrap_or_default();
                        if shared {
                            let (robot, auxiliary) = (current.robot, current.auxiliary);
                            current = self.assemble_into(
                                &robot,
                                &auxiliary,
                                &self.layout,
                                states,
                                storage,
                            )?;
                            spare = Some(ObservationSystem::default());
                        } else {
                            spare = Some(storage);
                        }
                    }
                }
                // A plain step that increases the residual: shorten it along
                // its direction first (backtracking), then damp it.
                if damping == 0.0 && fraction > MIN_FRACTION {
                    fraction *= 0.5;
                } else if damping_rule == Damping::Never || damping >= MAX_DAMPING {
                    stop = StopReason::Diverged;
                    break 'iterations;
                } else {
                    fraction = 1.0;
                    damping = if damping == 0.0 {
                        INITIAL_DAMPING
                    } else {
                        damping * 10.0
                    };
                }
            }
        }
        Ok(Run {
            best: current,
            history,
            stop,
        })
    }

    /// The minimum-norm route from `start` (see the module docs).
    fn minimum_norm_route(
        &self,
        start: (&Robot, &[f64]),
        effective: &[usize],
        states: &mut StudyStates,
        progress: &mut dyn FnMut(&IterationRecord) -> Result<(), Error>,
    ) -> Result<Run, Error> {
        let (start_robot, start_auxiliary) = start;
        let auxiliary_count = start_auxiliary.len();
        let layout = ColumnLayout::with_auxiliary(
            self.nominal.parameters().len(),
            effective,
            auxiliary_count,
            &self.base_auxiliary,
        );
        let rank = self.base.len() + self.base_auxiliary.len();
        let mut current = self.assemble(start_robot, start_auxiliary, &layout, states)?;
        let mut history = Vec::new();
        // Phase 1: minimum-norm steps over every parameter with an effect.
        let mut reached = false;
        'iterations: while history.len() < self.options.max_iterations {
            let matrix = view(current.system.matrix(), self.rows, layout.columns());
            let step = minimum_norm_step(matrix, &current.system.weighted_residuals(), rank)?;
            if self.negligible(&step, &current, effective) {
                current = self.polish(current, &step, effective);
                reached = true;
                break;
            }
            let mut fraction = 1.0;
            loop {
                let scaled: Vec<f64> = step.iter().map(|v| v * fraction).collect();
                let trial =
                    self.stepped(&current, &scaled, effective)
                        .and_then(|(robot, auxiliary)| {
                            self.assemble(&robot, &auxiliary, &layout, states)
                        });
                match trial {
                    Ok(trial) if trial.cost <= current.cost => {
                        let record = self.record(&trial, &scaled, 0.0);
                        progress(&record)?;
                        history.push(record);
                        current = trial;
                        break;
                    }
                    _ if fraction > MIN_FRACTION => fraction *= 0.5,
                    _ => break 'iterations,
                }
            }
        }
        let reached_cost = current.cost;
        let mut current =
            self.assemble(&current.robot, &current.auxiliary, &self.layout, states)?;
        if !reached {
            return Ok(Run {
                best: current,
                history,
                stop: StopReason::Diverged,
            });
        }
        // Phase 2: continuation of the non-base parameters back to nominal,
        // as far as an exact solution exists: first straight to nominal, then
        // by halves.
        let free: Vec<usize> = effective
            .iter()
            .copied()
            .filter(|i| !self.base.contains(i))
            .collect();
        let from: Vec<f64> = free
            .iter()
            .map(|i| current.robot.parameter(current.robot.parameters().id(*i)))
            .collect();
        let floor = self.rows as f64 * 1e-24;
        let (mut done, mut stride) = (0.0_f64, 1.0_f64);
        for _ in 0..CONTINUATION_ATTEMPTS {
            if done >= 1.0 {
                break;
            }
            let target = (done + stride).min(1.0);
            let mut robot = current.robot.clone();
            for (index, start_value) in free.iter().zip(&from) {
                let id = robot.parameters().id(*index);
                let nominal = self.nominal.parameter(id);
                robot.set_parameter(id, start_value + target * (nominal - start_value))?;
            }
            let mut stage_records = Vec::new();
            let run = self
                .assemble(&robot, &current.auxiliary, &self.layout, states)
                .and_then(|moved| {
                    self.descend(
                        moved,
                        Damping::WhenNeeded,
                        CONTINUATION_ITERATIONS,
                        states,
                        &mut |record| {
                            stage_records.push(*record);
                            Ok(())
                        },
                    )
                });
            match run {
                Ok(run)
                    if run.stop == StopReason::Converged
                        && run.best.cost <= reached_cost * 1.001 + floor =>
                {
                    for record in &run.history {
                        progress(record)?;
                    }
                    history.extend(run.history);
                    current = run.best;
                    done = target;
                    stride = 1.0 - done;
                }
                _ => stride *= 0.5,
            }
        }
        Ok(Run {
            best: current,
            history,
            stop: StopReason::Converged,
        })
    }
}

fn norm(values: &[f64]) -> f64 {
    values.iter().map(|v| v * v).sum::<f64>().sqrt()
}

/// Identifies the base parameters of `robot` from `study` (see the module docs).
///
/// # Errors
/// Invalid data; [`Error::TooFewEquations`] when there are no more equations
/// than identifiable unknowns; [`Error::Numerical`] when nothing is
/// identifiable or the data produce non-finite values.
pub fn identify(
    robot: &Robot,
    study: &Study,
    options: &IdentificationOptions,
) -> Result<Identification, Error> {
    identify_with_progress(robot, study, options, |_| ControlFlow::Continue(()))
}

/// [`identify`], calling `progress` after the starting point and after every
/// accepted update (to show progress on long identifications). When it
/// answers [`ControlFlow::Break`] the identification stops there with
/// [`Error::Interrupted`] (a user's Ctrl-C, a closed page).
///
/// # Errors
/// As [`identify`], and [`Error::Interrupted`].
pub fn identify_with_progress(
    robot: &Robot,
    study: &Study,
    options: &IdentificationOptions,
    mut progress: impl FnMut(&IterationRecord) -> ControlFlow<()>,
) -> Result<Identification, Error> {
    let mut progress = |record: &IterationRecord| match progress(record) {
        ControlFlow::Continue(()) => Ok(()),
        ControlFlow::Break(()) => Err(Error::Interrupted),
    };
    check_options(robot, options)?;
    let first = fit(robot, study, options, &mut progress)?;
    if !options.reject || first.outliers.is_empty() {
        return Ok(first);
    }
    let kept = study.without_samples(&outliers::outlier_samples(study, &first.outliers));
    let mut refit =
        fit(robot, &kept, options, &mut progress).map_err(|error| Error::Numerical {
            message: format!(
                "after rejecting {} outliers the rest cannot be identified: {error}",
                first.outliers.len()
            ),
        })?;
    refit.warnings.insert(
        0,
        format!(
            "{} observations beyond {} σ̂ were rejected and the rest identified again",
            first.outliers.len(),
            options.outlier_threshold
        ),
    );
    refit.rejected = first.outliers;
    Ok(refit)
}

/// Checks the options a user gives beyond the robot and data.
fn check_options(robot: &Robot, options: &IdentificationOptions) -> Result<(), Error> {
    let threshold = options.outlier_threshold;
    if !(threshold.is_finite() && threshold > 0.0) {
        return Err(Error::InvalidOption {
            setting: Setting::OutlierThreshold,
            message: format!("must be a positive number of robust σ, not {threshold}"),
        });
    }
    if !options.loss.is_l2() {
        Loss::with_scale(options.loss.kind, options.loss.scale)?;
    }
    if let Some(prior) = &options.prior {
        prior.check(robot)?;
    }
    Ok(())
}

/// One identification of `study` (see the module docs).
fn fit(
    robot: &Robot,
    study: &Study,
    options: &IdentificationOptions,
    progress: &mut dyn FnMut(&IterationRecord) -> Result<(), Error>,
) -> Result<Identification, Error> {
    let mut progress = |record: &IterationRecord| progress(record);
    study.check(robot)?;
    let priority = options.priority.clone().unwrap_or_else(|| robot.priority());
    priority.validate(robot.parameters())?;
    let mut states = StudyStates::default();
    study.evaluate_poses(robot, &mut states)?;
    let initial_auxiliary = study.initial_auxiliary(&states)?;
    // The base set: structural (random, constraint-satisfying data), then what
    // these data excite (paper §3.1, §4).
    let rank = structural_parameters_at(robot, study, &states, &priority, STRUCTURAL_SEED)?;
    let excited = excitation_at(robot, study, &mut states, &initial_auxiliary, &rank)?;
    let base = excited.report.base_parameters.clone();
    let base_auxiliary = excited.report.base_auxiliary.clone();
    if base.is_empty() {
        return Err(Error::Numerical {
            message:
                "no robot parameter is identifiable from these data (see `gecaro identifiable`)"
                    .into(),
        });
    }
    let unknowns = base.len() + base_auxiliary.len();
    let equations = study.equation_count();
    if equations <= unknowns {
        return Err(Error::TooFewEquations {
            equations,
            unknowns: unknowns + 1,
        });
    }
    let layout = ColumnLayout::with_auxiliary(
        robot.parameters().len(),
        &base,
        initial_auxiliary.len(),
        &base_auxiliary,
    );
    let problem = Problem {
        study,
        nominal: robot,
        options,
        base,
        base_auxiliary,
        layout,
        rows: study.row_count(),
        condition: excited.report.condition_number(),
        weighting: Weighting::default(),
    };
    // The excitation check built W_b at the nominal parameters already: reuse
    // it when every structural base parameter is excited (same columns).
    let start = match excited.system {
        Some(system) if excited.not_excited.is_empty() => {
            Problem::iterate_of(robot, &initial_auxiliary, system)?
        }
        _ => problem.assemble(robot, &initial_auxiliary, &problem.layout, &mut states)?,
    };
    let before = ErrorSummary::of(&start.system);
    let errors_before = start.system.observation_errors();
    let first = problem.record(&start, &[], 0.0);
    progress(&first)?;

    let (run, route) = match options.solver {
        Solver::LevenbergMarquardt => (
            problem.descend(
                start,
                Damping::Always,
                options.max_iterations,
                &mut states,
                &mut progress,
            )?,
            Route::LevenbergMarquardt,
        ),
        Solver::GaussNewton => {
            let plain = problem.descend(
                start,
                Damping::Never,
                options.max_iterations,
                &mut states,
                &mut progress,
            )?;
            if plain.stop == StopReason::Converged {
                (plain, Route::GaussNewton)
            } else {
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
                progress(&first)?;
                let robust = problem.minimum_norm_route(
                    (robot, &initial_auxiliary),
                    &effective,
                    &mut states,
                    &mut progress,
                )?;
                if robust.stop == StopReason::Converged || robust.best.cost < plain.best.cost {
                    (robust, Route::MinimumNorm)
                } else {
                    (plain, Route::GaussNewton)
                }
            }
        }
    };
    let prior_rows = options
        .prior
        .as_ref()
        .map(|prior| prior_rows(prior, robot, &problem, excited.report.relations()))
        .unwrap_or_default();
    let Reweighted {
        run: Run {
            best,
            history: updates,
            stop,
        },
        weighting,
        statistics,
        reweightings,
    } = problem.reweighted(run, options.loss, prior_rows, &mut states, &mut progress)?;
    let prior_std = |column: usize| {
        weighting
            .prior_rows
            .iter()
            .find(|row| row.column == column)
            .map(|row| row.sigma)
    };
    let mut history = vec![first];
    history.extend(updates);

    // Precision at the solution: σ² (W_bᵀ W_b)⁻¹, and the condition number of W_b
    // (of the data's rows: prior rows would hide a poor excitation).
    let system = &best.system;
    let columns = problem.layout.columns();
    let matrix = view(system.matrix(), system.rows(), columns);
    let (solved, mut condition_number) = precision(matrix, &best.normal, problem.condition)?;
    if !weighting.prior_rows.is_empty() {
        let rows = system.measured_rows();
        let data = view(&system.matrix()[..rows * columns], rows, columns);
        let right = system.weighted_residuals();
        let normal = NormalEquations::of(data, &right[..rows]);
        condition_number = precision(data, &normal, problem.condition)?.1;
    }
    // σ² = Σ w e²/(n_eff − b): ‖r‖²/(equations − b) in least squares.
    let variance = statistics.variance;
    let std = |column: usize| (variance * solved.inverse_normal_diagonal[column]).sqrt();
    let auxiliary_names = study.auxiliary_names();
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
            prior_std: None,
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
                prior_std: prior_std(auxiliary_columns + position),
            }
        })
        .collect();
    let moved: Vec<IdentifiedParameter> = robot
        .parameters()
        .ids()
        .iter()
        .filter(|id| {
            let index = robot.parameters().index_of(**id).unwrap_or(usize::MAX);
            !problem.base.contains(&index)
                && (best.robot.parameter(**id) - robot.parameter(**id)).abs() > 1e-12
        })
        .map(|id| IdentifiedParameter {
            name: id.to_string(),
            parameter: Some(*id),
            nominal: robot.parameter(*id),
            identified: best.robot.parameter(*id),
            std: f64::NAN,
            prior_std: None,
        })
        .collect();
    let warnings = warnings(
        study,
        &excited.not_excited,
        condition_number,
        &parameters,
        &moved,
    );
    let errors_after = best.system.observation_errors();
    let has_rotation = best.system.kinds().contains(&crate::RowKind::Angle);
    let outliers = outliers::find_outliers(
        study,
        &statistics,
        &errors_after,
        has_rotation,
        options.outlier_threshold,
    );
    Ok(Identification {
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
        after: ErrorSummary::of(&best.system),
        errors_after,
        errors_before,
        before,
        calibrated: best.robot,
        rank,
        history,
        route,
        parameters,
        auxiliary,
        residual_sigma: variance.sqrt(),
        stop_reason: stop,
        not_excited: excited.not_excited,
    })
}

/// The prior's rows for the base parameters of `problem` (weights set by the
/// reweighted phase), with the regrouped priors of [`Prior::base_sigma`].
fn prior_rows(
    prior: &Prior,
    robot: &Robot,
    problem: &Problem<'_>,
    relations: &[crate::Relation],
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

/// The warnings of an identification (see [`Identification::warnings`]).
fn warnings(
    study: &Study,
    not_excited: &[String],
    condition_number: f64,
    parameters: &[IdentifiedParameter],
    moved: &[IdentifiedParameter],
) -> Vec<String> {
    let mut warnings = Vec::new();
    if !not_excited.is_empty() {
        warnings.push(format!(
            "the data do not excite {}: not identified, left at their nominal values",
            not_excited.join(", ")
        ));
    }
    if condition_number > POOR_CONDITIONING {
        let mut relative: Vec<(&IdentifiedParameter, f64)> = parameters
            .iter()
            .map(|p| {
                (
                    p,
                    p.std / (p.identified.abs() + if p.name.starts_with('K') { 1.0 } else { 1e-3 }),
                )
            })
            .collect();
        relative.sort_by(|a, b| b.1.total_cmp(&a.1));
        let worst: Vec<String> = relative
            .iter()
            .take(3)
            .map(|(p, _)| format!("{} (σ {:.1e})", p.name, p.std))
            .collect();
        warnings.push(format!(
            "the data excite the robot poorly: condition number of W_b {condition_number:.1e} (above {POOR_CONDITIONING:.0e}); \
             the least determined parameters are {}; add configurations that move these joints more",
            worst.join(", ")
        ));
    }
    if !study.observes_scale() {
        warnings.push(
            "no measurement here observes the robot's scale (link and plane methods measure no length): \
             it is pinned by lengths outside the base set held at nominal, and noise can move it far; \
             add a distance measurement to the study to fix it"
                .into(),
        );
    }
    if !moved.is_empty() {
        warnings.push(format!(
            "{} parameters outside the base set were moved too: with them at nominal, the base set (chosen at \
             the nominal geometry) cannot reproduce these data",
            moved.len()
        ));
    }
    warnings
}

/// Error statistics of a (calibrated) robot on a study: per configuration (or
/// pair), the norm of its position-like residuals — distance to the measured
/// point, to the mean point of its set, to the plane, or the distance error —
/// and of its orientation residuals.
///
/// # Errors
/// Invalid data, or auxiliary unknowns that cannot be initialised.
pub fn evaluate(robot: &Robot, study: &Study) -> Result<ErrorSummary, Error> {
    study.check(robot)?;
    let mut states = StudyStates::default();
    study.evaluate_poses(robot, &mut states)?;
    let auxiliary = study.initial_auxiliary(&states)?;
    let layout = ColumnLayout::new(robot.parameters().len(), &[], auxiliary.len());
    let mut system = ObservationSystem::default();
    study.linearise(robot, &auxiliary, &layout, &mut states, &mut system)?;
    Ok(ErrorSummary::of(&system))
}
