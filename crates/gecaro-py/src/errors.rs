//! Library errors as Python exceptions (`gecaro.errors`): the same message as
//! the command line prints, in the class that says what kind of failure it is.
//!
//! | library error | Python exception |
//! |---|---|
//! | files, robot model, data, options | `InputError` (a `ValueError`) |
//! | too few independent equations | `NotIdentifiableError` |
//! | unreachable target, failed points generation, no convergence | `NotConvergedError` |
//! | a failed factorisation or plot | `NumericalError` |
//! | a progress hook stopped the work (Ctrl-C) | the `KeyboardInterrupt` raised by Python |

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

/// Conversion of the library's errors.
pub(crate) trait ToPyErr {
    /// The Python exception of this error.
    fn to_py(self) -> PyErr;
}

impl ToPyErr for gecaro_io::Error {
    fn to_py(self) -> PyErr {
        match self {
            gecaro_io::Error::OutputExists { path } => input(format!(
                "{} already exists (pass overwrite=True to replace it)",
                path.display()
            )),
            other => input(other.to_string()),
        }
    }
}

impl ToPyErr for gecaro_core::Error {
    fn to_py(self) -> PyErr {
        match self {
            gecaro_core::Error::Unreachable { .. } => NotConvergedError::new_err(self.to_string()),
            other => input(other.to_string()),
        }
    }
}

impl ToPyErr for gecaro_calib::Error {
    fn to_py(self) -> PyErr {
        use gecaro_calib::Error as Calib;
        match self {
            Calib::Model(model) => model.to_py(),
            Calib::TooFewEquations { .. } => NotIdentifiableError::new_err(self.to_string()),
            Calib::Generation { .. } => NotConvergedError::new_err(self.to_string()),
            Calib::Numerical { .. } => NumericalError::new_err(self.to_string()),
            Calib::Interrupted => pyo3::exceptions::PyKeyboardInterrupt::new_err("interrupted"),
            other => input(other.to_string()),
        }
    }
}

impl ToPyErr for gecaro_report::Error {
    fn to_py(self) -> PyErr {
        NumericalError::new_err(self.to_string())
    }
}

/// `result.map_err(ToPyErr::to_py)`, shorter.
pub(crate) trait IntoPyResult<T> {
    /// The result with a Python exception.
    fn py(self) -> PyResult<T>;
}

impl<T, E: ToPyErr> IntoPyResult<T> for Result<T, E> {
    fn py(self) -> PyResult<T> {
        self.map_err(ToPyErr::to_py)
    }
}
