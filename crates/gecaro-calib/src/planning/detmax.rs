//! D-optimal designs by Mitchell's DETMAX exchange with rank-r (Woodbury)
//! updates of M⁻¹ and of every candidate's G_u = X_u M⁻¹ X_uᵀ.
//!
//! Adding unit u multiplies det M by det(I + G_u), removing it by
//! det(I − G_u) (matrix determinant lemma), so a step needs the G_u only;
//! after a step on unit s, with U = M⁻¹X_sᵀ and C = (I ± X_s U)⁻¹,
//! M⁻¹ ← M⁻¹ ∓ U C Uᵀ and G_u ← G_u ∓ (X_u U) C (X_u U)ᵀ: O(K·r²·L) for
//! K candidates of r rows, no refactorisation per trial.

use nalgebra::DMatrix;

use super::columns::Blocks;
use super::spacing::Spacing;
use crate::Error;
use crate::error::Setting;

/// Steps between two recomputations of M⁻¹ and the G_u from scratch.
const REFRESH: usize = 32;

/// The exchange state: M⁻¹, and G_u = X_u M⁻¹ X_uᵀ of every candidate.
struct Exchange<'a> {
    candidates: &'a Blocks,
    inverse: DMatrix<f64>,
    gram: Vec<DMatrix<f64>>,
    chosen: Vec<bool>,
    /// Information of the kept units plus the ridge, the base of every refresh.
    base: DMatrix<f64>,
}

impl Exchange<'_> {
    /// Recomputes M⁻¹ and every G_u from the chosen units.
    fn refresh(&mut self) -> Result<(), Error> {
        let mut information = self.base.clone();
        for (unit, chosen) in self.chosen.iter().enumerate() {
            if *chosen {
                let block = self.candidates.of(unit);
                information += block.transpose() * block;
            }
        }
        self.inverse = information
            .cholesky()
            .ok_or_else(|| Error::Numerical {
                message: "planning: the information matrix is not positive definite".into(),
            })?
            .inverse();
        for (unit, gram) in self.gram.iter_mut().enumerate() {
            let block = self.candidates.of(unit);
            *gram = block * &self.inverse * block.transpose();
        }
        Ok(())
    }

    /// log det M of the chosen units (with the base).
    fn log_det(&self) -> Result<f64, Error> {
        let mut information = self.base.clone();
        for (unit, chosen) in self.chosen.iter().enumerate() {
            if *chosen {
                let block = self.candidates.of(unit);
                information += block.transpose() * block;
            }
        }
        let factor = information.cholesky().ok_or_else(|| Error::Numerical {
            message: "planning: the information matrix is not positive definite".into(),
        })?;
        Ok(2.0 * factor.l().diagonal().iter().map(|v| v.ln()).sum::<f64>())
    }

    /// det(I ± G_u): the factor by which adding (+) or removing (−) unit u
    /// multiplies det M.
    fn factor(&self, unit: usize, sign: f64) -> f64 {
        let gram = &self.gram[unit];
        (DMatrix::identity(gram.nrows(), gram.ncols()) + gram * sign).determinant()
    }

    /// Adds (sign +1) or removes (−1) unit `s`: a rank-r update of M⁻¹ and
    /// of every G_u.
    fn update(&mut self, s: usize, sign: f64) -> Result<(), Error> {
        let block = self.candidates.of(s);
        let u = &self.inverse * block.transpose();
        let core = DMatrix::identity(block.nrows(), block.nrows()) + (block * &u) * sign;
        let core_inverse = core.try_inverse().ok_or_else(|| Error::Numerical {
            message: "planning: a singular exchange step".into(),
        })?;
        self.inverse -= &u * &core_inverse * u.transpose() * sign;
        for (unit, gram) in self.gram.iter_mut().enumerate() {
            let v = self.candidates.of(unit) * &u;
            *gram -= &v * &core_inverse * v.transpose() * sign;
        }
        self.chosen[s] = sign > 0.0;
        Ok(())
    }

    /// The unit whose addition raises det M most (among the admissible ones
    /// not chosen and far enough from the chosen ones), with that factor.
    fn best_addition(&self, admissible: &[bool], spacing: &Spacing) -> Option<(usize, f64)> {
        self.best(|u| admissible[u] && !self.chosen[u] && spacing.free(u), 1.0)
    }

    /// The chosen unit whose removal lowers det M least, with that factor.
    fn best_removal(&self) -> Option<(usize, f64)> {
        self.best(|u| self.chosen[u], -1.0)
    }

    /// The eligible unit with the largest det(I ± G_u), and that value.
    fn best(&self, eligible: impl Fn(usize) -> bool, sign: f64) -> Option<(usize, f64)> {
        let mut best: Option<(usize, f64)> = None;
        for unit in (0..self.gram.len()).filter(|u| eligible(*u)) {
            let value = self.factor(unit, sign);
            if value.is_finite() && best.is_none_or(|(_, b)| value > b) {
                best = Some((unit, value));
            }
        }
        best
    }
}

