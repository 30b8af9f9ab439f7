//! Design criteria other than D, and the exchange that optimises them.
//!
//! The criteria are listed at [`Criterion`].
//!
//! None has the determinant lemma that makes D cheap, and E and O4 are not
//! smooth, so the exchange (Fedorov's, on pairs) shortlists: at design S it
//! ranks the candidates by the first-order gain trace(X_u G X_uᵀ), G = ∂c/∂M
//! (V diag(∂c/∂λ) Vᵀ for the spectral criteria, M⁻¹TM⁻¹ for test), evaluates
//! the criterion exactly for every swap of one of the [`SHORTLIST`] best with
//! a chosen unit, and makes the best swap while it improves the criterion.
//! It starts from the D-optimal design, which is well conditioned and
//! deterministic, so every criterion ends at least where D left it.

use nalgebra::{DMatrix, SymmetricEigen};

use super::columns::Blocks;
use super::spacing::Spacing;
use crate::Error;

/// Candidates evaluated exactly per exchange step.
const SHORTLIST: usize = 8;

/// What a plan optimises ([`crate::planning::plan_configurations`]).
///
/// With M = Σ X_uᵀX_u the information of the design in scaled base columns
/// and λ1 ≥ … ≥ λL its eigenvalues (λ = σ² of the scaled W_b):
///
/// | criterion | maximised | meaning |
/// |---|---|---|
/// | A | −trace M⁻¹ | the sum of the parameters' variances (error units², per σ²) |
/// | E | √λL = O3 | the worst-determined direction |
/// | O4 | λL/√λ1 = σL²/σ1 | the noise amplification index |
/// | O5 | 1/Σ λi^(−1/2) = 1/Σ 1/σi | |
/// | D | log det M | the volume of the confidence ellipsoid; O1 = exp(D/2L)/√m |
/// | test | −trace(M⁻¹ T) | T = Σ_t J_tᵀJ_t over the test poses' position rows: the calibrated robot's mean squared position error there, per σ² (after Klimchik et al.) |
#[derive(Clone, Debug, PartialEq)]
pub enum Criterion {
    /// D-optimal: the largest log det M (the smallest confidence ellipsoid).
    D,
    /// A-optimal: the smallest trace M⁻¹ (sum of the parameters' variances).
    A,
    /// E-optimal: the largest smallest singular value σL (O3).
    E,
    /// The largest noise amplification index O4 = σL²/σ1.
    O4,
    /// The largest O5 = 1/Σ 1/σi.
    O5,
    /// The smallest predicted position error of the calibrated robot at
    /// these test poses (motor variables).
    TestPoses(Vec<Vec<f64>>),
}

impl Criterion {
    /// The names users give.
    pub const NAMES: [&'static str; 6] = ["d", "a", "e", "o4", "o5", "test"];

    /// The criterion of a name of [`NAMES`](Self::NAMES); `test_poses` gives
    /// the poses of the `test` criterion.
    pub fn from_name(name: &str, test_poses: impl FnOnce() -> Vec<Vec<f64>>) -> Option<Self> {
        match name {
            "d" => Some(Criterion::D),
            "a" => Some(Criterion::A),
            "e" => Some(Criterion::E),
            "o4" => Some(Criterion::O4),
            "o5" => Some(Criterion::O5),
            "test" => Some(Criterion::TestPoses(test_poses())),
            _ => None,
        }
    }

    /// The criterion's name: d, a, e, o4, o5, test.
    pub fn name(&self) -> &'static str {
        match self {
            Criterion::D => "d",
            Criterion::A => "a",
            Criterion::E => "e",
            Criterion::O4 => "o4",
            Criterion::O5 => "o5",
            Criterion::TestPoses(_) => "test",
        }
    }

    /// What [`crate::planning::DesignQuality::value`] holds for this criterion.
    pub fn meaning(&self) -> &'static str {
        match self {
            Criterion::D => "log det(W_bᵀW_b)",
            Criterion::A => "trace (W_bᵀW_b)⁻¹",
            Criterion::E => "σL",
            Criterion::O4 => "σL²/σ1",
            Criterion::O5 => "1/Σ 1/σi",
            Criterion::TestPoses(_) => "predicted RMS position error at the test poses per unit σ",
        }
    }
}

/// A criterion made concrete for one set of base columns.
pub(super) enum Objective {
    D,
    A,
    E,
    O4,
    O5,
    /// T = Σ J_tᵀJ_t, and the number of test poses.
    Test(DMatrix<f64>, usize),
}

impl Objective {
    /// `criterion` made concrete: the test criterion's `T` and its number
    /// of test poses from `test`, which is called for it only.
    ///
    /// # Errors
    /// The error of `test`.
    pub(super) fn of(
        criterion: &Criterion,
        test: impl FnOnce() -> Result<(DMatrix<f64>, usize), Error>,
    ) -> Result<Self, Error> {
        Ok(match criterion {
            Criterion::D => Objective::D,
            Criterion::A => Objective::A,
            Criterion::E => Objective::E,
            Criterion::O4 => Objective::O4,
            Criterion::O5 => Objective::O5,
            Criterion::TestPoses(_) => {
                let (weight, poses) = test()?;
                Objective::Test(weight, poses)
            }
        })
    }

