//! Robust losses and the outlier statistics of an identification.
//!
//! Plain least squares (paper eq. 10) minimises `Σ r²`: one gross error
//! (a tracker losing the beam, a ball not seated) pulls every parameter. A
//! robust loss `Σ ρ(u_i)` grows more slowly for large residuals; it is
//! minimised by iteratively reweighted least squares (IRLS): each outer
//! iteration solves the weighted problem `Σ w_i r_i²` with
//! `w_i = ρ'(u_i)/u_i` from the previous residuals, until the weights settle.
//!
//! ## Units
//!
//! Residuals are first divided by their sensor's σ (the set's weight), so
//! that rows of different sets compare. The robust σ̂ is the normalised
//! median absolute deviation of those scaled row residuals, one per
//! measurement set and kind of row (lengths, angles: a set without sensor σ
//! has them in metres and radians, and a set's σ may be a rough guess; a
//! set's kind with fewer than 10 rows takes the σ̂ of all sets),
//! `σ̂ = 1.4826 · median |e − median e|`, which is the standard deviation
//! for Gaussian noise and is not moved by up to half the rows being gross.
//! An observation (a configuration of the position, frame, link and plane
//! methods, a pair of the distance method) has one or several rows; its
//! standardised residual is the RMS of its rows in units of σ̂,
//! `u_i = √(Σ_rows e² / rows) / σ̂`: about 1 for a clean observation of any
//! size, 20 for one whose rows are all 20 σ̂ off. Weights are per observation,
//! so a bad measurement is discounted as a whole.
//! Residuals are standardised by at least 1e-9 (metres for an unweighted set,
//! sensor σ for a weighted one): noise-free simulated data leave only
//! rounding, in which nothing is an outlier.
//!
//! ## Losses
//!
//! With `k` the loss scale ([`Loss::scale`], in units of σ̂):
//!
//! | loss | ρ grows | weight `w(u)` | default k |
//! |---|---|---|---|
//! | `l2` | as u² | 1 | — |
//! | `huber` | as u beyond k | 1 for u ≤ k, k/u beyond | 1.345 |
//! | `cauchy` | as log u | 1/(1 + (u/k)²) | 2.385 |
//! | `tukey` | not at all beyond k | (1 − (u/k)²)² for u < k, 0 beyond | 4.685 |
//!
//! The default scales give 95 % of the efficiency of least squares on
//! Gaussian noise (Holland & Welsch 1977). Huber's loss is convex: IRLS
//! reaches its unique minimum from the least-squares solution. Cauchy and
//! Tukey redescend (they can ignore a residual entirely) and have local
//! minima, so the identification runs Huber to convergence first and
//! continues from there with the chosen loss.

use std::fmt;
use std::str::FromStr;

use crate::Error;
use crate::error::Setting;
use crate::selection::median_of_parts;

/// Normalising constant of the median absolute deviation (1/Φ⁻¹(3/4)).
const MAD_TO_SIGMA: f64 = 1.482_602_218_505_602;

/// The kind of robust loss; see the module docs.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Hash)]
pub enum LossKind {
    /// Plain least squares (the paper's eq. 10).
    #[default]
    L2,
    /// Huber: quadratic within k σ̂, linear beyond.
    Huber,
    /// Cauchy (Lorentzian): logarithmic.
    Cauchy,
    /// Tukey's biweight: observations beyond k σ̂ get no weight.
    Tukey,
}

impl LossKind {
    /// Every loss, in the order of the docs.
    pub const ALL: [LossKind; 4] = [
        LossKind::L2,
        LossKind::Huber,
        LossKind::Cauchy,
        LossKind::Tukey,
    ];

    /// Their names, as users give them.
    pub const NAMES: [&'static str; 4] = ["l2", "huber", "cauchy", "tukey"];

    /// `l2`, `huber`, `cauchy` or `tukey`.
    pub fn as_str(self) -> &'static str {
        match self {
            LossKind::L2 => "l2",
            LossKind::Huber => "huber",
            LossKind::Cauchy => "cauchy",
            LossKind::Tukey => "tukey",
        }
    }

    /// The default scale k (units of σ̂): 95 % efficiency on Gaussian noise.
    pub fn default_scale(self) -> f64 {
        match self {
            LossKind::L2 => f64::INFINITY,
            LossKind::Huber => 1.345,
            LossKind::Cauchy => 2.385,
            LossKind::Tukey => 4.685,
        }
    }

    /// Whether the weight goes back towards 0 for large residuals (local minima).
    pub fn redescending(self) -> bool {
        matches!(self, LossKind::Cauchy | LossKind::Tukey)
    }
}

impl fmt::Display for LossKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl FromStr for LossKind {
    type Err = Error;

    fn from_str(name: &str) -> Result<Self, Error> {
        LossKind::ALL
            .into_iter()
            .find(|kind| kind.as_str().eq_ignore_ascii_case(name.trim()))
            .ok_or_else(|| Error::InvalidOption {
                setting: Setting::Loss,
                message: format!("unknown loss '{name}' (expected l2, huber, cauchy or tukey)"),
            })
    }
}

/// A robust loss with its scale; see the module docs.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Loss {
    /// Which loss.
    pub kind: LossKind,
    /// The scale k, in units of the robust σ̂.
    pub scale: f64,
}

impl Default for Loss {
    fn default() -> Self {
        Loss::new(LossKind::L2)
    }
}

impl Loss {
    /// `kind` with its default scale.
    pub fn new(kind: LossKind) -> Self {
        Loss {
            kind,
            scale: kind.default_scale(),
        }
    }

