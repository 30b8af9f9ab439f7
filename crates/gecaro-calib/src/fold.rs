//! Rows of the observation matrix folded as they are written (issue 36): a
//! tall system `W x ≈ r` of millions of rows is never held, only what every
//! least-squares computation on it reads.
//!
//! ## What is kept
//!
//! For the weighted rows `w_i` and right-hand sides `r_i` (both already
//! multiplied by the row's weight), in one of two forms ([`FoldKind`]):
//!
//! - [`FoldKind::Gram`]: the normal equations `G = WᵀW` and `g = Wᵀr`
//!   (`b²/2` multiply–adds a row). Enough where the normal equations are
//!   accurate (an equilibrated condition number below
//!   [`NORMAL_EQUATIONS_CONDITION`]).
//! - [`FoldKind::Factor`]: the R̃ of a QR of `[W | r]`, folded block by
//!   block (tall-skinny QR, [`TriangularFold`]): `R̃ = [R z; 0 ρ]`, with
//!   `W = QR`, `z = Qᵀr` and `ρ` the least-squares residual's norm. As
//!   accurate as a QR of W (the rank decisions of Appendix III read R); G
//!   and g follow as `RᵀR` and `Rᵀz`.
//!
//! ## Why it suffices
//!
//! Every computation of an identification on W is a least-squares problem
//! `min ‖W x − r‖²` (plain, damped, truncated, restricted to columns) or a
//! quantity of its covariance. For any square `R` and `z` with `RᵀR = WᵀW`
//! and `Rᵀz = Wᵀr`, `‖R x − z‖² = ‖W x − r‖² − const`: the same solutions,
//! the same column norms (Marquardt's scaling), the same singular values
//! and right singular vectors, the same `‖W·step‖²`. So [`FoldedRows::stand_in`]
//! hands those routines a c × c stand-in for W (the factor's R, or a square
//! root of G from its eigen-decomposition), and they run unchanged.
//!
//! Parts are folded in a fixed order whatever the number of cores, so the
//! results are the same on every machine; they differ from those of the
//! held W in floating-point order only.

use faer::{Mat, MatRef};

use crate::linalg::{
    NORMAL_EQUATIONS_CONDITION, NormalEquations, TriangularFold, add_normal_sums, stacked_factor,
};

/// The measured rows from which a system is streamed by default (about 330
/// position configurations). Folding costs half a QR's work (`b²/2`
/// multiply–adds a row against `b²`) and no held W: from a few hundred
/// configurations on, streaming is the faster, below it holding W is
/// (measured: docs/performance.md, "streamed from 1,000 rows").
pub const DEFAULT_STREAMED_ROWS: usize = 1_000;

/// What a fold keeps; see the module docs.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum FoldKind {
    /// The normal equations: where they are accurate enough.
    Gram,
    /// The triangular factor of `[W | r]`: as accurate as a QR of W.
    Factor,
}

/// Rows of `c` columns folded so far; see the module docs.
pub(crate) struct RowFold {
    columns: usize,
    sums: Folding,
    rows: usize,
}

/// What a [`RowFold`] sums into.
enum Folding {
    Gram {
        gram: Mat<f64>,
        projected: Mat<f64>,
    },
    Factor {
        fold: TriangularFold,
        /// `[W | r]` of the block being folded.
        augmented: Mat<f64>,
    },
}

impl RowFold {
    /// An empty fold of rows of `columns` entries, of about `rows` rows.
    pub(crate) fn new(columns: usize, kind: FoldKind, rows: usize) -> Self {
        let sums = match kind {
            FoldKind::Gram => Folding::Gram {
                gram: Mat::zeros(columns, columns),
                projected: Mat::zeros(columns, 1),
            },
            FoldKind::Factor => Folding::Factor {
                fold: TriangularFold::new(columns + 1, rows),
                augmented: Mat::zeros(0, 0),
            },
        };
        RowFold {
            columns,
            sums,
            rows: 0,
        }
    }

