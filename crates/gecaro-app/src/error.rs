//! Errors as a user reads them, whichever front end asked.
//!
//! An [`AppError`] has a [`ErrorKind`], which each front end maps to its exit
//! code, HTTP status or exception class, and a message made of parts: plain
//! text, and the names of settings and hints that each front end words its
//! own way ([`Dialect`]): the command line says `--error-level` and "use
//! --force", Python `error_level` and "pass overwrite=True", the web API
//! `error_level` and `"overwrite": true`. The libraries underneath never name
//! a front end's options; their errors are translated here, once.

use std::fmt;
use std::path::Path;

use gecaro_io::DocumentError;

/// What kind of failure an error is.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum ErrorKind {
    /// The request cannot be understood: an unknown name, an impossible
    /// combination or value of settings (command line 2, HTTP 400).
    Usage,
    /// Bad input: a file that cannot be read or parsed, a value that breaks
    /// a rule of the model, data that do not fit the method (3, HTTP 422).
    Input,
    /// A robot document that breaks rules of the model, with every problem
    /// ([`AppError::problems`]) (3, HTTP 422).
    InvalidRobot,
    /// No such file or ready robot (3, HTTP 404).
    NotFound,
    /// An output that exists, and replacing it was not asked for (3, HTTP 409).
    Exists,
    /// A file the front end may not use (outside a served folder) (3, HTTP 403).
    Forbidden,
    /// More than a front end takes at once (3, HTTP 413).
    TooLarge,
    /// A file that cannot be written (3, HTTP 500).
    Output,
    /// Fewer independent equations than unknowns (4, HTTP 422).
    NotIdentifiable,
    /// An iteration that did not converge, an unreachable target,
    /// configurations that cannot be generated (4, HTTP 422).
    NotConverged,
    /// A numerical failure on well-formed input (4, HTTP 422).
    Numerical,
    /// A solution the verdict does not trust (residuals beyond or far below
    /// the stated noise, implausible values, data that do not determine the
    /// robot, a scale or tool not measured): written, but not to be used
    /// blindly (command line 5; the web page and Python show it in the
    /// verdict).
    Untrusted,
    /// Stopped by the user (Ctrl-C, a cancelled job).
    Interrupted,
    /// A failure of gecaro itself, such as a plot that cannot be drawn (4, HTTP 500).
    Internal,
}

/// The words of one front end.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Dialect {
    /// `gecaro …` options: `--error-level`.
    CommandLine,
    /// Keyword arguments of the Python package: `error_level`.
    Python,
    /// Fields of the JSON API: `error_level`.
    Web,
}

impl Dialect {
    /// How this front end names the setting `key` (snake case, as the
    /// libraries' [`Setting::key`](gecaro_calib::Setting::key) and the JSON
    /// requests name it).
    pub fn setting(self, key: &str) -> String {
        match self {
            Dialect::CommandLine => match key {
                "plane" => "--plane-normal/--plane-point".into(),
                "format" => "--from".into(),
                "save_as" => "-o".into(),
                "cv" | "folds" => "--cv".into(),
                other => format!("--{}", other.replace('_', "-")),
            },
            Dialect::Python => match key {
                "cv" => "folds".into(),
                "plane" => "plane_normal/plane_point".into(),
                "save_as" => "path".into(),
                other => other.into(),
            },
            Dialect::Web => match key {
                "plane" => "plane_normal/plane_point".into(),
                other => other.into(),
            },
        }
    }

