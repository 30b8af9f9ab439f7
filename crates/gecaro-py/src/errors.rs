//! Errors as Python exceptions (`gecaro.errors`): the application layer's
//! error in Python's words (`error_level=`, `overwrite=True`), in the class
//! that says what kind of failure it is.
//!
//! | kind | Python exception |
//! |---|---|
//! | files, robot model, data, settings | `InputError` (a `ValueError`) |
//! | too few independent equations | `NotIdentifiableError` |
//! | unreachable target, failed points generation, no convergence | `NotConvergedError` |
//! | a numerical failure, a plot that cannot be drawn | `NumericalError` |
//! | a progress hook stopped the work (Ctrl-C) | the `KeyboardInterrupt` raised by Python |

use gecaro_app::{AppError, Dialect, ErrorKind};
use pyo3::prelude::*;

pyo3::import_exception!(gecaro.errors, InputError);
pyo3::import_exception!(gecaro.errors, NumericalError);
pyo3::import_exception!(gecaro.errors, NotIdentifiableError);
pyo3::import_exception!(gecaro.errors, NotConvergedError);
pyo3::import_exception!(gecaro.errors, LimitWarning);

/// An `InputError` with this message.
pub(crate) fn input(message: impl Into<String>) -> PyErr {
    InputError::new_err(message.into())
}

/// The Python exception of an application error.
pub(crate) fn to_py(error: AppError) -> PyErr {
    let message = match error.help(Dialect::Python) {
        Some(help) => format!("{} ({help})", error.message(Dialect::Python)),
        None => error.message(Dialect::Python),
    };
    match error.kind() {
        ErrorKind::NotIdentifiable => NotIdentifiableError::new_err(message),
        ErrorKind::NotConverged => NotConvergedError::new_err(message),
        ErrorKind::Numerical | ErrorKind::Internal | ErrorKind::Untrusted => {
            NumericalError::new_err(message)
        }
        ErrorKind::Interrupted => pyo3::exceptions::PyKeyboardInterrupt::new_err(message),
        _ => InputError::new_err(message),
    }
}

/// `result.map_err(to_py)`, shorter, for every error the application layer
/// words.
pub(crate) trait IntoPyResult<T> {
    /// The result with a Python exception.
    fn py(self) -> PyResult<T>;
}

impl<T, E: Into<AppError>> IntoPyResult<T> for Result<T, E> {
    fn py(self) -> PyResult<T> {
        self.map_err(|error| to_py(error.into()))
    }
}
