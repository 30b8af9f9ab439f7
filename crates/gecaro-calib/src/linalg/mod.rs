//! Dense linear algebra on the tall observation matrix W, with faer (the only
//! module that touches it; nalgebra for the tridiagonal form of small Gram
//! matrices). faer's own threads are off (`Par::Seq`: they slow these sizes
//! down on small machines); a tall W is cut into fixed row parts instead,
//! spread over the cores by [`crate::parallel`] and combined in order.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::matmul::triangular::{self, BlockStructure};
use faer::linalg::qr::no_pivoting::factor as qr_factor;
use faer::linalg::solvers::{Solve, SolveLstsq};
use faer::linalg::triangular_inverse::invert_lower_triangular;
use faer::linalg::triangular_solve::solve_upper_triangular_in_place;
use faer::{Accum, Mat, MatRef, Par};

use crate::Error;
use crate::parallel::run_parts;

mod spectrum;
pub(crate) use spectrum::{condition_number, eigenvalue_range, singular_values};

/// A row-major `rows × columns` view of `data` (the layout of
/// [`ObservationSystem`](crate::observation::ObservationSystem)).
pub(crate) fn view(data: &[f64], rows: usize, columns: usize) -> MatRef<'_, f64> {
    MatRef::from_row_major_slice(data, rows, columns)
}

/// An owned copy of the listed columns of `matrix`.
pub(crate) fn select_columns(matrix: MatRef<'_, f64>, columns: &[usize]) -> Mat<f64> {
    Mat::from_fn(matrix.nrows(), columns.len(), |i, j| {
        matrix[(i, columns[j])]
    })
}

/// The greedy, priority-ordered rank test of Appendix III.
///
/// Columns are taken in order; column j is kept when its distance from the
/// span of the columns kept before it, |R_jj| in a QR of `[kept, j]`, exceeds
/// the tolerance. The distances come from classical Gram–Schmidt with one
/// re-orthogonalisation ("twice is enough"), which is as accurate as
/// Householder for this purpose and, unlike a plain QR of the whole ordered
/// matrix, lets no rejected column rotate the later ones: faer's unpivoted QR
/// returns R_kk = 0 for every column after one whose |R_jj| ≈ 1e-15.
pub(crate) struct GreedyRank {
    /// |R_jj| of every column (its distance from the kept columns before it).
    pub(crate) diagonal: Vec<f64>,
    /// Indices of the kept columns, in order.
    pub(crate) kept: Vec<usize>,
    /// Euclidean norm of every column.
    pub(crate) norms: Vec<f64>,
}

/// See [`GreedyRank`]; `tolerance` is the numerical zero τ.
///
/// The matrix is small here (the c × c R̃ of [`column_geometry`]), so the
/// projections are plain loops over contiguous columns, without allocation
/// per column, and over the rows that can be non-zero: a column of the upper
/// triangular R̃ and the directions kept before it vanish below its diagonal.
pub(crate) fn greedy_rank(matrix: MatRef<'_, f64>, tolerance: f64) -> GreedyRank {
    let (rows, columns) = matrix.shape();
    let capacity = columns.min(rows);
    // The kept directions, orthonormal, one after the other, and how many of
    // their leading entries can be non-zero.
    let mut basis: Vec<f64> = Vec::with_capacity(rows * capacity);
    let mut supports: Vec<usize> = Vec::with_capacity(capacity);
    let mut residual = vec![0.0; rows];
    let mut projections = vec![0.0; capacity];
    let mut kept = Vec::new();
    let mut diagonal = Vec::with_capacity(columns);
    let mut norms = Vec::with_capacity(columns);
    for column in 0..columns {
        for (row, value) in residual.iter_mut().enumerate() {
            *value = matrix[(row, column)];
        }
        let own_support = residual
            .iter()
            .rposition(|v| *v != 0.0)
            .map_or(0, |last| last + 1);
        let support = supports.iter().copied().fold(own_support, usize::max);
        let active = &mut residual[..support];
        norms.push(dot(active, active).sqrt());
        let rank = kept.len();
        if rank > 0 {
            for _ in 0..2 {
                for ((direction, length), projection) in basis
                    .chunks_exact(rows)
                    .zip(&supports)
                    .zip(&mut projections)
                {
                    *projection = dot(&direction[..*length], &active[..*length]);
                }
                for ((direction, length), projection) in
                    basis.chunks_exact(rows).zip(&supports).zip(&projections)
                {
                    for (value, component) in active.iter_mut().zip(&direction[..*length]) {
                        *value -= projection * component;
                    }
                }
            }
        }
        let distance = dot(active, active).sqrt();
        diagonal.push(distance);
        if distance > tolerance && rank < capacity {
            basis.extend(residual.iter().map(|value| value / distance));
            supports.push(support);
            kept.push(column);
        }
    }
    GreedyRank {
        diagonal,
        kept,
        norms,
    }
}

/// `Σ a_i b_i`, in four interleaved sums (so that the compiler can keep
/// several products in flight; the order is fixed, so results are reproducible).
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut sums = [0.0; 4];
    let (a_chunks, b_chunks) = (a.chunks_exact(4), b.chunks_exact(4));
    let tail: f64 = a_chunks
        .remainder()
        .iter()
        .zip(b_chunks.remainder())
        .map(|(x, y)| x * y)
        .sum();
    for (x, y) in a_chunks.zip(b_chunks) {
        for ((sum, x), y) in sums.iter_mut().zip(x).zip(y) {
            *sum += x * y;
        }
    }
    (sums[0] + sums[1]) + (sums[2] + sums[3]) + tail
}

/// Rows of W in one part of [`column_geometry`] and [`NormalEquations`]:
/// parts are fixed by the matrix's size alone and combined in order, so the
/// results do not depend on the number of cores that computed them.
const PART_ROWS: usize = 2048;