    fn hint(self, hint: Hint) -> &'static str {
        match (hint, self) {
            (Hint::Overwrite, Dialect::CommandLine) => "use --force to overwrite it",
            (Hint::Overwrite, Dialect::Python) => "pass overwrite=True to replace it",
            (Hint::Overwrite, Dialect::Web) => "send \"overwrite\": true to replace it",
            (Hint::PlaneExample, Dialect::CommandLine) => {
                "for example: --plane-normal 0.3,0.5,0.81 --plane-point 0.3,0.2,0.6"
            }
            (Hint::PlaneExample, Dialect::Python) => {
                "for example: gecaro.Method(\"plane1\", plane_normal=(0.3, 0.5, 0.81), \
                 plane_point=(0.3, 0.2, 0.6))"
            }
            (Hint::PlaneExample, Dialect::Web) => {
                "for example: \"plane_normal\": [0.3, 0.5, 0.81], \"plane_point\": [0.3, 0.2, 0.6]"
            }
            (Hint::StrictLimits, Dialect::CommandLine) => "--strict-limits",
            (Hint::StrictLimits, Dialect::Python) => "strict_limits=True",
            (Hint::StrictLimits, Dialect::Web) => "\"strict_limits\": true",
            (Hint::Rebase, Dialect::CommandLine) => "--rebase",
            (Hint::Rebase, Dialect::Python) => "rebase=True",
            (Hint::Rebase, Dialect::Web) => "\"rebase\": true",
        }
    }
}

/// A phrase each front end words its own way.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum Hint {
    /// How to replace an existing output.
    Overwrite,
    /// How to give a plane.
    PlaneExample,
    /// The option that refuses joint values outside the limits.
    StrictLimits,
    /// The option that re-expresses a calibrated robot in its nominal's frame.
    Rebase,
}

/// One part of a message.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Part {
    Text(String),
    /// A setting, by its key.
    Setting(String),
    /// A setting with the value given (`--cv 1`, `folds=1`, `cv 1`).
    SettingValue(String, String),
    Hint(Hint),
}

impl From<&str> for Part {
    fn from(text: &str) -> Self {
        Part::Text(text.to_owned())
    }
}

impl From<String> for Part {
    fn from(text: String) -> Self {
        Part::Text(text)
    }
}

pub(crate) fn render(parts: &[Part], dialect: Dialect) -> String {
    parts
        .iter()
        .map(|part| match part {
            Part::Text(text) => text.clone(),
            Part::Setting(key) => dialect.setting(key),
            Part::SettingValue(key, value) => match dialect {
                Dialect::Python => format!("{}={value}", dialect.setting(key)),
                _ => format!("{} {value}", dialect.setting(key)),
            },
            Part::Hint(hint) => dialect.hint(*hint).to_owned(),
        })
        .collect()
}

/// A failed request; see the module docs.
#[derive(Clone, Debug, PartialEq)]
pub struct AppError {
    kind: ErrorKind,
    message: Vec<Part>,
    help: Vec<Part>,
    problems: Vec<DocumentError>,
}

impl AppError {
    pub(crate) fn new(kind: ErrorKind, message: Vec<Part>) -> Self {
        AppError {
            kind,
            message,
            help: Vec::new(),
            problems: Vec::new(),
        }
    }

    /// An error of `kind` with a plain message.
    pub fn plain(kind: ErrorKind, message: impl Into<String>) -> Self {
        AppError::new(kind, vec![Part::Text(message.into())])
    }

    /// A bad value of the setting `key`: `"{setting}: {message}"`.
    pub fn setting(key: &str, message: impl Into<String>) -> Self {
        AppError::new(
            ErrorKind::Usage,
            vec![
                Part::Setting(key.to_owned()),
                Part::Text(format!(": {}", message.into())),
            ],
        )
    }

    /// A bad value `value` of the setting `key`: `"{setting} {value}: {message}"`.
    pub fn setting_value(key: &str, value: impl fmt::Display, message: impl Into<String>) -> Self {
        AppError::new(
            ErrorKind::Usage,
            vec![
                Part::SettingValue(key.to_owned(), value.to_string()),
                Part::Text(format!(": {}", message.into())),
            ],
        )
    }

    /// An invalid robot document with every problem.
    pub fn invalid_robot(problems: Vec<DocumentError>) -> Self {
        let first = problems
            .first()
            .map_or_else(String::new, |problem| problem.message.clone());
        AppError {
            problems,
            ..AppError::plain(
                ErrorKind::InvalidRobot,
                format!("the robot is not valid: {first}"),
            )
        }
    }

