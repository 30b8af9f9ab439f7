//! The Gauss–Newton descent of a parallel robot's identification on its
//! base parameters (the module docs of [`super`]): the full step from the
//! base set's normal equations `W_bᵀW_b·Δ = W_bᵀr`, halved while it does not
//! lower the cost, with each observation's robust weight when a loss gives
//! one ([`super::reweighting`]).

use gecaro_core::parallel_model::ParallelModel;
use gecaro_data::sample::Sample;
use nalgebra::{DMatrix, DVector, Isometry3};

use super::auxiliary::Auxiliary;
use super::measure::{PlatformMeasure, PlatformNoise};
use super::observation::{NormalSystem, normal_system};
use crate::Error;

/// A Gauss–Newton step every component of which is below this part of its
/// parameter's σ ends the fit without a trial pass over the data: the
/// parameters are at the minimum to far within their precision.
const STEP_OF_SIGMA: f64 = 1e-3;

/// A Gaussian prior's pseudo-observations on the base parameters: for each,
/// its column, its nominal value and its prior σ_p, the row
/// `(s/σ_p)·(η₀ − η)` beside the data's, with `s` the rows' σ̂ of unit
/// weight (maximum a posteriori with the noise the data show).
#[derive(Clone, Debug, Default)]
pub(super) struct PriorRows {
    pub(super) rows: Vec<(usize, f64, f64)>,
    /// `s`.
    pub(super) unit: f64,
}

impl PriorRows {
    /// The same rows weighted by `unit` instead.
    pub(super) fn with_unit(&self, unit: f64) -> PriorRows {
        PriorRows {
            rows: self.rows.clone(),
            unit,
        }
    }

    /// Adds the rows at parameters `values` to `system`'s normal equations
    /// and cost.
    fn add_to(&self, system: &mut NormalSystem, values: &[f64]) {
        for &(column, nominal, sigma) in &self.rows {
            let weight = self.unit / sigma;
            let residual = weight * (nominal - values[column]);
            system.cost += residual * residual;
            system.prior_cost += residual * residual;
            system.gram[(column, column)] += weight * weight;
            system.projected[column] += weight * residual;
        }
    }
}

/// What a fit's samples are: their measure, their noise when stated, and
/// the auxiliary unknowns after the robot's parameters (stations'
/// corrections, a measuring leg: [`super::auxiliary`]).
#[derive(Clone, Copy)]
pub(super) struct Fit<'a> {
    pub(super) measure: PlatformMeasure,
    pub(super) noise: Option<PlatformNoise>,
    pub(super) auxiliary: &'a Auxiliary,
}

/// The normal system of `samples` measured as `fit` says at `model` (whose
/// parameters, with the stations' corrections after them, are `values`),
/// with the observations' `weights` and the `prior`'s rows; `poses` as
/// for [`normal_system`].
///
/// # Errors
/// As [`normal_system`].
fn system_at<M: ParallelModel>(
    model: &M,
    values: &[f64],
    samples: &[Sample],
    fit: Fit<'_>,
    (weights, prior): (Option<&[f64]>, &PriorRows),
    poses: &mut Vec<Isometry3<f64>>,
) -> Result<NormalSystem, Error> {
    let auxiliary = fit.auxiliary.at(&values[model.parameter_count()..]);
    let mut system = normal_system(
        model,
        samples,
        fit.measure,
        fit.noise,
        weights,
        &auxiliary,
        poses,
    )?;
    prior.add_to(&mut system, values);
    Ok(system)
}

/// Where a Gauss–Newton descent is: the parameters (and the auxiliary
/// unknowns after them), the robot they make, its normal system and
/// each sample's solved pose.
pub(super) struct Descent<M> {
    pub(super) values: Vec<f64>,
    pub(super) current: M,
    pub(super) system: NormalSystem,
    pub(super) poses: Vec<Isometry3<f64>>,
    /// Steps taken.
    pub(super) iterations: usize,
    pub(super) converged: bool,
    pub(super) diverged: bool,
}

