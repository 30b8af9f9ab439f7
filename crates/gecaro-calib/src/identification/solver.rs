//! The descent of an identification: Gauss–Newton steps on the base
//! parameters (the paper's scheme, with backtracking), Levenberg–Marquardt
//! damping, and the minimum-norm route with its continuation back to the base
//! set (see the parent module docs for when each is taken).

use gecaro_core::Robot;

use super::options::IdentificationOptions;
use super::verdict::StopReason;
use super::weighting::Weighting;
use crate::Error;
use crate::fold::FoldKind;
use crate::identifiability::{Excitation, RankReport, excitation_at};
use crate::linalg::{
    LeastSquaresRows, NORMAL_EQUATIONS_CONDITION, NormalEquations, damped_step, minimum_norm_step,
    predicted_decrease, step,
};
use crate::observation::ObservationSystem;
use crate::progress::{IterationRecord, Observer, Progress, Quiet, report};
use crate::rows::ColumnLayout;
use crate::study::{Study, StudyStates};

/// Largest damping tried before a step is declared impossible.
const MAX_DAMPING: f64 = 1e12;
const INITIAL_DAMPING: f64 = 1e-3;
/// A step that cannot lower the cost by more than this fraction is negligible.
const COST_TOLERANCE: f64 = 1e-12;
/// Shortest fraction of a step tried when backtracking.
const MIN_FRACTION: f64 = 1.0 / 64.0;
/// Updates over which a descent that reached its iteration limit is judged
/// flat ([`at_the_minimum`]).
const FLAT_UPDATES: usize = 5;
/// The relative decrease of the cost over the last [`FLAT_UPDATES`] below
/// which a descent at its iteration limit is at the minimum.
const FLAT_DECREASE: f64 = 1e-6;

/// Whether a descent that reached its iteration limit is at the minimum:
/// its last [`FLAT_UPDATES`] updates lowered the cost by less than
/// [`FLAT_DECREASE`] of it. On data with a model error beyond the noise
/// (a real UR10's position data, 14× the tracker's σ) the steps may keep
/// moving along directions the data barely see while the RMS stays flat
/// from iteration 13 to the limit: that is a minimum, whose verdict says
/// how far above the noise it is, not a failure to converge.
fn at_the_minimum(history: &[IterationRecord]) -> bool {
    let Some(window) = history.len().checked_sub(FLAT_UPDATES + 1) else {
        return false;
    };
    let (first, last) = (history[window].rms, history[history.len() - 1].rms);
    let decrease = first * first - last * last;
    last.is_finite() && decrease <= FLAT_DECREASE * last * last
}
/// Largest ratio of a step to the one before it at which the descent's
/// steps are taken to contract ([`Problem::is_final`]): near a minimum
/// Gauss–Newton shrinks them by orders of magnitude (1.9e-3, then 2.3e-6,
/// on the Stanford arm's 5,000 positions).
const FINAL_CONTRACTION: f64 = 0.1;
/// Continuation stages tried (the first goes straight to nominal).
const CONTINUATION_ATTEMPTS: usize = 8;
/// Iterations allowed to re-converge the base parameters after a stage.
const CONTINUATION_ITERATIONS: usize = 10;
/// Parameters, auxiliary values and the system they give.
#[derive(Clone)]
pub(super) struct Iterate {
    pub(super) robot: Robot,
    pub(super) auxiliary: Vec<f64>,
    pub(super) system: ObservationSystem,
    /// The system's normal equations (its step, predicted decrease, precision).
    pub(super) normal: NormalEquations,
    pub(super) cost: f64,
}

/// How a descent treats a step that increases the residual.
#[derive(Copy, Clone, PartialEq, Eq)]
pub(super) enum Damping {
    /// Plain steps only: stop (diverged) at the first increase.
    Never,
    /// Plain steps, damped when one increases the residual.
    WhenNeeded,
    /// Damped from the first step.
    Always,
}

