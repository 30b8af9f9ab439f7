//! A sensor's σ as Python gives it: a number or a text with its unit, read
//! by the rule of every front end ([`gecaro_io::StandardDeviation`]).

use pyo3::prelude::*;

/// A sensor's σ from Python: a number (metres; radians for orientations) or
/// a text with its unit (`"20um"`, `"0.01deg"`).
#[derive(FromPyObject)]
pub(crate) enum Sigma {
    Number(f64),
    Text(String),
}

impl From<Sigma> for gecaro_io::StandardDeviation {
    fn from(sigma: Sigma) -> Self {
        match sigma {
            Sigma::Number(number) => gecaro_io::StandardDeviation::Number(number),
            Sigma::Text(text) => gecaro_io::StandardDeviation::WithUnit(text),
        }
    }
}