/// A D-optimal choice of `wanted` admissible units, spaced as `spacing`
/// says, on top of the information `base` (kept units and the ridge
/// `ridge`), by DETMAX (add the best unit, remove the one whose removal
/// costs least, until the unit removed is the one just added) from two
/// starts, the better design kept: a deterministic greedy pass (each step
/// adds the unit with the largest det(I + G_u)), and, without a spacing
/// constraint, the heaviest units of the continuous D-optimal design
/// (`planning::continuous`). Returns the designs of both starts, the better
/// first (chosen flags, exchanges made); `step` runs after every step and
/// may stop the work.
pub(super) fn detmax(
    candidates: &Blocks,
    base: DMatrix<f64>,
    ridge: f64,
    wanted: usize,
    admissible: &[bool],
    spacing: &mut Spacing,
    mut step: impl FnMut() -> Result<(), Error>,
) -> Result<Vec<(Vec<bool>, usize)>, Error> {
    let width = candidates.width;
    let count = candidates.units.len();
    let mut exchange = Exchange {
        candidates,
        inverse: DMatrix::zeros(width, width),
        gram: vec![DMatrix::zeros(0, 0); count],
        chosen: vec![false; count],
        base: base.clone(),
    };
    exchange.refresh()?;
    let mut steps = 0;
    let mut advance = |exchange: &mut Exchange<'_>| -> Result<(), Error> {
        steps += 1;
        if steps % REFRESH == 0 {
            exchange.refresh()?;
        }
        step()
    };
    // Greedy pass.
    for placed in 0..wanted {
        let Some((unit, _)) = exchange.best_addition(admissible, spacing) else {
            return Err(Error::InvalidOption {
                setting: Setting::MinDistance,
                message: format!(
                    "only {placed} of the {wanted} units asked lie that far apart in the pool: \
                     lower the distance or give a larger pool"
                ),
            });
        };
        exchange.update(unit, 1.0)?;
        spacing.place(unit, true);
        advance(&mut exchange)?;
    }
    let greedy = improve(&mut exchange, wanted, admissible, spacing, &mut advance)?;
    if spacing.is_active() || wanted == 0 {
        return Ok(vec![(exchange.chosen, greedy)]);
    }
    // The continuous optimum's heaviest units, exchanged the same way.
    let weights = super::continuous::d_optimal_weights(candidates, admissible, ridge)?;
    let mut rounded = Exchange {
        candidates,
        inverse: DMatrix::zeros(width, width),
        gram: vec![DMatrix::zeros(0, 0); count],
        chosen: super::continuous::heaviest(&weights, wanted),
        base,
    };
    if rounded.chosen.iter().filter(|c| **c).count() < wanted {
        return Ok(vec![(exchange.chosen, greedy)]);
    }
    rounded.refresh()?;
    let continuous = improve(&mut rounded, wanted, admissible, spacing, &mut advance)?;
    let (from_greedy, from_continuous) = (
        (exchange.chosen.clone(), greedy),
        (rounded.chosen.clone(), continuous),
    );
    if rounded.log_det()? > exchange.log_det()? {
        Ok(vec![from_continuous, from_greedy])
    } else {
        Ok(vec![from_greedy, from_continuous])
    }
}

