//! The outlier report: observations whose standardised residual at the
//! solution exceeds a threshold (see [`Loss`](crate::robust::Loss) for the units), located
//! in their set and data file.

use super::observations::{ObservationLocation, locate};
use super::statistics::ResidualStatistics;
use crate::observation::ObservationErrors;
use crate::study::Study;

/// The default outlier threshold, in robust σ̂.
pub const DEFAULT_OUTLIER_THRESHOLD: f64 = 3.0;

/// An observation with a residual beyond the outlier threshold.
#[derive(Clone, Debug, PartialEq)]
pub struct Outlier {
    /// Where it comes from: its set, file, kind, number and lines.
    pub location: ObservationLocation,
    /// Its position-like error at the solution (metres).
    pub error: f64,
    /// Its orientation error at the solution (radians), for data with orientations.
    pub rotation_error: Option<f64>,
    /// Its standardised residual u (units of the robust σ̂).
    pub standardized: f64,
    /// Its weight in the final fit (1 in least squares, 0 when ignored).
    pub weight: f64,
}

/// The outliers of `study` at a solution with `statistics` and per-observation
/// errors `errors` (numbered across sets, as the system numbers them), worst first.
pub(super) fn find_outliers(
    study: &Study,
    statistics: &ResidualStatistics,
    errors: &ObservationErrors,
    threshold: f64,
) -> Vec<Outlier> {
    if !statistics.standardized.iter().any(|u| *u > threshold) {
        return Vec::new();
    }
    let beyond = |number: usize| {
        statistics
            .standardized
            .get(number)
            .is_some_and(|u| *u > threshold)
    };
    let mut outliers: Vec<Outlier> = locate(study, beyond)
        .into_iter()
        .map(|(number, located)| {
            let standardized = statistics.standardized[number];
            let (error, rotation) = errors.get(number).unwrap_or((f64::NAN, f64::NAN));
            Outlier {
                location: located,
                error,
                rotation_error: errors.has_angles().then_some(rotation),
                standardized,
                weight: statistics.weights.get(number).copied().unwrap_or(1.0),
            }
        })
        .collect();
    outliers.sort_by(|a, b| b.standardized.total_cmp(&a.standardized));
    outliers
}

/// `study` without the samples of `outliers`.
pub(super) fn inliers(study: &Study, outliers: &[Outlier]) -> Study {
    study.without_samples(&outlier_samples(study, outliers))
}

/// The samples of `outliers`, per set of `study` (for [`Study::without_samples`]).
pub(super) fn outlier_samples(study: &Study, outliers: &[Outlier]) -> Vec<Vec<usize>> {
    let mut dropped = vec![Vec::new(); study.sets.len()];
    for outlier in outliers {
        dropped[outlier.location.set].extend(&outlier.location.samples);
    }
    dropped
}
