//! The spectrum of W and of small Gram matrices: singular values and the
//! condition number (Appendix III, the excitation check of §4), and the
//! extreme eigenvalues of W_bᵀW_b by Lanczos' tridiagonal form (a million
//! rows without a factorisation).

use faer::MatRef;

use crate::Error;

/// Below this condition number, [`condition_number`] takes the eigenvalues
/// of WᵀW: their relative accuracy, about c·ε·κ², is then better than 1e-6
/// and they cost half a singular value decomposition.
const EIGENVALUE_ROUTE_LIMIT: f64 = 1e4;

/// Trial points per end and sweep of [`tridiagonal_extremes`].
const MULTISECTION_POINTS: usize = 4;

/// Singular values, largest first.
///
/// # Errors
/// [`Error::Numerical`] if the SVD does not converge (non-finite input).
pub(crate) fn singular_values(matrix: MatRef<'_, f64>) -> Result<Vec<f64>, Error> {
    matrix.singular_values().map_err(|error| Error::Numerical {
        message: format!("singular value decomposition failed: {error:?}"),
    })
}

/// `σ_max / σ_min` of a full-column-rank matrix (∞ when rank deficient, 1 when empty).
///
/// # Errors
/// As [`singular_values`].
pub(crate) fn condition_number(matrix: MatRef<'_, f64>) -> Result<f64, Error> {
    if matrix.ncols() > 0 && matrix.nrows() >= matrix.ncols() {
        let gram = matrix.transpose() * matrix;
        if let Some((smallest, largest)) = eigenvalue_range(gram.as_ref())
            && smallest > 0.0
            && largest < EIGENVALUE_ROUTE_LIMIT.powi(2) * smallest
        {
            return Ok((largest / smallest).sqrt());
        }
    }
    let values = singular_values(matrix)?;
    Ok(match (values.first(), values.last()) {
        (Some(largest), Some(smallest)) if *smallest > 0.0 => largest / smallest,
        (Some(_), Some(_)) => f64::INFINITY,
        _ => 1.0,
    })
}

/// The smallest and largest eigenvalues of the symmetric matrix whose lower
/// triangle is `gram` (`None` if they are not finite).
///
/// nalgebra reduces the matrix to tridiagonal form (Householder); only the two
/// extreme eigenvalues of the tridiagonal matrix are then needed, which
/// [`tridiagonal_extremes`] finds in a fraction of the time of nalgebra's
/// implicit QR iteration for all of them.
pub(crate) fn eigenvalue_range(gram: MatRef<'_, f64>) -> Option<(f64, f64)> {
    let size = gram.nrows();
    let symmetric = nalgebra::DMatrix::from_fn(size, size, |i, j| gram[(i.max(j), i.min(j))]);
    if size == 0 || !symmetric.iter().all(|v| v.is_finite()) {
        return None;
    }
    let (diagonal, off_diagonal) =
        nalgebra::SymmetricTridiagonal::new(symmetric).unpack_tridiagonal();
    tridiagonal_extremes(diagonal.as_slice(), off_diagonal.as_slice())
}

/// The smallest and largest eigenvalues of the symmetric tridiagonal matrix T
/// with `diagonal` (length n ≥ 1) and `off_diagonal` (length n − 1), each to
/// a few ε relative to itself or ε²·‖T‖, whichever is larger (`None` if an
/// entry is not finite or its square overflows).
///
/// Sylvester's law of inertia: the number of negative pivots of the LDLᵀ
/// factorisation of T − xI (the Sturm count) is the number of eigenvalues
/// below x. Both ends are bracketed by Gershgorin's discs and narrowed
/// together, [`MULTISECTION_POINTS`] trial points per end and sweep, whose
/// independent pivot recurrences keep the divider busy (a dependent chain of
/// divisions is what limits one bisection). The counts are backward stable,
/// so the eigenvalues are as accurate as T itself (absolute error of order
/// n·ε·‖T‖, as for the QR iteration).
pub(super) fn tridiagonal_extremes(diagonal: &[f64], off_diagonal: &[f64]) -> Option<(f64, f64)> {
    const LANES: usize = 2 * MULTISECTION_POINTS;
    let size = diagonal.len();
    // b²_{i−1} beside d_i (0 beside d_0).
    let couplings: Vec<f64> = std::iter::once(0.0)
        .chain(off_diagonal.iter().map(|b| b * b))
        .collect();
    if size == 0
        || couplings.len() != size
        || !diagonal.iter().chain(&couplings).all(|v| v.is_finite())
    {
        return None;
    }
    // Gershgorin's discs contain every eigenvalue.
    let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
    for (i, d) in diagonal.iter().enumerate() {
        let radius = off_diagonal.get(i).map_or(0.0, |b| b.abs())
            + i.checked_sub(1).map_or(0.0, |k| off_diagonal[k].abs());
        low = low.min(d - radius);
        high = high.max(d + radius);
    }
    let scale = low.abs().max(high.abs());
    // dstebz's pivot floor: a zero pivot counts as a tiny negative one.
    let pivot_floor = f64::MIN_POSITIVE * couplings.iter().copied().fold(1.0, f64::max);
    let floor = (f64::EPSILON * f64::EPSILON * scale).max(pivot_floor);
    let resolved = |(a, b): (f64, f64)| b - a <= 4.0 * f64::EPSILON * a.abs().max(b.abs()) + floor;
    // Brackets (a, b): for the smallest eigenvalue, none below a and at least
    // one below b; for the largest, fewer than n below a and all below b.
    let margin = 2.0 * f64::EPSILON * scale * size as f64 + floor;
    let mut smallest = (low - margin, high + margin);
    let mut largest = smallest;
    let mut points = [0.0; LANES];
    while !(resolved(smallest) && resolved(largest)) {
        for k in 0..MULTISECTION_POINTS {
            let fraction = (k + 1) as f64 / (MULTISECTION_POINTS + 1) as f64;
            points[k] = smallest.0 + fraction * (smallest.1 - smallest.0);
            points[MULTISECTION_POINTS + k] = largest.0 + fraction * (largest.1 - largest.0);
        }
        // Pivot i of T − xI: d_i − x − b²_{i−1} / pivot_{i−1} (no coupling
        // before the first: 0 / 1).
        let mut pivots = [1.0; LANES];
        let mut below = [0usize; LANES];
        for (entry, coupling) in diagonal.iter().zip(&couplings) {
            for ((pivot, point), count) in pivots.iter_mut().zip(&points).zip(&mut below) {
                let value = entry - point - coupling / *pivot;
                *pivot = if value.abs() < pivot_floor {
                    -pivot_floor
                } else {
                    value
                };
                *count += usize::from(*pivot < 0.0);
            }
        }
        for k in 0..MULTISECTION_POINTS {
            if below[k] == 0 {
                smallest.0 = smallest.0.max(points[k]);
            } else {
                smallest.1 = smallest.1.min(points[k]);
            }
            let upper = MULTISECTION_POINTS + k;
            if below[upper] < size {
                largest.0 = largest.0.max(points[upper]);
            } else {
                largest.1 = largest.1.min(points[upper]);
            }
        }
    }
    Some((
        0.5 * (smallest.0 + smallest.1),
        0.5 * (largest.0 + largest.1),
    ))
}
