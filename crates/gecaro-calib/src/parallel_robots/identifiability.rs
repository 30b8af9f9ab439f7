//! The identifiable parameters of a platform (Appendix III, as for a serial
//! robot): QR of the observation matrix W, the base set in vocabulary order,
//! and what each regrouped parameter stands in.

use faer::Mat;
use gecaro_core::gough_stewart::{GoughStewart, LEGS, PARAMETER_COUNT, PARAMETERS_PER_LEG};
use gecaro_data::sample::Sample;

use super::measure::PlatformMeasure;
use super::observation::{PlatformRows, platform_rows};
use crate::Error;
use crate::identifiability::{ParameterStatus, RELATIVE_ZERO_FLOOR};
use crate::linalg::{
    column_geometry, condition_number, greedy_rank, largest_column_norm, regrouping_relations,
    select_columns,
};

/// The identifiable parameters of a platform for one measure.
#[derive(Clone, Debug, PartialEq)]
pub struct PlatformRankReport {
    /// What was measured.
    pub measure: PlatformMeasure,
    /// Every parameter's name ([`GoughStewart::parameter_names`]).
    pub names: Vec<String>,
    /// Every parameter's status: identifiable, regrouped, of no effect, or
    /// excluded (the tool point when only poses are measured).
    pub statuses: Vec<ParameterStatus>,
    /// The identifiable parameters' indices, in vocabulary order.
    pub base: Vec<usize>,
    /// What each regrouped parameter's effect is carried by.
    pub relations: Vec<PlatformRelation>,
    /// The condition number of the base columns of W.
    pub condition_number: f64,
    /// Rows of W (equations).
    pub rows: usize,
    /// The numerical zero τ (eq. 34, with its floor).
    pub tolerance: f64,
}

/// A regrouped parameter: its effect on the measurements is that of
/// `Σ coefficient·base parameter`, so each of those identifies its own value
/// plus `coefficient ×` this parameter's error.
#[derive(Clone, Debug, PartialEq)]
pub struct PlatformRelation {
    /// The regrouped parameter's index.
    pub parameter: usize,
    /// `(base parameter index, coefficient)`, coefficients above 10⁻⁹.
    pub terms: Vec<(usize, f64)>,
}

impl PlatformRankReport {
    /// How many parameters are identifiable.
    pub fn rank(&self) -> usize {
        self.base.len()
    }
}

/// The identifiable parameters of `platform` measured by `measure` at the
/// configurations of `samples` (their measured values are not used).
///
/// # Errors
/// Samples without the measure's columns or six actuator values, actuator
/// values no pose has, or fewer equations than candidate parameters.
pub fn platform_identifiability(
    platform: &GoughStewart,
    samples: &[Sample],
    measure: PlatformMeasure,
) -> Result<PlatformRankReport, Error> {
    let rows = platform_rows(platform, samples, measure, None, &mut Vec::new())?;
    rank_of(&rows, measure)
}

/// The candidate parameters of a measure: every leg parameter, and the tool
/// point's when it is measured.
pub(super) fn candidates(measure: PlatformMeasure) -> usize {
    if measure.measures_tool() {
        PARAMETER_COUNT
    } else {
        LEGS * PARAMETERS_PER_LEG
    }
}

/// [`platform_identifiability`] of rows already made.
pub(super) fn rank_of(
    rows: &PlatformRows,
    measure: PlatformMeasure,
) -> Result<PlatformRankReport, Error> {
    let columns = candidates(measure);
    let equations = rows.matrix.nrows();
    if equations < columns {
        return Err(Error::TooFewEquations {
            equations,
            unknowns: columns,
        });
    }
    let matrix = rows.matrix.get(.., ..columns);
    let geometry = column_geometry(matrix);
    let tolerance = (columns as f64 * f64::EPSILON).max(RELATIVE_ZERO_FLOOR)
        * largest_column_norm(geometry.as_ref());
    let rank = greedy_rank(geometry.as_ref(), tolerance);
    let mut statuses = vec![ParameterStatus::Excluded; PARAMETER_COUNT];
    for (column, status) in statuses.iter_mut().enumerate().take(columns) {
        *status = if rank.norms[column] <= tolerance {
            ParameterStatus::NoEffect
        } else if rank.kept.contains(&column) {
            ParameterStatus::Identifiable
        } else {
            ParameterStatus::Regrouped
        };
    }
    let base = rank.kept.clone();
    let regrouped: Vec<usize> = (0..columns)
        .filter(|c| statuses[*c] == ParameterStatus::Regrouped)
        .collect();
    let relations = if regrouped.is_empty() {
        Vec::new()
    } else {
        let (beta, _) = regrouping_relations(geometry.as_ref(), &base, &regrouped);
        regrouped
            .iter()
            .enumerate()
            .map(|(j, parameter)| PlatformRelation {
                parameter: *parameter,
                terms: base
                    .iter()
                    .enumerate()
                    .filter(|(k, _)| beta[(*k, j)].abs() > 1e-9)
                    .map(|(k, index)| (*index, beta[(k, j)]))
                    .collect(),
            })
            .collect()
    };
    let base_columns: Mat<f64> = select_columns(geometry.as_ref(), &base);
    Ok(PlatformRankReport {
        measure,
        names: GoughStewart::parameter_names(),
        statuses,
        condition_number: condition_number(base_columns.as_ref())?,
        base,
        relations,
        rows: equations,
        tolerance,
    })
}
