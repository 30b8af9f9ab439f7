//! A Gaussian prior on the robot's parameters: physical values stay physical.
//!
//! Each parameter η_k is believed to lie near its nominal value with standard
//! deviation σ_k: one σ per kind (lengths d and r in metres, angles α, θ and
//! β in radians, gains K as a fraction of their nominal value, compliances
//! c absolutely, [`COMPLIANCE_PRIOR`] unless overridden), with
//! per-parameter overrides. The identification then maximises the posterior
//! instead of the likelihood (maximum a posteriori): it minimises
//! `Σ (r_i/σ_s)² + Σ_k ((η_k − η_k,nominal)/σ_k)²`, that is eq. 10 with one
//! pseudo-observation row per identified parameter, and reports the posterior
//! σ, `√diag((W_bᵀW_b/σ̂² + Σ_p⁻¹)⁻¹)`. A parameter the data excite well
//! (its data σ far below σ_k) is not moved by its prior; one they barely
//! excite stays within a few σ_k of nominal instead of running away.
//!
//! ## Regrouped parameters
//!
//! The identified parameters are the base set of Appendix III: a base
//! parameter that absorbs others (`d3 + r2`, say) stands for their linear
//! combination `η_b + Σ_j β_j η_j`, the others being held at nominal. Its
//! prior is the prior of that combination: independent Gaussian priors give
//! `σ_b² = σ_k² + Σ_j β_j² σ_j²`, with the regrouping coefficients β_j of
//! [`RankReport::relations`](crate::identifiability::RankReport::relations) (on the data at the nominal robot).
//! Parameters the data do not excite are not identified and keep their
//! nominal value, which is also their prior mean. The auxiliary unknowns
//! (plane coefficients) have no prior.
//!
//! ## Noise scale
//!
//! The prior's rows are weighed against the data by the data's residual σ̂
//! (a posteriori, from the weighted residuals, re-estimated with the fit),
//! so that a study whose sets carry no sensor σ (weight 1, metres) is treated
//! as one whose sets do.

use gecaro_core::{ParameterId, Robot};

pub use gecaro_data::prior::{COMPLIANCE_PRIOR, Prior, PriorError};

use crate::Error;
use crate::error::Setting;
use crate::identifiability::Relation;

impl From<PriorError> for Error {
    fn from(error: PriorError) -> Self {
        Error::InvalidOption {
            setting: Setting::Prior,
            message: error.0,
        }
    }
}

/// The prior σ of a base parameter that regroups others (see the module
/// docs): `√(σ_b² + Σ β_j² σ_j²)` over its relation, if it has one.
pub(crate) fn base_sigma(
    prior: &Prior,
    robot: &Robot,
    id: ParameterId,
    relations: &[Relation],
) -> f64 {
    let own = prior.sigma(id, robot.parameter(id));
    let name = id.to_string();
    let absorbed: f64 = relations
        .iter()
        .filter(|relation| relation.base == name)
        .flat_map(|relation| &relation.absorbed)
        .filter_map(|(other, coefficient)| {
            let other: ParameterId = other.parse().ok()?;
            Some((coefficient * prior.sigma(other, robot.parameter(other))).powi(2))
        })
        .sum();
    (own * own + absorbed).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A regrouped base parameter carries its partners' prior.
    #[test]
    fn a_base_parameter_carries_its_partners_prior() {
        let robot = Robot::template("arm", "RRPRRR").expect("template");
        let mut prior = Prior::new(0.005, 0.01, 0.02).expect("prior");
        let id = |name: &str| name.parse::<ParameterId>().expect("name");
        prior.overrides.push((id("d3"), 0.001));
        let relations = [Relation {
            base: "d3".into(),
            absorbed: vec![("r2".into(), -1.0)],
        }];
        let combined = base_sigma(&prior, &robot, id("d3"), &relations);
        assert!((combined - (0.001_f64.powi(2) + 0.005_f64.powi(2)).sqrt()).abs() < 1e-15);
        let error: Error = Prior::new(-1.0, 0.01, 0.01).expect_err("no σ").into();
        assert!(matches!(
            error,
            Error::InvalidOption {
                setting: Setting::Prior,
                ..
            }
        ));
    }
}
