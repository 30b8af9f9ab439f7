//! What the verdict's global test and residual σ read: the residuals as
//! measured, whatever weights a robust loss gave them in the fit.
//!
//! A robust loss weights the fit; it does not change what the data say. The
//! test used to read the loss-weighted residuals `Σ w (r/σ)²`, and a loss
//! with a small scale weighs most residuals down: `--loss huber --loss-scale
//! 0.5` passed a σ stated 1.7× too small ("fits the stated noise"), Cauchy's
//! 2.5×, and without `--sigma` the residual σ came out 9.3e-153 mm. So with a
//! robust loss the test reads the residuals of every observation within the
//! outlier threshold, unweighted: `χ² = Σ (r/σ)²` over them, ν their
//! equations less the unknowns. The outliers stay out (they are reported,
//! and a block of them is a change of the cell: [`super::change`]); the
//! truncation at 3 σ̂ leaves out 5·10⁻⁶ of Gaussian observations of three
//! rows, nothing the test sees. In least squares every residual is read,
//! as before.

use super::statistics::ResidualStatistics;
use crate::observation::ObservationSystem;
use crate::robust::Loss;

/// A robust loss's scale is named when more than this part of the
/// observations weigh less than one half in the fit: the loss then treats
/// the residuals' own spread as gross errors.
const DOWN_WEIGHTED_PART: f64 = 0.25;

/// What the global test reads.
pub(super) struct Tested {
    /// Per observation: 1 read, 0 left out (an outlier); empty when every
    /// observation is read with weight 1 (least squares).
    pub(super) weights: Vec<f64>,
    /// `Σ (r/σ)²` over the rows read.
    pub(super) cost: f64,
    /// Their independent equations less the unknowns.
    pub(super) freedom: usize,
}

/// What the global test of `system` reads (module docs): in least squares
/// the fit's own `cost` and `freedom`; with a robust loss the residuals of
/// the observations whose standardised residual is within `threshold`,
/// unweighted, out of `equations` less `unknowns`.
pub(super) fn tested(
    system: &ObservationSystem,
    statistics: &ResidualStatistics,
    loss: &Loss,
    threshold: f64,
    (equations, unknowns): (usize, usize),
    (cost, freedom): (f64, usize),
) -> Tested {
    if loss.is_l2() {
        return Tested {
            weights: Vec::new(),
            cost,
            freedom,
        };
    }
    let weights: Vec<f64> = statistics
        .standardized
        .iter()
        .map(|u| if *u > threshold { 0.0 } else { 1.0 })
        .collect();
    let observations = system.row_observations();
    let (mut cost, mut dropped) = (0.0, 0_usize);
    for (row, scaled) in system.scaled_rows() {
        if weights[observations[row] as usize] > 0.0 {
            cost += scaled * scaled;
        } else {
            dropped += 1;
        }
    }
    Tested {
        weights,
        cost,
        freedom: equations.saturating_sub(dropped).saturating_sub(unknowns),
    }
}

/// A warning when a robust loss's scale is below the residuals' own spread
/// (more than [`DOWN_WEIGHTED_PART`] of the observations weigh less than one
/// half in the fit).
pub(super) fn loss_scale_warning(loss: &Loss, weights: &[f64]) -> Option<String> {
    if loss.is_l2() || weights.is_empty() {
        return None;
    }
    let down = weights.iter().filter(|w| **w < 0.5).count();
    let part = down as f64 / weights.len() as f64;
    (part > DOWN_WEIGHTED_PART).then(|| {
        format!(
            "the robust loss's scale ({} σ̂) is below the residuals' own spread: {:.0} % of the \
             observations weigh less than one half in the fit, as gross errors would; the fit is \
             then less precise than it can be (its σ may not say so) — the loss's default scale \
             is {} σ̂",
            loss.scale,
            100.0 * part,
            loss.kind.default_scale()
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::robust::LossKind;

    #[test]
    fn a_scale_below_the_spread_is_named() {
        let huber = Loss::with_scale(LossKind::Huber, 0.5).expect("loss");
        let weights: Vec<f64> = (0..100).map(|k| if k < 40 { 0.3 } else { 1.0 }).collect();
        let warning = loss_scale_warning(&huber, &weights).expect("named");
        assert!(
            warning.contains("40 %") && warning.contains("1.345"),
            "{warning}"
        );
        let few: Vec<f64> = (0..100).map(|k| if k < 10 { 0.3 } else { 1.0 }).collect();
        assert!(loss_scale_warning(&huber, &few).is_none());
        assert!(loss_scale_warning(&Loss::default(), &weights).is_none());
    }
}
