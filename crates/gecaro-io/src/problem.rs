//! Problems of a robot document, each at a [`Location`]: the TOML reader
//! turns a location into a line, the web page into a highlighted cell.

use gecaro_core::Field;
use serde::Serialize;

/// Where in a document a problem is.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Location {
    /// The document as a whole (the list of frames).
    Document,
    /// A key of the top level (`angle_unit`).
    Key {
        /// The key.
        key: String,
    },
    /// A key of frame `frame`.
    Frame {
        /// Frame number j.
        frame: usize,
        /// The key (`sigma`, `alpha`, ..., `K`).
        key: String,
    },
    /// A key of leg `leg` (1..6) of a parallel robot.
    Leg {
        /// Leg number, 1-based.
        leg: usize,
        /// The key (`base`, `platform`, `length`, `gain`, `min`, `max`).
        key: String,
    },
    /// A key of arm `arm` (1..3) of a Delta robot.
    Arm {
        /// Arm number, 1-based.
        arm: usize,
        /// The key (`base`, `azimuth`, `offset`, `gain`, `upper_arm`,
        /// `forearm`, `platform`, `min`, `max`).
        key: String,
    },
    /// A coupling matrix (`Cm` or `Cj`).
    Coupling {
        /// The matrix.
        matrix: String,
    },
    /// The priority matrix, or one of its rows.
    Priority {
        /// The row (frame), if one is at fault.
        row: Option<usize>,
    },
}

impl std::fmt::Display for Location {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Location::Document => f.write_str("frame"),
            Location::Key { key } => f.write_str(key),
            Location::Frame { frame, key } => write!(f, "frame {frame}, {key}"),
            Location::Leg { leg, key } => write!(f, "leg {leg}, {key}"),
            Location::Arm { arm, key } => write!(f, "arm {arm}, {key}"),
            Location::Coupling { matrix } => write!(f, "coupling.{matrix}"),
            Location::Priority { row: None } => f.write_str("priority.matrix"),
            Location::Priority { row: Some(row) } => write!(f, "priority.matrix row {row}"),
        }
    }
}

/// A problem of a document, at a location.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct DocumentError {
    /// Where.
    pub location: Location,
    /// What is wrong.
    pub message: String,
}

impl DocumentError {
    pub(crate) fn new(location: Location, message: impl Into<String>) -> Self {
        DocumentError {
            location,
            message: message.into(),
        }
    }
}

/// A model error with its location.
pub(crate) fn model_error(error: gecaro_core::Error) -> DocumentError {
    match error {
        gecaro_core::Error::Invalid { field, message } => {
            let location = match field {
                Field::Frame { index, key } => Location::Frame {
                    frame: index,
                    key: key.into(),
                },
                Field::Coupling(name) => Location::Coupling {
                    matrix: name.into(),
                },
                Field::Priority { row } => Location::Priority { row },
                Field::Key(key) => Location::Key { key: key.into() },
                Field::Leg { number, key } => Location::Leg {
                    leg: number,
                    key: key.into(),
                },
                Field::Arm { number, key } => Location::Arm {
                    arm: number,
                    key: key.into(),
                },
                _ => Location::Document,
            };
            DocumentError::new(location, message)
        }
        other => DocumentError::new(Location::Document, other.to_string()),
    }
}