    /// Folds the rows `matrix` (row `i` of W, weighted) with their weighted
    /// right-hand sides `right`.
    pub(crate) fn push(&mut self, matrix: MatRef<'_, f64>, right: &[f64]) {
        let (rows, columns) = matrix.shape();
        debug_assert!(columns == self.columns && right.len() == rows);
        self.rows += rows;
        match &mut self.sums {
            Folding::Gram { gram, projected } => add_normal_sums(
                gram,
                projected,
                matrix,
                MatRef::from_column_major_slice(right, rows, 1),
            ),
            Folding::Factor { fold, augmented } => {
                if augmented.nrows() < rows {
                    *augmented = Mat::zeros(rows, columns + 1);
                }
                augmented.get_mut(..rows, ..columns).copy_from(matrix);
                for (i, value) in right.iter().enumerate() {
                    augmented[(i, columns)] = *value;
                }
                fold.push(augmented.get(..rows, ..));
            }
        }
    }

    /// What the rows folded come to.
    pub(crate) fn finish(self) -> FoldedRows {
        FoldedRows {
            columns: self.columns,
            rows: self.rows,
            sums: match self.sums {
                Folding::Gram { gram, projected } => Sums::Gram { gram, projected },
                Folding::Factor { fold, .. } => Sums::Factor(fold.factor()),
            },
        }
    }
}

/// Rows folded into normal equations or a triangular factor; see the module docs.
#[derive(Clone, Debug)]
pub(crate) struct FoldedRows {
    columns: usize,
    rows: usize,
    sums: Sums,
}

/// What [`FoldedRows`] keep.
#[derive(Clone, Debug)]
enum Sums {
    /// `WᵀW` (lower triangle) and `Wᵀr`.
    Gram { gram: Mat<f64>, projected: Mat<f64> },
    /// R̃ of `[W | r]`, (c + 1) × (c + 1).
    Factor(Mat<f64>),
}

impl FoldedRows {
    /// No rows, in `columns` columns, of `kind`.
    pub(crate) fn empty(columns: usize, kind: FoldKind) -> Self {
        RowFold::new(columns, kind, 1).finish()
    }

    /// Number of rows folded.
    pub(crate) fn row_count(&self) -> usize {
        self.rows
    }

    /// The rows of `self` and then of every one of `others` (of the same
    /// kind, in order).
    pub(crate) fn merged(mut self, others: impl IntoIterator<Item = FoldedRows>) -> Self {
        let others: Vec<FoldedRows> = others.into_iter().collect();
        self.rows += others.iter().map(|other| other.rows).sum::<usize>();
        self.sums = match self.sums {
            Sums::Gram {
                mut gram,
                mut projected,
            } => {
                for other in &others {
                    if let Sums::Gram {
                        gram: other_gram,
                        projected: other_projected,
                    } = &other.sums
                    {
                        gram += other_gram;
                        projected += other_projected;
                    }
                }
                Sums::Gram { gram, projected }
            }
            Sums::Factor(factor) => {
                let mut factors = vec![factor];
                factors.extend(others.into_iter().filter_map(|other| match other.sums {
                    Sums::Factor(factor) => Some(factor),
                    Sums::Gram { .. } => None,
                }));
                Sums::Factor(stacked_factor(&factors))
            }
        };
        self
    }

    /// The rows of `self` and `matrix` (weighted, row-major `rows × c`,
    /// with weighted right-hand sides `right`): a few rows appended.
    pub(crate) fn with_rows(&self, matrix: MatRef<'_, f64>, right: &[f64]) -> Self {
        let mut fold = RowFold::new(self.columns, self.kind(), matrix.nrows());
        fold.push(matrix, right);
        self.clone().merged([fold.finish()])
    }

    /// The rows with their right-hand sides `r` moved to `r − W·step`, a
    /// linear step ([`crate::observation::ObservationSystem::apply_linear_step`]):
    /// `Wᵀr` less `WᵀW·step`, or a factor's `z` less `R·step` (the part of
    /// `r` outside the span of W, the factor's last diagonal entry, stays).
    pub(crate) fn apply_step(&mut self, step: &[f64]) {
        let c = self.columns;
        match &mut self.sums {
            Sums::Gram { gram, projected } => {
                for i in 0..c {
                    let change: f64 = (0..c).map(|j| gram[(i.max(j), i.min(j))] * step[j]).sum();
                    projected[(i, 0)] -= change;
                }
            }
            Sums::Factor(factor) => {
                for i in 0..c {
                    let change: f64 = (i..c).map(|j| factor[(i, j)] * step[j]).sum();
                    factor[(i, c)] -= change;
                }
            }
        }
    }

