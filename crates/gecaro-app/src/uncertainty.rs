//! What an identification's covariance says, in the forms people look at:
//! the correlation matrix of the identified unknowns (a heatmap), and the
//! covariance of each named frame's position (its uncertainty ellipsoid).
//!
//! The covariance is eq. 11's `σ² (W_bᵀW_b)⁻¹`, rows and columns in the
//! order of the auxiliary unknowns, then the base parameters
//! ([`Identification::covariance`]); its units are metres and radians. The
//! correlation of unknowns `i` and `j` is `C_ij / √(C_ii C_jj)`, in
//! [−1, 1]; an unknown of zero variance (none is) would give 0.

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
    let covariance = result.covariance.as_ref()?;
    let names: Vec<String> = result
        .auxiliary
        .iter()
        .chain(&result.parameters)
        .map(|p| p.name.clone())
        .collect();
    let count = covariance.nrows();
    if names.len() != count {
        return None;
    }
    let scale: Vec<f64> = (0..count)
        .map(|i| covariance[(i, i)].max(0.0).sqrt())
        .collect();
    let values = (0..count)
        .map(|i| {
            (0..count)
                .map(|j| {
                    let denominator = scale[i] * scale[j];
                    if denominator > 0.0 {
                        (covariance[(i, j)] / denominator).clamp(-1.0, 1.0)
                    } else {
                        0.0
                    }
                })
                .collect()
        })
        .collect();
    Some(Correlation { names, values })
}

/// The covariance (m²) of named frame `frame`'s identified origin — its
/// unknowns `FRAME.x`, `FRAME.y`, `FRAME.z` — row by row; `None` when one
/// of them was not identified or there is no covariance.
pub fn position_covariance(result: &Identification, frame: &str) -> Option<[[f64; 3]; 3]> {
    let covariance = result.covariance.as_ref()?;
    let index = |axis: &str| {
        let name = format!("{frame}.{axis}");
        result.auxiliary.iter().position(|p| p.name == name)
    };
    let indices = [index("x")?, index("y")?, index("z")?];
    let mut block = [[0.0; 3]; 3];
    for (row, &i) in indices.iter().enumerate() {
        for (column, &j) in indices.iter().enumerate() {
            block[row][column] = covariance[(i, j)];
        }
    }
    Some(block)
}
