//! The joint steps of the numerical inverse model
//! ([`inverse_kinematics`](super::inverse_kinematics)): for the task
//! Jacobian J (k×n: the k rows of the target, the n joints) and the task
//! error Δx, the damped least-squares step
//! `Δq = (JᵀJ + λI)⁻¹JᵀΔx = Jᵀ(JJᵀ + λI)⁻¹Δx`, the same with the joints
//! held at a limit taken out of it (an active set), and the Newton step
//! (λ = 0, or `J⁻¹Δx` for a square J).
//!
//! Every step is written into a vector the caller keeps from iteration to
//! iteration, so that an iteration allocates nothing for a point (k = 3)
//! or a frame (k = 6). `Jᵀv` is summed in the order of nalgebra's
//! matrix–vector product (row by row of J), so the steps are those of the
//! product bit for bit.

use nalgebra::{DMatrix, DVector, Matrix3, Matrix6, SMatrix, SVector, Vector3, Vector6};

use crate::frame::Joint;

/// The damped least-squares steps `(JᵀJ + λI)⁻¹JᵀΔx` of one J, computed
/// as `Jᵀ(JJᵀ + λI)⁻¹Δx` when J has no more rows than columns (the smaller
/// product; with λ = 0, the smallest step that meets the linearised
/// target). The product to invert does not change with λ: it is formed
/// once for every damping tried.
pub(super) struct DampedSystem<'a> {
    jacobian: &'a DMatrix<f64>,
    product: Product,
}

/// The product [`DampedSystem`] inverts.
#[allow(clippy::large_enum_variant)] // one per iterate, on the stack: no allocation
enum Product {
    /// JJᵀ of a frame's rows (six), on the stack.
    Six(Matrix6<f64>),
    /// JJᵀ of a point's rows (three), on the stack.
    Three(Matrix3<f64>),
    /// JJᵀ of other rows (a plane's one).
    Wide(DMatrix<f64>),
    /// JᵀJ of a J with more rows than columns.
    Tall(DMatrix<f64>),
}

impl<'a> DampedSystem<'a> {
    pub(super) fn new(jacobian: &'a DMatrix<f64>) -> Self {
        let (rows, columns) = jacobian.shape();
        let product = match rows {
            _ if rows > columns => Product::Tall(jacobian.transpose() * jacobian),
            6 => Product::Six(outer_sum(jacobian)),
            3 => Product::Three(outer_sum(jacobian)),
            _ => Product::Wide(jacobian * jacobian.transpose()),
        };
        DampedSystem { jacobian, product }
    }

    /// The J of the system.
    pub(super) fn jacobian(&self) -> &DMatrix<f64> {
        self.jacobian
    }

    /// The step for the damping λ, into `step` (n values); `false` when
    /// the product to invert does not factorise or the step is not finite.
    pub(super) fn step(&self, error: &DVector<f64>, damping: f64, step: &mut DVector<f64>) -> bool {
        let jacobian = self.jacobian;
        match &self.product {
            Product::Six(product) => match wide_solve(product, error, damping) {
                Some(solved) => transpose_times(jacobian, solved.as_slice(), step),
                None => return false,
            },
            Product::Three(product) => match wide_solve(product, error, damping) {
                Some(solved) => transpose_times(jacobian, solved.as_slice(), step),
                None => return false,
            },
            Product::Wide(product) => match damped(product.clone(), damping).cholesky() {
                Some(factor) => transpose_times(jacobian, factor.solve(error).as_slice(), step),
                None => return false,
            },
            Product::Tall(product) => match damped(product.clone(), damping).cholesky() {
                Some(factor) => step.copy_from(&factor.solve(&(jacobian.transpose() * error))),
                None => return false,
            },
        }
        step.as_slice().iter().all(|v| v.is_finite())
    }
}

/// `Jᵀv` into `out` (J of `v.len()` rows), each entry summed over the
/// rows of J in order (as nalgebra's product of the transposed J and v
/// sums it). Inlined, so that for a point's or a frame's `v` (a fixed
/// length) the sums are unrolled.
#[inline(always)]
fn transpose_times(jacobian: &DMatrix<f64>, v: &[f64], out: &mut DVector<f64>) {
    let rows = v.len();
    // (J is column-major: each chunk is a column, entry j of Jᵀv.)
    for (column, entry) in jacobian.as_slice().chunks_exact(rows).zip(out.iter_mut()) {
        let mut sum = column[0] * v[0];
        for i in 1..rows {
            sum += column[i] * v[i];
        }
        *entry = sum;
    }
}