/// A `c × c` matrix R̃ with the column geometry of the tall `rows × c` matrix
/// W: `R̃ᵀR̃ = WᵀW`, so every column norm, distance between a column and the
/// span of others, least-squares relation and singular value of W is that of
/// R̃. R̃ is the R of a Householder QR of W (`W = Q·R`, Q orthogonal), computed
/// as a tall-skinny QR: the R of each part of [`PART_ROWS`] rows (on all
/// cores), stacked, factored again. Orthogonal transformations only, so it is
/// as accurate as one QR of W. R is a valid factor even when columns of W are
/// dependent (its diagonal is then not the greedy |R_jj| — the greedy pass on
/// R̃ computes those).
pub(crate) fn column_geometry(matrix: MatRef<'_, f64>) -> Mat<f64> {
    let parts = row_parts(matrix);
    if parts.len() == 1 {
        return triangular_factor(matrix);
    }
    let factors = run_parts(parts, triangular_factor);
    stacked_factor(&factors)
}

/// The R of a QR of the rows of all `factors` stacked (each c × c): the R of
/// rows whose parts were factored separately (tall-skinny QR).
pub(crate) fn stacked_factor(factors: &[Mat<f64>]) -> Mat<f64> {
    let columns = factors.first().map_or(0, |factor| factor.ncols());
    let height = factors.iter().map(|factor| factor.nrows()).sum();
    let mut fold = TriangularFold::new(columns, height);
    for factor in factors {
        fold.push(factor.as_ref());
    }
    fold.factor()
}

