//! The reweighted phase of an identification: a robust loss by iteratively
//! reweighted least squares ([`Loss`]), a Gaussian prior as
//! pseudo-observation rows ([`Prior`](crate::prior::Prior)), or both.
//!
//! Without a robust loss or a prior it only takes the statistics of the
//! least-squares solution (for the outlier report and σ). Otherwise it
//! starts from that solution. Each outer iteration
//! computes, at the current parameters, the robust σ̂ of the scaled
//! residuals, the observations' standardised residuals `u_i` and their
//! weights `w(u_i)`, and the data's a-posteriori variance under those weights
//! `s² = Σ w_i e_i² / (n_eff − b)` (`e` the rows scaled by their sensor σ,
//! `n_eff` the equations of observations with a non-zero weight, `b` the
//! identified unknowns) which weighs the prior's rows against the data
//! (row weight `s/σ_k`). It then re-converges the Gauss–Newton descent with
//! these weights fixed. It stops when no weight moves by more than 1e-3 and
//! `s²` by less than a relative 1e-3, or after [`MAX_REWEIGHTINGS`].
//!
//! Precision: `cov = s² (W̃ᵀW̃)⁻¹`, W̃ the weighted W_b with the prior rows:
//! for a fixed-weight IRLS solution the usual sandwich-free approximation
//! (the weights are treated as known), and with a prior the posterior
//! covariance `(W_bᵀW_b/s² + Σ_p⁻¹)⁻¹`.

use super::solver::{Damping, Problem, Run};
use super::statistics::ResidualStatistics;
use super::weighting::{PriorRow, Weighting};
use crate::Error;
use crate::progress::Observer;
use crate::robust::{Loss, LossKind};
use crate::study::StudyStates;

/// Outer iterations (reweightings) allowed per loss stage.
pub const MAX_REWEIGHTINGS: usize = 50;
/// A weight change below this ends the reweighting.
const WEIGHT_TOLERANCE: f64 = 1e-3;

/// What the reweighted phase produced.
pub(super) struct Reweighted {
    /// The run from the nominal robot: the least-squares updates, then those
    /// of every reweighting.
    pub(super) run: Run,
    /// The weighting of the final system.
    pub(super) weighting: Weighting,
    /// Statistics at the solution, under the final weights.
    pub(super) statistics: ResidualStatistics,
    /// Outer iterations taken.
    pub(super) reweightings: usize,
}

impl Problem<'_> {
    /// The reweighted phase after the least-squares `run` (see the module
    /// docs); `prior` holds the prior rows (weights to be set), empty without
    /// a prior.
    pub(super) fn reweighted(
        &self,
        run: Run,
        loss: Loss,
        prior: Vec<PriorRow>,
        states: &mut StudyStates,
        observer: &mut dyn Observer,
    ) -> Result<Reweighted, Error> {
        let equations = self.study.equation_count();
        let unknowns = self.layout.columns();
        if loss.is_l2() && prior.is_empty() {
            let statistics = ResidualStatistics::of(&run.best.system, &loss, equations, unknowns);
            return Ok(Reweighted {
                run,
                weighting: Weighting::default(),
                statistics,
                reweightings: 0,
            });
        }
        // Redescending losses start from Huber's unique minimum.
        let stages = if loss.kind.redescending() {
            vec![Loss::new(LossKind::Huber), loss]
        } else {
            vec![loss]
        };
        let Run {
            best: mut current,
            mut history,
            mut stop,
        } = run;
        let mut weighting = Weighting {
            observation_weights: Vec::new(),
            prior_rows: prior,
            gauge: self.weighting.gauge.clone(),
        };
        let mut reweightings = 0;
        let mut variance = f64::NAN;
        // The statistics of `current` under the last stage's loss, when the
        // last stage settled (otherwise taken after the loop).
        let mut settled_statistics = None;
        for stage in &stages {
            settled_statistics = None;
            for _ in 0..MAX_REWEIGHTINGS {
                let statistics =
                    ResidualStatistics::of(&current.system, stage, equations, unknowns);
                if statistics.effective_equations <= unknowns && weighting.prior_rows.is_empty() {
                    return Err(Error::Numerical {
                        message: format!(
                            "the {} loss gives no weight to so many observations that {} equations are left for {unknowns} unknowns; \
                             raise the loss scale or use huber",
                            stage.kind, statistics.effective_equations
                        ),
                    });
                }
                let weight = |observation: usize| {
                    weighting
                        .observation_weights
                        .get(observation)
                        .copied()
                        .unwrap_or(1.0)
                };
                let moved = statistics
                    .weights
                    .iter()
                    .enumerate()
                    .map(|(observation, w)| (w - weight(observation)).abs())
                    .fold(0.0, f64::max);
                if reweightings > 0
                    && moved <= WEIGHT_TOLERANCE
                    && (statistics.variance - variance).abs() <= 1e-3 * variance
                {
                    settled_statistics = Some(statistics);
                    break;
                }
                variance = statistics.variance;
                weighting.observation_weights = if stage.is_l2() {
                    Vec::new()
                } else {
                    statistics.weights
                };
                for row in &mut weighting.prior_rows {
                    row.weight = variance.sqrt() / row.sigma;
                }
                let problem = self.with_weighting(weighting.clone());
                let (robot, auxiliary) = (current.robot, current.auxiliary);
                let reweighted = problem.assemble_into(
                    &robot,
                    &auxiliary,
                    &problem.layout,
                    states,
                    current.system,
                )?;
                let run = problem.descend(
                    reweighted,
                    Damping::WhenNeeded,
                    self.options.max_iterations,
                    states,
                    observer,
                )?;
                history.extend(run.history);
                current = run.best;
                stop = run.stop;
                reweightings += 1;
            }
        }
        let mut statistics = settled_statistics.unwrap_or_else(|| {
            let last = stages.last().copied().unwrap_or_default();
            ResidualStatistics::of(&current.system, &last, equations, unknowns)
        });
        // The final system was solved with the weights and the variance set
        // before its descent: those are the ones to report.
        if !weighting.observation_weights.is_empty() {
            statistics.weights = weighting.observation_weights.clone();
        }
        statistics.variance = variance;
        Ok(Reweighted {
            run: Run {
                best: current,
                history,
                stop,
            },
            weighting,
            statistics,
            reweightings,
        })
    }
}
