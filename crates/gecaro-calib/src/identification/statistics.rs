//! The statistics of an iterate's residuals under a loss: the robust σ̂ per
//! measurement set and kind of row, each observation's standardised residual
//! and weight, and the a-posteriori variance (see [`super::reweighting`]).

use std::ops::Range;

use crate::observation::ObservationSystem;
use crate::parallel::scan_parts;
use crate::robust::{Loss, robust_sigma_parts};
use crate::rows::RowKind;

/// The smallest σ̂ residuals are standardised by (scaled units: metres of an
/// unweighted set, σ of a weighted one): below it residuals are rounding,
/// and none is an outlier.
const RESIDUAL_FLOOR: f64 = 1e-9;

/// Whether a sum of squares `cost` of `rows` scaled rows is rounding: its
/// RMS below [`RESIDUAL_FLOOR`] (noise-free, simulated data fitted).
pub(super) fn at_rounding(cost: f64, rows: usize) -> bool {
    cost <= rows as f64 * RESIDUAL_FLOOR * RESIDUAL_FLOOR
}
/// Rows of one kind a set needs for its own σ̂.
const MINIMUM_ROWS: usize = 10;

/// `rows` cut into contiguous parts ([`scan_parts`]). The σ̂ is the same,
/// bit for bit, for any cut.
fn row_parts(rows: Range<usize>) -> Vec<Range<usize>> {
    scan_parts(rows.len())
        .into_iter()
        .map(|part| rows.start + part.start..rows.start + part.end)
        .collect()
}

/// The robust σ̂ of the `count` values `values(rows)` yields for the parts
/// of `rows`.
fn sigma_in_parts<I: Iterator<Item = f64>>(
    rows: Range<usize>,
    count: usize,
    values: impl Fn(Range<usize>) -> I + Sync,
) -> f64 {
    let parts = row_parts(rows);
    robust_sigma_parts(count, parts.len(), |part| values(parts[part].clone()))
}
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
        const KINDS: [RowKind; 2] = [RowKind::Length, RowKind::Angle];
        let slot_of = |row: usize| usize::from(kinds[row] == RowKind::Angle);
        // Rows of set `set` of a kind, counted from their kinds alone.
        let counted = |set: usize, kind: RowKind| {
            kinds[system.set_rows()[set].clone()]
                .iter()
                .filter(|row| **row == kind)
                .count()
        };
        // The σ̂ of a set's (or all sets') scaled residuals of a kind, read
        // where they are, and how many there are.
        let set_sigma = |set: usize, slot: usize| {
            let count = counted(set, KINDS[slot]);
            let sigma = sigma_in_parts(system.set_rows()[set].clone(), count, |rows| {
                system.scaled_of_kind_within(set, KINDS[slot], rows)
            });
            (sigma, count)
        };
        let all_sigma = |kind: RowKind| {
            let sets = system.set_rows();
            let rows =
                sets.first().map_or(0, |set| set.start)..sets.last().map_or(0, |set| set.end);
            let count = (0..sets.len()).map(|set| counted(set, kind)).sum();
            sigma_in_parts(rows, count, |rows| {
                (0..sets.len())
                    .flat_map(move |set| system.scaled_of_kind_within(set, kind, rows.clone()))
            })
        };
        // All sets' σ̂ of a kind: a single set's own, otherwise computed
        // only if a set needs it or to report it.
        let single = system.set_rows().len() == 1;
        let mut pooled: [Option<f64>; 2] = [None; 2];
        // Each observation's standardised residual is the RMS of its rows',
        // summed here as the rows are standardised.
        // Noise-free (simulated) data leave rounding residuals: no outliers
        // among them, and no weights from them.
        // Sums of squares (standardised in place below) and row counts, and
        // the plain sum of squares of the scaled rows (the variance's when
        // every weight is 1).
        let mut squares = vec![0.0; system.observation_count()];
        let mut rows = vec![0_u32; system.observation_count()];
        let mut plain = 0.0;
        for set in 0..system.set_rows().len() {
            let mut sigmas = [0.0; 2];
            for slot in 0..KINDS.len() {
                let (own, count) = set_sigma(set, slot);
                sigmas[slot] = if single {
                    *pooled[slot].insert(own)
                } else if count >= MINIMUM_ROWS {
                    own
                } else {
                    *pooled[slot].get_or_insert_with(|| all_sigma(KINDS[slot]))
                };
            }
            for (row, scaled) in system.scaled_rows_of(set) {
                let standardized = scaled / sigmas[slot_of(row)].max(RESIDUAL_FLOOR);
                let observation = observations[row] as usize;
                squares[observation] += standardized * standardized;
                rows[observation] += 1;
                plain += scaled * scaled;
            }
        }
        let slot = usize::from(!kinds.contains(&RowKind::Length));
        let robust_sigma = pooled[slot].unwrap_or_else(|| all_sigma(KINDS[slot]));
        let mut standardized = squares;
        for (u, rows) in standardized.iter_mut().zip(&rows) {
            *u = (*u / f64::from((*rows).max(1))).sqrt();
        }
        let weights: Vec<f64> = standardized.iter().map(|u| loss.weight(*u)).collect();
        // Rows of the observations a robust loss ignores, counted by
        // observation.
        let discarded: usize = weights
            .iter()
            .zip(&rows)
            .filter(|(weight, _)| **weight == 0.0)
            .map(|(_, rows)| *rows as usize)
            .sum();
        let effective_equations = equations.saturating_sub(discarded);
        // Every weight 1 (least squares): the plain sum, in the same order.
        let weighted: f64 = if weights.iter().all(|weight| *weight == 1.0) {
            plain
        } else {
            system
                .scaled_rows()
                .map(|(row, e)| weights[observations[row] as usize] * e * e)
                .sum()
        };
        ResidualStatistics {
            robust_sigma,
            standardized,
            weights,
            variance: weighted / effective_equations.saturating_sub(unknowns).max(1) as f64,
            effective_equations,
        }
    }
}
