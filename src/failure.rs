//! Errors as the user sees them, with the exit codes of `docs/errors.md`:
//! 2 usage, 3 bad input (files, values), 4 numerical failure.

use miette::Diagnostic;

/// Exit code for a command line that cannot be understood (clap uses it too).
pub(crate) const EXIT_USAGE: u8 = 2;
/// Exit code for bad input: files, values, names.
pub(crate) const EXIT_INPUT: u8 = 3;
/// Exit code for well-formed input that cannot give a trustworthy answer:
/// too few equations, divergence, an iteration limit, an unreachable target.
pub(crate) const EXIT_NUMERICAL: u8 = 4;

/// A failed command.
#[derive(Debug, thiserror::Error, Diagnostic)]
pub(crate) enum Failure {
    /// A file could not be read, parsed or written.
    #[error(transparent)]
    File(#[from] gecaro_io::Error),
    /// A value breaks a rule of the robot model.
    #[error(transparent)]
    Model(gecaro_core::Error),
    /// Measurements that do not fit the method or the robot.
    #[error("{0}")]
    Input(String),
    /// The inverse model or an identification did not converge.
    #[error("{0}")]
    Numerical(String),
    /// The command line asks for something impossible.
    #[error("{message}")]
    Usage {
        /// What is wrong.
        message: String,
        /// How to fix it.
        #[help]
        help: Option<String>,
    },
}

impl From<gecaro_core::Error> for Failure {
    fn from(error: gecaro_core::Error) -> Self {
        match error {
            gecaro_core::Error::Unreachable { .. } => Failure::Numerical(error.to_string()),
            other => Failure::Model(other),
        }
    }
}

impl From<gecaro_calib::Error> for Failure {
    fn from(error: gecaro_calib::Error) -> Self {
        use gecaro_calib::Error as Calib;
        match error {
            Calib::Model(model) => model.into(),
            Calib::InvalidOption { setting, message } => Failure::usage(
                format!("--{}: {message}", setting.key().replace('_', "-")),
                None,
            ),
            Calib::Generation { .. } | Calib::Numerical { .. } | Calib::TooFewEquations { .. } => {
                Failure::Numerical(error.to_string())
            }
            _ => Failure::Input(error.to_string()),
        }
    }
}

impl From<gecaro_report::Error> for Failure {
    fn from(error: gecaro_report::Error) -> Self {
        Failure::Numerical(error.to_string())
    }
}

impl Failure {
    pub(crate) fn usage(message: impl Into<String>, help: impl Into<Option<String>>) -> Self {
        Failure::Usage {
            message: message.into(),
            help: help.into(),
        }
    }

    pub(crate) fn exit_code(&self) -> u8 {
        match self {
            Failure::Usage { .. } => EXIT_USAGE,
            Failure::File(_) | Failure::Model(_) | Failure::Input(_) => EXIT_INPUT,
            Failure::Numerical(_) => EXIT_NUMERICAL,
        }
    }
}