/// JJᵀ for a J of `R` rows, as the sum of its columns' outer products in
/// column order: each entry is the rows' dot product, summed in the same
/// order, read from contiguous columns rather than strided rows.
fn outer_sum<const R: usize>(jacobian: &DMatrix<f64>) -> SMatrix<f64, R, R> {
    let mut lower = [[0.0; R]; R];
    for column in jacobian.as_slice().chunks_exact(R) {
        for i in 0..R {
            for k in 0..=i {
                lower[i][k] += column[i] * column[k];
            }
        }
    }
    SMatrix::from_fn(|i, k| if k <= i { lower[i][k] } else { lower[k][i] })
}

/// The damped step of `system` from `joint_positions` into `step`, with
/// the joints held at a limit it would push beyond taken out of it (an
/// active set; `joints` the robot's, `None` when the limits are not kept):
/// their columns of J are zeroed (in `held`, of J's shape) and the step is
/// taken again by the others, until none pushes beyond. Clamping such a
/// joint instead would cut the step after it is chosen, so the others
/// would not make up for it and the descent would crawl along the limit.
/// Without limits, or with no joint pushing beyond one, the step is the
/// system's. `false` as [`DampedSystem::step`].
pub(super) fn bounded_step(
    joints: Option<&[Joint]>,
    joint_positions: &DVector<f64>,
    (system, error, damping): (&DampedSystem<'_>, &DVector<f64>, f64),
    step: &mut DVector<f64>,
    held: &mut DMatrix<f64>,
) -> bool {
    if !system.step(error, damping, step) {
        return false;
    }
    let Some(joints) = joints else {
        return true;
    };
    let mut holding = false;
    loop {
        let mut blocked = false;
        for (index, ((q, joint), change)) in joint_positions
            .as_slice()
            .iter()
            .zip(joints)
            .zip(step.as_slice())
            .enumerate()
        {
            if pushes_beyond(joint, *q, *change) {
                if !holding {
                    held.copy_from(system.jacobian());
                    holding = true;
                }
                held.column_mut(index).fill(0.0);
                blocked = true;
            }
        }
        // (A zeroed column gives its joint no step: each round holds a new one.)
        if !blocked {
            return true;
        }
        if !DampedSystem::new(held).step(error, damping, step) {
            return false;
        }
    }
}

/// Whether a joint at `q` held at one of its limits would be pushed beyond
/// it by a `change` of that sign (a step, or the descent direction `Jᵀ Δx`).
pub(super) fn pushes_beyond(joint: &Joint, q: f64, change: f64) -> bool {
    (q <= joint.qmin && change < 0.0) || (q >= joint.qmax && change > 0.0)
}

/// The smallest `Δq` with `J Δq = Δx` (J of full row rank), or the
/// least-squares one for a J with more rows than columns, into `step`;
/// `false` when the product to invert is singular (a singular
/// configuration).
pub(super) fn newton_step(
    jacobian: &DMatrix<f64>,
    error: &DVector<f64>,
    step: &mut DVector<f64>,
) -> bool {
    if jacobian.is_square() && matches!(jacobian.nrows(), 3 | 6) {
        // A square J (a frame for six joints, a point for three): Δq = J⁻¹Δx
        // by LU, cheaper than the product and with J's own conditioning.
        square_solve(jacobian, error, step) && step.iter().all(|v| v.is_finite())
    } else {
        DampedSystem::new(jacobian).step(error, 0.0, step)
    }
}

/// `product + λI`.
fn damped(mut product: DMatrix<f64>, damping: f64) -> DMatrix<f64> {
    for i in 0..product.nrows() {
        product[(i, i)] += damping;
    }
    product
}

/// `J⁻¹Δx` for a square J of 6 or 3 rows, by LU, into `step`; `false` when
/// J is singular.
fn square_solve(jacobian: &DMatrix<f64>, error: &DVector<f64>, step: &mut DVector<f64>) -> bool {
    let (values, right) = (jacobian.as_slice(), error.as_slice());
    let solved = match jacobian.nrows() {
        6 => Matrix6::from_column_slice(values)
            .lu()
            .solve(&Vector6::from_column_slice(right))
            .map(|solved| step.copy_from_slice(solved.as_slice())),
        3 => Matrix3::from_column_slice(values)
            .lu()
            .solve(&Vector3::from_column_slice(right))
            .map(|solved| step.copy_from_slice(solved.as_slice())),
        _ => None,
    };
    solved.is_some()
}

/// `(JJᵀ + λI)⁻¹Δx` for a J of `R` rows, from its `product` JJᵀ.
fn wide_solve<const R: usize>(
    product: &SMatrix<f64, R, R>,
    error: &DVector<f64>,
    damping: f64,
) -> Option<SVector<f64, R>> {
    let mut product = *product;
    for i in 0..R {
        product[(i, i)] += damping;
    }
    let right = SVector::<f64, R>::from_column_slice(error.as_slice());
    Some(product.cholesky()?.solve(&right))
}