/// `matrix` cut into consecutive parts of [`PART_ROWS`] rows (the last one longer).
fn row_parts(matrix: MatRef<'_, f64>) -> Vec<MatRef<'_, f64>> {
    let rows = matrix.nrows();
    let count = (rows / PART_ROWS).max(1);
    (0..count)
        .map(|part| {
            let start = part * PART_ROWS;
            let end = if part + 1 == count {
                rows
            } else {
                start + PART_ROWS
            };
            matrix.subrows(start, end - start)
        })
        .collect()
}

/// Bytes of the block that [`triangular_factor`] factors at once: small
/// enough to stay in the core's cache and to come from the allocator's
/// reused memory rather than fresh pages (which cost about 2.5 µs each to
/// touch on a virtual machine).
const FOLD_BYTES: usize = 96 * 1024;

/// The c × c R of a QR of `matrix` (zero rows below when it has fewer rows
/// than columns); see [`TriangularFold`].
fn triangular_factor(matrix: MatRef<'_, f64>) -> Mat<f64> {
    let mut fold = TriangularFold::new(matrix.ncols(), matrix.nrows());
    fold.push(matrix);
    fold.factor()
}

/// The R of a QR of rows given a few at a time, folding each block into a
/// running R: `R ← R of [R; next rows]`. Orthogonal transformations only, so
/// it is as accurate as one QR of all the rows, which are never held
/// together. Unblocked Householder, which for these narrow matrices is faster
/// than faer's blocked default (measured in docs/performance.md).
pub(crate) struct TriangularFold {
    columns: usize,
    /// Rows folded at once (below the carried rows of R).
    fold: usize,
    block: Mat<f64>,
    coefficients: Mat<f64>,
    scratch: MemBuffer,
    reduced: Mat<f64>,
    /// Rows of R on top of the block: none before the first fold.
    carried: usize,
}

impl TriangularFold {
    const BLOCK_SIZE: usize = 1;

    /// A fold of rows of `columns` entries, about `rows` of them in all (the
    /// block is no larger than they need).
    pub(crate) fn new(columns: usize, rows: usize) -> Self {
        let fold = (FOLD_BYTES / size_of::<f64>() / columns.max(1))
            .saturating_sub(columns)
            .max(2 * columns)
            .max(1);
        let capacity = columns + fold.min(rows.max(1));
        TriangularFold {
            columns,
            fold: fold.min(rows.max(1)),
            block: Mat::<f64>::zeros(capacity, columns),
            coefficients: Mat::<f64>::zeros(Self::BLOCK_SIZE, columns),
            scratch: MemBuffer::new(qr_factor::qr_in_place_scratch::<f64>(
                capacity,
                columns,
                Self::BLOCK_SIZE,
                Par::Seq,
                Default::default(),
            )),
            reduced: Mat::<f64>::zeros(columns, columns),
            carried: 0,
        }
    }

    /// Folds the rows of `matrix` (`columns` wide) into R.
    pub(crate) fn push(&mut self, matrix: MatRef<'_, f64>) {
        let (rows, columns) = (matrix.nrows(), self.columns);
        debug_assert_eq!(matrix.ncols(), columns);
        let mut start = 0;
        while start < rows {
            let count = self.fold.min(rows - start);
            let carried = self.carried;
            let height = carried + count;
            self.block
                .get_mut(..carried, ..)
                .copy_from(self.reduced.get(..carried, ..));
            self.block
                .get_mut(carried..height, ..)
                .copy_from(matrix.subrows(start, count));
            let size = height.min(columns);
            qr_factor::qr_in_place(
                self.block.get_mut(..height, ..),
                self.coefficients.get_mut(.., ..size),
                Par::Seq,
                MemStack::new(&mut self.scratch),
                Default::default(),
            );
            for j in 0..columns {
                for i in 0..columns {
                    self.reduced[(i, j)] = if i <= j && i < size {
                        self.block[(i, j)]
                    } else {
                        0.0
                    };
                }
            }
            self.carried = size;
            start += count;
        }
    }

    /// R (c × c, upper triangular; zero rows below the rows folded).
    pub(crate) fn factor(self) -> Mat<f64> {
        self.reduced
    }
}

/// The normal equations of a weighted system `W x ≈ r`: WᵀW (its lower
/// triangle, the strict upper one zero: what a Cholesky factorisation or an
/// eigensolver with `Side::Lower` reads) and Wᵀr, summed over the parts of
/// [`row_parts`] (on all cores for a tall W). An iterate computes them once:
/// they give its step, its predicted decrease and its precision, and their
/// finiteness is that of W and r.
#[derive(Clone, Debug)]
pub(crate) struct NormalEquations {
    gram: Mat<f64>,
    projected: Mat<f64>,
}

impl NormalEquations {
    /// WᵀW and Wᵀr.
    pub(crate) fn of(matrix: MatRef<'_, f64>, right: &[f64]) -> Self {
        let (gram, projected) = part_sums(matrix, right);
        NormalEquations { gram, projected }
    }

    /// The normal equations with `gram` (WᵀW: its lower triangle is read)
    /// and `projected` (Wᵀr, a column), summed elsewhere (rows folded as
    /// they were written, [`crate::fold`]).
    pub(crate) fn from_sums(gram: Mat<f64>, projected: Mat<f64>) -> Self {
        NormalEquations { gram, projected }
    }

    /// The sum of squares `‖r − W·step‖²` after a step, from `cost = ‖r‖²`:
    /// `cost − 2 stepᵀWᵀr + stepᵀWᵀW step`.
    pub(crate) fn cost_after(&self, cost: f64, step: &[f64]) -> f64 {
        let curvature: f64 = self
            .gram_times(step)
            .iter()
            .zip(step)
            .map(|(a, b)| a * b)
            .sum();
        let slope: f64 = step
            .iter()
            .enumerate()
            .map(|(i, s)| s * self.projected[(i, 0)])
            .sum();
        (cost - 2.0 * slope + curvature).max(0.0)
    }

    /// Whether every entry is finite (false when W or r has a NaN or an infinity).
    pub(crate) fn is_finite(&self) -> bool {
        self.gram.is_all_finite() && self.projected.is_all_finite()
    }

    /// The condition number of W with its columns scaled to unit norm,
    /// `κ(W·D)` with `D = diag(1/‖w_j‖)`, from the lower triangle of WᵀW
    /// (∞ when a column is zero or the eigenvalues are not finite). What the
    /// accuracy of a Cholesky factorisation of WᵀW depends on (van der
    /// Sluis): a column's unit (a compliance in rad/(N·m) against lengths in
    /// metres) changes W's own condition number, not this one.
    pub(crate) fn equilibrated_condition(&self) -> f64 {
        match self.equilibrated_eigenvalue_range() {
            Some((smallest, largest)) if smallest > 0.0 => (largest / smallest).sqrt(),
            _ => f64::INFINITY,
        }
    }

    /// WᵀW with its columns scaled to unit norm, `D WᵀW D` (both
    /// triangles), and the column norms `‖w_j‖` (`D⁻¹`); `None` when a
    /// column is zero or not finite.
    pub(crate) fn equilibrated(&self) -> Option<(Mat<f64>, Vec<f64>)> {
        let size = self.gram.nrows();
        let norms: Vec<f64> = (0..size).map(|j| self.gram[(j, j)].sqrt()).collect();
        if !norms.iter().all(|n| n.is_finite() && *n > 0.0) {
            return None;
        }
        let scale: Vec<f64> = norms.iter().map(|n| n.recip()).collect();
        let scaled = Mat::<f64>::from_fn(size, size, |i, j| {
            self.gram[(i.max(j), i.min(j))] * scale[i] * scale[j]
        });
        Some((scaled, norms))
    }

    /// The smallest and largest eigenvalues of the
    /// [`equilibrated`](Self::equilibrated) WᵀW (multisection, no
    /// eigenvectors); `None` as there, or when they are not finite.
    pub(crate) fn equilibrated_eigenvalue_range(&self) -> Option<(f64, f64)> {
        let (scaled, _) = self.equilibrated()?;
        eigenvalue_range(scaled.as_ref())
    }

    /// `WᵀW · x`, from the lower triangle.
    fn gram_times(&self, x: &[f64]) -> Vec<f64> {
        let n = x.len();
        (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| {
                        let entry = if i >= j {
                            self.gram[(i, j)]
                        } else {
                            self.gram[(j, i)]
                        };
                        entry * x[j]
                    })
                    .sum()
            })
            .collect()
    }

    /// The part of ‖r‖² that a least-squares step over `columns` of W
    /// explains, `gᵀ G⁺ g` with G = WᵀW and g = Wᵀr on those columns, and
    /// its numerical rank: the eigenvalues of G above `relative_tolerance`
    /// times the largest (G squares W's condition: 1e-12 here is 1e-6 on
    /// the singular values of W). For a few dozen columns this costs nothing
    /// beside W itself, whatever its height.
    pub(crate) fn explained(&self, columns: &[usize], relative_tolerance: f64) -> (f64, usize) {
        let n = columns.len();
        let gram = nalgebra::DMatrix::from_fn(n, n, |i, j| {
            let (a, b) = (columns[i].max(columns[j]), columns[i].min(columns[j]));
            self.gram[(a, b)]
        });
        let projected = nalgebra::DVector::from_fn(n, |i, _| self.projected[(columns[i], 0)]);
        let eigen = gram.symmetric_eigen();
        let largest = eigen.eigenvalues.iter().copied().fold(0.0, f64::max);
        let mut explained = 0.0;
        let mut rank = 0;
        for (k, value) in eigen.eigenvalues.iter().enumerate() {
            if *value > relative_tolerance * largest {
                let component = eigen.eigenvectors.column(k).dot(&projected);
                explained += component * component / value;
                rank += 1;
            }
        }
        (explained, rank)
    }

    /// (WᵀW)⁻¹ = L⁻ᵀL⁻¹ (Cholesky), both triangles, as nalgebra's; `None`
    /// when WᵀW is not positive definite or the inverse is not finite.
    pub(crate) fn inverse(&self) -> Option<nalgebra::DMatrix<f64>> {
        let n = self.gram.nrows();
        let cholesky = self.gram.llt(faer::Side::Lower).ok()?;
        let mut inverse_factor = Mat::<f64>::zeros(n, n);
        invert_lower_triangular(inverse_factor.as_mut(), cholesky.L(), Par::Seq);
        let inverse = inverse_factor.transpose() * &inverse_factor;
        let inverse = nalgebra::DMatrix::from_fn(n, n, |i, j| inverse[(i, j)]);
        inverse.iter().all(|v| v.is_finite()).then_some(inverse)
    }

    /// The correlation matrix of the least-squares estimate, from
    /// [`inverse`](Self::inverse): `ρ_ij = C_ij / √(C_ii C_jj)`, as a
    /// row-major n×n vector; `None` when WᵀW is not positive definite.
    pub(crate) fn correlations(&self) -> Option<Vec<f64>> {
        let covariance = self.inverse()?;
        let n = covariance.nrows();
        let mut correlations = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                correlations[i * n + j] =
                    covariance[(i, j)] / (covariance[(i, i)] * covariance[(j, j)]).sqrt();
            }
        }
        correlations
            .iter()
            .all(|v| v.is_finite())
            .then_some(correlations)
    }

    /// The diagonal of `G⁻¹ DᵀD G⁻¹`, for G = WᵀW and D the rows of W that
    /// are measurements (`data`; the others are a prior's pseudo-observations):
    /// the part of the covariance `G⁻¹` the data's noise makes. Computed as
    /// the squared column norms of `D G⁻¹`, over the parts of [`row_parts`]
    /// (memory bounded by a part), a sum of squares — not as `G⁻¹` less the
    /// prior's part, a difference of nearly equal numbers wherever the prior
    /// dominates (a parameter held to 1 cm whose noise σ is a micrometre:
    /// their squares differ in the eighth digit, within the rounding of an
    /// ill-conditioned G). `None` when G is not positive definite.
    pub(crate) fn data_part_diagonal(&self, data: MatRef<'_, f64>) -> Option<Vec<f64>> {
        sandwich_diagonal(&self.gram, data)
    }

    /// Wᵀr, a column.
    pub(crate) fn projected(&self) -> &Mat<f64> {
        &self.projected
    }

    /// After the residuals moved by the linear model, `r ← r − W·step`:
    /// `Wᵀr ← Wᵀr − WᵀW·step`.
    pub(crate) fn apply_step(&mut self, step: &[f64]) {
        for (i, change) in self.gram_times(step).into_iter().enumerate() {
            self.projected[(i, 0)] -= change;
        }
    }
}