/// What a computed step is worth at an iterate ([`Problem::worth`]).
#[derive(Copy, Clone, PartialEq, Eq, Debug)]
pub(super) enum StepWorth {
    /// Worth an evaluation: the descent goes on.
    Descent,
    /// Small against the parameters (`‖Δ‖ ≤ step_tolerance · (1 + ‖η‖)`):
    /// applied through the linear model, exact to O(‖Δ‖²).
    Small,
    /// Not small, yet unable to lower the cost by more than a relative
    /// 1e-12: a direction the data barely see (rounding at the minimum, or a
    /// near-null direction of W). Left out: the linear model is exact along
    /// it only to first order, and a long step's second-order effect is what
    /// the data would see. (A noise-free frame fit of the Stanford arm, 60
    /// configurations, took a 0.12 rad step along θ3, θ4 and the tilt of z4
    /// that way: the linear model said 1e-14 m, the calibrated robot was
    /// 0.011 mm from its own data.)
    Unproductive,
}

/// The result of one descent.
pub(super) struct Run {
    pub(super) best: Iterate,
    pub(super) history: Vec<IterationRecord>,
    pub(super) stop: StopReason,
}

/// Everything an identification iterates on.
pub(super) struct Problem<'a> {
    pub(super) study: &'a Study,
    pub(super) nominal: &'a Robot,
    pub(super) options: &'a IdentificationOptions,
    /// Vocabulary indices of the base parameters (column order).
    pub(super) base: Vec<usize>,
    /// Indices of the identified auxiliary unknowns.
    pub(super) base_auxiliary: Vec<usize>,
    /// Columns: identified auxiliary unknowns, then base parameters.
    pub(super) layout: ColumnLayout,
    pub(super) rows: usize,
    /// Condition number of W_b at the start with its columns scaled to
    /// unit norm ([`NormalEquations::equilibrated_condition`]): chooses
    /// between the normal equations and QR (see `linalg::step`).
    pub(super) condition: f64,
    /// Robust weights and prior rows of the reweighted phase (none in plain least squares).
    pub(super) weighting: Weighting,
    /// Base parameters at the end of `base` that a pass joined to the
    /// structural base set ([`super::tied`]): held by a prior, they are left
    /// out of the excitation's condition number and of the unknowns the
    /// data must determine.
    pub(super) joined: usize,
}

impl<'a> Problem<'a> {
    /// The problem of `study` on the base set of `rank` that the data
    /// excite at `from` (paper §4's excitation check), with `nominal` the
    /// robot the pass is reported against and holds fixed outside the base
    /// set, and the iterate at `from` with `auxiliary` (the excitation
    /// check's own system when every structural base parameter is excited:
    /// the same columns). `states` holds the poses at `from`.
    ///
    /// # Errors
    /// Nothing identifiable, no more equations than unknowns, or a system
    /// that is not finite.
    pub(super) fn excited(
        nominal: &'a Robot,
        study: &'a Study,
        options: &'a IdentificationOptions,
        rank: &RankReport,
        (from, auxiliary): (&Robot, &[f64]),
        states: &mut StudyStates,
    ) -> Result<(Problem<'a>, Excitation, Iterate), Error> {
        let mut excited =
            excitation_at(from, study, states, auxiliary, rank, options.streamed_rows)?;
        let base = excited.report.base_parameters.clone();
        let base_auxiliary = excited.report.base_auxiliary.clone();
        if base.is_empty() {
            return Err(Error::Numerical {
                message: "no robot parameter is identifiable from these data (see the \
                          identifiable parameters of the method)"
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
            nominal.parameters().len(),
            &base,
            auxiliary.len(),
            &base_auxiliary,
        );
        let mut problem = Problem {
            study,
            nominal,
            options,
            base,
            base_auxiliary,
            layout,
            rows: study.row_count(),
            // Set from the starting iterate's W_b below.
            condition: f64::INFINITY,
            weighting: Weighting::default(),
            joined: 0,
        };
        // The excitation check built W_b at `from` already: reuse it when
        // every structural base parameter is excited (same columns).
        let start = match excited.system.take() {
            Some(system) if excited.not_excited.is_empty() => {
                Problem::iterate_of(from, auxiliary, system)?
            }
            _ => problem.assemble(from, auxiliary, &problem.layout, states)?,
        };
        // The solver's choice (normal equations or QR) by the condition
        // number that decides their accuracy: that of W_b with unit columns.
        problem.condition = start.normal.equilibrated_condition();
        Ok((problem, excited, start))
    }

    /// This problem with `weighting` (robust weights, prior rows).
    pub(super) fn with_weighting(&self, weighting: Weighting) -> Problem<'a> {
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
            joined: self.joined,
        }
    }

