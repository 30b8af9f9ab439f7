//! The continuous D-optimal design of a pool: weights w_u ≥ 0, Σ w_u = 1,
//! that maximise det M(w), M(w) = Σ w_u X_uᵀX_u, found by the
//! multiplicative algorithm (Titterington 1976; Silvey, Titterington &
//! Torsney 1978): w_u ← w_u · tr(M(w)⁻¹ X_uᵀX_u) / p, with p the number of
//! columns. Each step raises det M(w); at the optimum every unit of
//! positive weight has tr(M⁻¹X_uᵀX_u) = p (the Kiefer–Wolfowitz
//! equivalence theorem), and no unit more.
//!
//! An exact design of k units is then rounded from the weights (the k
//! heaviest), as a start for the exchange (`planning::detmax`): the greedy
//! start builds a design one unit at a time and can leave the exchange in a
//! local optimum that the continuous optimum avoids.

use faer::linalg::matmul::matmul;
use faer::linalg::solvers::DenseSolveCore;
use faer::{Accum, Mat, Par};

use super::columns::Blocks;
use crate::Error;

/// Iterations of the multiplicative algorithm: enough for the support of
/// the optimum, which is all the rounding needs (on a pool of 500 Stanford
/// position candidates, 100 and 300 iterations give the same plan of 76;
/// 40 do not).
const ITERATIONS: usize = 100;
/// Stop when max_u tr(M⁻¹X_uᵀX_u) ≤ p (1 + this): near the optimum.
const EQUIVALENCE_TOLERANCE: f64 = 1e-3;

/// The weights of the continuous D-optimal design over the `admissible`
/// units of `candidates` (zero for the others); `ridge` keeps M(w)
/// positive definite.
///
/// # Errors
/// [`Error::Numerical`] when M(w) is not positive definite.
pub(super) fn d_optimal_weights(
    candidates: &Blocks,
    admissible: &[bool],
    ridge: f64,
) -> Result<Vec<f64>, Error> {
    let count = admissible.iter().filter(|a| **a).count();
    if count == 0 {
        return Ok(vec![0.0; candidates.units.len()]);
    }
    let width = candidates.width;
    let mut weights: Vec<f64> = admissible
        .iter()
        .map(|a| if *a { 1.0 / count as f64 } else { 0.0 })
        .collect();
    // Every unit's rows stacked once (column-major, as faer holds them):
    // M(w) = Xᵀ diag(w) X and the variances tr(M⁻¹X_uᵀX_u) = Σ_rows
    // (X M⁻¹) ∘ X are then two products of the tall matrix per iteration,
    // each a blocked multiplication.
    let unit_of_row: Vec<usize> = candidates
        .units
        .iter()
        .enumerate()
        .flat_map(|(unit, block)| std::iter::repeat_n(unit, block.nrows()))
        .collect();
    let total_rows = unit_of_row.len();
    let mut stacked = Mat::<f64>::zeros(total_rows, width);
    let mut row = 0;
    for block in &candidates.units {
        for c in 0..width {
            for r in 0..block.nrows() {
                stacked[(row + r, c)] = block[(r, c)];
            }
        }
        row += block.nrows();
    }
    let mut scaled = Mat::<f64>::zeros(total_rows, width);
    let mut moment = Mat::<f64>::zeros(width, width);
    let mut products = Mat::<f64>::zeros(total_rows, width);
    let mut row_roots = vec![0.0; total_rows];
    let mut row_variances = vec![0.0; total_rows];
    let mut variances = vec![0.0; weights.len()];
    for _ in 0..ITERATIONS {
        for (root, unit) in row_roots.iter_mut().zip(&unit_of_row) {
            *root = weights[*unit].sqrt();
        }
        for c in 0..width {
            let (from, to) = (stacked.col(c), scaled.col_mut(c));
            for ((out, value), root) in to.iter_mut().zip(from.iter()).zip(&row_roots) {
                *out = value * root;
            }
        }
        matmul(
            moment.as_mut(),
            Accum::Replace,
            scaled.transpose(),
            scaled.as_ref(),
            1.0,
            Par::Seq,
        );
        for d in 0..width {
            moment[(d, d)] += ridge;
        }
        let inverse = moment
            .llt(faer::Side::Lower)
            .map_err(|_| Error::Numerical {
                message: "planning: the continuous design's information is not positive definite"
                    .into(),
            })?
            .inverse();
        matmul(
            products.as_mut(),
            Accum::Replace,
            stacked.as_ref(),
            inverse.as_ref(),
            1.0,
            Par::Seq,
        );
        row_variances.iter_mut().for_each(|v| *v = 0.0);
        for c in 0..width {
            for ((variance, p), x) in row_variances
                .iter_mut()
                .zip(products.col(c).iter())
                .zip(stacked.col(c).iter())
            {
                *variance += p * x;
            }
        }
        variances.iter_mut().for_each(|v| *v = 0.0);
        for (variance, unit) in row_variances.iter().zip(&unit_of_row) {
            variances[*unit] += variance;
        }
        let largest = variances
            .iter()
            .zip(admissible)
            .filter(|(_, a)| **a)
            .map(|(v, _)| *v)
            .fold(0.0, f64::max);
        if largest <= width as f64 * (1.0 + EQUIVALENCE_TOLERANCE) {
            break;
        }
        for (weight, variance) in weights.iter_mut().zip(&variances) {
            *weight *= variance / width as f64;
        }
        let total: f64 = weights.iter().sum();
        for weight in &mut weights {
            *weight /= total;
        }
    }
    Ok(weights)
}

/// The `wanted` heaviest units (ties by index), as chosen flags.
pub(super) fn heaviest(weights: &[f64], wanted: usize) -> Vec<bool> {
    let mut order: Vec<usize> = (0..weights.len()).filter(|u| weights[*u] > 0.0).collect();
    order.sort_by(|a, b| weights[*b].total_cmp(&weights[*a]).then(a.cmp(b)));
    let mut chosen = vec![false; weights.len()];
    for unit in order.into_iter().take(wanted) {
        chosen[unit] = true;
    }
    chosen
}