/// `diag(H⁻¹ DᵀD H⁻¹)` for a symmetric positive definite `hessian` H (its
/// lower triangle is read) and rows `data` D: the squared column norms of
/// `D H⁻¹`, summed over row parts (a sum of squares, not a difference of
/// inverses, so a prior's tight hold does not cancel digits); `None` when
/// H is not positive definite or the result is not finite.
pub(crate) fn sandwich_diagonal(hessian: &Mat<f64>, data: MatRef<'_, f64>) -> Option<Vec<f64>> {
    let n = hessian.nrows();
    let cholesky = hessian.llt(faer::Side::Lower).ok()?;
    let inverse = cholesky.solve(Mat::<f64>::identity(n, n));
    let mut diagonal = vec![0.0; n];
    for part in row_parts(data) {
        let product = part * &inverse;
        for (j, sum) in diagonal.iter_mut().enumerate() {
            *sum += product.col(j).squared_norm_l2();
        }
    }
    diagonal.iter().all(|v| v.is_finite()).then_some(diagonal)
}

/// `‖W·step‖²`, the most a least-squares step can lower ‖r‖² by: from the
/// normal equations (`stepᵀWᵀW step`) when W is well conditioned (see
/// [`NORMAL_EQUATIONS_CONDITION`]), else row by row.
pub(crate) fn predicted_decrease<R: LeastSquaresRows>(
    normal: &NormalEquations,
    step: &[f64],
    condition: f64,
    rows: impl FnOnce() -> R,
) -> f64 {
    if condition < NORMAL_EQUATIONS_CONDITION {
        return normal
            .gram_times(step)
            .iter()
            .zip(step)
            .map(|(a, b)| a * b)
            .sum();
    }
    let rows = rows();
    let matrix = rows.matrix();
    (0..matrix.nrows())
        .map(|row| {
            (0..matrix.ncols())
                .map(|column| matrix[(row, column)] * step[column])
                .sum::<f64>()
                .powi(2)
        })
        .sum()
}

/// Adds the rows `part` (with their right-hand sides `right`, a column) to
/// the sums `gram` (WᵀW, lower triangle) and `projected` (Wᵀr).
pub(crate) fn add_normal_sums(
    gram: &mut Mat<f64>,
    projected: &mut Mat<f64>,
    part: MatRef<'_, f64>,
    right: MatRef<'_, f64>,
) {
    triangular::matmul(
        gram.as_mut(),
        BlockStructure::TriangularLower,
        Accum::Add,
        part.transpose(),
        BlockStructure::Rectangular,
        part,
        BlockStructure::Rectangular,
        1.0,
        Par::Seq,
    );
    faer::linalg::matmul::matmul(
        projected.as_mut(),
        Accum::Add,
        part.transpose(),
        right,
        1.0,
        Par::Seq,
    );
}

fn part_sums(matrix: MatRef<'_, f64>, right: &[f64]) -> (Mat<f64>, Mat<f64>) {
    let mut start = 0;
    let parts: Vec<(MatRef<'_, f64>, MatRef<'_, f64>)> = row_parts(matrix)
        .into_iter()
        .map(|part| {
            let rows = part.nrows();
            let right = MatRef::from_column_major_slice(&right[start..start + rows], rows, 1);
            start += rows;
            (part, right)
        })
        .collect();
    let mut sums = run_parts(parts, |(part, right)| {
        let mut gram = Mat::<f64>::zeros(part.ncols(), part.ncols());
        let mut projected = Mat::<f64>::zeros(part.ncols(), 1);
        add_normal_sums(&mut gram, &mut projected, part, right);
        (gram, projected)
    })
    .into_iter();
    let (mut gram, mut projected) = sums.next().expect("at least one part");
    for (part_gram, part_projected) in sums {
        gram += part_gram;
        projected += part_projected;
    }
    (gram, projected)
}

/// The largest column norm of `matrix` (0 for an empty matrix).
pub(crate) fn largest_column_norm(matrix: MatRef<'_, f64>) -> f64 {
    (0..matrix.ncols())
        .map(|j| matrix.col(j).norm_l2())
        .fold(0.0, f64::max)
}

