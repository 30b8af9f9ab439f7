//! The statistics of an iterate's residuals under a loss: the robust σ̂ per
//! measurement set and kind of row, each observation's standardised residual
//! and weight, and the a-posteriori variance (see [`super::reweighting`]).

use crate::observation::ObservationSystem;
use crate::robust::{Loss, robust_sigma_of};
use crate::rows::RowKind;

/// The smallest σ̂ residuals are standardised by (scaled units: metres of an
/// unweighted set, σ of a weighted one): below it residuals are rounding,
/// and none is an outlier.
const RESIDUAL_FLOOR: f64 = 1e-9;
/// Rows of one kind a set needs for its own σ̂.
const MINIMUM_ROWS: usize = 10;
/// The statistics of the residuals of one iterate under a loss.
#[derive(Clone, Debug)]
pub(super) struct ResidualStatistics {
    /// The robust σ̂ of the scaled measured rows.
    pub(super) robust_sigma: f64,
    /// Each observation's standardised residual u_i (units of σ̂).
    pub(super) standardized: Vec<f64>,
    /// Each observation's weight under the loss.
    pub(super) weights: Vec<f64>,
    /// The a-posteriori variance of the scaled rows under these weights.
    pub(super) variance: f64,
    /// Equations of the observations with a non-zero weight.
    pub(super) effective_equations: usize,
}

impl ResidualStatistics {
    /// The statistics of `system` under `loss`; `equations` counts the
    /// study's independent equations, `unknowns` the identified unknowns.
    pub(super) fn of(
        system: &ObservationSystem,
        loss: &Loss,
        equations: usize,
        unknowns: usize,
    ) -> Self {
        let observations = system.row_observations();
        // σ̂ per set and kind of row: lengths and angles of a set without
        // sensor σ are in metres and radians, which do not compare, and each
        // set is judged by its own noise (its σ may be a rough guess). A set's
        // kind with fewer than MINIMUM_ROWS rows takes the σ̂ of all sets.
        // The scaled residuals are read where they are (millions of rows
        // are not copied).
        let kinds = system.kinds();
        let sigma_of = |values: Vec<f64>| (values.len(), robust_sigma_of(values));
        let of_kind = |kind: RowKind| move |(row, _): &(usize, f64)| kinds[*row] == kind;
        let set_sigma = |set: usize, kind: RowKind| {
            sigma_of(
                system
                    .scaled_rows_of(set)
                    .filter(of_kind(kind))
                    .map(|(_, e)| e)
                    .collect(),
            )
        };
        let all_sigma = |kind: RowKind| {
            sigma_of(
                system
                    .scaled_rows()
                    .filter(of_kind(kind))
                    .map(|(_, e)| e)
                    .collect(),
            )
            .1
        };
        // All sets' σ̂ of a kind: a single set's own, otherwise computed
        // only if a set needs it or to report it.
        const KINDS: [RowKind; 2] = [RowKind::Length, RowKind::Angle];
        let single = system.set_rows().len() == 1;
        let mut pooled: [Option<f64>; 2] = [None; 2];
        // Each observation's standardised residual is the RMS of its rows',
        // summed here as the rows are standardised.
        // Noise-free (simulated) data leave rounding residuals: no outliers
        // among them, and no weights from them.
        // Sums of squares (standardised in place below) and row counts.
        let mut squares = vec![0.0; system.observation_count()];
        let mut rows = vec![0_u32; system.observation_count()];
        for set in 0..system.set_rows().len() {
            for (slot, kind) in KINDS.into_iter().enumerate() {
                let (count, own) = set_sigma(set, kind);
                let sigma = if single {
                    *pooled[slot].insert(own)
                } else if count >= MINIMUM_ROWS {
                    own
                } else {
                    *pooled[slot].get_or_insert_with(|| all_sigma(kind))
                };
                for (row, scaled) in system.scaled_rows_of(set).filter(of_kind(kind)) {
                    let standardized = scaled / sigma.max(RESIDUAL_FLOOR);
                    let observation = observations[row] as usize;
                    squares[observation] += standardized * standardized;
                    rows[observation] += 1;
                }
            }
        }
        let slot = usize::from(!kinds.contains(&RowKind::Length));
        let robust_sigma = pooled[slot].unwrap_or_else(|| all_sigma(KINDS[slot]));
        let mut standardized = squares;
        for (u, rows) in standardized.iter_mut().zip(rows) {
            *u = (*u / f64::from(rows.max(1))).sqrt();
        }
        let weights: Vec<f64> = standardized.iter().map(|u| loss.weight(*u)).collect();
        let discarded = observations
            .iter()
            .filter(|o| weights[**o as usize] == 0.0)
            .count();
        let effective_equations = equations.saturating_sub(discarded);
        let weighted: f64 = system
            .scaled_rows()
            .map(|(row, e)| weights[observations[row] as usize] * e * e)
            .sum();
        ResidualStatistics {
            robust_sigma,
            standardized,
            weights,
            variance: weighted / effective_equations.saturating_sub(unknowns).max(1) as f64,
            effective_equations,
        }
    }
}
