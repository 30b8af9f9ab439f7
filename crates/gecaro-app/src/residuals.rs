//! The residuals of an identification, observation by observation, as a CSV
//! file a spreadsheet or a script reads (`gecaro identify --residuals`, the
//! page's "Download the residuals", Python's `Identification.residuals_csv`).
//!
//! One row per observation (a configuration, or a pair for the link and
//! distance methods), numbered across the study's sets as the identification
//! numbers them, with the lines of its data file:
//!
//! | column | meaning |
//! |---|---|
//! | `set`, `file`, `kind`, `observation` | its set (from 1), the set's label, `configuration` or `pair`, its number in the set (from 1) |
//! | `lines` | the data file's lines of its samples, separated by spaces |
//! | `error_before_mm`, `error_after_mm` | its position-like error with the nominal and the calibrated robot |
//! | `rotation_before_deg`, `rotation_after_deg` | its orientation error (only for data with orientations) |
//! | `residual_sigmas` | its standardised residual at the solution (robust σ̂) |
//! | `weight` | its weight in the final fit (1 in least squares) |
//! | `outlier` | `true` beyond the outlier threshold |
//! | `dx_mm`, `dy_mm`, `dz_mm` | a measured point's deviation from the calibrated robot's, along the robot's base axes ([`point_deviations`](crate::point_deviations); only when the study measures points, empty on other rows) |

use gecaro_calib::identification::{Identification, locate_observations};
use gecaro_calib::study::Study;

use crate::deviations::PointDeviation;

use crate::error::{AppError, ErrorKind};

/// The residuals of `result`, identified from `study`, as CSV text, with
/// the measured points' `deviations` ([`crate::point_deviations`]) when
/// there are any.
///
/// # Errors
/// [`ErrorKind::Numerical`] if the CSV cannot be written (it always can: the
/// writer is in memory).
pub fn residuals_csv(
    study: &Study,
    result: &Identification,
    deviations: Option<&[PointDeviation]>,
) -> Result<String, AppError> {
    let rotation = result.before.rms_rotation.is_some();
    // Each observation's deviation, by its index (none for the others).
    let mut by_observation: Vec<Option<[f64; 3]>> = Vec::new();
    for point in deviations.unwrap_or_default() {
        if by_observation.len() <= point.index {
            by_observation.resize(point.index + 1, None);
        }
        by_observation[point.index] = Some(point.deviation);
    }
    let mut header = residual_header(rotation);
    if !by_observation.is_empty() {
        header.extend(["dx_mm", "dy_mm", "dz_mm"]);
    }
    let mut rows = Vec::new();
    let number = |value: Option<f64>| value.map_or_else(String::new, |v| format!("{v}"));
    for (index, located) in locate_observations(study).iter().enumerate() {
        let before = result.errors_before.get(index);
        let after = result.errors_after.get(index);
        let standardized = result.standardized.get(index).copied();
        let mut row = vec![
            (located.set + 1).to_string(),
            located.label.clone(),
            located.kind.to_owned(),
            (located.observation + 1).to_string(),
            located
                .lines
                .iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(" "),
            number(before.map(|e| e.0 * 1e3)),
            number(after.map(|e| e.0 * 1e3)),
        ];
        if rotation {
            row.push(number(before.map(|e| e.1.to_degrees())));
            row.push(number(after.map(|e| e.1.to_degrees())));
        }
        row.push(number(standardized));
        row.push(number(result.observation_weights.get(index).copied()));
        row.push(
            standardized
                .is_some_and(|u| u > result.outlier_threshold)
                .to_string(),
        );
        if !by_observation.is_empty() {
            let deviation = by_observation.get(index).copied().flatten();
            for axis in 0..3 {
                row.push(number(deviation.map(|d| d[axis] * 1e3)));
            }
        }
        rows.push(row);
    }
    residual_table(&header, rows)
}

/// The columns every residuals file begins with — an observation's place,
/// its errors before and after (their rotations when the data have
/// orientations), its standardised residual, weight and whether it stands
/// out — the serial and the parallel ones alike.
pub(crate) fn residual_header(rotation: bool) -> Vec<&'static str> {
    let mut header = vec![
        "set",
        "file",
        "kind",
        "observation",
        "lines",
        "error_before_mm",
        "error_after_mm",
    ];
    if rotation {
        header.extend(["rotation_before_deg", "rotation_after_deg"]);
    }
    header.extend(["residual_sigmas", "weight", "outlier"]);
    header
}

/// A residuals file's CSV text: `header`, then `rows` (the serial and the
/// parallel residuals write theirs alike).
///
/// # Errors
/// [`ErrorKind::Numerical`] if the CSV cannot be written (it always can:
/// the writer is in memory).
pub(crate) fn residual_table(header: &[&str], rows: Vec<Vec<String>>) -> Result<String, AppError> {
    let failed = |error: csv::Error| {
        AppError::plain(
            ErrorKind::Numerical,
            format!("cannot write the residuals: {error}"),
        )
    };
    let mut writer = csv::Writer::from_writer(Vec::new());
    writer.write_record(header).map_err(failed)?;
    for row in rows {
        writer.write_record(&row).map_err(failed)?;
    }
    let bytes = writer
        .into_inner()
        .map_err(|error| failed(error.into_error().into()))?;
    String::from_utf8(bytes).map_err(|error| {
        AppError::plain(
            ErrorKind::Numerical,
            format!("cannot write the residuals: {error}"),
        )
    })
}
