//! The one error type of `gecaro-core`.

use std::fmt;

/// Where in a robot description a problem was found.
///
/// File readers (`gecaro-io`) map a `Field` back to a line of the file the
/// description came from, so every message can name the file, line and key.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Field {
    /// The list of frames as a whole (count, order).
    Frames,
    /// One key of frame `index` (0..=n+1), such as `sigma` or `qmin`.
    Frame {
        /// Frame number j, 0 for the base frame.
        index: usize,
        /// The key of the frame table (`sigma`, `alpha`, `d`, `theta`, `r`, `beta`,
        /// `qmin`, `qmax`, `offset`, `K`).
        key: &'static str,
    },
    /// A coupling matrix, `Cm` or `Cj` (eq. 4).
    Coupling(&'static str),
    /// A key of the robot as a whole, such as `gravity` or a `payload`.
    Key(&'static str),
    /// One key of leg `number` (1..6) of a parallel robot, such as `base`.
    Leg {
        /// Leg number, 1-based.
        number: usize,
        /// The key of the leg's table (`base`, `platform`, `length`, `gain`,
        /// `min`, `max`).
        key: &'static str,
    },
    /// One key of arm `number` (1..3) of a Delta robot, such as `forearm`.
    Arm {
        /// Arm number, 1-based.
        number: usize,
        /// The key of the arm's table (`base`, `azimuth`, `offset`, `gain`,
        /// `upper_arm`, `forearm`, `platform`, `min`, `max`).
        key: &'static str,
    },
    /// The priority matrix, optionally one row (frame) of it.
    Priority {
        /// The row (frame number) at fault, if one is.
        row: Option<usize>,
    },
}

impl fmt::Display for Field {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Field::Frames => f.write_str("frames"),
            Field::Frame { index, key } => write!(f, "frame {index}, `{key}`"),
            Field::Coupling(name) => write!(f, "coupling matrix `{name}`"),
            Field::Key(key) => write!(f, "`{key}`"),
            Field::Leg { number, key } => write!(f, "leg {number}, `{key}`"),
            Field::Arm { number, key } => write!(f, "arm {number}, `{key}`"),
            Field::Priority { row: None } => f.write_str("priority matrix"),
            Field::Priority { row: Some(row) } => write!(f, "priority matrix, row {row}"),
        }
    }
}

/// Errors of the robot model and the kinematic models.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A robot description breaks a rule of the model (paper §2).
    #[error("{field}: {message}")]
    Invalid {
        /// Where the problem is.
        field: Field,
        /// What is wrong, in words a user can act on.
        message: String,
    },
    /// A configuration does not have one motor value per joint.
    #[error("a configuration needs {expected} motor values (one per joint), got {found}")]
    ConfigurationLength {
        /// Number of joints n.
        expected: usize,
        /// Number of values given.
        found: usize,
    },
    /// A configuration holds NaN or an infinite value.
    #[error("motor value qm{joint} is not a finite number ({value})")]
    NonFiniteConfiguration {
        /// Joint number, 1-based.
        joint: usize,
        /// The offending value.
        value: f64,
    },
    /// A parameter name that is not in the robot's vocabulary.
    #[error("unknown parameter `{name}`{}", suggestion_text(.suggestion))]
    UnknownParameter {
        /// The name as given.
        name: String,
        /// The closest valid name, if one is close.
        suggestion: Option<String>,
    },
    /// A target was given with NaN or infinite coordinates.
    #[error("the {what} target is not finite")]
    NonFiniteTarget {
        /// `position` or `frame`.
        what: &'static str,
    },
    /// A compiled model passed with a robot it was not compiled from (or
    /// that changed since).
    #[error(
        "the compiled kinematic model is not {robot}'s as it is now (its parameters, offsets or \
         couplings differ): compile the model of the robot solved"
    )]
    ModelMismatch {
        /// The robot's name.
        robot: String,
    },
    /// The direct model of a parallel robot found no pose that closes its
    /// legs from the start pose.
    #[error(
        "no platform pose closes the legs at these actuator values (legs still {residual:.3e} m \
         off): values outside what the platform can take, or a start across a singularity"
    )]
    NoAssembly {
        /// The largest leg residual left (m).
        residual: f64,
    },
    /// The numerical inverse geometric model did not reach its target.
    #[error(
        "target not reached by the inverse geometric model after {iterations} iterations \
         (remaining error {residual:.3e}; tolerance {tolerance:.1e}): {}",
        unreachable_text(*.met_limit)
    )]
    Unreachable {
        /// Iterations spent.
        iterations: usize,
        /// Norm of the remaining pose difference (metres and radians).
        residual: f64,
        /// The tolerance that was asked for.
        tolerance: f64,
        /// Whether a joint limit bore on the search: an iterate it tried
        /// had a joint at or beyond a limit (held there). When not, the
        /// same search without the limits takes the same steps to the
        /// same end.
        met_limit: bool,
    },
}

fn unreachable_text(met_limit: bool) -> &'static str {
    if met_limit {
        "a joint met its limit on the way: it is out of reach within the joint limits, \
         or needs another start configuration"
    } else {
        "no joint met a limit on the way: it is out of reach, or needs another start \
         configuration"
    }
}

fn suggestion_text(suggestion: &Option<String>) -> String {
    match suggestion {
        Some(name) => format!(" (did you mean `{name}`?)"),
        None => String::new(),
    }
}

impl Error {
    pub(crate) fn invalid(field: Field, message: impl Into<String>) -> Self {
        Error::Invalid {
            field,
            message: message.into(),
        }
    }
}

/// A number as messages show it: the shortest decimal that reads back the
/// same, in scientific notation when that would be long (beyond 10¹⁵, or
/// below 10⁻⁴ but not zero): `1e308` is not printed as 309 digits, nor
/// `1e-320` as 320.
///
/// ```
/// use gecaro_core::Compact;
///
/// assert_eq!(Compact(3.5).to_string(), "3.5");
/// assert_eq!(Compact(1e308).to_string(), "1e308");
/// assert_eq!(Compact(-2.5e-320).to_string(), "-2.5e-320");
/// assert_eq!(Compact(0.0).to_string(), "0");
/// ```
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Compact(pub f64);

impl fmt::Display for Compact {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let magnitude = self.0.abs();
        if magnitude != 0.0 && magnitude.is_finite() && !(1e-4..1e15).contains(&magnitude) {
            write!(f, "{:e}", self.0)
        } else {
            write!(f, "{}", self.0)
        }
    }
}
