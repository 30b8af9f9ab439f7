//! Identification of a parallel robot's parameters: Gauss–Newton on the base set
//! (module docs of [`super`]), with the precision of every parameter and a
//! serial robot's verdict.

use gecaro_core::parallel_model::{ParallelModel, ParameterUnit};
use gecaro_data::sample::Sample;
use nalgebra::Isometry3;

use super::identifiability::{PlatformRankReport, rank_of};
use super::measure::{PlatformMeasure, PlatformNoise};
use super::observation::{NormalSystem, normal_system, platform_rows};
use super::plausible::{PLAUSIBLE_ANGLE, PLAUSIBLE_GAIN, PLAUSIBLE_LENGTH};
use super::region::{PlatformRegion, where_it_holds};
use super::registration::{in_base_frame, measurement_frame};
use crate::Error;
use crate::identifiability::ParameterStatus;
use crate::identification::{
    DEFAULT_OUTLIER_THRESHOLD, Loss, MAX_REWEIGHTINGS, NoiseTest, Outcome, noise_test,
};
use gecaro_core::JointRegion;
use nalgebra::{DMatrix, DVector};

/// A Gauss–Newton step every component of which is below this part of its
/// parameter's σ ends the fit without a trial pass over the data: the
/// parameters are at the minimum to far within their precision.
const STEP_OF_SIGMA: f64 = 1e-3;

/// Observations named as standing out, at most.
const MAX_OUTLIERS_NAMED: usize = 10;

/// How an identification of a platform runs.
#[derive(Clone, Debug, PartialEq)]
pub struct PlatformIdentificationOptions {
    /// Gauss–Newton iterations at most.
    pub max_iterations: usize,
    /// The relative decrease of the cost below which the fit has converged.
    pub tolerance: f64,
    /// The region the platform will be used in (a range of each actuator's
    /// values), over which the verdict predicts its error; `None`: the
    /// actuators' ranges.
    pub work_region: Option<JointRegion>,
    /// The loss: plain least squares by default; a robust one reweights
    /// each observation by its residual after the least-squares fit
    /// ([`identify_platform`]).
    pub loss: Loss,
}

impl Default for PlatformIdentificationOptions {
    fn default() -> Self {
        Self {
            max_iterations: crate::identification::DEFAULT_MAX_ITERATIONS,
            tolerance: 1e-10,
            work_region: None,
            loss: Loss::default(),
        }
    }
}

/// One parameter of an identified platform.
#[derive(Clone, Debug, PartialEq)]
pub struct PlatformParameter {
    /// Its name (`a1x`, `l3`, `K6`, `tz`).
    pub name: String,
    /// The nominal value (m; a gain dimensionless).
    pub nominal: f64,
    /// The identified value (the nominal one unless identifiable).
    pub identified: f64,
    /// `σ̂·√diag((WᵀW)⁻¹)` when identified.
    pub sigma: Option<f64>,
    /// Identifiable, regrouped, of no effect or excluded.
    pub status: ParameterStatus,
}

/// An identified parallel robot.
#[derive(Clone, Debug)]
pub struct PlatformIdentification<M> {
    /// The robot with the identified parameters.
    pub calibrated: M,
    /// Every parameter, in vocabulary order.
    pub parameters: Vec<PlatformParameter>,
    /// The identifiable parameters and the regrouping at the nominal ones.
    pub rank: PlatformRankReport,
    /// What the measurements say of the fit.
    pub outcome: Outcome,
    /// The χ² test of the residuals against the stated noise.
    pub noise_test: Option<NoiseTest>,
    /// RMS of the equations' residuals before and after (m: legs for poses,
    /// coordinates for points).
    pub rms_before: f64,
    /// See [`rms_before`](Self::rms_before).
    pub rms_after: f64,
    /// Gauss–Newton iterations made.
    pub iterations: usize,
    /// The parameters whose value no platform has (names).
    pub implausible: Vec<String>,
    /// Where the result holds: the predicted error at the measured poses
    /// and over the work region; `None` for a fit that is no solution.
    pub region: Option<PlatformRegion>,
    /// The observations whose residual stands out from the fit: their
    /// first line (a distance's pair by its first row) and the RMS of their
    /// rows in units of the stated σ (of σ̂ without one), above
    /// [`DEFAULT_OUTLIER_THRESHOLD`], the largest first (at most ten).
    pub outliers: Vec<(Option<usize>, f64)>,
    /// The base frame in the instrument's frame, when the data were in
    /// another frame and were registered ([`super::measurement_frame`]).
    pub registered: Option<Isometry3<f64>>,
    /// The loss the fit minimised.
    pub loss: Loss,
    /// Reweightings of a robust loss (0 for least squares).
    pub reweightings: usize,
    /// Each observation's robust weight at the solution, in order (empty
    /// for least squares).
    pub weights: Vec<f64>,
    /// The robust σ̂ of a row the weights were formed with (in units of the
    /// stated σ; m without one): the RMS of the observations within the
    /// outlier threshold of it, from the rows' median absolute deviation;
    /// `None` for least squares.
    pub robust_sigma: Option<f64>,
}