    /// What this fold keeps.
    pub(crate) fn kind(&self) -> FoldKind {
        match self.sums {
            Sums::Gram { .. } => FoldKind::Gram,
            Sums::Factor(_) => FoldKind::Factor,
        }
    }

    /// `WᵀW` (lower triangle) and `Wᵀr`.
    pub(crate) fn normal_sums(&self) -> (Mat<f64>, Mat<f64>) {
        let factor = match &self.sums {
            Sums::Gram { gram, projected } => return (gram.clone(), projected.clone()),
            Sums::Factor(factor) => factor,
        };
        let c = self.columns;
        let r = factor.get(..c, ..c);
        let z = factor.get(..c, c..c + 1);
        let gram = Mat::from_fn(c, c, |i, j| {
            if i >= j {
                (0..=j).map(|k| r[(k, i)] * r[(k, j)]).sum()
            } else {
                0.0
            }
        });
        (gram, r.transpose() * z)
    }

    /// A c × c stand-in for the rows and their right-hand sides, `(R, z)`
    /// with `RᵀR = WᵀW` and `Rᵀz = Wᵀr` (row-major R): the factor's, or
    /// `Λ^½Vᵀ` and `Λ^-½Vᵀg` from the eigen-decomposition `G = VΛVᵀ` (rows
    /// of eigenvalues without weight, below 1e-14 of the largest, are zero).
    pub(crate) fn stand_in(&self) -> (Vec<f64>, Vec<f64>) {
        let c = self.columns;
        let (gram, projected) = match &self.sums {
            Sums::Factor(factor) => {
                let matrix = (0..c)
                    .flat_map(|i| (0..c).map(move |j| factor[(i, j)]))
                    .collect();
                return (matrix, (0..c).map(|i| factor[(i, c)]).collect());
            }
            Sums::Gram { gram, projected } => (gram, projected),
        };
        let gram = nalgebra::DMatrix::from_fn(c, c, |i, j| gram[(i.max(j), i.min(j))]);
        let eigen = gram.symmetric_eigen();
        let largest = eigen.eigenvalues.iter().copied().fold(0.0, f64::max);
        let mut matrix = vec![0.0; c * c];
        let mut right = vec![0.0; c];
        for k in 0..c {
            let value = eigen.eigenvalues[k];
            // Also a NaN: no row.
            if value.partial_cmp(&(1e-14 * largest)) != Some(std::cmp::Ordering::Greater) {
                continue;
            }
            let root = value.sqrt();
            let vector = eigen.eigenvectors.column(k);
            for j in 0..c {
                matrix[k * c + j] = root * vector[j];
            }
            right[k] = (0..c).map(|j| vector[j] * projected[(j, 0)]).sum::<f64>() / root;
        }
        (matrix, right)
    }

    /// Whether every sum is finite (false when a row had a NaN or an infinity).
    pub(crate) fn is_finite(&self) -> bool {
        match &self.sums {
            Sums::Gram { gram, projected } => gram.is_all_finite() && projected.is_all_finite(),
            Sums::Factor(factor) => factor.is_all_finite(),
        }
    }

