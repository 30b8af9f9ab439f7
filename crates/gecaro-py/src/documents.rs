//! The JSON documents of the results as Python objects (dicts, lists,
//! floats), converted directly by pythonize; and as JSON text.

use pyo3::prelude::*;
use serde::Serialize;

use crate::errors::input;

/// `value` as Python objects: what `json.loads` of its JSON gives, but for
/// non-finite numbers, which stay floats (`nan`) instead of `None`.
pub(crate) fn to_python<'py>(
    py: Python<'py>,
    value: &impl Serialize,
) -> PyResult<Bound<'py, PyAny>> {
    pythonize::pythonize(py, value).map_err(|error| input(error.to_string()))
}

/// `value` as JSON text, as the command line's `--json` prints it.
pub(crate) fn to_json(value: &impl Serialize) -> PyResult<String> {
    serde_json::to_string_pretty(value).map_err(|error| input(error.to_string()))
}