/// Gauss–Newton on `base` from `from` (with `weights` on the observations,
/// or none, and the `prior`'s rows, which `from`'s system has), at most
/// `max_iterations` steps: the full step, halved while it
/// does not lower the cost; converged when the predicted decrease or every
/// step is negligible (the predicted decrease below `tolerance` of the cost),
/// diverged when no step lowers the cost at the first.
pub(super) fn descend<M: ParallelModel>(
    nominal: &M,
    samples: &[Sample],
    fit: Fit<'_>,
    (weights, prior): (Option<&[f64]>, &PriorRows),
    base: &[usize],
    from: Descent<M>,
    (max_iterations, tolerance): (usize, f64),
) -> Result<Descent<M>, Error> {
    let Descent {
        mut values,
        mut current,
        mut system,
        mut poses,
        ..
    } = from;
    let count = system.rows;
    let mut iterations = 0;
    let mut converged = false;
    let mut diverged = false;
    while iterations < max_iterations {
        iterations += 1;
        let (inverse, solution) = base_system(&system, base)?;
        let cost = system.cost;
        // Gauss–Newton's predicted decrease `gᵀ·Δ`: below the tolerance the
        // parameters are the minimum, and no trial pass over the data is
        // needed to say so; nor when every step is a negligible part of its
        // parameter's σ (σ̂² of the unit weight from this cost).
        let predicted: f64 = base
            .iter()
            .zip(solution.iter())
            .map(|(column, step)| system.projected[*column] * step)
            .sum();
        let unit_variance = cost / count.saturating_sub(base.len()).max(1) as f64;
        let negligible = solution.iter().enumerate().all(|(k, step)| {
            step.abs() <= STEP_OF_SIGMA * (inverse[(k, k)] * unit_variance).sqrt()
        });
        if iterations > 1 && (predicted <= tolerance * cost || negligible) {
            // Iterations count the steps taken.
            iterations -= 1;
            converged = true;
            break;
        }
        // The full step, halved while it does not lower the cost.
        let mut accepted = None;
        for halving in 0..20 {
            let scale = 0.5f64.powi(halving);
            let mut trial = values.clone();
            for (column, step) in base.iter().zip(solution.iter()) {
                trial[*column] += scale * step;
            }
            let Ok(model) = nominal.with_parameters(&trial[..nominal.parameter_count()]) else {
                continue;
            };
            let mut trial_poses = poses.clone();
            let Ok(trial_system) = system_at(
                &model,
                &trial,
                samples,
                fit,
                (weights, prior),
                &mut trial_poses,
            ) else {
                continue;
            };
            if trial_system.cost <= cost {
                accepted = Some((trial, model, trial_system, trial_poses));
                break;
            }
        }
        let Some((trial, model, trial_system, trial_poses)) = accepted else {
            // No step lowers the cost: the current parameters are the
            // minimum to the precision of the arithmetic, or the fit failed.
            converged = iterations > 1;
            diverged = !converged;
            break;
        };
        let decrease = (cost - trial_system.cost) / cost.max(f64::MIN_POSITIVE);
        (values, current, system, poses) = (trial, model, trial_system, trial_poses);
        if decrease < tolerance {
            converged = true;
            break;
        }
    }
    Ok(Descent {
        values,
        current,
        system,
        poses,
        iterations,
        converged,
        diverged,
    })
}

/// [`descend`] from `from` under another weighting `(weights, prior)`: the
/// normal system re-formed at `from`'s parameters with it first (a robust
/// loss's new weights, a prior's rows added after the least-squares fit).
///
/// # Errors
/// As [`descend`].
pub(super) fn descend_reweighted<M: ParallelModel>(
    nominal: &M,
    samples: &[Sample],
    fit: Fit<'_>,
    weighting: (Option<&[f64]>, &PriorRows),
    base: &[usize],
    mut from: Descent<M>,
    limits: (usize, f64),
) -> Result<Descent<M>, Error> {
    from.system = system_at(
        &from.current,
        &from.values,
        samples,
        fit,
        weighting,
        &mut from.poses,
    )?;
    descend(nominal, samples, fit, weighting, base, from, limits)
}

/// The normal equations of the base columns: their inverse (the
/// parameters' covariance before σ̂²) and the Gauss–Newton step.
///
/// # Errors
/// [`Error::Numerical`] when they are not positive definite (a base set
/// that the data do not determine).
pub(super) fn base_system(
    system: &NormalSystem,
    base: &[usize],
) -> Result<(DMatrix<f64>, DVector<f64>), Error> {
    let gram = DMatrix::from_fn(base.len(), base.len(), |i, j| {
        system.gram[(base[i], base[j])]
    });
    let projected = DVector::from_fn(base.len(), |i, _| system.projected[base[i]]);
    let cholesky = gram.cholesky().ok_or_else(|| Error::Numerical {
        message: "the normal equations of the identifiable parameters are not positive definite"
            .into(),
    })?;
    Ok((cholesky.inverse(), cholesky.solve(&projected)))
}
