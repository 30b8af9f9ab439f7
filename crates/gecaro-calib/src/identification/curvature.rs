//! The residuals' curvature, which Gauss–Newton leaves out, where the
//! precision needs it.
//!
//! ## Why
//!
//! The identified parameters θ̂ are a stationary point of the weighted sum
//! of squares `F(θ) = ½‖r(θ)‖²` (prior and gauge rows included), with
//! `r = Δy = y − f(θ)` and `W = ∂f/∂θ`. Its Hessian is
//!
//! ```text
//! H = WᵀW − S,   S = Σᵢ rᵢ ∇²fᵢ,
//! ```
//!
//! and Gauss–Newton's normal matrix `G = WᵀW` leaves S out. By the implicit
//! function theorem the estimate moves with the data as `dθ̂ = H⁻¹ Dᵀ dy`
//! (D the measured rows), so the spread its noise gives it is
//! `σ² H⁻¹ DᵀD H⁻¹`, not `σ² G⁻¹ DᵀD G⁻¹`. S is of the order of the
//! residuals times the model's second derivatives; where G is well
//! conditioned it changes nothing. Along G's near-null directions it does:
//! parameters that only the real robot's deviations let the data see, which
//! the second pass adds under its prior (PUMA 560 position data at error
//! level 1: r7 absorbed with θ6 and r6, equilibrated eigenvalue 1e-8 where
//! S's entries reach 3e-4 of the diagonal), spread 1.8–2.2 times G's noise
//! σ, and twice its finite-difference sensitivity to the data.
//!
//! ## How
//!
//! S is measured only along the directions where it can matter. With G
//! equilibrated (`G̃ = Δ⁻¹GΔ⁻¹`, Δ its diagonal's square root), nothing is
//! done unless its smallest eigenvalue is below [`ONSET`]; then every
//! eigen-direction v below [`BAND`] is measured (at most
//! [`MAX_DIRECTIONS`], smallest first). For each, the rows W at `θ̂ ± h u`
//! (`u = Δ⁻¹v` scaled to a largest entry of 1, h = [`STEP`]: two
//! linearisations) against the measured residuals r at θ̂ give
//! `S u = (W₊ᵀr − W₋ᵀr)/2h`. The rows are held for it when they fit in
//! [`HELD_ENTRIES`] (a streamed system's too, then with one more
//! linearisation at θ̂); beyond, the folded gradients give
//! `S u = G u + (g₊ − g₋)/2h`, `g = Wᵀr` at each point, which subtracts
//! nearly equal numbers: it did not resolve a curvature of 4e-8 of G's
//! diagonal (PUMA 560, level 2, seed 8: r7 still 2× its noise σ) that the
//! held rows do. With `P = VVᵀ` on the span of the measured directions, S is
//! taken as `S̃P + PS̃ − PS̃P`: exact on the span and between the span and
//! the rest, zero between the other directions, where an entry `s` of S̃
//! moves `H⁻¹` by about `s²/(λ_a λ_b)` (below 1e-3 for the entries of 3e-4
//! measured, with eigenvalues above 1e-2). The band is needed: the near-null
//! direction's own curvature can be tiny while its coupling with the next
//! directions is not. Restricting S to a subset of *parameters* instead
//! (those the prior holds) made H indefinite: the near-null direction mixes
//! held and free parameters.
//!
//! Measured on PUMA 560 position data: the noise σ against the
//! finite-difference sensitivity of the whole identification, every
//! parameter within 1 % at levels 1 (seed 7) and 2 (seed 8), where r7 was at
//! 2×; `cargo run --release --example precision` (40 noise draws), the
//! spread of every parameter over its noise σ 0.67–1.39 in all 24 cases of
//! PUMA 560 and industrial6, position and frame, levels 1 and 2, seeds 7–9
//! (it was up to 2.32, always r7 with position data).

use faer::{Mat, MatRef};

use super::options::IdentificationOptions;
use super::solver::{Iterate, Problem};
use super::weighting::Weighting;
use crate::Error;
use crate::linalg::{LeastSquaresRows, eigenvalue_range};
use crate::study::StudyStates;

/// The smallest equilibrated eigenvalue of G below which the curvature is
/// measured: a well-conditioned base set (the Stanford's position data,
/// 2.5e-3–5e-3) costs nothing; PUMA 560 position data with the second
/// pass's parameters (2e-7–1e-8) cost two linearisations a direction (six
/// directions at m = 5,000: 13 with the held rows' own, of the run's about
/// 50; 0.20–0.22 s for the whole command).
const ONSET: f64 = 1e-4;

/// Then every direction below this equilibrated eigenvalue is measured.
const BAND: f64 = 1e-2;

/// The most directions measured (two linearisations each).
const MAX_DIRECTIONS: usize = 12;

/// The most entries of W held to measure the curvature directly (64 MB);
/// larger streamed systems difference their folded gradients instead.
const HELD_ENTRIES: usize = 8 << 20;

/// The central difference's step along a direction whose largest entry is
/// 1 (metres, radians, gains): with held rows, 1e-5 and 1e-7 give the same
/// noise σ to five digits (r7, PUMA 560 at level 2, seed 8).
const STEP: f64 = 1e-6;