/// The least-squares relations `W₂ ≈ W₁·β` between two groups of columns of
/// `matrix` (column indices `first` and `second`), and the relative misfit
/// ‖W₂ⱼ − W₁βⱼ‖ / ‖W₂ⱼ‖ of each column of W₂ (eq. 36–37). One QR of
/// `[W₁ W₂] = Q·[R₁₁ R₁₂; 0 R₂₂]` gives both: β = R₁₁⁻¹R₁₂, the misfit of
/// column j is ‖R₂₂ⱼ‖ and its norm ‖[R₁₂ⱼ; R₂₂ⱼ]‖. W₁ must have full column
/// rank.
pub(crate) fn regrouping_relations(
    matrix: MatRef<'_, f64>,
    first: &[usize],
    second: &[usize],
) -> (Mat<f64>, Vec<f64>) {
    let ordered: Vec<usize> = first.iter().chain(second).copied().collect();
    let factor = triangular_factor(select_columns(matrix, &ordered).as_ref());
    let (base, others) = (first.len(), second.len());
    let mut beta = factor.get(..base, base..).to_owned();
    solve_upper_triangular_in_place(factor.get(..base, ..base), beta.as_mut(), Par::Seq);
    let misfits = (0..others)
        .map(|j| {
            let column = factor.col(base + j);
            column.get(base..).norm_l2() / column.norm_l2()
        })
        .collect();
    (beta, misfits)
}

/// The solution of `min ‖W x − r‖` and the diagonal of `(WᵀW)⁻¹`.
pub(crate) struct LeastSquares {
    pub(crate) solution: Vec<f64>,
    /// diag((WᵀW)⁻¹) = squared row norms of R⁻¹ for W = QR.
    pub(crate) inverse_normal_diagonal: Vec<f64>,
}

/// The condition number of W below which [`step`] uses the normal equations:
/// they square it, and 1e5² · ε ≈ 1e-6 relative accuracy in the step is ample
/// for an iteration whose residual is recomputed exactly each time.
pub(crate) const NORMAL_EQUATIONS_CONDITION: f64 = 1e5;

/// The least-squares step `min ‖W x − r‖`: through the normal equations
/// `WᵀW x = Wᵀr` (Cholesky) when W is well conditioned (`condition` below
/// [`NORMAL_EQUATIONS_CONDITION`]) — a quarter of the cost of a QR of the tall
/// W — and through QR otherwise or if the Cholesky factorisation fails.
pub(crate) fn step<R: LeastSquaresRows>(
    normal: &NormalEquations,
    condition: f64,
    rows: impl FnOnce() -> R,
) -> Vec<f64> {
    if condition < NORMAL_EQUATIONS_CONDITION
        && let Ok(cholesky) = normal.gram.llt(faer::Side::Lower)
    {
        let solution = cholesky.solve(&normal.projected);
        return (0..solution.nrows()).map(|i| solution[(i, 0)]).collect();
    }
    let rows = rows();
    solve_with_covariance(rows.matrix(), rows.right())
        .0
        .solution
}

/// The rows W of a least-squares problem and their right-hand sides, which
/// [`step`] and [`predicted_decrease`] make only on their QR route (a tall
/// system's weighted right-hand sides, a folded one's stand-in).
pub(crate) trait LeastSquaresRows {
    /// W.
    fn matrix(&self) -> MatRef<'_, f64>;
    /// The right-hand sides.
    fn right(&self) -> &[f64];
}

impl LeastSquaresRows for (MatRef<'_, f64>, &[f64]) {
    fn matrix(&self) -> MatRef<'_, f64> {
        self.0
    }

    fn right(&self) -> &[f64] {
        self.1
    }
}

/// See [`LeastSquares`]; `matrix` must have full column rank and at least as
/// many rows as columns. One QR gives both, and the condition number of W
/// (that of R).
pub(crate) fn solve_with_covariance(matrix: MatRef<'_, f64>, right: &[f64]) -> (LeastSquares, f64) {
    let qr = matrix.qr();
    let solution = qr.solve_lstsq(MatRef::from_column_major_slice(right, right.len(), 1));
    let columns = matrix.ncols();
    let r = qr.thin_R().get(..columns, ..columns);
    let mut inverse = Mat::<f64>::identity(columns, columns);
    solve_upper_triangular_in_place(r, inverse.as_mut(), Par::Seq);
    let condition = condition_number(r).unwrap_or(f64::INFINITY);
    (
        LeastSquares {
            solution: (0..columns).map(|i| solution[(i, 0)]).collect(),
            inverse_normal_diagonal: (0..columns)
                .map(|i| inverse.row(i).norm_l2().powi(2))
                .collect(),
        },
        condition,
    )
}

/// The precision of a least-squares solution with full-rank W: diag((WᵀW)⁻¹)
/// and the condition number of W. Through the normal equations (Cholesky
/// inverse, eigenvalues of WᵀW) when W is well conditioned (`condition`
/// below [`NORMAL_EQUATIONS_CONDITION`]), through QR otherwise.
///
/// # Errors
/// [`Error::Numerical`] if W has non-finite entries.
pub(crate) fn precision(
    matrix: MatRef<'_, f64>,
    normal: &NormalEquations,
    condition: f64,
) -> Result<(LeastSquares, f64), Error> {
    if !normal.gram.is_all_finite() {
        return Err(Error::Numerical {
            message: "the observation matrix has non-finite entries".into(),
        });
    }
    let columns = matrix.ncols();
    if condition < NORMAL_EQUATIONS_CONDITION {
        let gram = &normal.gram;

        if let (Ok(cholesky), Some((smallest, largest))) =
            (gram.llt(faer::Side::Lower), eigenvalue_range(gram.as_ref()))
        {
            // WᵀW = LLᵀ: (WᵀW)⁻¹ = L⁻ᵀL⁻¹, whose diagonal holds the squared
            // column norms of L⁻¹.
            let mut inverse_factor = Mat::<f64>::zeros(columns, columns);
            invert_lower_triangular(inverse_factor.as_mut(), cholesky.L(), Par::Seq);
            let condition = if smallest > 0.0 {
                (largest / smallest).sqrt()
            } else {
                f64::INFINITY
            };
            return Ok((
                LeastSquares {
                    solution: vec![0.0; columns],
                    inverse_normal_diagonal: (0..columns)
                        .map(|i| inverse_factor.col(i).get(i..).squared_norm_l2())
                        .collect(),
                },
                condition,
            ));
        }
    }
    Ok(solve_with_covariance(matrix, &vec![0.0; matrix.nrows()]))
}

