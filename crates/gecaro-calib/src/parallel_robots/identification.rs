//! Identification of a parallel robot's parameters: Gauss–Newton on the base set
//! (module docs of [`super`]), with the precision of every parameter and a
//! serial robot's verdict.

use gecaro_core::parallel_model::{ParallelModel, ParameterUnit};
use gecaro_data::sample::Sample;
use nalgebra::Isometry3;

use super::identifiability::{PlatformRankReport, rank_of};
use super::measure::{PlatformMeasure, PlatformNoise};
use super::observation::{PlatformRows, platform_rows};
use crate::Error;
use crate::identifiability::ParameterStatus;
use crate::identification::{NoiseTest, Outcome, noise_test};
use crate::linalg::{select_columns, solve_with_covariance};

/// A joint centre, length or tool coordinate that moved further than this
/// from its nominal value (m) is no platform's error but a mistaken file
/// or data set.
const PLAUSIBLE_LENGTH: f64 = 0.05;

/// An angle (a Delta's arm azimuth or offset) that moved further than this
/// (rad, 5°), the same.
const PLAUSIBLE_ANGLE: f64 = 0.087;

/// A gain off its nominal value by more than this fraction, the same.
const PLAUSIBLE_GAIN: f64 = 0.1;

/// How an identification of a platform runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlatformIdentificationOptions {
    /// Gauss–Newton iterations at most.
    pub max_iterations: usize,
    /// The relative decrease of the cost below which the fit has converged.
    pub tolerance: f64,
}

impl Default for PlatformIdentificationOptions {
    fn default() -> Self {
        Self {
            max_iterations: crate::identification::DEFAULT_MAX_ITERATIONS,
            tolerance: 1e-10,
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
    let mut poses: Vec<Isometry3<f64>> = Vec::new();
    let mut rows = platform_rows(nominal, samples, measure, noise, &mut poses)?;
    let rank = rank_of(nominal, &rows, measure)?;
    let count = rows.residuals.len();
    let rms = |rows: &PlatformRows| {
        let sigma = noise.map_or(1.0, |noise| noise.length);
        (rows.cost() / count as f64).sqrt() * sigma
    };
    let rms_before = rms(&rows);
    let mut current = nominal.clone();
    let mut values = nominal.parameters();
    let mut iterations = 0;
    let mut converged = false;
    let mut diverged = false;
    while iterations < options.max_iterations {
        iterations += 1;
        let base = select_columns(rows.matrix.as_ref(), &rank.base);
        let (solution, _) = solve_with_covariance(base.as_ref(), &rows.residuals);
        let cost = rows.cost();
        // The full step, halved while it does not lower the cost.
        let mut accepted = None;
        for halving in 0..20 {
            let scale = 0.5f64.powi(halving);
            let mut trial = values.clone();
            for (column, step) in rank.base.iter().zip(&solution.solution) {
                trial[*column] += scale * step;
            }
            let Ok(platform) = nominal.with_parameters(&trial) else {
                continue;
            };
            let mut trial_poses = poses.clone();
            let Ok(trial_rows) =
                platform_rows(&platform, samples, measure, noise, &mut trial_poses)
            else {
                continue;
            };
            if trial_rows.cost() <= cost {
                accepted = Some((trial, platform, trial_rows, trial_poses));
                break;
            }
        }
        let Some((trial, platform, trial_rows, trial_poses)) = accepted else {
            // No step lowers the cost: the current parameters are the
            // minimum to the precision of the arithmetic, or the fit failed.
            converged = iterations > 1;
            diverged = !converged;
            break;
        };
        let decrease = (cost - trial_rows.cost()) / cost.max(f64::MIN_POSITIVE);
        (values, current, rows, poses) = (trial, platform, trial_rows, trial_poses);
        if decrease < options.tolerance {
            converged = true;
            break;
        }
    }
    let base = select_columns(rows.matrix.as_ref(), &rank.base);
    let (precision, _) = solve_with_covariance(base.as_ref(), &rows.residuals);
    let freedom = count.saturating_sub(rank.rank());
    let test = noise.map(|_| noise_test(rows.cost(), freedom));
    // σ̂ of a unit weight: √(χ²/ν) with σ stated, the residuals' own otherwise.
    let unit_sigma = (rows.cost() / freedom.max(1) as f64).sqrt();
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
                .map(|k| unit_sigma * precision.inverse_normal_diagonal[k].sqrt()),
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
        rms_after: rms(&rows),
        iterations,
        implausible,
    })
}
