//! The identifiable parameters of a parallel robot (Appendix III, as for a
//! serial robot): QR of the observation matrix W with its columns in the
//! order of [`candidates`] (the tool point first), the base set, and what
//! each regrouped parameter stands in.

use faer::Mat;
use gecaro_core::parallel_model::ParallelModel;
use gecaro_data::sample::Sample;

use super::auxiliary::Auxiliary;
use super::measure::PlatformMeasure;
use super::observation::{PlatformRows, platform_rows};
use crate::Error;
use crate::identifiability::{ParameterStatus, RELATIVE_ZERO_FLOOR};
use crate::linalg::{
    column_geometry, condition_number, greedy_rank, largest_column_norm, regrouping_relations,
    select_columns,
};

/// The identifiable parameters of a parallel robot for one measure.
#[derive(Clone, Debug, PartialEq)]
pub struct PlatformRankReport {
    /// What was measured.
    pub measure: PlatformMeasure,
    /// Every parameter's name ([`ParallelModel::parameter_names`]).
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

/// The identifiable parameters of `model` measured by `measure` at the
/// configurations of `samples` (their measured values are not used).
///
/// # Errors
/// A measure the structure cannot take, samples without the measure's
/// columns or the model's number of actuator values, actuator values no
/// pose has, or fewer equations than candidate parameters.
pub fn platform_identifiability<M: ParallelModel>(
    model: &M,
    samples: &[Sample],
    measure: PlatformMeasure,
) -> Result<PlatformRankReport, Error> {
    let rows = platform_rows(
        model,
        samples,
        measure,
        None,
        &Auxiliary::none(),
        &mut Vec::new(),
    )?;
    rank_of(model, &rows, measure)
}

/// The candidate parameters of a measure, in the order QR keeps them: the
/// tool point's first when it is measured (the point a user measured is
/// identified; what a point does not observe is left to the platform's
/// joints), then the others in vocabulary order — for a measuring leg,
/// without the parameters of the frames' convention, which are excluded.
fn candidates(model: &impl ParallelModel, measure: PlatformMeasure) -> Vec<usize> {
    let tool = model.tool_parameters();
    let others = (0..model.parameter_count()).filter(|index| !tool.contains(index));
    if measure.measures_tool() {
        model.tool_parameters().chain(others).collect()
    } else if measure == PlatformMeasure::Leg {
        // Nothing outside the robot sees its frames: the parameters that
        // hold them by the structure's convention keep their stated values
        // (QR's pivoting would hold others, its own choice of frames).
        let frames = model.frame_parameters();
        others.filter(|index| !frames.contains(index)).collect()
    } else {
        others.collect()
    }
}

/// [`platform_identifiability`] of rows already made.
pub(super) fn rank_of(
    model: &impl ParallelModel,
    rows: &PlatformRows,
    measure: PlatformMeasure,
) -> Result<PlatformRankReport, Error> {
    let order = candidates(model, measure);
    let columns = order.len();
    let equations = rows.matrix.nrows();
    if equations < columns {
        return Err(Error::TooFewEquations {
            equations,
            unknowns: columns,
        });
    }
    let geometry = column_geometry(select_columns(rows.matrix.as_ref(), &order).as_ref());
    let tolerance = (columns as f64 * f64::EPSILON).max(RELATIVE_ZERO_FLOOR)
        * largest_column_norm(geometry.as_ref());
    let rank = greedy_rank(geometry.as_ref(), tolerance);
    // Statuses by column of the ordered W, then by parameter.
    let status_of = |column: usize| {
        if rank.norms[column] <= tolerance {
            ParameterStatus::NoEffect
        } else if rank.kept.contains(&column) {
            ParameterStatus::Identifiable
        } else {
            ParameterStatus::Regrouped
        }
    };
    let mut statuses = vec![ParameterStatus::Excluded; model.parameter_count()];
    for (column, parameter) in order.iter().enumerate() {
        statuses[*parameter] = status_of(column);
    }
    let kept = rank.kept.clone();
    let regrouped: Vec<usize> = (0..columns)
        .filter(|c| status_of(*c) == ParameterStatus::Regrouped)
        .collect();
    let relations = if regrouped.is_empty() {
        Vec::new()
    } else {
        let (beta, _) = regrouping_relations(geometry.as_ref(), &kept, &regrouped);
        regrouped
            .iter()
            .enumerate()
            .map(|(j, column)| PlatformRelation {
                parameter: order[*column],
                terms: kept
                    .iter()
                    .enumerate()
                    .filter(|(k, _)| beta[(*k, j)].abs() > 1e-9)
                    .map(|(k, kept_column)| (order[*kept_column], beta[(k, j)]))
                    .collect(),
            })
            .collect()
    };
    let base_columns: Mat<f64> = select_columns(geometry.as_ref(), &kept);
    // The base set in vocabulary order (the identification's columns).
    let mut base: Vec<usize> = kept.iter().map(|column| order[*column]).collect();
    base.sort_unstable();
    Ok(PlatformRankReport {
        measure,
        names: model.parameter_names(),
        statuses,
        condition_number: condition_number(base_columns.as_ref())?,
        base,
        relations,
        rows: equations,
        tolerance,
    })
}
