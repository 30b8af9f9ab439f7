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

use gecaro_core::{ParameterId, ParameterKind, Robot};

use crate::Error;
use crate::error::Setting;
use crate::identifiability::Relation;

/// The prior σ of a joint's compliance c_j (rad/(N·m), or m/N for a
/// prismatic joint) about its nominal value: ten times the softest joint
/// of an industrial arm (1e-5 rad/(N·m)), so that it holds back only a
/// compliance the data barely see (issue 38).
pub const COMPLIANCE_PRIOR: f64 = 1e-4;

/// A Gaussian prior; see the module docs.
#[derive(Clone, Debug, PartialEq)]
pub struct Prior {
    /// σ of lengths (d, r), metres.
    pub length: f64,
    /// σ of angles (α, θ, β), radians.
    pub angle: f64,
    /// σ of gains K, as a fraction of the nominal gain (0.01 for 1 %).
    pub gain: f64,
    /// Per-parameter σ, in the same units as its kind's (overrides the kind's).
    pub overrides: Vec<(ParameterId, f64)>,
}

impl Prior {
    /// A prior with one σ per kind and no overrides.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] (`--prior`) unless every σ is finite and positive.
    pub fn new(length: f64, angle: f64, gain: f64) -> Result<Self, Error> {
        let prior = Prior {
            length,
            angle,
            gain,
            overrides: Vec::new(),
        };
        for (what, value) in [("length", length), ("angle", angle), ("gain", gain)] {
            check_sigma(value, || format!("the {what} σ"))?;
        }
        Ok(prior)
    }

    /// Checks the prior against `robot`: finite positive σ per kind, and
    /// overrides that each name a parameter of it, once, with a finite
    /// positive σ.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] (`--prior`) naming the kind or parameter.
    pub fn check(&self, robot: &Robot) -> Result<(), Error> {
        Prior::new(self.length, self.angle, self.gain)?;
        for (position, (id, sigma)) in self.overrides.iter().enumerate() {
            if robot.parameters().index_of(*id).is_none() {
                return Err(Error::InvalidOption {
                    setting: Setting::Prior,
                    message: format!("the prior names {id}, which {} does not have", robot.name()),
                });
            }
            if self.overrides[..position]
                .iter()
                .any(|(other, _)| other == id)
            {
                return Err(Error::InvalidOption {
                    setting: Setting::Prior,
                    message: format!("the prior gives {id} twice"),
                });
            }
            check_sigma(*sigma, || format!("the σ of {id}"))?;
        }
        Ok(())
    }

    /// The prior σ of parameter `id` alone (absolute: metres or radians, or
    /// gain units), whose nominal value is `nominal`.
    pub fn sigma(&self, id: ParameterId, nominal: f64) -> f64 {
        let relative = self
            .overrides
            .iter()
            .find(|(other, _)| *other == id)
            .map(|(_, sigma)| *sigma);
        match id.kind {
            ParameterKind::D | ParameterKind::R => relative.unwrap_or(self.length),
            ParameterKind::Alpha
            | ParameterKind::Theta
            | ParameterKind::Beta
            | ParameterKind::GravityTilt => relative.unwrap_or(self.angle),
            ParameterKind::Gain => {
                relative.unwrap_or(self.gain) * nominal.abs().max(f64::MIN_POSITIVE)
            }
            ParameterKind::Compliance => relative.unwrap_or(COMPLIANCE_PRIOR),
        }
    }

    /// The prior σ of a base parameter that regroups others (see the module
    /// docs): `√(σ_b² + Σ β_j² σ_j²)` over its relation, if it has one.
    pub fn base_sigma(&self, robot: &Robot, id: ParameterId, relations: &[Relation]) -> f64 {
        let own = self.sigma(id, robot.parameter(id));
        let name = id.to_string();
        let absorbed: f64 = relations
            .iter()
            .filter(|relation| relation.base == name)
            .flat_map(|relation| &relation.absorbed)
            .filter_map(|(other, coefficient)| {
                let other: ParameterId = other.parse().ok()?;
                Some((coefficient * self.sigma(other, robot.parameter(other))).powi(2))
            })
            .sum();
        (own * own + absorbed).sqrt()
    }
}

/// `5 mm, 0.5°, 1 %` (and how many parameters have their own σ), as
/// people write a prior.
impl std::fmt::Display for Prior {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} mm, {}°, {} %",
            self.length * 1e3,
            self.angle.to_degrees(),
            self.gain * 1e2
        )?;
        match self.overrides.len() {
            0 => Ok(()),
            1 => write!(f, ", 1 parameter with its own σ"),
            count => write!(f, ", {count} parameters with their own σ"),
        }
    }
}

fn check_sigma(value: f64, what: impl FnOnce() -> String) -> Result<(), Error> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(Error::InvalidOption {
            setting: Setting::Prior,
            message: format!("{} must be a positive number, not {value}", what()),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sigmas_by_kind_and_override() {
        let robot = Robot::template("arm", "RRPRRR").expect("template");
        let mut prior = Prior::new(0.005, 0.01, 0.02).expect("prior");
        let id = |name: &str| name.parse::<ParameterId>().expect("name");
        assert_eq!(prior.sigma(id("d3"), 0.0), 0.005);
        assert_eq!(prior.sigma(id("theta2"), 0.0), 0.01);
        assert!((prior.sigma(id("K1"), 2.0) - 0.04).abs() < 1e-15);
        prior.overrides.push((id("d3"), 0.001));
        assert_eq!(prior.sigma(id("d3"), 0.0), 0.001);
        prior.check(&robot).expect("valid");
        assert_eq!(
            prior.to_string(),
            "5 mm, 0.5729577951308232°, 2 %, 1 parameter with its own σ"
        );
        // A regrouped base parameter carries its partners' prior.
        let relations = [Relation {
            base: "d3".into(),
            absorbed: vec![("r2".into(), -1.0)],
        }];
        let combined = prior.base_sigma(&robot, id("d3"), &relations);
        assert!((combined - (0.001_f64.powi(2) + 0.005_f64.powi(2)).sqrt()).abs() < 1e-15);
    }

    #[test]
    fn bad_priors_are_named() {
        assert!(Prior::new(-1.0, 0.01, 0.01).is_err());
        assert!(Prior::new(0.001, f64::NAN, 0.01).is_err());
        let robot = Robot::template("arm", "RRPRRR").expect("template");
        let mut prior = Prior::new(0.005, 0.01, 0.02).expect("prior");
        prior.overrides.push(("d9".parse().expect("name"), 0.001));
        let error = prior.check(&robot).expect_err("no d9");
        assert!(error.to_string().contains("d9"), "{error}");
        prior.overrides = vec![("d3".parse().expect("name"), 0.0)];
        assert!(prior.check(&robot).is_err());
    }
}
