//! A split the data cannot make: two parameters whose columns are nearly
//! the same, told apart only by a lever far below the noise.
//!
//! A tool point 0.3–0.6 mm off axis n makes θ_n (the joint's zero) and
//! θ_{n+1} (the tool's turn about its axis) two parameters at the nominal
//! geometry, so the base set keeps both; the data tell them apart only
//! through that lever (ρ = −1.000, condition number 5.5·10⁵). Their sum is
//! determined, their split drifts with the noise and the model error, and
//! "implausible" fired or not by chance. So when two identified parameters
//! correlate beyond [`SPLIT_CORRELATION`] and both are known to no better
//! than [`UNDETERMINED_ANGLE`] (angles) or [`UNDETERMINED_LENGTH`]
//! (lengths), the one of lower priority (the later column) is held at its
//! stated value and the study identified again: its effect is carried by
//! the other, as a regrouping would. The refit is kept when it converges
//! and explains the data as well (its sum of squares within a 1 % F test
//! of the original), and a warning names the pair.

use gecaro_core::{ParameterId, ParameterKind};

use super::result::Identification;

/// Correlation beyond which two parameters are one direction of the data.
pub const SPLIT_CORRELATION: f64 = 0.9999;

/// An angle known to no better than this (rad, 1°) is undetermined.
pub const UNDETERMINED_ANGLE: f64 = 0.0175;

/// A length known to no better than this (m) is undetermined.
pub const UNDETERMINED_LENGTH: f64 = 0.01;

/// The parameter to hold when `result` splits a pair the data cannot tell
/// apart (module docs), with the pair's words; `None` otherwise.
pub(super) fn undetermined_split(result: &Identification) -> Option<(ParameterId, String)> {
    let undetermined = |name: &str| {
        result
            .parameters
            .iter()
            .find(|p| p.name == name)
            .is_some_and(|p| {
                let Some(id) = p.parameter else { return false };
                let limit = match id.kind {
                    ParameterKind::Alpha | ParameterKind::Theta | ParameterKind::Beta => {
                        UNDETERMINED_ANGLE
                    }
                    ParameterKind::D | ParameterKind::R => UNDETERMINED_LENGTH,
                    _ => return false,
                };
                !p.std.is_finite() || p.std > limit
            })
    };
    let (kept, held, rho) = result
        .correlated
        .iter()
        .find(|(a, b, rho)| rho.abs() > SPLIT_CORRELATION && undetermined(a) && undetermined(b))?;
    let id: ParameterId = held.parse().ok()?;
    let std = result
        .parameters
        .iter()
        .find(|p| &p.name == held)
        .map_or(f64::NAN, |p| p.std);
    Some((
        id,
        format!(
            "{kept} and {held} are one direction of these data (ρ = {rho:+.4}; their split known \
             to ±{std:.2e} only): {held} was held at its stated value and {kept} carries their \
             sum, as a regrouping would"
        ),
    ))
}
