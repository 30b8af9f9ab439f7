//! Errors as the user of the command line sees them, with the exit codes of
//! `docs/errors.md`: 2 usage, 3 bad input (files, values), 4 numerical
//! failure. Every error is an [`AppError`] worded for the command line.

use gecaro_app::{AppError, Dialect, ErrorKind};

/// Exit code for a command line that cannot be understood (clap uses it too).
pub(crate) const EXIT_USAGE: u8 = 2;
/// Exit code for bad input: files, values, names.
pub(crate) const EXIT_INPUT: u8 = 3;
/// Exit code for well-formed input that cannot give a trustworthy answer:
/// too few equations, divergence, an iteration limit, an unreachable target.
pub(crate) const EXIT_NUMERICAL: u8 = 4;
/// A result written but not trusted by the verdict (residuals beyond or far
/// below the stated noise, implausible values, data that do not determine the
/// robot, a scale or tool not measured).
pub(crate) const EXIT_UNTRUSTED: u8 = 5;
/// Exit code of a command stopped by Ctrl-C (128 + SIGINT).
pub(crate) const EXIT_INTERRUPTED: u8 = 130;

/// A failed command.
#[derive(Debug)]
pub(crate) struct Failure(AppError);

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        // Names from files reach the terminal escaped, never raw.
        f.write_str(&crate::format::shown_lines(
            &self.0.message(Dialect::CommandLine),
        ))
    }
}

impl std::error::Error for Failure {}

impl miette::Diagnostic for Failure {
    fn help<'a>(&'a self) -> Option<Box<dyn std::fmt::Display + 'a>> {
        self.0.help(Dialect::CommandLine).map(|help| {
            Box::new(crate::format::shown_lines(&help.to_string()).into_owned())
                as Box<dyn std::fmt::Display>
        })
    }
}

impl From<AppError> for Failure {
    fn from(error: AppError) -> Self {
        Failure(error)
    }
}

impl From<gecaro_io::Error> for Failure {
    fn from(error: gecaro_io::Error) -> Self {
        Failure(error.into())
    }
}

impl From<gecaro_core::Error> for Failure {
    fn from(error: gecaro_core::Error) -> Self {
        Failure(error.into())
    }
}

impl From<gecaro_calib::Error> for Failure {
    fn from(error: gecaro_calib::Error) -> Self {
        Failure(error.into())
    }
}

impl From<gecaro_report::Error> for Failure {
    fn from(error: gecaro_report::Error) -> Self {
        Failure(error.into())
    }
}

impl Failure {
    /// A command line asking for something impossible, with advice.
    pub(crate) fn usage(message: impl Into<String>, help: impl Into<Option<String>>) -> Self {
        let error = AppError::plain(ErrorKind::Usage, message);
        Failure(match help.into() {
            Some(help) => error.with_advice(help),
            None => error,
        })
    }

    /// Bad input.
    pub(crate) fn input(message: impl Into<String>) -> Self {
        Failure(AppError::plain(ErrorKind::Input, message))
    }

    /// Well-formed input without a trustworthy answer.
    pub(crate) fn numerical(message: impl Into<String>) -> Self {
        Failure(AppError::plain(ErrorKind::Numerical, message))
    }

    /// The exit code of `docs/errors.md`.
    pub(crate) fn exit_code(&self) -> u8 {
        match self.0.kind() {
            ErrorKind::Usage => EXIT_USAGE,
            ErrorKind::NotIdentifiable
            | ErrorKind::NotConverged
            | ErrorKind::Numerical
            | ErrorKind::Internal => EXIT_NUMERICAL,
            ErrorKind::Interrupted => EXIT_INTERRUPTED,
            ErrorKind::Untrusted => EXIT_UNTRUSTED,
            _ => EXIT_INPUT,
        }
    }
}