/// DETMAX from the exchange's chosen units; the number of exchanges made.
fn improve(
    exchange: &mut Exchange<'_>,
    wanted: usize,
    admissible: &[bool],
    spacing: &mut Spacing,
    advance: &mut impl FnMut(&mut Exchange<'_>) -> Result<(), Error>,
) -> Result<usize, Error> {
    // From exact M⁻¹ and G_u (a greedy pass starts from the ridge alone,
    // where the updates lose the most digits).
    exchange.refresh()?;
    let mut exchanges = 0;
    for _ in 0..20 * wanted.max(1) {
        let Some((added, gain)) = exchange.best_addition(admissible, spacing) else {
            break;
        };
        exchange.update(added, 1.0)?;
        spacing.place(added, true);
        let (removed, loss) = exchange.best_removal().unwrap_or((added, 1.0 / gain));
        exchange.update(removed, -1.0)?;
        spacing.place(removed, false);
        advance(exchange)?;
        if removed == added || gain * loss <= 1.0 + 1e-10 {
            if removed != added {
                // No real improvement: undo the swap.
                exchange.update(added, -1.0)?;
                spacing.place(added, false);
                exchange.update(removed, 1.0)?;
                spacing.place(removed, true);
            }
            break;
        }
        exchanges += 1;
    }
    Ok(exchanges)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulation::Sampler;

    /// The rank-r updates of M⁻¹ and of every G_u equal a recomputation.
    #[test]
    fn woodbury_updates_equal_a_refresh() {
        let mut sampler = Sampler::new(5);
        let candidates = Blocks {
            units: (0..12)
                .map(|_| DMatrix::from_fn(3, 5, |_, _| sampler.uniform(-1.0, 1.0)))
                .collect(),
            width: 5,
        };
        let mut exchange = Exchange {
            candidates: &candidates,
            inverse: DMatrix::zeros(5, 5),
            gram: vec![DMatrix::zeros(0, 0); 12],
            chosen: vec![false; 12],
            base: DMatrix::identity(5, 5) * 0.1,
        };
        exchange.refresh().expect("positive definite");
        for (unit, sign) in [
            (0, 1.0),
            (3, 1.0),
            (7, 1.0),
            (3, -1.0),
            (11, 1.0),
            (0, -1.0),
        ] {
            exchange.update(unit, sign).expect("update");
        }
        let (inverse, gram) = (exchange.inverse.clone(), exchange.gram.clone());
        exchange.refresh().expect("positive definite");
        assert!((&inverse - &exchange.inverse).abs().max() < 1e-12 * exchange.inverse.abs().max());
        for (updated, fresh) in gram.iter().zip(&exchange.gram) {
            assert!((updated - fresh).abs().max() < 1e-12 * fresh.abs().max().max(1.0));
        }
        assert_eq!(
            exchange.chosen,
            [
                false, false, false, false, false, false, false, true, false, false, false, true
            ]
        );
    }

    /// On small pools, the design equals the best of every choice
    /// (exhaustive search), and lies within the continuous relaxation's
    /// bound log det(k·M(w*)).
    #[test]
    fn small_pools_reach_the_exhaustive_optimum() {
        let (units, wanted, width) = (12, 5, 5);
        let mut optimal = 0;
        for seed in 0..20 {
            let mut sampler = Sampler::new(100 + seed);
            let candidates = Blocks {
                units: (0..units)
                    .map(|_| DMatrix::from_fn(2, width, |_, _| sampler.uniform(-1.0, 1.0)))
                    .collect(),
                width,
            };
            let ridge = 1e-9;
            let base = DMatrix::identity(width, width) * ridge;
            let log_det = |chosen: &[bool]| {
                let mut information = base.clone();
                for (unit, c) in chosen.iter().enumerate() {
                    if *c {
                        information += candidates.of(unit).transpose() * candidates.of(unit);
                    }
                }
                information.determinant().ln()
            };
            let mut best = f64::NEG_INFINITY;
            for mask in 0u32..(1 << units) {
                if mask.count_ones() as usize == wanted {
                    let chosen: Vec<bool> = (0..units).map(|u| mask & (1 << u) != 0).collect();
                    best = best.max(log_det(&chosen));
                }
            }
            let mut spacing = Spacing::new(vec![Vec::new(); units], 0.0);
            let (chosen, _) = detmax(
                &candidates,
                base.clone(),
                ridge,
                wanted,
                &[true; 12],
                &mut spacing,
                || Ok(()),
            )
            .expect("design")
            .swap_remove(0);
            let found = log_det(&chosen);
            assert!(found <= best + 1e-9);
            if found >= best - 1e-9 {
                optimal += 1;
            }
            let weights =
                crate::planning::continuous::d_optimal_weights(&candidates, &[true; 12], ridge)
                    .expect("weights");
            let mut relaxed = base.clone();
            for (unit, weight) in weights.iter().enumerate() {
                relaxed += candidates.of(unit).transpose()
                    * candidates.of(unit)
                    * (*weight * wanted as f64);
            }
            assert!(best <= relaxed.determinant().ln() + 1e-6, "the bound holds");
        }
        // Measured: 19 of 20 with both starts, 15 of 20 from the greedy start alone.
        assert!(optimal >= 19, "{optimal} of 20 designs are optimal");
    }
}