/// The Hessian `H = G − S` of the sum of squares at `best` in the columns
/// of `problem` under `weighting` (the final robust weights and prior
/// rows), where the curvature matters (module docs); `None` where G is
/// well conditioned and H is G, or where the measured H is not positive
/// definite (the caller keeps G's precision). The check that decides it
/// reads the equilibrated G's extreme eigenvalues only (what the solver's
/// choice reads); the eigenvectors are computed past it.
///
/// # Errors
/// Errors of the model near `best`, which it evaluated.
pub(super) fn newton_hessian(
    problem: &Problem<'_>,
    weighting: &Weighting,
    best: &Iterate,
) -> Result<Option<Mat<f64>>, Error> {
    let Some((equilibrated, norms)) = best.normal.equilibrated() else {
        return Ok(None);
    };
    match eigenvalue_range(equilibrated.as_ref()) {
        Some((smallest, _)) if smallest < ONSET => {}
        _ => return Ok(None),
    }
    let Ok(eigen) = equilibrated.self_adjoint_eigen(faer::Side::Lower) else {
        return Ok(None);
    };
    let columns = norms.len();
    let measured = (0..columns.min(MAX_DIRECTIONS))
        .take_while(|k| eigen.S()[*k] < BAND)
        .count();
    // V: the measured directions (equilibrated coordinates, orthonormal).
    let directions = eigen.U().subcols(0, measured).to_owned();
    let problem = problem.with_weighting(weighting.clone());
    let values: Vec<f64> = (0..measured).map(|k| eigen.S()[k]).collect();
    let curvatures = measured_curvatures(&problem, best, &norms, (directions.as_ref(), &values))?;
    if !curvatures.is_all_finite() {
        return Ok(None);
    }
    // S̃ ≈ R Vᵀ + V Rᵀ − V M Vᵀ, R = S̃V, M = VᵀR (symmetrised); H = Δ(G̃ − S̃)Δ.
    let crossed = directions.transpose() * &curvatures;
    let m = (&crossed + crossed.transpose()) * 0.5;
    let curvature = &curvatures * directions.transpose() + &directions * curvatures.transpose()
        - &directions * &m * directions.transpose();
    let hessian = Mat::from_fn(columns, columns, |i, j| {
        (equilibrated[(i, j)] - curvature[(i, j)]) * norms[i] * norms[j]
    });
    Ok(hessian.llt(faer::Side::Lower).is_ok().then_some(hessian))
}

/// `S̃V` for the orthonormal `directions` V of the equilibrated G (columns;
/// `values` their eigenvalues, `norms` the column norms Δ of W), measured
/// by central differences (module docs): a column per direction.
///
/// # Errors
/// Errors of the model near `best`.
fn measured_curvatures(
    problem: &Problem<'_>,
    best: &Iterate,
    norms: &[f64],
    (directions, values): (MatRef<'_, f64>, &[f64]),
) -> Result<Mat<f64>, Error> {
    let (columns, count) = directions.shape();
    let mut states = StudyStates::default();
    // The rows are held for the measurement where they fit in
    // [`HELD_ENTRIES`] (a streamed system's too): W at θ̂ ± h u against the
    // measured residuals at θ̂ (weighted).
    let (held_options, held_problem);
    let rows = best.system.measured_rows();
    let (problem, residuals) = if !best.system.is_folded() {
        (
            problem,
            Some(best.system.solver_rows(true).right().to_vec()),
        )
    } else if rows.saturating_mul(columns) <= HELD_ENTRIES {
        held_options = IdentificationOptions {
            streamed_rows: usize::MAX,
            ..problem.options.clone()
        };
        held_problem = Problem {
            options: &held_options,
            ..problem.with_weighting(problem.weighting.clone())
        };
        let at = held_problem.assemble(
            &best.robot,
            &best.auxiliary,
            &held_problem.layout,
            &mut states,
        )?;
        let residuals = at.system.solver_rows(true).right().to_vec();
        (&held_problem, Some(residuals))
    } else {
        (problem, None)
    };
    let residuals = residuals
        .as_deref()
        .map(|r| MatRef::from_column_major_slice(r, r.len(), 1));
    let mut curvatures = Mat::<f64>::zeros(columns, count);
    for k in 0..count {
        let v = directions.col(k);
        // u = Δ⁻¹v, scaled to a largest entry of 1 (by `size`).
        let size = (0..columns).fold(0.0_f64, |m, i| m.max((v[i] / norms[i]).abs()));
        let mut gradients = [Mat::<f64>::zeros(0, 0), Mat::<f64>::zeros(0, 0)];
        for (gradient, sign) in gradients.iter_mut().zip([1.0, -1.0]) {
            let step: Vec<f64> = (0..columns)
                .map(|i| sign * STEP * v[i] / (norms[i] * size))
                .collect();
            let (robot, auxiliary) = problem.stepped(best, &step, &problem.base)?;
            let moved = problem.assemble(&robot, &auxiliary, &problem.layout, &mut states)?;
            *gradient = match &residuals {
                // `W(θ̂ ± h u)ᵀ r(θ̂)`: the rows moved, the residuals not.
                Some(residuals) => moved.system.solver_rows(true).matrix().transpose() * residuals,
                None => moved.normal.projected().clone(),
            };
        }
        // Held rows: S u = (W₊ᵀr − W₋ᵀr)/2h. Folded: S u = G u − H u
        // = G u + (g₊ − g₋)/2h, and Δ⁻¹G u = G̃v/size = λv/size. Then
        // S̃v = size · Δ⁻¹ S u.
        let value = if residuals.is_some() { 0.0 } else { values[k] };
        for i in 0..columns {
            let difference = (gradients[0][(i, 0)] - gradients[1][(i, 0)]) / (2.0 * STEP);
            curvatures[(i, k)] = value * v[i] + size * difference / norms[i];
        }
    }
    Ok(curvatures)
}