    /// The criterion's value at information `m`: larger is better.
    pub(super) fn value(&self, m: &DMatrix<f64>) -> f64 {
        let weighted = |t: &DMatrix<f64>| match m.clone().cholesky() {
            Some(cholesky) => -(cholesky.solve(t)).trace(),
            None => f64::NEG_INFINITY,
        };
        match self {
            Objective::A => weighted(&DMatrix::identity(m.nrows(), m.ncols())),
            Objective::Test(t, _) => weighted(t),
            _ => self.spectral(m.symmetric_eigenvalues().as_slice()),
        }
    }

    /// A spectral criterion of the eigenvalues `values` (any order).
    fn spectral(&self, values: &[f64]) -> f64 {
        let smallest = values
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min)
            .max(0.0);
        let largest = values.iter().copied().fold(0.0, f64::max);
        match self {
            Objective::D => values.iter().map(|v| v.max(0.0).ln()).sum(),
            Objective::E => smallest.sqrt(),
            Objective::O4 if largest > 0.0 => smallest / largest.sqrt(),
            Objective::O5 if smallest > 0.0 => {
                1.0 / values.iter().map(|v| v.sqrt().recip()).sum::<f64>()
            }
            _ => 0.0,
        }
    }

    /// The value as reported: the criterion in its natural sign and unit.
    pub(super) fn reported(&self, value: f64) -> f64 {
        match self {
            Objective::A => -value,
            Objective::Test(_, poses) => (-value / (*poses).max(1) as f64).max(0.0).sqrt(),
            _ => value,
        }
    }

    /// G = ∂c/∂M at `m`, for ranking candidates by trace(X G Xᵀ).
    fn gradient(&self, m: &DMatrix<f64>) -> DMatrix<f64> {
        if let Objective::Test(t, _) = self
            && let Some(cholesky) = m.clone().cholesky()
        {
            let inverse = cholesky.inverse();
            return &inverse * t * &inverse;
        }
        let SymmetricEigen {
            eigenvectors,
            eigenvalues,
        } = m.clone().symmetric_eigen();
        let tiny = eigenvalues.max() * 1e-15 + f64::MIN_POSITIVE;
        let smallest = eigenvalues.min().max(tiny);
        let largest = eigenvalues.max().max(tiny);
        let weights = eigenvalues.map(|value| {
            let value = value.max(tiny);
            match self {
                Objective::A | Objective::Test(..) => value.powi(-2),
                Objective::D => value.recip(),
                // A soft minimum: the directions within a few percent of λL
                // all count, so that ties do not hide a candidate's value.
                Objective::E => (-(value / smallest - 1.0) * 20.0).exp(),
                Objective::O4 => {
                    let at_smallest = (-(value / smallest - 1.0) * 20.0).exp();
                    let at_largest = if value >= largest * (1.0 - 1e-12) {
                        0.5 * smallest / largest
                    } else {
                        0.0
                    };
                    at_smallest - at_largest
                }
                Objective::O5 => value.powf(-1.5),
            }
        });
        &eigenvectors * DMatrix::from_diagonal(&weights) * eigenvectors.transpose()
    }
}

/// Improves the design `chosen` for `objective` by exchanges of one unit
/// (see the module docs). Returns the number of exchanges made; `step`
/// runs after each and may stop the work.
pub(super) fn exchange(
    candidates: &Blocks,
    base: &DMatrix<f64>,
    chosen: &mut [bool],
    admissible: &[bool],
    spacing: &mut Spacing,
    objective: &Objective,
    mut step: impl FnMut() -> Result<(), Error>,
) -> Result<usize, Error> {
    let wanted = chosen.iter().filter(|c| **c).count();
    let mut exchanges = 0;
    for _ in 0..20 * wanted.max(1) {
        let information = candidates.information(base, (0..chosen.len()).filter(|u| chosen[*u]));
        let current = objective.value(&information);
        let gradient = objective.gradient(&information);
        let mut ranked: Vec<(usize, f64)> = (0..chosen.len())
            .filter(|u| admissible[*u] && !chosen[*u] && spacing.freeable(*u))
            .map(|u| {
                let block = candidates.of(u);
                (u, (block * &gradient).component_mul(block).sum())
            })
            .filter(|(_, score)| score.is_finite())
            .collect();
        ranked.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
        let mut best: Option<(usize, usize, f64)> = None;
        for (added, _) in ranked.into_iter().take(SHORTLIST) {
            let block = candidates.of(added);
            let with = &information + block.transpose() * block;
            for removed in (0..chosen.len()).filter(|u| chosen[*u]) {
                if !spacing.free_without(added, removed) {
                    continue;
                }
                let block = candidates.of(removed);
                let value = objective.value(&(&with - block.transpose() * block));
                if best.is_none_or(|(_, _, b)| value > b) {
                    best = Some((added, removed, value));
                }
            }
        }
        let Some((added, removed, value)) = best else {
            break;
        };
        // No real improvement (NaN values never improve).
        if value.partial_cmp(&(current + 1e-10 * current.abs()))
            != Some(std::cmp::Ordering::Greater)
        {
            break;
        }
        chosen[removed] = false;
        spacing.place(removed, false);
        chosen[added] = true;
        spacing.place(added, true);
        exchanges += 1;
        step()?;
    }
    Ok(exchanges)
}
