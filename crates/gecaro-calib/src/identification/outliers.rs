//! The outlier report: observations whose standardised residual at the
//! solution exceeds a threshold (see [`crate::Loss`] for the units), located
//! in their set and data file.

use super::statistics::ResidualStatistics;
use crate::study::Study;

/// The default outlier threshold, in robust σ̂.
pub const DEFAULT_OUTLIER_THRESHOLD: f64 = 3.0;

/// An observation with a residual beyond the outlier threshold.
#[derive(Clone, Debug, PartialEq)]
pub struct Outlier {
    /// Index of its measurement set in the study.
    pub set: usize,
    /// The set's label (usually its data file).
    pub label: String,
    /// `configuration` or `pair`.
    pub kind: &'static str,
    /// Its index within the set (0-based, configurations or pairs).
    pub observation: usize,
    /// Indices of its samples in the set.
    pub samples: Vec<usize>,
    /// Lines of the data file its samples came from, when known.
    pub lines: Vec<usize>,
    /// Its position-like error at the solution (metres).
    pub error: f64,
    /// Its orientation error at the solution (radians), for data with orientations.
    pub rotation_error: Option<f64>,
    /// Its standardised residual u (units of the robust σ̂).
    pub standardized: f64,
    /// Its weight in the final fit (1 in least squares, 0 when ignored).
    pub weight: f64,
}

impl Outlier {
    /// `file.csv: configuration 17 (line 19)` and the like.
    pub fn location(&self) -> String {
        let lines = match self.lines.as_slice() {
            [] => String::new(),
            [line] => format!(" (line {line})"),
            lines => format!(
                " (lines {})",
                lines
                    .iter()
                    .map(usize::to_string)
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        };
        format!(
            "{}: {} {}{lines}",
            self.label,
            self.kind,
            self.observation + 1
        )
    }
}

/// The outliers of `study` at a solution with `statistics` and per-observation
/// errors `errors` (numbered across sets, as the system numbers them), worst first.
pub(super) fn find_outliers(
    study: &Study,
    statistics: &ResidualStatistics,
    errors: &[(f64, f64)],
    has_rotation: bool,
    threshold: f64,
) -> Vec<Outlier> {
    let mut outliers = Vec::new();
    if !statistics.standardized.iter().any(|u| *u > threshold) {
        return outliers;
    }
    let mut base = 0;
    for (set_index, set) in study.sets.iter().enumerate() {
        let observations = set.method.observation_samples(&set.samples);
        let kind = if observations.iter().any(|members| members.len() > 1) {
            "pair"
        } else {
            "configuration"
        };
        for (observation, samples) in observations.iter().enumerate() {
            let number = base + observation;
            let Some(&standardized) = statistics.standardized.get(number) else {
                continue;
            };
            if standardized <= threshold {
                continue;
            }
            let (error, rotation) = errors.get(number).copied().unwrap_or((f64::NAN, f64::NAN));
            outliers.push(Outlier {
                set: set_index,
                label: set.label.clone(),
                kind,
                observation,
                lines: samples
                    .iter()
                    .filter_map(|index| set.samples[*index].line)
                    .collect(),
                samples: samples.clone(),
                error,
                rotation_error: has_rotation.then_some(rotation),
                standardized,
                weight: statistics.weights.get(number).copied().unwrap_or(1.0),
            });
        }
        base += observations.len();
    }
    outliers.sort_by(|a, b| b.standardized.total_cmp(&a.standardized));
    outliers
}

/// `study` without the samples of `outliers`.
pub(super) fn inliers(study: &Study, outliers: &[Outlier]) -> Study {
    study.without_samples(&outlier_samples(study, outliers))
}

/// The samples of `outliers`, per set of `study` (for [`Study::without_samples`]).
fn outlier_samples(study: &Study, outliers: &[Outlier]) -> Vec<Vec<usize>> {
    let mut dropped = vec![Vec::new(); study.sets.len()];
    for outlier in outliers {
        dropped[outlier.set].extend(&outlier.samples);
    }
    dropped
}