    /// An output that exists, to be replaced only on request.
    pub fn exists(path: &Path) -> Self {
        AppError::new(
            ErrorKind::Exists,
            vec![
                Part::Text(format!("{} already exists (", path.display())),
                Part::Hint(Hint::Overwrite),
                Part::Text(")".into()),
            ],
        )
    }

    /// This error with a help line.
    #[must_use]
    pub(crate) fn with_help(mut self, help: Vec<Part>) -> Self {
        self.help = help;
        self
    }

    /// This error with a help line, the same in every front end's words.
    #[must_use]
    pub fn with_advice(self, advice: impl Into<String>) -> Self {
        self.with_help(vec![Part::Text(advice.into())])
    }

    /// This error's kind.
    pub fn kind(&self) -> ErrorKind {
        self.kind
    }

    /// The message in a front end's words.
    pub fn message(&self, dialect: Dialect) -> String {
        render(&self.message, dialect)
    }

    /// What to do about it, in a front end's words, when there is advice.
    pub fn help(&self, dialect: Dialect) -> Option<String> {
        (!self.help.is_empty()).then(|| render(&self.help, dialect))
    }

    /// The problems of an invalid robot document, each at its location.
    pub fn problems(&self) -> &[DocumentError] {
        &self.problems
    }
}

impl fmt::Display for AppError {
    /// The message in the words of the JSON API (the libraries' own terms).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message(Dialect::Web))
    }
}

impl std::error::Error for AppError {}

impl From<gecaro_core::Error> for AppError {
    fn from(error: gecaro_core::Error) -> Self {
        let kind = match error {
            gecaro_core::Error::Unreachable { .. } => ErrorKind::NotConverged,
            _ => ErrorKind::Input,
        };
        AppError::plain(kind, error.to_string())
    }
}

impl From<gecaro_calib::Error> for AppError {
    fn from(error: gecaro_calib::Error) -> Self {
        use gecaro_calib::Error as Calib;
        match error {
            Calib::Model(model) => model.into(),
            Calib::InvalidOption { setting, message } => {
                let error = AppError::setting(setting.key(), message);
                if setting == gecaro_calib::Setting::Plane {
                    error.with_help(vec![Part::Hint(Hint::PlaneExample)])
                } else {
                    error
                }
            }
            Calib::WrongUnit { quantity, unit, .. } => {
                AppError::plain(ErrorKind::Input, error.to_string()).with_help(vec![
                    Part::Text(format!("state the data's {quantity} unit: ")),
                    Part::SettingValue(format!("{quantity}_unit"), unit.to_owned()),
                ])
            }
            Calib::UnknownMethod { .. } => AppError::plain(ErrorKind::Usage, error.to_string()),
            Calib::TooFewEquations { .. } => {
                AppError::plain(ErrorKind::NotIdentifiable, error.to_string())
            }
            Calib::Generation { .. } => AppError::plain(ErrorKind::NotConverged, error.to_string()),
            Calib::Numerical { .. } => AppError::plain(ErrorKind::Numerical, error.to_string()),
            Calib::Interrupted => AppError::plain(ErrorKind::Interrupted, "interrupted"),
            _ => AppError::plain(ErrorKind::Input, error.to_string()),
        }
    }
}

impl From<gecaro_io::Error> for AppError {
    fn from(error: gecaro_io::Error) -> Self {
        use gecaro_io::Error as Io;
        match &error {
            Io::OutputExists { path } => AppError::exists(path),
            Io::Write { .. } => AppError::plain(ErrorKind::Output, error.to_string()),
            Io::Read { cause, .. } if cause.kind() == std::io::ErrorKind::NotFound => {
                AppError::plain(ErrorKind::NotFound, error.to_string())
            }
            Io::UnknownRobot { .. } => AppError::plain(ErrorKind::NotFound, error.to_string()),
            _ => AppError::plain(ErrorKind::Input, error.to_string()),
        }
    }
}

impl From<gecaro_report::Error> for AppError {
    fn from(error: gecaro_report::Error) -> Self {
        AppError::plain(ErrorKind::Internal, error.to_string())
    }
}
