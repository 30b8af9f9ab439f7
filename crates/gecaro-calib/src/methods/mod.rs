//! The seven calibration methods of paper §3, as observation models.
//!
//! Every method is the paper's eq. 5, `0 = f(q, X, η)`, linearised as eq. 6,
//! `Δy = Ψ Δη`: given the current parameters it writes the residuals Δy and the
//! rows of W for a data set ([`CalibrationMethod::linearise`]), and it can
//! generate configurations that satisfy its constraint
//! ([`Sensor::generate`]). Identifiability, identification and
//! points generation are written once against this trait.
//!
//! | name | method | rows | paper |
//! |---|---|---|---|
//! | `position` | position measure | 3 per configuration | eq. 7, rows 1–3 |
//! | `frame` | frame (location) measure | 6 per configuration | eq. 7 |
//! | `point-link` | point link | 3 per configuration | eq. 12, rows 1–3 |
//! | `frame-link` | frame link | 6 per configuration | eq. 12 |
//! | `plane1` | plane link 1, plane equation | 1 per configuration | eq. 15 |
//! | `plane2` | plane link 2, plane normal | 1 per configuration | eq. 17 |
//! | `distance` | distance measure | 1 per pair | eq. 19–20 |
//!
//! Link and plane-normal equations hold between configurations. Instead of
//! one reference pair per configuration, each configuration is compared with
//! the mean of its set: `(J_i − J̄)Δη = −(y_i − ȳ)`. Since
//! `Σ_{i<j} ‖e_i − e_j‖² = k·Σ_i ‖e_i − ē‖²` for a set of k, this is eq. 12
//! (or 17) written for *every* pair of the set at once, in k rows instead of
//! k(k−1)/2, and it treats every configuration alike. The centring uses up one
//! equation per set and per dimension ([`CalibrationMethod::dependent_rows`]).
//!
//! To add an eighth method: write one file with a type implementing
//! [`CalibrationMethod`] and its [`MethodInfo`], and list it in [`METHODS`].
//! Two provided methods only make it faster and are safe to leave alone:
//! [`jacobian_rows`](CalibrationMethod::jacobian_rows) (say
//! [`JacobianRows::Position`](gecaro_core::JacobianRows::Position) when no orientation row is read) and
//! [`independent_configurations`](CalibrationMethod::independent_configurations)
//! (rows of one configuration depend on it alone: evaluated and written in
//! parallel blocks). A method whose `generate_like` reads the data's poses
//! without having auxiliary unknowns must say so in
//! [`uses_starting_poses`](CalibrationMethod::uses_starting_poses).

mod distance;
mod frame;
mod link;
mod link_methods;
mod plane;
mod plane_equation;
mod plane_normal;
mod position;
mod readings;
mod sets;

use crate::error::Error;
use crate::sample::DataColumn;
use crate::samples::SampleSlice;

pub use crate::method::{CalibrationMethod, CloneMethod, MethodInfo, MethodOptions, Sensor};
pub use crate::plane::Plane;

/// The seven methods, in the order of the paper's menus.
pub const METHODS: &[MethodInfo] = &[
    position::INFO,
    frame::INFO,
    link_methods::POINT_LINK,
    link_methods::FRAME_LINK,
    plane_equation::INFO,
    plane_normal::INFO,
    distance::INFO,
];

/// The method called `name`, built with `options`.
///
/// # Errors
/// [`Error::UnknownMethod`] (listing the methods) or the method's option errors.
pub fn method(name: &str, options: &MethodOptions) -> Result<Box<dyn CalibrationMethod>, Error> {
    method_info(name)?.build(options)
}

/// The registry entry of the method called `name`.
///
/// # Errors
/// [`Error::UnknownMethod`] listing the methods.
pub fn method_info(name: &str) -> Result<&'static MethodInfo, Error> {
    METHODS
        .iter()
        .find(|info| info.name == name)
        .ok_or_else(|| Error::UnknownMethod {
            name: name.to_owned(),
            available: METHODS.iter().map(|info| info.name).collect(),
        })
}

/// Whether `method` groups its samples (sets of link methods, pairs of
/// distances): its units are then those groups, else single samples.
pub fn grouped(method: &dyn CalibrationMethod) -> bool {
    method
        .data_columns()
        .iter()
        .any(|c| matches!(c, DataColumn::Set | DataColumn::Pair))
}

/// The units of `samples` for `method`: the sample indices of each set or
/// pair (link and distance methods, grouped as the methods group them, in
/// order of first appearance), single samples otherwise.
pub fn units(method: &dyn CalibrationMethod, samples: SampleSlice<'_>) -> Vec<Vec<usize>> {
    if grouped(method) {
        sets::groups(samples)
    } else {
        (0..samples.len()).map(|index| vec![index]).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_methods_list_the_seven() {
        let error = method("plane3", &MethodOptions::default()).expect_err("no such method");
        let message = error.to_string();
        for info in METHODS {
            assert!(message.contains(info.name), "{message}");
        }
        assert_eq!(METHODS.len(), 7);
    }
}
