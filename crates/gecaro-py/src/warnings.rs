//! What a job says a user should know, as Python warnings: joints outside
//! their limits as a `LimitWarning` (`strict_limits=True` refuses such data
//! instead).

use std::ffi::CString;

use gecaro_app::{Dialect, Note};
use pyo3::prelude::*;

use crate::errors::{LimitWarning, input};

/// Raises the warnings among `notes` as `LimitWarning`s.
pub(crate) fn warn_notes(py: Python<'_>, notes: &[Note]) -> PyResult<()> {
    for note in notes.iter().filter(|note| note.warning) {
        let message =
            CString::new(note.text(Dialect::Python)).map_err(|error| input(error.to_string()))?;
        PyErr::warn(py, &py.get_type::<LimitWarning>(), &message, 2)?;
    }
    Ok(())
}
