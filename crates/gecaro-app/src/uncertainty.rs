//! What an identification's covariance says, in the forms people look at:
//! the correlation matrix of the identified unknowns (a heatmap), and the
//! covariance of each named frame's position (its uncertainty ellipsoid),
//! from [`Identification::correlation`] and
//! [`Identification::frame_position_covariance`] (eq. 11's covariance;
//! metres and radians).

use std::collections::BTreeMap;

use gecaro_calib::identification::Identification;
use serde::Serialize;

/// The correlation matrix of an identification's unknowns.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Correlation {
    /// The unknowns, in the covariance's order: auxiliary (named frames'
    /// `NAME.x` …), then the base parameters.
    pub names: Vec<String>,
    /// Row by row, `names.len()` × `names.len()`, symmetric, 1 on the diagonal.
    pub values: Vec<Vec<f64>>,
}

/// The correlation matrix of `result`'s unknowns, or `None` without a
/// covariance (W_bᵀW_b not positive definite).
pub fn correlation(result: &Identification) -> Option<Correlation> {
    let matrix = result.correlation()?;
    Some(Correlation {
        names: result
            .unknown_names()
            .into_iter()
            .map(String::from)
            .collect(),
        values: matrix
            .row_iter()
            .map(|row| row.iter().copied().collect())
            .collect(),
    })
}

/// Each named frame's origin covariance (m², row by row), by its name:
/// its uncertainty ellipsoid (frames whose origin was not identified are
/// left out).
pub fn frame_covariances(result: &Identification) -> BTreeMap<String, [[f64; 3]; 3]> {
    result
        .frames
        .iter()
        .filter_map(|frame| {
            let block = result.frame_position_covariance(&frame.name)?;
            Some((
                frame.name.clone(),
                [0, 1, 2].map(|i| [0, 1, 2].map(|j| block[(i, j)])),
            ))
        })
        .collect()
}
