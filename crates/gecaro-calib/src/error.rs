//! The one error type of `gecaro-calib`.

/// Errors of the calibration methods, identifiability and identification.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// An error of the robot model or the kinematics.
    #[error(transparent)]
    Model(#[from] gecaro_core::Error),
    /// No method has this name.
    #[error("unknown method `{name}`; the methods are: {}", .available.join(", "))]
    UnknownMethod {
        /// The name as given.
        name: String,
        /// The method names.
        available: Vec<&'static str>,
    },
    /// A method option is missing or impossible (a zero plane normal, ...).
    #[error("{option}: {message}")]
    InvalidOption {
        /// The option, as named on the command line (`--plane-normal`).
        option: &'static str,
        /// What is wrong.
        message: String,
    },
    /// The measurements do not fit the method (a set of one configuration, a
    /// pair used three times, a missing column, ...).
    #[error("{}{message}", line_prefix(.line))]
    InvalidData {
        /// The line of the data file, when the samples came from one.
        line: Option<usize>,
        /// What is wrong.
        message: String,
    },
    /// Fewer independent equations than unknowns.
    #[error(
        "too few equations: the data give {equations} independent equations for {unknowns} \
         unknowns; add configurations (at least {unknowns} equations are needed, several \
         times more for a good identification)"
    )]
    TooFewEquations {
        /// Independent equations available.
        equations: usize,
        /// Unknowns to determine.
        unknowns: usize,
    },
    /// Configurations satisfying the method's constraint could not be found.
    #[error("points generation failed: {message}")]
    Generation {
        /// What could not be satisfied.
        message: String,
    },
    /// The caller's progress hook asked to stop (a user's Ctrl-C).
    #[error("interrupted")]
    Interrupted,
    /// A dense factorisation failed (only with non-finite input).
    #[error("numerical failure: {message}")]
    Numerical {
        /// What failed.
        message: String,
    },
}

fn line_prefix(line: &Option<usize>) -> String {
    match line {
        Some(line) => format!("line {line}: "),
        None => String::new(),
    }
}
