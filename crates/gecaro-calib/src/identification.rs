//! Identification (paper §3.1, eq. 9–10): iterative linearised least squares.
//!
//! The identifiable parameters are first determined on the data themselves
//! (Appendix III, [`crate::identifiable_parameters`]). Then, from the nominal
//! parameters, each iteration rebuilds W_b and Δy from the updated
//! parameters and solves `W_b Δη_b = Δy` in the least-squares sense (eq. 10,
//! QR of W_b); the base parameters and the methods' auxiliary unknowns are
//! updated by Δη_b. The regrouped parameters keep their nominal values: their
//! effect is carried by the base parameters that absorb them.
//!
//! Plain Gauss–Newton steps, as in the paper, are the default. When a plain
//! step would increase the residual, the step is damped (Levenberg–Marquardt,
//! `min ‖W Δ − Δy‖² + λ‖D Δ‖²` with D the column norms of W) until it lowers
//! it, and λ is relaxed again after each success. The iteration stops when
//! the correction the data ask for is negligible, `‖Δη_b‖ ≤ tol·(1 + ‖η_b‖)`
//! (converged; that last correction is not counted as an update), when no
//! damping lowers the residual any more (diverged), or at the iteration
//! limit. The best iterate is always returned with the reason it stopped.
//!
//! Precision (eq. 10's least squares): `σ² = ‖r‖²/(equations − b)`, and
//! `cov(Δη_b) = σ² (W_bᵀW_b)⁻¹` at the solution.

use gecaro_core::{ParameterId, PriorityMatrix, Robot};

use crate::Error;
use crate::identifiability::{RankReport, excitation_at, structural_parameters};
use crate::linalg::{condition_number, damped_step, solve_with_covariance, view};
use crate::observation::{ColumnLayout, ObservationSystem};
use crate::study::{Study, StudyStates};

/// How steps are taken.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum Solver {
    /// Plain Gauss–Newton steps (eq. 10), damped only when one would increase the residual.
    #[default]
    GaussNewton,
    /// Levenberg–Marquardt damping from the first step.
    LevenbergMarquardt,
}

/// Settings of [`identify`].
#[derive(Clone, Debug, PartialEq)]
pub struct IdentificationOptions {
    /// Step rule.
    pub solver: Solver,
    /// Iteration limit (parameter updates).
    pub max_iterations: usize,
    /// Priority matrix; the robot's when `None`.
    pub priority: Option<PriorityMatrix>,
    /// A step is negligible when `‖Δη_b‖ ≤ step_tolerance · (1 + ‖η_b‖)`.
    pub step_tolerance: f64,
}

impl Default for IdentificationOptions {
    fn default() -> Self {
        IdentificationOptions {
            solver: Solver::GaussNewton,
            max_iterations: 30,
            priority: None,
            step_tolerance: 1e-10,
        }
    }
}

/// Why the iteration stopped.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum StopReason {
    /// The last step was negligible.
    Converged,
    /// The iteration limit was reached first.
    IterationLimit,
    /// No step, however damped, lowered the residual: the linearisation does
    /// not hold from here (errors too large, or wrong data).
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
    /// Norm of the update ‖Δη_b‖ (0 for the starting point).
    pub step: f64,
    /// The damping λ of the update (0 for a plain step).
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
        let has_angles = system.kinds().contains(&crate::RowKind::Angle);
        let angles: Vec<f64> = errors.iter().map(|e| e.1).collect();
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
    /// Standard deviation of the identified value.
    pub std: f64,
}

/// The result of [`identify`].
#[derive(Clone, Debug)]
pub struct Identification {
    /// The robot with the identified parameters (the best iterate).
    pub calibrated: Robot,
    /// The structural identifiable parameters (random data like these, Appendix III).
    pub rank: RankReport,
    /// Entry 0 is the starting point; then one entry per accepted update.
    pub history: Vec<IterationRecord>,
    /// Errors of the observations at the nominal parameters.
    pub before: ErrorSummary,
    /// Errors of the observations at the identified parameters.
    pub after: ErrorSummary,
    /// Condition number of W_b at the solution.
    pub condition_number: f64,
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
}