    /// `kind` with scale `scale` (units of σ̂).
    ///
    /// # Errors
    /// [`Error::InvalidOption`] (`--loss-scale`) unless the scale is finite and positive.
    pub fn with_scale(kind: LossKind, scale: f64) -> Result<Self, Error> {
        if !(scale.is_finite() && scale > 0.0) {
            return Err(Error::InvalidOption {
                setting: Setting::LossScale,
                message: format!("must be a positive number (in robust σ), not {scale}"),
            });
        }
        Ok(Loss { kind, scale })
    }

    /// `kind` with `scale`, or its default scale: what a user asks for.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] (`--loss-scale`) for a scale with `l2` (it has
    /// none) or a scale that is not finite and positive.
    pub fn from_parts(kind: LossKind, scale: Option<f64>) -> Result<Self, Error> {
        match scale {
            Some(_) if kind == LossKind::L2 => Err(Error::InvalidOption {
                setting: Setting::LossScale,
                message:
                    "l2 has no scale; a scale goes with a robust loss (huber, cauchy or tukey)"
                        .into(),
            }),
            Some(scale) => Loss::with_scale(kind, scale),
            None => Ok(Loss::new(kind)),
        }
    }

    /// Whether this is plain least squares.
    pub fn is_l2(&self) -> bool {
        self.kind == LossKind::L2
    }

    /// The IRLS weight `ρ'(u)/u` of a standardised residual `u ≥ 0`.
    pub fn weight(&self, u: f64) -> f64 {
        let k = self.scale;
        match self.kind {
            LossKind::L2 => 1.0,
            LossKind::Huber => {
                if u <= k {
                    1.0
                } else {
                    k / u
                }
            }
            LossKind::Cauchy => 1.0 / (1.0 + (u / k).powi(2)),
            LossKind::Tukey => {
                if u < k {
                    (1.0 - (u / k).powi(2)).powi(2)
                } else {
                    0.0
                }
            }
        }
    }
}

impl fmt::Display for Loss {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_l2() {
            f.write_str("l2")
        } else {
            write!(f, "{} (k = {} σ̂)", self.kind, self.scale)
        }
    }
}

/// The normalised median absolute deviation of `values` (see the module
/// docs); 0 for no values.
pub fn robust_sigma(values: &[f64]) -> f64 {
    robust_sigma_parts(values.len(), 1, |_| values.iter().copied())
}

/// [`robust_sigma`] of the `count` values that `values(0)`, …,
/// `values(parts − 1)` yield between them, without holding them
/// ([`crate::selection`]): millions of residuals are read where they are,
/// the parts on all cores. The same value, bit for bit, for any split.
pub(crate) fn robust_sigma_parts<I: Iterator<Item = f64>>(
    count: usize,
    parts: usize,
    values: impl Fn(usize) -> I + Sync,
) -> f64 {
    if count == 0 {
        return 0.0;
    }
    let centre = median_of_parts(count, parts, &values);
    MAD_TO_SIGMA
        * median_of_parts(count, parts, |part| {
            values(part).map(move |value| (value - centre).abs())
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_follow_their_definitions() {
        let huber = Loss::new(LossKind::Huber);
        assert_eq!(huber.weight(1.0), 1.0);
        assert!((huber.weight(2.69) - 0.5).abs() < 1e-12);
        let cauchy = Loss::with_scale(LossKind::Cauchy, 2.0).expect("scale");
        assert!((cauchy.weight(2.0) - 0.5).abs() < 1e-12);
        let tukey = Loss::with_scale(LossKind::Tukey, 4.0).expect("scale");
        assert!((tukey.weight(2.0) - 0.5625).abs() < 1e-12);
        assert_eq!(tukey.weight(4.0), 0.0);
        assert_eq!(Loss::default().weight(1e9), 1.0);
        // Weights fall with the residual for every robust loss.
        for kind in [LossKind::Huber, LossKind::Cauchy, LossKind::Tukey] {
            let loss = Loss::new(kind);
            let weights: Vec<f64> = (0..100).map(|u| loss.weight(u as f64 * 0.1)).collect();
            assert!(weights.windows(2).all(|w| w[1] <= w[0]), "{kind}");
            assert!(weights[99] < 0.5, "{kind}");
        }
    }

    #[test]
    fn names_and_scales_are_checked() {
        assert_eq!("Huber".parse::<LossKind>().ok(), Some(LossKind::Huber));
        let unknown = "l1".parse::<LossKind>().expect_err("unknown");
        assert!(
            unknown.to_string().contains("unknown loss 'l1'"),
            "{unknown}"
        );
        assert!(Loss::from_parts(LossKind::L2, Some(2.0)).is_err());
        assert_eq!(
            Loss::from_parts(LossKind::Tukey, None).ok(),
            Some(Loss::new(LossKind::Tukey))
        );
        for scale in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let error = Loss::with_scale(LossKind::Huber, scale).expect_err("bad scale");
            assert!(error.to_string().contains("loss scale"), "{error}");
        }
    }

    #[test]
    fn robust_sigma_ignores_gross_values() {
        let mut sampler = crate::simulation::Sampler::new(5);
        let clean: Vec<f64> = (0..20_000).map(|_| sampler.gaussian(2.0)).collect();
        assert!((robust_sigma(&clean) - 2.0).abs() < 0.05);
        // 10 % gross values move it by less than a fifth.
        let mut dirty = clean.clone();
        for value in dirty.iter_mut().step_by(10) {
            *value += 1e3;
        }
        assert!((robust_sigma(&dirty) - 2.0).abs() < 0.4);
        assert_eq!(robust_sigma(&[]), 0.0);
        // Odd and even counts: the middle value, the mean of the two middle ones.
        let median =
            |values: &[f64]| crate::selection::median_of(values.len(), || values.iter().copied());
        assert_eq!(median(&[5.0, 1.0, 3.0]), 3.0);
        assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), 2.5);
    }
}