/// Where a Gauss–Newton descent is: the parameters, the robot they make,
/// its normal system and each sample's solved pose.
struct Descent<M> {
    values: Vec<f64>,
    current: M,
    system: NormalSystem,
    poses: Vec<Isometry3<f64>>,
    /// Steps taken.
    iterations: usize,
    converged: bool,
    diverged: bool,
}

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

/// Observation weights that moved less than this: the reweighting settled.
const WEIGHT_TOLERANCE: f64 = 1e-3;

/// Gauss–Newton on `base` from `from` (with `weights` on the observations,
/// or none), at most the options' iterations: the full step, halved while it
/// does not lower the cost; converged when the predicted decrease or every
/// step is negligible, diverged when no step lowers the cost at the first.
fn descend<M: ParallelModel>(
    nominal: &M,
    samples: &[Sample],
    (measure, noise): (PlatformMeasure, Option<PlatformNoise>),
    weights: Option<&[f64]>,
    base: &[usize],
    from: Descent<M>,
    options: &PlatformIdentificationOptions,
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
    while iterations < options.max_iterations {
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
        if iterations > 1 && (predicted <= options.tolerance * cost || negligible) {
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
            let Ok(model) = nominal.with_parameters(&trial) else {
                continue;
            };
            let mut trial_poses = poses.clone();
            let Ok(trial_system) =
                normal_system(&model, samples, measure, noise, weights, &mut trial_poses)
            else {
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
        if decrease < options.tolerance {
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

/// Identifies `nominal`'s parameters from `samples` measured by `measure`,
/// their noise `noise` when stated (each row weighted by its σ, the
/// residuals tested against it).
///
/// # Errors
/// The samples' own errors (missing columns, actuator values with no pose),
/// too few equations, a numerical failure.
pub fn identify_platform<M: ParallelModel>(
    nominal: &M,
    samples: &[Sample],
    measure: PlatformMeasure,
    noise: Option<PlatformNoise>,
    options: &PlatformIdentificationOptions,
) -> Result<PlatformIdentification<M>, Error> {
    // Data an instrument took in its own frame, brought into the base frame.
    let registered = measurement_frame(nominal, samples, measure);
    let moved;
    let samples = match &registered {
        Some(frame) => {
            moved = in_base_frame(samples, frame);
            moved.as_slice()
        }
        None => samples,
    };
    let mut rank = structural_rank(nominal, samples, measure, noise)?;
    let mut poses: Vec<Isometry3<f64>> = Vec::new();
    let system = normal_system(nominal, samples, measure, noise, None, &mut poses)?;
    let count = system.rows;
    if count < rank.base.len() {
        return Err(Error::TooFewEquations {
            equations: count,
            unknowns: rank.base.len(),
        });
    }
    let rms = |system: &NormalSystem| {
        let sigma = noise.map_or(1.0, |noise| noise.length);
        (system.cost / count as f64).sqrt() * sigma
    };
    let rms_before = rms(&system);
    let start = Descent {
        values: nominal.parameters(),
        current: nominal.clone(),
        system,
        poses,
        iterations: 0,
        converged: false,
        diverged: false,
    };
    let fit = (measure, noise);
    let mut descent = descend(nominal, samples, fit, None, &rank.base, start, options)?;
    let mut iterations = descent.iterations;
    // A robust loss: each observation weighted by its residual over the
    // robust σ̂ (iteratively reweighted least squares from the
    // least-squares fit), until the weights settle.
    let (mut weights, mut robust_sigma, mut reweightings) = (Vec::new(), None, 0);
    if !options.loss.is_l2() && descent.converged {
        // Rounding residuals of noise-free data are no noise.
        let floor = if noise.is_some() { 1e-6 } else { 1e-12 };
        for _ in 0..MAX_REWEIGHTINGS {
            // The noise of a row, whatever a few gross observations do.
            let spread = crate::robust::robust_sigma(&descent.system.residuals);
            let sigma = trimmed_sigma(
                &descent.system.errors,
                measure.rows_per_observation(nominal),
                rank.base.len(),
                spread.max(floor),
            )
            .max(floor);
            let next: Vec<f64> = descent
                .system
                .errors
                .iter()
                .map(|error| options.loss.weight(error / sigma))
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
            descent.system = normal_system(
                &descent.current,
                samples,
                measure,
                noise,
                Some(&weights),
                &mut descent.poses,
            )?;
            descent = descend(
                nominal,
                samples,
                fit,
                Some(&weights),
                &rank.base,
                descent,
                options,
            )?;
            iterations += descent.iterations;
            reweightings += 1;
            if !descent.converged {
                break;
            }
        }
    }
    let Descent {
        values,
        current,
        system,
        poses,
        converged,
        diverged,
        ..
    } = descent;
    let (inverse, _) = base_system(&system, &rank.base)?;
    rank.rows = count;
    rank.condition_number = condition(&system, &rank.base);
    // What the test and σ̂ read: in least squares the fit's cost; with a
    // robust loss the residuals as measured of the observations within the
    // outlier threshold of σ̂ (as a serial robot's, `identification::tested`:
    // the loss weights the fit, not what the data say).
    // An observation stands out beyond the threshold of the robust σ̂ and,
    // when σ is stated, of the stated σ too: an RMS of a pose's correlated
    // closure rows is spread wider than χ² of its rows says, and a clean
    // pose at 2.7 σ stood out of a σ̂ of 0.88 σ.
    let scale = robust_sigma.map(|sigma| {
        if noise.is_some() {
            sigma.max(1.0)
        } else {
            sigma
        }
    });
    let rows_each = measure.rows_per_observation(nominal);
    let (tested_cost, tested_rows) = match scale {
        None => (system.cost, count),
        Some(scale) => system
            .errors
            .iter()
            .filter(|error| **error / scale <= DEFAULT_OUTLIER_THRESHOLD)
            .fold((0.0, 0), |(cost, rows), error| {
                (cost + error * error * rows_each as f64, rows + rows_each)
            }),
    };
    let freedom = tested_rows.saturating_sub(rank.rank());
    let test = noise.map(|_| noise_test(tested_cost, freedom));
    // σ̂ of a unit weight: √(χ²/ν) with σ stated, the residuals' own otherwise.
    let unit_sigma = (tested_cost / freedom.max(1) as f64).sqrt();
    let nominal_values = nominal.parameters();
    let parameters: Vec<PlatformParameter> = nominal
        .parameter_names()
        .into_iter()
        .enumerate()
        .map(|(index, name)| PlatformParameter {
            name,
            nominal: nominal_values[index],
            identified: values[index],
            sigma: rank
                .base
                .iter()
                .position(|c| *c == index)
                .map(|k| unit_sigma * inverse[(k, k)].sqrt()),
            status: rank.statuses[index],
        })
        .collect();
    let implausible: Vec<String> = parameters
        .iter()
        .enumerate()
        .filter(|(index, parameter)| {
            let moved = (parameter.identified - parameter.nominal).abs();
            match nominal.parameter_unit(*index) {
                ParameterUnit::Gain => moved > PLAUSIBLE_GAIN * parameter.nominal.abs(),
                ParameterUnit::Angle => moved > PLAUSIBLE_ANGLE,
                ParameterUnit::Length => moved > PLAUSIBLE_LENGTH,
            }
        })
        .map(|(_, parameter)| parameter.name.clone())
        .collect();
    let solved = converged && !diverged;
    // The observations that stand out, in units of the stated σ (of σ̂
    // without one: the rows are then in metres).
    let scale = match scale {
        // With a robust loss, those left out of the test.
        Some(scale) => scale,
        None if noise.is_some() => 1.0,
        None => unit_sigma.max(f64::MIN_POSITIVE),
    };
    let mut outliers: Vec<(Option<usize>, f64)> = system
        .errors
        .iter()
        .copied()
        .enumerate()
        .map(|(index, error)| {
            (
                samples[index * measure.samples_per_observation()].line,
                error / scale,
            )
        })
        .filter(|(_, ratio)| *ratio > DEFAULT_OUTLIER_THRESHOLD)
        .collect();
    outliers.sort_by(|a, b| b.1.total_cmp(&a.1));
    outliers.truncate(MAX_OUTLIERS_NAMED);
    // The floor a held-out position measurement of a perfect platform
    // shows, √3 σ̂ of a coordinate; the posterior covariance σ̂²·(W_bᵀW_b)⁻¹
    // (rows weighted by 1/σ: σ̂ is the unit weight's).
    let region = solved
        .then(|| {
            // A held-out distance's noise is one coordinate's, a point's three.
            let coordinates: f64 = if measure == PlatformMeasure::Distance {
                1.0
            } else {
                3.0
            };
            let floor = coordinates.sqrt() * unit_sigma * noise.map_or(1.0, |noise| noise.length);
            where_it_holds(
                &current,
                measure,
                samples,
                |index| match measure {
                    PlatformMeasure::Pose => measure.measured(&samples[index]).ok(),
                    PlatformMeasure::Point | PlatformMeasure::Distance => poses.get(index).copied(),
                },
                (&rank.base, &(inverse * unit_sigma.powi(2))),
                floor,
                options.work_region.as_ref(),
            )
        })
        .flatten();
    let outcome = if diverged {
        Outcome::Diverged
    } else if !converged {
        Outcome::NotConverged
    } else if !implausible.is_empty() {
        Outcome::Implausible
    } else {
        match test {
            Some(test) if test.exceeded() => Outcome::ExceedsNoise,
            Some(test) if test.below() => Outcome::BelowNoise,
            _ if region
                .as_ref()
                .is_some_and(|region| !region.holds_everywhere) =>
            {
                Outcome::Regional
            }
            Some(_) => Outcome::FitsNoise,
            None => Outcome::Untested,
        }
    };
    Ok(PlatformIdentification {
        calibrated: current,
        parameters,
        rank,
        outcome,
        noise_test: test,
        rms_before,
        // The residuals as measured, whatever weights a robust loss gave.
        rms_after: if robust_sigma.is_some() {
            let squares: f64 = system.errors.iter().map(|error| error * error).sum();
            (squares / system.errors.len().max(1) as f64).sqrt()
                * noise.map_or(1.0, |noise| noise.length)
        } else {
            rms(&system)
        },
        iterations,
        implausible,
        region,
        outliers,
        registered,
        loss: options.loss,
        reweightings,
        weights,
        robust_sigma,
    })
}

/// Configurations the rank analysis takes at most: the structure's rank
/// shows in a few thousand equations; more add precision, not rank.
const RANK_SAMPLES: usize = 2000;

/// The identifiable parameters from at most [`RANK_SAMPLES`] configurations
/// spread evenly over the data (all of them below that).
pub(super) fn structural_rank<M: ParallelModel>(
    nominal: &M,
    samples: &[Sample],
    measure: PlatformMeasure,
    noise: Option<PlatformNoise>,
) -> Result<PlatformRankReport, Error> {
    // Whole observations (a distance's pairs), spread.
    let size = measure.samples_per_observation();
    let observations = samples.len() / size;
    let picked = RANK_SAMPLES / size;
    let taken: Vec<Sample> = if samples.len() <= RANK_SAMPLES {
        samples.to_vec()
    } else {
        (0..picked)
            .flat_map(|k| {
                let first = k * observations / picked * size;
                samples[first..first + size].to_vec()
            })
            .collect()
    };
    let rows = platform_rows(nominal, &taken, measure, noise, &mut Vec::new())?;
    rank_of(nominal, &rows, measure)
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

/// The condition number of the base columns of W: `√(λmax/λmin)` of their
/// normal equations.
fn condition(system: &NormalSystem, base: &[usize]) -> f64 {
    let gram = DMatrix::from_fn(base.len(), base.len(), |i, j| {
        system.gram[(base[i], base[j])]
    });
    let values = gram.symmetric_eigenvalues();
    let (smallest, largest) = (values.min(), values.max());
    if smallest > 0.0 {
        (largest / smallest).sqrt()
    } else {
        f64::INFINITY
    }
}