/// The Levenberg–Marquardt step: `min ‖W x − r‖² + λ‖D x‖²` with D the
/// column norms of W (Marquardt's scaling), as the least-squares solution of
/// `[W; √λ D] x = [r; 0]`.
pub(crate) fn damped_step(matrix: MatRef<'_, f64>, right: &[f64], damping: f64) -> Vec<f64> {
    let (rows, columns) = matrix.shape();
    let mut augmented = Mat::<f64>::zeros(rows + columns, columns);
    augmented.get_mut(..rows, ..).copy_from(matrix);
    for j in 0..columns {
        augmented[(rows + j, j)] =
            (damping.sqrt() * matrix.col(j).norm_l2()).max(f64::MIN_POSITIVE);
    }
    let mut extended = Mat::<f64>::zeros(rows + columns, 1);
    for (i, value) in right.iter().enumerate() {
        extended[(i, 0)] = *value;
    }
    let solution = augmented.qr().solve_lstsq(&extended);
    (0..columns).map(|i| solution[(i, 0)]).collect()
}

/// The minimum-norm least-squares solution of `W x ≈ r` restricted to the
/// `rank` largest singular values (truncated SVD): for a W whose rank is known
/// to be `rank`, the step of smallest norm among the best ones.
///
/// # Errors
/// [`Error::Numerical`] if the SVD does not converge.
pub(crate) fn minimum_norm_step(
    matrix: MatRef<'_, f64>,
    right: &[f64],
    rank: usize,
) -> Result<Vec<f64>, Error> {
    let svd = matrix.thin_svd().map_err(|error| Error::Numerical {
        message: format!("singular value decomposition failed: {error:?}"),
    })?;
    let (u, s, v) = (svd.U(), svd.S().column_vector(), svd.V());
    let mut step = vec![0.0; matrix.ncols()];
    for k in 0..rank.min(s.nrows()) {
        if s[k] <= 0.0 {
            break;
        }
        let coefficient = (0..right.len()).map(|i| u[(i, k)] * right[i]).sum::<f64>() / s[k];
        for (j, value) in step.iter_mut().enumerate() {
            *value += coefficient * v[(j, k)];
        }
    }
    Ok(step)
}

#[cfg(test)]
mod tests {
    use super::spectrum::tridiagonal_extremes;
    use super::*;

    /// A seeded 120×12 matrix whose column 3 is column 0 + column 1.
    fn dependent_matrix() -> (Vec<f64>, usize, usize) {
        tall_dependent_matrix(120)
    }