    /// This problem on `study` (the same samples with other loads).
    pub(super) fn with_study<'b>(&self, study: &'b Study) -> Problem<'b>
    where
        'a: 'b,
    {
        Problem {
            study,
            ..self.with_weighting(self.weighting.clone())
        }
    }

    pub(super) fn assemble(
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
    pub(super) fn assemble_into(
        &self,
        robot: &Robot,
        auxiliary: &[f64],
        layout: &ColumnLayout,
        states: &mut StudyStates,
        mut system: ObservationSystem,
    ) -> Result<Iterate, Error> {
        system.set_observation_weights(self.weighting.observation_weights.clone());
        system.set_folding(self.folding());
        self.study
            .linearise(robot, auxiliary, layout, states, &mut system)?;
        self.weighting.append_rows(&mut system, robot);
        Self::iterate_of(robot, auxiliary, system)
    }

    /// How this problem's systems are written: folded as they are written
    /// when they are tall ([`IdentificationOptions::streamed_rows`]), into
    /// the normal equations where they are accurate, else into a
    /// triangular factor (see [`crate::fold`]).
    pub(super) fn folding(&self) -> Option<FoldKind> {
        self.study
            .is_streamed(self.options.streamed_rows)
            .then_some(if self.condition < NORMAL_EQUATIONS_CONDITION {
                FoldKind::Gram
            } else {
                FoldKind::Factor
            })
    }

    /// The iterate of a system written at `robot` and `auxiliary`.
    pub(super) fn iterate_of(
        robot: &Robot,
        auxiliary: &[f64],
        system: ObservationSystem,
    ) -> Result<Iterate, Error> {
        let cost = system.weighted_cost();
        let normal = system.normal_equations();
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

    pub(super) fn record(&self, iterate: &Iterate, step: &[f64], damping: f64) -> IterationRecord {
        IterationRecord {
            rms: (iterate.cost / iterate.system.rows().max(1) as f64).sqrt(),
            step: norm(step),
            damping,
        }
    }

    /// The length of a negligible step over `parameters` at `iterate`:
    /// `step_tolerance · (1 + ‖η_b‖)`.
    fn negligible(&self, iterate: &Iterate, parameters: &[usize]) -> f64 {
        let robot = &iterate.robot;
        let scale = norm(
            &parameters
                .iter()
                .map(|i| robot.parameter(robot.parameters().id(*i)))
                .collect::<Vec<_>>(),
        );
        self.options.step_tolerance * (1.0 + scale)
    }

    /// Whether a plain step of the descent is its last: the steps contract
    /// (‖Δ_k‖ ≤ ρ‖Δ_{k−1}‖ with ρ ≤ [`FINAL_CONTRACTION`]) so fast that
    /// the steps after this one, at most ρ/(1 − ρ)·‖Δ_k‖ together (a
    /// geometric series: Gauss–Newton's linear convergence at its slowest;
    /// it is quadratic on data that fit), are negligible. The step is then
    /// applied without W evaluated at its end ([`Problem::last_step`]).
    fn is_final(&self, step: &[f64], previous: &IterationRecord, iterate: &Iterate) -> bool {
        if previous.damping != 0.0 || previous.step <= 0.0 {
            return false;
        }
        let length = norm(step);
        let contraction = length / previous.step;
        contraction <= FINAL_CONTRACTION
            && contraction / (1.0 - contraction) * length <= self.negligible(iterate, &self.base)
    }

    /// The iterate after a final step ([`Problem::is_final`]): W kept from
    /// the step's start, the residuals `r − WΔ` of the linear model (exact
    /// to O(‖Δ‖²), [`Problem::polish`]) — a folded system's measured
    /// residuals, whose rows of W are not held, evaluated at the new
    /// parameters (the model's poses, no Jacobian).
    ///
    /// # Errors
    /// When the model cannot be evaluated at the new parameters.
    fn last_step(
        &self,
        current: Iterate,
        step: &[f64],
        states: &mut StudyStates,
    ) -> Result<Iterate, Error> {
        if !current.system.is_folded() {
            return Ok(self.polish(current, step, &self.base));
        }
        let (robot, auxiliary) = self.stepped(&current, step, &self.base)?;
        let mut measured = current.system.for_residuals();
        let layout =
            ColumnLayout::with_auxiliary(robot.parameters().len(), &[], auxiliary.len(), &[]);
        self.study
            .linearise(&robot, &auxiliary, &layout, states, &mut measured)?;
        let mut current = current;
        current.system.apply_linear_step(step);
        current.system.take_measured_residuals(&measured);
        current.normal.apply_step(step);
        current.cost = current.system.weighted_cost();
        current.robot = robot;
        current.auxiliary = auxiliary;
        Ok(current)
    }

    /// What a step over `parameters` (vocabulary indices, after the
    /// auxiliary columns) is worth at `iterate` (see [`StepWorth`]): small
    /// against the parameters, or unable to lower the cost by more than a
    /// relative 1e-12 (a least-squares step lowers ‖r‖² by ‖W·Δ‖² at most).
    /// The second test ends iterations on noisy, ill-conditioned data, where
    /// rounding keeps the computed correction from vanishing at the minimum.
    pub(super) fn worth(&self, step: &[f64], iterate: &Iterate, parameters: &[usize]) -> StepWorth {
        if norm(step) <= self.negligible(iterate, parameters) {
            return StepWorth::Small;
        }
        let decrease = predicted_decrease(&iterate.normal, step, self.condition, || {
            iterate.system.solver_rows(false)
        });
        if decrease <= COST_TOLERANCE * iterate.cost {
            StepWorth::Unproductive
        } else {
            StepWorth::Descent
        }
    }

    /// The last iterate of a descent whose `step` is not worth another
    /// evaluation: a small step applied by [`Problem::polish`], an
    /// unproductive one left out.
    fn finish(
        &self,
        current: Iterate,
        step: &[f64],
        worth: StepWorth,
        parameters: &[usize],
    ) -> Iterate {
        match worth {
            StepWorth::Small => self.polish(current, step, parameters),
            StepWorth::Unproductive | StepWorth::Descent => current,
        }
    }

    /// Adds `step` (auxiliary columns first, then `parameters`) to an iterate.
    pub(super) fn stepped(
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
    pub(super) fn polish(
        &self,
        mut current: Iterate,
        step: &[f64],
        parameters: &[usize],
    ) -> Iterate {
        let Ok((robot, auxiliary)) = self.stepped(&current, step, parameters) else {
            return current;
        };
        // A folded system's measured residuals stay (see
        // `apply_linear_step`): its cost follows the normal equations.
        let folded_cost = current.normal.cost_after(current.cost, step);
        current.system.apply_linear_step(step);
        current.normal.apply_step(step);
        current.cost = if current.system.is_folded() {
            folded_cost
        } else {
            current.system.weighted_cost()
        };
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
    pub(super) fn descend(
        &self,
        start: Iterate,
        damping_rule: Damping,
        max_iterations: usize,
        states: &mut StudyStates,
        observer: &mut dyn Observer,
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
            let mut fraction = 1.0;
            loop {
                // The rows (a tall system's right-hand sides, a folded
                // one's stand-in) are made only where the step reads them.
                let rows = || current.system.solver_rows(false);
                let mut step = if damping == 0.0 {
                    step(&current.normal, self.condition, rows)
                } else {
                    let rows = rows();
                    damped_step(rows.matrix(), rows.right(), damping)
                };
                if damping <= INITIAL_DAMPING && fraction == 1.0 {
                    let worth = self.worth(&step, &current, &self.base);
                    if worth != StepWorth::Descent {
                        current = self.finish(current, &step, worth, &self.base);
                        stop = StopReason::Converged;
                        break 'iterations;
                    }
                    if damping == 0.0
                        && history
                            .last()
                            .is_some_and(|previous| self.is_final(&step, previous, &current))
                    {
                        current = self.last_step(current, &step, states)?;
                        let record = self.record(&current, &step, damping);
                        report(observer, Progress::Iteration(&record))?;
                        history.push(record);
                        stop = StopReason::Converged;
                        break 'iterations;
                    }
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
                        report(observer, Progress::Iteration(&record))?;
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
        if stop == StopReason::IterationLimit && at_the_minimum(&history) {
            stop = StopReason::Converged;
        }
        Ok(Run {
            best: current,
            history,
            stop,
        })
    }

    /// The minimum-norm route from `start` (see the module docs).
    pub(super) fn minimum_norm_route(
        &self,
        start: (&Robot, &[f64]),
        effective: &[usize],
        states: &mut StudyStates,
        observer: &mut dyn Observer,
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
        let mut stuck = false;
        'iterations: while history.len() < self.options.max_iterations {
            // Data rows, and any a prior or gauge appends.
            let rows = current.system.solver_rows(false);
            let step = minimum_norm_step(rows.matrix(), rows.right(), rank)?;
            drop(rows);
            let worth = self.worth(&step, &current, effective);
            if worth != StepWorth::Descent {
                current = self.finish(current, &step, worth, effective);
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
                        report(observer, Progress::Iteration(&record))?;
                        history.push(record);
                        current = trial;
                        break;
                    }
                    _ if fraction > MIN_FRACTION => fraction *= 0.5,
                    _ => {
                        stuck = true;
                        break 'iterations;
                    }
                }
            }
        }
        // A flat phase at its iteration limit has reached its minimum too.
        reached |= !stuck && at_the_minimum(&history);
        let reached_cost = current.cost;
        let mut current =
            self.assemble(&current.robot, &current.auxiliary, &self.layout, states)?;
        if !reached {
            return Ok(Run {
                best: current,
                history,
                stop: if stuck {
                    StopReason::Diverged
                } else {
                    StopReason::IterationLimit
                },
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
            let run = self
                .assemble(&robot, &current.auxiliary, &self.layout, states)
                .and_then(|moved| {
                    self.descend(
                        moved,
                        Damping::WhenNeeded,
                        CONTINUATION_ITERATIONS,
                        states,
                        &mut Quiet,
                    )
                });
            match run {
                Ok(run)
                    if run.stop == StopReason::Converged
                        && run.best.cost <= reached_cost * 1.001 + floor =>
                {
                    for record in &run.history {
                        report(observer, Progress::Iteration(record))?;
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

pub(super) fn norm(values: &[f64]) -> f64 {
    values.iter().map(|v| v * v).sum::<f64>().sqrt()
}

#[cfg(test)]
mod flat_tests {
    use super::*;

    fn history(rms: &[f64]) -> Vec<IterationRecord> {
        rms.iter()
            .map(|rms| IterationRecord {
                rms: *rms,
                step: 1.0,
                damping: 0.0,
            })
            .collect()
    }

    #[test]
    fn a_flat_tail_is_a_minimum_and_a_descent_is_not() {
        let flat = [
            9.0,
            5.0,
            0.25,
            0.25 + 1e-8,
            0.25,
            0.25 - 1e-9,
            0.25 - 2e-9,
            0.25 - 3e-9,
        ];
        assert!(at_the_minimum(&history(&flat)));
        let descending = [9.0, 5.0, 0.30, 0.29, 0.28, 0.27, 0.26, 0.25];
        assert!(!at_the_minimum(&history(&descending)));
        assert!(!at_the_minimum(&history(&[0.25, 0.25, 0.25])));
    }
}