impl Identification {
    /// Number of parameter updates.
    pub fn iterations(&self) -> usize {
        self.history.len() - 1
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
}

/// The state being iterated: parameters, auxiliary values and their system.
struct Iterate {
    robot: Robot,
    auxiliary: Vec<f64>,
    system: ObservationSystem,
    cost: f64,
}

/// Largest damping tried before a step is declared impossible.
const MAX_DAMPING: f64 = 1e12;
const INITIAL_DAMPING: f64 = 1e-3;
/// Seed of the random data of the structural analysis: fixed, so that an
/// identification is a pure function of its inputs.
const STRUCTURAL_SEED: u64 = 0x6ECA20;

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
    identify_with_progress(robot, study, options, |_| {})
}

/// [`identify`], calling `progress` after the starting point and after every
/// accepted update (to show progress on long identifications).
///
/// # Errors
/// As [`identify`].
pub fn identify_with_progress(
    robot: &Robot,
    study: &Study,
    options: &IdentificationOptions,
    mut progress: impl FnMut(&IterationRecord),
) -> Result<Identification, Error> {
    study.check(robot)?;
    let priority = options.priority.clone().unwrap_or_else(|| robot.priority());
    priority.validate(robot.parameters())?;
    let mut states = StudyStates::default();
    study.evaluate(robot, &mut states)?;
    let initial_auxiliary = study.initial_auxiliary(&states)?;
    // The base set: structural (random, constraint-satisfying data), then only
    // what these data excite (paper §3.1, §4).
    let rank = structural_parameters(robot, study, &priority, STRUCTURAL_SEED)?;
    let excited = excitation_at(robot, study, &states, &initial_auxiliary, &rank)?;
    let not_excited = excited.not_excited;
    let excited = excited.report;
    let base = &excited.base_parameters;
    let base_auxiliary = &excited.base_auxiliary;
    let unknowns = base.len() + base_auxiliary.len();
    if base.is_empty() {
        return Err(Error::Numerical {
            message:
                "no robot parameter is identifiable from these data (see `gecaro identifiable`)"
                    .into(),
        });
    }
    let equations = study.equation_count();
    if equations <= unknowns {
        return Err(Error::TooFewEquations {
            equations,
            unknowns: unknowns + 1,
        });
    }
    let auxiliary_count = initial_auxiliary.len();
    let layout = ColumnLayout::with_auxiliary(
        robot.parameters().len(),
        base,
        auxiliary_count,
        base_auxiliary,
    );

    let assemble =
        |robot: &Robot, auxiliary: &[f64], states: &mut StudyStates| -> Result<Iterate, Error> {
            study.evaluate(robot, states)?;
            let mut system = ObservationSystem::default();
            study.assemble(states, auxiliary, &layout, &mut system);
            let cost: f64 = system.weighted_residuals().iter().map(|r| r * r).sum();
            if !cost.is_finite() || !system.matrix().iter().all(|v| v.is_finite()) {
                return Err(Error::Numerical {
                    message: "the residuals became non-finite".into(),
                });
            }
            Ok(Iterate {
                robot: robot.clone(),
                auxiliary: auxiliary.to_vec(),
                system,
                cost,
            })
        };
    let rms = |cost: f64, rows: usize| (cost / rows.max(1) as f64).sqrt();

    let mut current = assemble(robot, &initial_auxiliary, &mut states)?;
    let before = ErrorSummary::of(&current.system);
    let rows = current.system.rows();
    let mut history = vec![IterationRecord {
        rms: rms(current.cost, rows),
        step: 0.0,
        damping: 0.0,
    }];
    progress(&history[0]);
    let mut damping = match options.solver {
        Solver::GaussNewton => 0.0,
        Solver::LevenbergMarquardt => INITIAL_DAMPING,
    };
    let mut stop_reason = StopReason::IterationLimit;
    let negligible = |step: &[f64], robot: &Robot| {
        let scale = base
            .iter()
            .map(|index| robot.parameter(robot.parameters().id(*index)).powi(2))
            .sum::<f64>()
            .sqrt();
        norm(step) <= options.step_tolerance * (1.0 + scale)
    };
    while history.len() <= options.max_iterations {
        let matrix = view(current.system.matrix(), rows, layout.columns());
        let right = current.system.weighted_residuals();
        let mut accepted = None;
        loop {
            let step = if damping == 0.0 {
                solve_with_covariance(matrix, &right).solution
            } else {
                damped_step(matrix, &right, damping)
            };
            // Converged when the correction the data ask for is negligible
            // (judged on an undamped or lightly damped step only).
            if damping <= INITIAL_DAMPING && negligible(&step, &current.robot) {
                stop_reason = StopReason::Converged;
                break;
            }
            let trial = apply_step(&current, &step, base, base_auxiliary)
                .and_then(|(robot, auxiliary)| assemble(&robot, &auxiliary, &mut states));
            match trial {
                Ok(trial) if trial.cost <= current.cost => {
                    accepted = Some((trial, step));
                    break;
                }
                _ if damping >= MAX_DAMPING => {
                    // No step lowers the residual: the linearisation does not hold here.
                    stop_reason = StopReason::Diverged;
                    break;
                }
                // A step that increases the residual: damp it (Levenberg–Marquardt).
                _ => {
                    damping = if damping == 0.0 {
                        INITIAL_DAMPING
                    } else {
                        damping * 10.0
                    }
                }
            }
        }
        let Some((trial, step)) = accepted else {
            break;
        };
        history.push(IterationRecord {
            rms: rms(trial.cost, rows),
            step: norm(&step),
            damping,
        });
        progress(&history[history.len() - 1]);
        current = trial;
        damping = match options.solver {
            // Back to plain steps as soon as a damped one has succeeded.
            Solver::GaussNewton => {
                if damping <= INITIAL_DAMPING {
                    0.0
                } else {
                    damping / 10.0
                }
            }
            Solver::LevenbergMarquardt => (damping / 10.0).max(1e-12),
        };
    }

    // Precision at the solution: σ² (W_bᵀ W_b)⁻¹.
    let matrix = view(current.system.matrix(), rows, layout.columns());
    let right = current.system.weighted_residuals();
    let solved = solve_with_covariance(matrix, &right);
    let degrees_of_freedom = (equations - unknowns) as f64;
    let variance = current.cost / degrees_of_freedom;
    let std = |column: usize| (variance * solved.inverse_normal_diagonal[column]).sqrt();
    let auxiliary_names = study.auxiliary_names();
    let auxiliary_columns = base_auxiliary.len();
    let auxiliary = base_auxiliary
        .iter()
        .enumerate()
        .map(|(column, &index)| IdentifiedParameter {
            name: auxiliary_names[index].clone(),
            parameter: None,
            nominal: initial_auxiliary[index],
            identified: current.auxiliary[index],
            std: std(column),
        })
        .collect();
    let parameters = base
        .iter()
        .enumerate()
        .map(|(position, &index)| {
            let id = robot.parameters().id(index);
            IdentifiedParameter {
                name: id.to_string(),
                parameter: Some(id),
                nominal: robot.parameter(id),
                identified: current.robot.parameter(id),
                std: std(auxiliary_columns + position),
            }
        })
        .collect();
    Ok(Identification {
        condition_number: condition_number(matrix)?,
        after: ErrorSummary::of(&current.system),
        before,
        calibrated: current.robot,
        rank,
        history,
        parameters,
        auxiliary,
        residual_sigma: variance.sqrt(),
        stop_reason,
        not_excited,
    })
}

fn norm(values: &[f64]) -> f64 {
    values.iter().map(|v| v * v).sum::<f64>().sqrt()
}

/// The robot and auxiliary values after adding `step` (auxiliary columns first).
fn apply_step(
    current: &Iterate,
    step: &[f64],
    base: &[usize],
    base_auxiliary: &[usize],
) -> Result<(Robot, Vec<f64>), Error> {
    let mut robot = current.robot.clone();
    let mut auxiliary = current.auxiliary.clone();
    for (column, index) in base_auxiliary.iter().enumerate() {
        auxiliary[*index] += step[column];
    }
    let mut deltas = vec![0.0; robot.parameters().len()];
    for (position, index) in base.iter().enumerate() {
        deltas[*index] = step[base_auxiliary.len() + position];
    }
    robot.apply_deltas(&deltas)?;
    Ok((robot, auxiliary))
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
    study.evaluate(robot, &mut states)?;
    let auxiliary = study.initial_auxiliary(&states)?;
    let layout = ColumnLayout::new(robot.parameters().len(), &[], auxiliary.len());
    let mut system = ObservationSystem::default();
    study.assemble(&states, &auxiliary, &layout, &mut system);
    Ok(ErrorSummary::of(&system))
}
