//! The warnings of an identification beyond its verdict: poor excitation,
//! strongly correlated parameters, an unobserved scale, parameters moved
//! outside the base set (see [`super::Identification::warnings`]).

use super::parameter::IdentifiedParameter;
use crate::linalg::NormalEquations;

/// Above this condition number of W_b the data are called poorly exciting.
pub const POOR_CONDITIONING: f64 = 1e4;

/// Above this |ρ| two identified parameters are named as strongly
/// correlated ([`Identification::correlated`](super::Identification::correlated); FIGAROH lists such pairs too).
pub const STRONG_CORRELATION: f64 = 0.95;

/// The correlation warning holds these words.
pub(super) const CORRELATED_WARNING: &str = "strongly correlated";

/// A set-up warning ([`RankReport::set_up_warnings`](crate::identifiability::RankReport::set_up_warnings)) holds these words.
pub(super) const SET_UP_WARNING: &str = "turns about the measured point";

/// The warning that the data's W_b is poorly conditioned starts so.
pub(super) const POOR_EXCITATION: &str = "the data excite the robot poorly";

/// The warning that names strongly correlated pairs (none without them).
pub(super) fn correlation_warning(correlated: &[(String, String, f64)]) -> Option<String> {
    if correlated.is_empty() {
        return None;
    }
    let listed: Vec<String> = correlated
        .iter()
        .take(5)
        .map(|(a, b, rho)| format!("{a}–{b} ({rho:+.3})"))
        .collect();
    Some(format!(
        "{} pair{} of parameters {} {CORRELATED_WARNING} (|ρ| > {STRONG_CORRELATION}): {}{}; \
         the data tell each pair apart poorly, and their errors compensate each other",
        correlated.len(),
        if correlated.len() == 1 { "" } else { "s" },
        if correlated.len() == 1 { "is" } else { "are" },
        listed.join(", "),
        if correlated.len() > 5 { ", …" } else { "" }
    ))
}

/// The pairs of columns (named `names`, in column order) whose estimates
/// correlate beyond [`STRONG_CORRELATION`], strongest first (none when the
/// normal equations are not positive definite).
pub(super) fn strongly_correlated(
    normal: &NormalEquations,
    names: &[&str],
) -> Vec<(String, String, f64)> {
    let Some(correlations) = normal.correlations() else {
        return Vec::new();
    };
    let n = names.len();
    let mut pairs: Vec<(String, String, f64)> = (0..n)
        .flat_map(|i| ((i + 1)..n).map(move |j| (i, j)))
        .filter_map(|(i, j)| {
            let rho = correlations.get(i * n + j).copied()?;
            (rho.abs() > STRONG_CORRELATION)
                .then(|| (names[i].to_owned(), names[j].to_owned(), rho))
        })
        .collect();
    pairs.sort_by(|a, b| b.2.abs().total_cmp(&a.2.abs()));
    pairs
}

/// The warnings of an identification (see [`Identification::warnings`](super::Identification::warnings))
/// beyond the set-up's ([`RankReport::set_up_warnings`](crate::identifiability::RankReport::set_up_warnings)).
pub(super) fn warnings_of(
    not_excited: &[String],
    condition_number: f64,
    parameters: &[IdentifiedParameter],
    moved: &[IdentifiedParameter],
) -> Vec<String> {
    let mut warnings = Vec::new();
    if !not_excited.is_empty() {
        warnings.push(format!(
            "the data do not excite {}: not identified, left at their nominal values",
            not_excited.join(", ")
        ));
    }
    if condition_number > POOR_CONDITIONING {
        let mut relative: Vec<(&IdentifiedParameter, f64)> = parameters
            .iter()
            .map(|p| {
                (
                    p,
                    p.std / (p.identified.abs() + if p.name.starts_with('K') { 1.0 } else { 1e-3 }),
                )
            })
            .collect();
        relative.sort_by(|a, b| b.1.total_cmp(&a.1));
        let worst: Vec<String> = relative
            .iter()
            .take(3)
            .map(|(p, _)| format!("{} (σ {:.1e})", p.name, p.std))
            .collect();
        warnings.push(format!(
            "{POOR_EXCITATION}: condition number of W_b {condition_number:.1e} (above {POOR_CONDITIONING:.0e}); \
             the least determined parameters are {}; add configurations that move these joints more",
            worst.join(", ")
        ));
    }
    if !moved.is_empty() {
        warnings.push(format!(
            "{} parameters outside the base set were moved too: with them at nominal, the base set (chosen at \
             the nominal geometry) cannot reproduce these data",
            moved.len()
        ));
    }
    warnings
}
