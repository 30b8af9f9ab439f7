//! Observability indices of a data set: how well its configurations excite
//! the identifiable parameters, from the singular values σ1 ≥ … ≥ σL of the
//! base columns W_b of the observation matrix (Appendix III).
//!
//! Before the singular values are taken, each column of W_b is multiplied by
//! its parameter's error unit — the unit of `--error-level`: 1 cm for lengths,
//! 1° for angles, 1 % of the value for gains, and [`AUXILIARY_UNIT`] for the
//! methods' own unknowns (plane coefficients) — so that σ is in metres of
//! measurement per unit of parameter error, and parameters of different
//! kinds compare. Rows are weighted by 1/σ of their sensor, as in eq. 10.
//!
//! | index | formula | after | larger is better |
//! |---|---|---|---|
//! | O1 | (σ1⋯σL)^(1/L) / √m | Borm & Menq (1991) | yes |
//! | O2 | σL / σ1 (inverse condition number) | Driels & Pathre (1990) | yes |
//! | O3 | σL (minimum singular value) | Nahvi & Hollerbach (1996) | yes |
//! | O4 | σL² / σ1 (noise amplification index) | Nahvi & Hollerbach (1996) | yes |
//! | O5 | 1 / Σ 1/σi | Sun & Hollerbach (2008) | yes |
//!
//! m is the number of configurations. Maximising O1 is D-optimality,
//! O3 E-optimality, O5 close to A-optimality.

use gecaro_core::ParameterKind;

use crate::simulation::error_unit;

/// The scale of an auxiliary unknown's column: plane coefficients are a unit
/// normal (dimensionless, like radians) and an offset (metres); 0.01 matches
/// 1 cm for the offset and about half a degree for the normal.
pub const AUXILIARY_UNIT: f64 = 0.01;

/// The five observability indices of a W_b (see the module docs).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Observability {
    /// O1 = (σ1⋯σL)^(1/L)/√m.
    pub o1: f64,
    /// O2 = σL/σ1.
    pub o2: f64,
    /// O3 = σL.
    pub o3: f64,
    /// O4 = σL²/σ1.
    pub o4: f64,
    /// O5 = 1/Σ(1/σi).
    pub o5: f64,
}

impl Observability {
    /// The indices of the singular values `values` (any order) of a W_b from
    /// `configurations` configurations. All zero when a singular value is
    /// zero (a rank-deficient W_b observes nothing in some direction), and
    /// when there are no values or configurations.
    pub fn from_singular_values(values: &[f64], configurations: usize) -> Self {
        let zero = Observability {
            o1: 0.0,
            o2: 0.0,
            o3: 0.0,
            o4: 0.0,
            o5: 0.0,
        };
        let largest = values.iter().copied().fold(0.0, f64::max);
        let smallest = values.iter().copied().fold(f64::INFINITY, f64::min);
        let positive = smallest > 0.0; // false for zero and NaN
        if values.is_empty() || configurations == 0 || !positive {
            return zero;
        }
        let count = values.len() as f64;
        let mean_log = values.iter().map(|v| v.ln()).sum::<f64>() / count;
        Observability {
            o1: mean_log.exp() / (configurations as f64).sqrt(),
            o2: smallest / largest,
            o3: smallest,
            o4: smallest * smallest / largest,
            o5: 1.0 / values.iter().map(|v| v.recip()).sum::<f64>(),
        }
    }
}

/// The column scale of a robot parameter of this kind with this value (gains
/// are scaled relative to their value).
pub(crate) fn column_unit(kind: ParameterKind, value: f64) -> f64 {
    match kind {
        ParameterKind::Gain => error_unit(kind) * value.abs().max(f64::MIN_POSITIVE),
        _ => error_unit(kind),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_indices_of_known_singular_values() {
        let indices = Observability::from_singular_values(&[1.0, 4.0, 2.0], 4);
        assert!((indices.o1 - 2.0 / 2.0).abs() < 1e-15);
        assert_eq!(indices.o2, 0.25);
        assert_eq!(indices.o3, 1.0);
        assert_eq!(indices.o4, 0.25);
        assert!((indices.o5 - 1.0 / 1.75).abs() < 1e-15);
        let rank_deficient = Observability::from_singular_values(&[3.0, 0.0], 10);
        assert_eq!(rank_deficient.o1, 0.0);
        assert_eq!(rank_deficient.o5, 0.0);
        assert_eq!(Observability::from_singular_values(&[], 10).o3, 0.0);
    }
}
