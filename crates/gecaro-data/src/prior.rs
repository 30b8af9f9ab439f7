//! A Gaussian prior's values on a robot's parameters: one σ per kind
//! (lengths d and r in metres, angles α, θ and β in radians, gains K as a
//! fraction of their nominal value, compliances c absolutely,
//! [`COMPLIANCE_PRIOR`] unless overridden) and per-parameter overrides, as
//! files state them and the identification reads them
//! (`gecaro_calib::identification` states the maths).
//!
//! ```
//! use gecaro_data::prior::Prior;
//!
//! let prior = Prior::new(0.005, 0.5f64.to_radians(), 0.01)?;
//! assert_eq!(prior.sigma("d3".parse().expect("a name"), 0.0), 0.005);
//! # Ok::<(), gecaro_data::prior::PriorError>(())
//! ```

use gecaro_core::{ParameterId, ParameterKind, Robot};

/// The prior σ of a joint's compliance c_j (rad/(N·m), or m/N for a
/// prismatic joint) about its nominal value: ten times the softest joint
/// of an industrial arm (1e-5 rad/(N·m)), so that it holds back only a
/// compliance the data barely see (issue 38).
pub const COMPLIANCE_PRIOR: f64 = 1e-4;

/// A prior that is none: a σ that is not a positive number, or an
/// override naming a parameter the robot lacks or naming one twice.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PriorError(pub String);

impl std::fmt::Display for PriorError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for PriorError {}

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
    /// Unless every σ is finite and positive, naming it.
    pub fn new(length: f64, angle: f64, gain: f64) -> Result<Self, PriorError> {
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
    /// Naming the kind or parameter.
    pub fn check(&self, robot: &Robot) -> Result<(), PriorError> {
        Prior::new(self.length, self.angle, self.gain)?;
        for (position, (id, sigma)) in self.overrides.iter().enumerate() {
            if robot.parameters().index_of(*id).is_none() {
                return Err(PriorError(format!(
                    "the prior names {id}, which {} does not have",
                    robot.name()
                )));
            }
            if self.overrides[..position]
                .iter()
                .any(|(other, _)| other == id)
            {
                return Err(PriorError(format!("the prior gives {id} twice")));
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

fn check_sigma(value: f64, what: impl FnOnce() -> String) -> Result<(), PriorError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(PriorError(format!(
            "{} must be a positive number, not {value}",
            what()
        )))
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
