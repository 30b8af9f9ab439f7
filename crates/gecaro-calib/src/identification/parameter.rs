//! One identified parameter: its values and precision, and, for a regrouped
//! base parameter, the combination its deviation stands for (Appendix III).
//! A leaf beneath the result and the verdict, which both read it.

use gecaro_core::ParameterId;

/// An identified base parameter or auxiliary unknown.
#[derive(Clone, Debug, PartialEq)]
pub struct IdentifiedParameter {
    /// Its name (`theta2`, or an auxiliary name such as `a`).
    pub name: String,
    /// The robot parameter; `None` for an auxiliary unknown.
    pub parameter: Option<ParameterId>,
    /// Value before identification (nominal; initial for auxiliary unknowns).
    pub nominal: f64,
    /// Identified value.
    pub identified: f64,
    /// Standard deviation of the identified value (posterior, with a prior):
    /// the uncertainty about the true value.
    pub std: f64,
    /// The part of [`std`](Self::std) that the measurement noise makes: the
    /// spread the estimate would show over repeated measurements of the same
    /// robot. Equal to `std` without a prior; below it for a parameter a
    /// prior holds (or the gauge of an unmeasured scale), whose `std` also
    /// carries the prior's uncertainty about the true value:
    /// `σ_noise² = σ̂² [(WᵀW)⁻¹ − (WᵀW)⁻¹PᵀP(WᵀW)⁻¹]_ii`, P the prior's rows
    /// of W.
    pub noise_std: f64,
    /// Its prior standard deviation, with a prior (regrouping included).
    pub prior_std: Option<f64>,
    /// The parameters this base parameter absorbs, with their coefficients
    /// β (Appendix III's regrouping relations): its deviation then stands
    /// for the combination `Δη_b + Σ β_j Δη_j`, not for the physical
    /// parameter alone. Empty for a physical parameter.
    pub absorbs: Vec<(String, f64)>,
}

impl IdentifiedParameter {
    /// Whether the value is a combination of parameters (see [`Self::absorbs`]).
    pub fn is_regrouped(&self) -> bool {
        !self.absorbs.is_empty()
    }

    /// The combination a regrouped parameter's deviation stands for, as
    /// text (`theta2 + theta3`, `r1 − 0.2·d3`); `None` for a physical one.
    pub fn combination(&self) -> Option<String> {
        if self.absorbs.is_empty() {
            return None;
        }
        let mut text = self.name.clone();
        for (name, coefficient) in &self.absorbs {
            let sign = if *coefficient < 0.0 { '−' } else { '+' };
            let size = coefficient.abs();
            if (size - 1.0).abs() < 1e-9 {
                text.push_str(&format!(" {sign} {name}"));
            } else {
                text.push_str(&format!(" {sign} {}·{name}", format_coefficient(size)));
            }
        }
        Some(text)
    }
}

/// A coefficient of a regrouping relation with 4 significant digits.
fn format_coefficient(value: f64) -> String {
    let text = format!("{value:.4}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    if text == "0" {
        format!("{value:.3e}")
    } else {
        text.to_owned()
    }
}
