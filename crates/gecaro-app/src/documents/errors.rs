//! Error statistics over observations and how one robot's compare with
//! another's on the same measurements (metres; radians for orientations).

use gecaro_calib::identification::ErrorSummary;
use serde::Serialize;

/// How a compared robot (the calibrated one) fares against the robot (the
/// nominal, or the table's) on the same measurements: the verdict of an
/// evaluation on held-out data.
#[derive(Clone, Debug, Serialize)]
pub struct ComparisonJson {
    /// `better`, `worse`, or `same` (RMS within 5 % of the robot's).
    pub outcome: &'static str,
    /// The compared robot's RMS over the robot's (position-like errors).
    pub rms_ratio: f64,
    /// In words, with both RMS values in millimetres.
    pub summary: String,
}

impl ComparisonJson {
    /// RMS ratios within this of 1 are `same`.
    const SAME: f64 = 0.05;

    /// The comparison of the compared robot's errors `compared` with the
    /// robot's `robot` (position-like RMS, metres).
    pub fn of(robot: &ErrorSummary, compared: &ErrorSummary) -> Self {
        let ratio = compared.rms / robot.rms;
        let (outcome, words) = if !ratio.is_finite() {
            (
                if compared.rms < robot.rms {
                    "better"
                } else {
                    "same"
                },
                "exact on these data".to_owned(),
            )
        } else if (ratio - 1.0).abs() <= Self::SAME {
            ("same", "as accurate as the robot compared with".to_owned())
        } else if ratio < 1.0 {
            (
                "better",
                format!("{}× smaller errors", three_digits(1.0 / ratio)),
            )
        } else {
            (
                "worse",
                format!("WORSE: {}× larger errors", three_digits(ratio)),
            )
        };
        ComparisonJson {
            outcome,
            rms_ratio: ratio,
            summary: format!(
                "{words} (RMS {:.4} mm against {:.4} mm)",
                compared.rms * 1e3,
                robot.rms * 1e3
            ),
        }
    }
}

/// A factor with three significant digits: 673, 10.3, 1.29.
fn three_digits(factor: f64) -> String {
    match factor {
        f if f >= 100.0 => format!("{f:.0}"),
        f if f >= 10.0 => format!("{f:.1}"),
        f => format!("{f:.2}"),
    }
}

/// Error statistics over observations (metres; radians for orientations).
#[derive(Clone, Debug, Serialize)]
pub struct SummaryJson {
    /// Root mean square.
    pub rms: f64,
    /// Mean.
    pub mean: f64,
    /// Largest.
    pub max: f64,
    /// Number of observations.
    pub count: usize,
    /// RMS of the orientation errors, for methods that measure orientation.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rms_rotation: Option<f64>,
    /// Largest orientation error.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_rotation: Option<f64>,
}

impl From<&ErrorSummary> for SummaryJson {
    fn from(summary: &ErrorSummary) -> Self {
        SummaryJson {
            rms: summary.rms,
            mean: summary.mean,
            max: summary.max,
            count: summary.count,
            rms_rotation: summary.rms_rotation,
            max_rotation: summary.max_rotation,
        }
    }
}
