//! A parallel robot's residuals, observation by observation, as CSV
//! (`gecaro identify hexapod --residuals`, Python's `residuals=`, the
//! page's *Download the residuals (CSV)*): the serial residuals' columns
//! ([`crate::residuals`]), one row per observation — a configuration, or a
//! distance's pair — numbered within its data file:
//!
//! | column | meaning |
//! |---|---|
//! | `set`, `file`, `kind`, `observation` | its file (from 1, in the order given), the file's label, `configuration` or `pair`, its number in the file (from 1) |
//! | `lines` | the file's lines of its samples, separated by spaces |
//! | `error_before_mm`, `error_after_mm` | the direct model's position error (a pose's origin, the tool point, a pair's distance) with the nominal and the calibrated platform, in the base frame |
//! | `rotation_before_deg`, `rotation_after_deg` | a measured pose's orientation error (only for poses) |
//! | `residual_sigmas` | the RMS of its rows at the solution, in units of the stated σ (of σ̂ without one; with a robust loss, of its robust σ̂) |
//! | `weight` | its weight in the final fit (1 in least squares, 0 for a measurement dropped by `--reject`) |
//! | `outlier` | `true` beyond the outlier threshold |

use gecaro_calib::identification::DEFAULT_OUTLIER_THRESHOLD;
use gecaro_calib::parallel_robots::{PlatformErrors, PlatformIdentification};
use gecaro_core::parallel_robot::ParallelRobot;

use crate::error::AppError;
use crate::residuals::{residual_header, residual_table};

/// Where the identification's observations are, in its order: each one's
/// set (file) and the lines of its samples.
#[derive(Clone, Debug)]
pub(super) struct ObservationPlaces {
    /// The sets' labels, in order.
    pub(super) labels: Vec<String>,
    /// Each sample's set and line, in order.
    pub(super) samples: Vec<(usize, Option<usize>)>,
    /// Samples an observation takes (2 for a distance's pair).
    pub(super) taken: usize,
}

/// The residuals CSV (module docs) of `result`, its observations at
/// `places`, the direct model's errors `before` and `after` it.
///
/// # Errors
/// As [`residual_table`].
pub(super) fn platform_residuals_csv(
    result: &PlatformIdentification<ParallelRobot>,
    places: &ObservationPlaces,
    (before, after): (&PlatformErrors, &PlatformErrors),
) -> Result<String, AppError> {
    let rotation = !before.observation_angles.is_empty();
    let header = residual_header(rotation);
    let mut rows = Vec::new();
    let number = |value: Option<f64>| value.map_or_else(String::new, |v| format!("{v}"));
    let mut in_set = vec![0usize; places.labels.len()];
    let kind = if places.taken == 2 {
        "pair"
    } else {
        "configuration"
    };
    for (index, observation) in places.samples.chunks_exact(places.taken).enumerate() {
        let set = &observation[0].0;
        in_set[*set] += 1;
        let ratio = result.residual_ratios.get(index).copied();
        let mut row = vec![
            (set + 1).to_string(),
            places.labels[*set].clone(),
            kind.to_owned(),
            in_set[*set].to_string(),
            observation
                .iter()
                .map(|(_, line)| line.map_or_else(|| "?".into(), |line| line.to_string()))
                .collect::<Vec<_>>()
                .join(" "),
            number(before.observations.get(index).map(|error| error * 1e3)),
            number(after.observations.get(index).map(|error| error * 1e3)),
        ];
        if rotation {
            for errors in [before, after] {
                row.push(number(
                    errors
                        .observation_angles
                        .get(index)
                        .map(|angle| angle.to_degrees()),
                ));
            }
        }
        row.push(number(ratio));
        // Dropped (`reject`): weight 0; the others' weights count the kept.
        let dropped_before = result.dropped.partition_point(|dropped| *dropped < index);
        let weight = if result.dropped.binary_search(&index).is_ok() {
            0.0
        } else {
            result
                .weights
                .get(index - dropped_before)
                .copied()
                .unwrap_or(1.0)
        };
        row.push(number(Some(weight)));
        row.push(
            ratio
                .is_some_and(|ratio| ratio > DEFAULT_OUTLIER_THRESHOLD)
                .to_string(),
        );
        rows.push(row);
    }
    residual_table(&header, rows)
}