    /// The same with `rows` rows.
    fn tall_dependent_matrix(rows: usize) -> (Vec<f64>, usize, usize) {
        let columns = 12;
        let mut state = 12345_u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1_u64 << 53) as f64 - 0.5
        };
        let mut data: Vec<f64> = (0..rows * columns).map(|_| next()).collect();
        for i in 0..rows {
            data[i * columns + 3] = data[i * columns] + data[i * columns + 1];
        }
        (data, rows, columns)
    }

    /// Extreme eigenvalues by nalgebra's implicit QR iteration (all of them).
    fn extremes_by_qr(diagonal: &[f64], off_diagonal: &[f64]) -> (f64, f64) {
        let size = diagonal.len();
        let matrix = nalgebra::DMatrix::from_fn(size, size, |i, j| match i.abs_diff(j) {
            0 => diagonal[i],
            1 => off_diagonal[i.min(j)],
            _ => 0.0,
        });
        let values = matrix.symmetric_eigenvalues();
        (values.min(), values.max())
    }

    #[test]
    fn tridiagonal_extremes_of_special_matrices() {
        let cases: [(&[f64], &[f64]); 6] = [
            // One entry; diagonal (a zero coupling splits the matrix); zero matrix.
            (&[2.5], &[]),
            (&[3.0, -1.0, 7.0], &[0.0, 0.0]),
            (&[0.0, 0.0, 0.0], &[0.0, 0.0]),
            // The second-difference matrix: eigenvalues 2 − 2cos(kπ/(n+1)).
            (&[2.0; 8], &[-1.0; 7]),
            // Wilkinson's W21⁺ (nearly equal largest pair), indefinite shift of it.
            (
                &[
                    10.0, 9.0, 8.0, 7.0, 6.0, 5.0, 4.0, 3.0, 2.0, 1.0, 0.0, 1.0, 2.0, 3.0, 4.0,
                    5.0, 6.0, 7.0, 8.0, 9.0, 10.0,
                ],
                &[1.0; 20],
            ),
            (&[-1e-3, 4e5, -2e5], &[3e2, 1e-4]),
        ];
        for (diagonal, off_diagonal) in cases {
            let (smallest, largest) = tridiagonal_extremes(diagonal, off_diagonal).expect("finite");
            let (expected_smallest, expected_largest) = extremes_by_qr(diagonal, off_diagonal);
            // Relative to ‖T‖, with an absolute floor for the zero matrix.
            let tolerance = 1e-14 * expected_smallest.abs().max(expected_largest.abs()) + 1e-300;
            assert!(
                (smallest - expected_smallest).abs() <= tolerance
                    && (largest - expected_largest).abs() <= tolerance,
                "{diagonal:?}: ({smallest}, {largest}) vs ({expected_smallest}, {expected_largest})"
            );
        }
        let second_difference = tridiagonal_extremes(&[2.0; 8], &[-1.0; 7]).expect("finite");
        let exact = |k: f64| 2.0 - 2.0 * (k * std::f64::consts::PI / 9.0).cos();
        assert!((second_difference.0 - exact(1.0)).abs() < 1e-15 * 4.0);
        assert!((second_difference.1 - exact(8.0)).abs() < 1e-15 * 4.0);
        assert_eq!(tridiagonal_extremes(&[], &[]), None);
        assert_eq!(tridiagonal_extremes(&[1.0, f64::NAN], &[1.0]), None);
        assert_eq!(tridiagonal_extremes(&[1.0, 1.0], &[1e200]), None);
    }

    proptest::proptest! {
        // Seeded, so that a run is repeatable (cases that once failed are
        // replayed first from proptest-regressions/).
        #![proptest_config(proptest::test_runner::Config {
            rng_seed: proptest::test_runner::RngSeed::Fixed(1),
            ..proptest::test_runner::Config::default()
        })]

        #[test]
        fn tridiagonal_extremes_agree_with_the_qr_iteration(
            entries in proptest::collection::vec((-1e3..1e3_f64, -1e3..1e3_f64), 1..40),
        ) {
            let diagonal: Vec<f64> = entries.iter().map(|e| e.0).collect();
            let off_diagonal: Vec<f64> = entries[1..].iter().map(|e| e.1).collect();
            let (smallest, largest) =
                tridiagonal_extremes(&diagonal, &off_diagonal).expect("finite");
            let (expected_smallest, expected_largest) = extremes_by_qr(&diagonal, &off_diagonal);
            // Both are backward stable: absolute agreement to a few n·ε·‖T‖.
            let scale = expected_smallest.abs().max(expected_largest.abs()).max(1.0);
            let tolerance = 8.0 * diagonal.len() as f64 * f64::EPSILON * scale;
            proptest::prop_assert!((smallest - expected_smallest).abs() <= tolerance);
            proptest::prop_assert!((largest - expected_largest).abs() <= tolerance);
        }

        #[test]
        fn regrouping_relations_agree_with_least_squares(
            seed in 0_u64..1000,
            scale in -8.0..0.0_f64,
        ) {
            // 12 columns: 0–6 independent (column 2 scaled by 10^scale), 7–11
            // combinations of them plus a part outside their span.
            let mut state = seed;
            let mut next = || {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (state >> 11) as f64 / (1_u64 << 53) as f64 - 0.5
            };
            let rows = 40;
            let mut matrix = Mat::<f64>::from_fn(rows, 12, |_, _| next());
            for i in 0..rows {
                matrix[(i, 2)] *= 10_f64.powf(scale);
            }
            let coefficients = Mat::<f64>::from_fn(7, 5, |_, _| next());
            let outside = Mat::<f64>::from_fn(rows, 5, |_, _| 1e-3 * next());
            let combined = matrix.get(.., ..7) * &coefficients + &outside;
            matrix.get_mut(.., 7..).copy_from(&combined);
            let first = [6, 0, 2, 5, 1, 3, 4];
            let second = [9, 7, 11, 8, 10];
            let (beta, misfits) = regrouping_relations(matrix.as_ref(), &first, &second);
            let kept = select_columns(matrix.as_ref(), &first);
            let regrouped = select_columns(matrix.as_ref(), &second);
            let expected = kept.qr().solve_lstsq(&regrouped);
            let misfit = &kept * &expected - &regrouped;
            // Two backward-stable solutions agree to about ε·κ(kept), and κ
            // grows as 10^-scale with the shrunk column.
            let agreement = 1e-9_f64.max(1e-13 * 10_f64.powf(-scale));
            for j in 0..second.len() {
                for k in 0..first.len() {
                    let size = expected.col(j).norm_l2();
                    proptest::prop_assert!(
                        (beta[(k, j)] - expected[(k, j)]).abs() <= agreement * size,
                        "β[{k}, {j}]: {} vs {}", beta[(k, j)], expected[(k, j)]
                    );
                }
                let relative = misfit.col(j).norm_l2() / regrouped.col(j).norm_l2();
                proptest::prop_assert!((misfits[j] - relative).abs() <= agreement * relative);
            }
        }
    }

    #[test]
    fn covariance_diagonal_matches_the_normal_equations() {
        let data = [1.0, 2.0, 0.5, 1.0, 0.0, 1.0, 3.0, 1.0, -1.0, 0.5, 2.0, 1.0];
        let right = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        let (solved, _) = solve_with_covariance(view(&data, 6, 2), &right);
        let equations = NormalEquations::of(view(&data, 6, 2), &right);
        let rows = || (view(&data, 6, 2), right.as_slice());
        let normal = step(&equations, 1.0, rows);
        let through_qr = step(&equations, f64::INFINITY, rows);
        let (precise, _) = precision(view(&data, 6, 2), &equations, 1.0).expect("finite");
        let (precise_qr, _) =
            precision(view(&data, 6, 2), &equations, f64::INFINITY).expect("finite");
        let w = nalgebra::DMatrix::from_row_slice(6, 2, &data);
        let inverse = (w.transpose() * &w).try_inverse().expect("regular");
        let expected = &inverse * w.transpose() * nalgebra::DVector::from_column_slice(&right);
        for i in 0..2 {
            assert!((inverse[(i, i)] - solved.inverse_normal_diagonal[i]).abs() < 1e-12);
            assert!((expected[i] - solved.solution[i]).abs() < 1e-12);
            assert!((expected[i] - normal[i]).abs() < 1e-12);
            assert!((expected[i] - through_qr[i]).abs() < 1e-12);
            assert!((inverse[(i, i)] - precise.inverse_normal_diagonal[i]).abs() < 1e-12);
            assert!((inverse[(i, i)] - precise_qr.inverse_normal_diagonal[i]).abs() < 1e-12);
        }
        // Zero damping is the plain least-squares step.
        let plain = damped_step(view(&data, 6, 2), &right, 0.0);
        assert!((plain[0] - expected[0]).abs() < 1e-12 && (plain[1] - expected[1]).abs() < 1e-12);
    }

    /// The `kept` columns of the row-major `data`, column `scaled` times `scale`.
    fn with_column_scaled(
        data: &[f64],
        (rows, columns): (usize, usize),
        kept: &[usize],
        scaled: usize,
        scale: f64,
    ) -> Mat<f64> {
        Mat::from_fn(rows, kept.len(), |i, j| {
            let value = data[i * columns + kept[j]];
            if kept[j] == scaled {
                value * scale
            } else {
                value
            }
        })
    }

    #[test]
    fn condition_numbers_agree_with_the_singular_values_on_both_routes() {
        let (data, rows, columns) = tall_dependent_matrix(200);
        // Drop the dependent column 3, then scale column 5 to set the conditioning.
        let independent: Vec<usize> = (0..columns).filter(|c| *c != 3).collect();
        for scale in [1.0, 1e-2, 1e-5, 1e-9] {
            let matrix = with_column_scaled(&data, (rows, columns), &independent, 5, scale);
            let values = singular_values(matrix.as_ref()).expect("svd");
            let expected = values[0] / values[values.len() - 1];
            let computed = condition_number(matrix.as_ref()).expect("finite");
            assert!(
                (computed - expected).abs() < 1e-6 * expected,
                "scale {scale}: {computed} vs {expected}"
            );
        }
    }

    #[test]
    fn the_equilibrated_condition_ignores_the_columns_units() {
        let (data, rows, columns) = tall_dependent_matrix(200);
        let independent: Vec<usize> = (0..columns).filter(|c| *c != 3).collect();
        // The reference: the singular values of W with unit columns.
        let unit = Mat::from_fn(rows, independent.len(), |i, j| {
            let norm = (0..rows)
                .map(|r| data[r * columns + independent[j]].powi(2))
                .sum::<f64>()
                .sqrt();
            data[i * columns + independent[j]] / norm
        });
        let values = singular_values(unit.as_ref()).expect("svd");
        let expected = values[0] / values[values.len() - 1];
        // A column in other units (a compliance in rad/(N·m) against
        // metres) moves W's own condition number, not this one.
        for scale in [1.0, 1e-3, 1e4] {
            let matrix = with_column_scaled(&data, (rows, columns), &independent, 5, scale);
            let normal = NormalEquations::of(matrix.as_ref(), &vec![0.0; rows]);
            let computed = normal.equilibrated_condition();
            assert!(
                (computed - expected).abs() < 1e-8 * expected,
                "scale {scale}: {computed} vs {expected}"
            );
            let own = condition_number(matrix.as_ref()).expect("finite");
            if scale != 1.0 {
                assert!(own > 10.0 * computed, "scale {scale}: {own} vs {computed}");
            }
        }
        // A zero column: no condition.
        let zero = Mat::from_fn(rows, 2, |i, j| if j == 0 { i as f64 } else { 0.0 });
        let normal = NormalEquations::of(zero.as_ref(), &vec![0.0; rows]);
        assert_eq!(normal.equilibrated_condition(), f64::INFINITY);
    }

    #[test]
    fn minimum_norm_step_ignores_the_null_space() {
        // W has a zero singular value along (1, -1): the minimum-norm step has no component there.
        let data = [1.0, 1.0, 2.0, 2.0, 3.0, 3.0];
        let step = minimum_norm_step(view(&data, 3, 2), &[2.0, 4.0, 6.0], 1).expect("svd");
        assert!(
            (step[0] - 1.0).abs() < 1e-12 && (step[1] - 1.0).abs() < 1e-12,
            "{step:?}"
        );
    }

    #[test]
    fn column_geometry_keeps_inner_products() {
        // Fewer rows than columns; one block; several blocks of one part;
        // several parts on all cores
        // (the last part longer than the others).
        for rows in [5, 120, 1000, 5 * PART_ROWS + 77] {
            let (data, rows, columns) = tall_dependent_matrix(rows);
            let w = view(&data, rows, columns);
            let reduced = column_geometry(w);
            let gram = w.transpose() * w;
            let reduced_gram = reduced.transpose() * &reduced;
            assert!(
                (&gram - reduced_gram).norm_l2() < 1e-13 * gram.norm_l2(),
                "{rows} rows"
            );
            // The greedy analysis gives the same answer on W and on R̃.
            assert_eq!(
                greedy_rank(w, 1e-9).kept,
                greedy_rank(reduced.as_ref(), 1e-9).kept
            );
            // R̃ is upper triangular.
            for j in 0..columns {
                for i in j + 1..columns {
                    assert_eq!(reduced[(i, j)], 0.0);
                }
            }
        }
    }

    #[test]
    fn normal_equations_sum_the_parts() {
        let (data, rows, columns) = tall_dependent_matrix(3 * PART_ROWS + 5);
        let w = view(&data, rows, columns);
        let right: Vec<f64> = (0..rows).map(|i| (i as f64 * 0.37).sin()).collect();
        let mut equations = NormalEquations::of(w, &right);
        let full = w.transpose() * w;
        let lower = Mat::from_fn(
            columns,
            columns,
            |i, j| if i >= j { full[(i, j)] } else { 0.0 },
        );
        let projected = w.transpose() * MatRef::from_column_major_slice(&right, rows, 1);
        assert!((&equations.gram - &lower).norm_l2() < 1e-12 * full.norm_l2());
        assert!((&equations.projected - &projected).norm_l2() < 1e-12 * projected.norm_l2());
        assert!(equations.is_finite());
        // ‖W·s‖² both ways, and the update of Wᵀr for r ← r − W·s.
        let step: Vec<f64> = (0..columns).map(|j| 0.1 * j as f64 - 0.4).collect();
        let moved = w * MatRef::from_column_major_slice(&step, columns, 1);
        let exact = moved.norm_l2().powi(2);
        for condition in [1.0, f64::INFINITY] {
            let predicted = predicted_decrease(&equations, &step, condition, || (w, &right[..]));
            assert!(
                (predicted - exact).abs() < 1e-12 * exact,
                "{predicted} vs {exact}"
            );
        }
        let shifted: Vec<f64> = (0..rows).map(|i| right[i] - moved[(i, 0)]).collect();
        equations.apply_step(&step);
        let expected = NormalEquations::of(w, &shifted);
        assert!(
            (&equations.projected - &expected.projected).norm_l2() < 1e-10 * projected.norm_l2()
        );
        // A NaN anywhere in W shows.
        let mut broken = data.clone();
        broken[7 * columns + 2] = f64::NAN;
        assert!(!NormalEquations::of(view(&broken, rows, columns), &right).is_finite());
    }

    #[test]
    fn greedy_rank_matches_an_independent_qr_and_skips_dependent_columns() {
        let (data, rows, columns) = dependent_matrix();
        let rank = greedy_rank(view(&data, rows, columns), 1e-9);
        assert_eq!(rank.kept, [0, 1, 2, 4, 5, 6, 7, 8, 9, 10, 11]);
        assert!(rank.diagonal[3] < 1e-14, "{:?}", rank.diagonal);
        // The kept columns' |R_jj| equal those of a Householder QR (nalgebra) of the kept columns.
        let kept = nalgebra::DMatrix::from_fn(rows, rank.kept.len(), |i, j| {
            data[i * columns + rank.kept[j]]
        });
        let r = kept.qr().r();
        for (position, column) in rank.kept.iter().enumerate() {
            assert!((r[(position, position)].abs() - rank.diagonal[*column]).abs() < 1e-12);
        }
    }
}