    /// The column geometry of W: an upper triangular R with `RᵀR = WᵀW`
    /// (the inner products of its columns). A factor fold's own R; for a
    /// Gram fold, the Cholesky factor `Lᵀ` of G where the normal equations
    /// are accurate (equilibrated condition number below
    /// [`NORMAL_EQUATIONS_CONDITION`]: every column is then far from the
    /// span of the others, and no rank decision is close), `None` elsewhere.
    pub(crate) fn geometry(&self) -> Option<Mat<f64>> {
        let c = self.columns;
        let (gram, projected) = match &self.sums {
            Sums::Factor(factor) => return Some(factor.get(..c, ..c).to_owned()),
            Sums::Gram { gram, projected } => (gram, projected),
        };
        let lower = gram.llt(faer::Side::Lower).ok()?;
        let normal = NormalEquations::from_sums(gram.clone(), projected.clone());
        (normal.equilibrated_condition() < NORMAL_EQUATIONS_CONDITION)
            .then(|| lower.L().transpose().to_owned())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::view;

    /// Seeded rows and right-hand sides.
    fn rows(count: usize, columns: usize, seed: u64) -> (Vec<f64>, Vec<f64>) {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let mut next = || rng.random_range(-0.5..0.5);
        let matrix = (0..count * columns).map(|_| next()).collect();
        let right = (0..count).map(|_| next()).collect();
        (matrix, right)
    }

    fn solve(matrix: &[f64], rows: usize, columns: usize, right: &[f64]) -> Vec<f64> {
        crate::linalg::solve_with_covariance(view(matrix, rows, columns), right)
            .0
            .solution
    }

    /// Both folds, in parts, stand in for the whole rows: the same
    /// least-squares solution, normal equations and column norms.
    #[test]
    fn a_fold_stands_in_for_its_rows() {
        let (count, columns) = (1000, 7);
        let (matrix, right) = rows(count, columns, 3);
        let whole = solve(&matrix, count, columns, &right);
        let expected_gram: Vec<f64> = (0..columns)
            .flat_map(|i| {
                let matrix = &matrix;
                (0..columns).map(move |j| {
                    (0..count)
                        .map(|k| matrix[k * columns + i] * matrix[k * columns + j])
                        .sum::<f64>()
                })
            })
            .collect();
        for kind in [FoldKind::Gram, FoldKind::Factor] {
            let parts: Vec<FoldedRows> = [0..300, 300..310, 310..1000]
                .into_iter()
                .map(|range| {
                    let mut fold = RowFold::new(columns, kind, range.len());
                    fold.push(
                        view(
                            &matrix[range.start * columns..range.end * columns],
                            range.len(),
                            columns,
                        ),
                        &right[range.clone()],
                    );
                    fold.finish()
                })
                .collect();
            let mut parts = parts.into_iter();
            let first = parts.next().expect("three parts");
            let folded = first.merged(parts);
            assert_eq!(folded.row_count(), count);
            let (gram, _) = folded.normal_sums();
            for i in 0..columns {
                for j in 0..=i {
                    let expected = expected_gram[i * columns + j];
                    assert!(
                        (gram[(i, j)] - expected).abs() < 1e-10 * expected_gram[0].abs(),
                        "{kind:?} G[{i},{j}] {} vs {expected}",
                        gram[(i, j)]
                    );
                }
            }
            let (stand_in, z) = folded.stand_in();
            let solution = solve(&stand_in, columns, columns, &z);
            for (a, b) in solution.iter().zip(&whole) {
                assert!((a - b).abs() < 1e-10, "{kind:?}: {a} vs {b}");
            }
        }
    }

    /// Appended rows count as folded ones.
    #[test]
    fn appended_rows_join_the_fold() {
        let (count, columns) = (200, 4);
        let (matrix, right) = rows(count, columns, 11);
        let whole = solve(&matrix, count, columns, &right);
        for kind in [FoldKind::Gram, FoldKind::Factor] {
            let mut fold = RowFold::new(columns, kind, 150);
            fold.push(view(&matrix[..150 * columns], 150, columns), &right[..150]);
            let folded = fold.finish().with_rows(
                view(&matrix[150 * columns..], count - 150, columns),
                &right[150..],
            );
            let (stand_in, z) = folded.stand_in();
            let solution = solve(&stand_in, columns, columns, &z);
            for (a, b) in solution.iter().zip(&whole) {
                assert!((a - b).abs() < 1e-10, "{kind:?}: {a} vs {b}");
            }
        }
        assert!(FoldedRows::empty(3, FoldKind::Gram).is_finite());
    }
}
