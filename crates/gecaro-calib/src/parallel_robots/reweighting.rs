//! A robust loss on a parallel robot's observations (as
//! [`crate::identification::Loss`] on a serial robot's): iteratively
//! reweighted least squares from the least-squares fit, each observation's
//! weight `w = ρ'(u)/u` of its residual `u` over the robust σ̂ of a row, its
//! rows multiplied by `√w` ([`super::observation::normal_system`]).

use gecaro_core::parallel_model::ParallelModel;
use gecaro_data::sample::Sample;

use super::descent::{Descent, Fit, PriorRows, descend_reweighted};
use crate::Error;
use crate::identification::{DEFAULT_OUTLIER_THRESHOLD, Loss, MAX_REWEIGHTINGS};

/// Observation weights that moved less than this: the reweighting settled.
const WEIGHT_TOLERANCE: f64 = 1e-3;

/// The σ of a row that standardises the observations' residuals `errors`
/// (each the RMS of its `rows` rows) under a robust loss: from `start`
/// (the rows' median absolute deviation, which gross errors do not move),
/// the RMS of the observations within the outlier threshold of it, with
/// their degrees of freedom (`unknowns` less), until the observations kept
/// settle. The median absolute deviation alone reads the rows' fitted
/// residuals, whose spread shrinks unevenly with their leverage (a
/// hexapod's 60 clean poses: 0.74 where their σ̂ is 0.94), and named a
/// clean pose an outlier.
fn trimmed_sigma(errors: &[f64], rows: usize, unknowns: usize, start: f64) -> f64 {
    let mut sigma = start;
    for _ in 0..20 {
        let (squares, kept) = errors
            .iter()
            .filter(|error| **error <= DEFAULT_OUTLIER_THRESHOLD * sigma)
            .fold((0.0, 0usize), |(squares, kept), error| {
                (squares + error * error * rows as f64, kept + rows)
            });
        let next = (squares / kept.saturating_sub(unknowns).max(1) as f64).sqrt();
        if next.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater)
            || (next - sigma).abs() <= 1e-9 * sigma
        {
            break;
        }
        sigma = next;
    }
    sigma
}

/// The descent after a robust loss's reweighting, and what it did.
pub(super) struct Reweighted<M> {
    /// The last descent (the least-squares one for least squares).
    pub(super) descent: Descent<M>,
    /// Each observation's weight in it (empty for least squares).
    pub(super) weights: Vec<f64>,
    /// The robust σ̂ of a row the weights were formed with.
    pub(super) robust_sigma: Option<f64>,
    /// Reweightings made.
    pub(super) reweightings: usize,
    /// Gauss–Newton steps of the reweighted descents (those of the
    /// `descent` given not counted).
    pub(super) iterations: usize,
}

/// The least-squares `descent` of `samples` measured by `fit` (with the
/// `prior`'s rows), reweighted by `loss` until no weight moves by more than [`WEIGHT_TOLERANCE`] (at
/// most [`MAX_REWEIGHTINGS`] times), each descent on `base` within `limits`
/// (iterations, tolerance). Least squares, or a descent that did not
/// converge, is returned as it is.
///
/// # Errors
/// As [`descend_reweighted`].
pub(super) fn reweighted<M: ParallelModel>(
    nominal: &M,
    samples: &[Sample],
    fit: Fit<'_>,
    (base, prior): (&[usize], &PriorRows),
    loss: &Loss,
    mut descent: Descent<M>,
    limits: (usize, f64),
) -> Result<Reweighted<M>, Error> {
    let (measure, noise) = (fit.measure, fit.noise);
    let mut iterations = 0;
    let (mut weights, mut robust_sigma, mut reweightings) = (Vec::new(), None, 0);
    if !loss.is_l2() && descent.converged {
        // Rounding residuals of noise-free data are no noise.
        let floor = if noise.is_some() { 1e-6 } else { 1e-12 };
        for _ in 0..MAX_REWEIGHTINGS {
            // The noise of a row, whatever a few gross observations do.
            let spread = crate::robust::robust_sigma(&descent.system.residuals);
            let sigma = trimmed_sigma(
                &descent.system.errors,
                measure.rows_per_observation(nominal),
                base.len(),
                spread.max(floor),
            )
            .max(floor);
            let next: Vec<f64> = descent
                .system
                .errors
                .iter()
                .map(|error| loss.weight(error / sigma))
                .collect();
            let moved = if weights.len() == next.len() {
                weights
                    .iter()
                    .zip(&next)
                    .map(|(a, b): (&f64, &f64)| (a - b).abs())
                    .fold(0.0, f64::max)
            } else {
                f64::INFINITY
            };
            robust_sigma = Some(sigma);
            if moved <= WEIGHT_TOLERANCE {
                break;
            }
            weights = next;
            // A prior weighs against the noise the data show, robustly
            // (the least-squares σ̂ carries the gross errors).
            let prior = prior.with_unit(sigma);
            let prior = &prior;
            descent = descend_reweighted(
                nominal,
                samples,
                fit,
                (Some(&weights), prior),
                base,
                descent,
                limits,
            )?;
            iterations += descent.iterations;
            reweightings += 1;
            if !descent.converged {
                break;
            }
        }
    }
    Ok(Reweighted {
        descent,
        weights,
        robust_sigma,
        reweightings,
        iterations,
    })
}
