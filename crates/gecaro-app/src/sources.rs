//! What a request works on: a robot ([`RobotSource`]) and measurements
//! ([`DataSource`]) as each front end names them, and the format of a data
//! file as an instrument wrote it ([`DataFormatSpec`]).

use std::io::Read as _;
use std::path::Path;

use gecaro_calib::study::{DataColumn, Samples};
use gecaro_io::{
    AngleUnit, ColumnMap, DataFormat, DataUnits, Delimiter, LengthUnit, RobotDocument, RobotFile,
};
use serde::Deserialize;

use crate::error::{AppError, ErrorKind};
use crate::files::Files;
use crate::limits::MAX_TABLE_JOINTS;

/// The robot of a request.
#[derive(Clone, Debug, Deserialize)]
#[serde(untagged)]
pub enum RobotSource {
    /// A robot file, or the name of a ready robot (`stanford`).
    Named(String),
    /// A robot document: a robot file's content as JSON (the web page's table).
    Document(Box<RobotDocument>),
    /// A robot loaded already (a Python `Robot`).
    #[serde(skip)]
    Loaded(Box<RobotFile>),
}

impl RobotSource {
    /// The robot, loaded through `files` when it names a file.
    ///
    /// # Errors
    /// A file that cannot be read or parsed, an unknown name, or a document
    /// that breaks rules of the model ([`ErrorKind::InvalidRobot`], with
    /// every problem).
    pub fn load(&self, files: &dyn Files) -> Result<RobotFile, AppError> {
        match self {
            RobotSource::Named(name) => load_named(name, files),
            RobotSource::Document(document) => robot_of_document(document),
            RobotSource::Loaded(file) => Ok((**file).clone()),
        }
    }
}

/// A robot file of `files`, else a ready robot (as `gecaro_io::load_robot`
/// does on the file system).
fn load_named(name: &str, files: &dyn Files) -> Result<RobotFile, AppError> {
    if files.is_file(name) {
        let (path, text) = files.read_text(name, &["toml"])?;
        return Ok(gecaro_io::parse_robot_file(&text, &path)?);
    }
    match gecaro_io::ready_robot(name) {
        Some(robot) => Ok(robot?),
        None => {
            let path = Path::new(name);
            if path.extension().is_some() || name.contains(['/', std::path::MAIN_SEPARATOR]) {
                // Looks like a path: say the file is missing rather than list robots only.
                files.read_text(name, &["toml"])?;
            }
            Err(gecaro_io::Error::UnknownRobot {
                name: name.to_owned(),
                available: gecaro_io::ready_robots()
                    .iter()
                    .map(|ready| ready.name.to_owned())
                    .collect(),
            }
            .into())
        }
    }
}

/// The validated robot of a document, with at most [`MAX_TABLE_JOINTS`] joints.
///
/// # Errors
/// [`ErrorKind::InvalidRobot`] with every problem of the document.
pub fn robot_of_document(document: &RobotDocument) -> Result<RobotFile, AppError> {
    if document.frame.len() > MAX_TABLE_JOINTS + 2 {
        return Err(AppError::invalid_robot(vec![gecaro_io::DocumentError {
            location: gecaro_io::Location::Document,
            message: format!(
                "{} frames: gecaro takes robot documents of up to {MAX_TABLE_JOINTS} joints",
                document.frame.len()
            ),
        }]));
    }
    let problems = document.problems();
    if !problems.is_empty() {
        return Err(AppError::invalid_robot(problems));
    }
    document
        .to_robot_file("robot")
        .map_err(|problem| AppError::invalid_robot(vec![problem]))
}

/// Where the measurements of a request come from.
#[derive(Clone, Debug, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
#[allow(
    clippy::large_enum_variant,
    reason = "a request holds one source per set, made once: its size is nothing beside the data"
)]
pub enum DataSource {
    /// A data file (CSV): a path, or a name in the web page's folder.
    File(String),
    /// A data file's text (an upload), with a name for messages.
    Csv {
        /// The file's content.
        text: String,
        /// Its name (for messages).
        name: Option<String>,
    },
    /// Samples built already (Python arrays), with a label for messages.
    #[serde(skip)]
    Samples {
        /// The samples, shared with whoever made them (a Python `Data`)
        /// and with the study read from them; a set that changes them
        /// copies them first.
        samples: Samples,
        /// What names them in messages and reports.
        label: String,
    },
}

/// Samples read for a method, with what a user should know about the file.
#[derive(Clone, Debug)]
pub struct DataRead {
    /// The samples, in the file's order; shared with the request's when it
    /// gave them ([`DataSource::Samples`]).
    pub samples: Samples,
    /// The file as messages name it.
    pub label: String,
    /// Columns of the file the method does not use (left alone).
    pub unused_columns: Vec<String>,
    /// What the reader changed that a user should know.
    pub notes: Vec<String>,
}

/// A request's CSV file: a name opened through a front end's [`Files`], or
/// an upload's text with the name messages give it.
pub(crate) enum CsvInput<'a> {
    /// A file of the front end's.
    File(&'a str),
    /// An upload's text.
    Text {
        /// The file's content.
        text: &'a str,
        /// Its name in messages.
        label: &'a str,
    },
}

impl CsvInput<'_> {
    /// The whole text of the file (at most `most` bytes: beyond, it is not
    /// `what`) and the path its messages name.
    ///
    /// # Errors
    /// A file that cannot be read, or one too large.
    pub(crate) fn read_text(
        &self,
        files: &dyn Files,
        most: u64,
        what: &str,
    ) -> Result<(String, std::path::PathBuf), AppError> {
        self.parse(files, |mut content, path| {
            let mut text = String::new();
            content
                .reader()
                .take(most + 1)
                .read_to_string(&mut text)
                .map_err(|cause| gecaro_io::Error::Read {
                    path: path.to_owned(),
                    cause,
                })?;
            if text.len() as u64 > most {
                let size = if most >= 1 << 20 {
                    format!("{} MB", most >> 20)
                } else {
                    format!("{} kB", most >> 10)
                };
                return Err(AppError::from(gecaro_io::Error::Format {
                    path: path.to_owned(),
                    message: format!("over {size}: not {what}"),
                }));
            }
            Ok((text, path.to_owned()))
        })
    }

    /// The file read by `parse` (its content, and the path its messages
    /// name).
    ///
    /// # Errors
    /// A file that cannot be opened, and `parse`'s.
    pub(crate) fn parse<T>(
        &self,
        files: &dyn Files,
        parse: impl FnOnce(gecaro_io::Content<'_>, &Path) -> Result<T, AppError>,
    ) -> Result<T, AppError> {
        match self {
            CsvInput::File(name) => {
                let mut opened = files.open(name, &["csv"])?;
                parse(opened.bytes.content(), &opened.path)
            }
            CsvInput::Text { text, label } => {
                parse(gecaro_io::Content::Whole(text.as_bytes()), Path::new(label))
            }
        }
    }
}

/// The largest points file read (bytes): a drawing's or a fixture's few
/// points, not a data set.
const MAX_POINTS_BYTES: u64 = 1 << 20;

/// Where a file of named points comes from (base points, a user frame's
/// points; JSON: `{"file": name}` or `{"csv": {"text": …, "name": …}}`).
#[derive(Clone, Debug, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields, bound = "")]
pub enum PointsSource<P> {
    /// A points file (CSV).
    File(String),
    /// A points file's text (an upload), with a name for messages.
    Csv {
        /// The file's content.
        text: String,
        /// Its name (for messages).
        name: Option<String>,
    },
    /// Points given already (Python arrays).
    #[serde(skip)]
    Points(Vec<P>),
}

impl<P: Clone> PointsSource<P> {
    /// The points as messages name them: the file's name, the upload's, or
    /// `the points`.
    pub fn label(&self) -> String {
        match self {
            PointsSource::File(name) => name.clone(),
            PointsSource::Csv { name, .. } => {
                name.clone().unwrap_or_else(|| "uploaded points".into())
            }
            PointsSource::Points(_) => "the points".into(),
        }
    }

    /// The points: those given, or `parse` of the file's text (at most
    /// [`MAX_POINTS_BYTES`]) and the path its messages name; `what` names
    /// such a file.
    ///
    /// # Errors
    /// A file that cannot be read, one too large, and `parse`'s.
    pub(crate) fn load(
        &self,
        files: &dyn Files,
        what: &str,
        parse: impl FnOnce(&str, &Path) -> Result<Vec<P>, gecaro_io::Error>,
    ) -> Result<Vec<P>, AppError> {
        let label = self.label();
        let input = match self {
            PointsSource::Points(points) => return Ok(points.clone()),
            PointsSource::File(name) => CsvInput::File(name),
            PointsSource::Csv { text, .. } => CsvInput::Text {
                text,
                label: &label,
            },
        };
        let (text, path) = input.read_text(files, MAX_POINTS_BYTES, what)?;
        Ok(parse(&text, &path)?)
    }
}

/// Refuses a file of more rows (`what`: configurations, targets) than the
/// front end takes ([`Files::max_samples`]).
///
/// # Errors
/// [`ErrorKind::TooLarge`], naming the file.
pub(crate) fn check_row_count(
    files: &dyn Files,
    label: &str,
    count: usize,
    what: &str,
) -> Result<(), AppError> {
    let most = files.max_samples();
    if count > most {
        return Err(AppError::plain(
            ErrorKind::TooLarge,
            format!("{label} has {count} {what}; up to {most} are taken here"),
        ));
    }
    Ok(())
}

impl DataSource {
    /// The name of the data in messages.
    pub fn label(&self) -> String {
        match self {
            DataSource::File(name) => name.clone(),
            DataSource::Csv { name, .. } => name.clone().unwrap_or_else(|| "uploaded data".into()),
            DataSource::Samples { label, .. } => label.clone(),
        }
    }

    /// The samples for a robot with joints `joint_types`, with the
    /// `columns` after `qm1..qmn`, in `format`.
    ///
    /// # Errors
    /// A file that cannot be read, or content that does not fit (naming the
    /// file, line and column).
    pub fn read(
        &self,
        files: &dyn Files,
        joint_types: &[gecaro_core::FrameType],
        columns: &[DataColumn],
        format: &DataFormat,
    ) -> Result<DataRead, AppError> {
        let label = self.label();
        let input = match self {
            DataSource::File(name) => CsvInput::File(name),
            DataSource::Csv { text, .. } => CsvInput::Text {
                text,
                label: &label,
            },
            DataSource::Samples { samples, label } => {
                return Ok(DataRead {
                    samples: samples.clone(),
                    label: label.clone(),
                    unused_columns: Vec::new(),
                    notes: Vec::new(),
                });
            }
        };
        let file = input.parse(files, |content, path| {
            Ok(gecaro_io::parse_samples_from(
                content,
                path,
                (joint_types, columns),
                format,
            )?)
        })?;
        check_row_count(files, &label, file.samples.len(), "configurations")?;
        Ok(DataRead {
            samples: file.samples,
            label,
            unused_columns: file.unused_columns,
            notes: file.notes,
        })
    }
}

/// How a data file is written, as a user gives it: units of the columns that
/// do not state theirs, and columns under other names.
#[derive(Clone, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(deny_unknown_fields)]
pub struct DataFormatSpec {
    /// `m` (default) or `mm`: positions, distances, prismatic joints.
    pub length_unit: Option<String>,
    /// `rad` (default) or `deg`: revolute joints.
    pub angle_unit: Option<String>,
    /// Other column names: `x=X_mm,qm1=A1`.
    pub columns: Option<String>,
    /// The field separator: `auto` (default: found from the header),
    /// `comma`, `semicolon`, `tab`.
    pub delimiter: Option<String>,
    /// Numbers with a decimal comma: allowed by default where fields are not
    /// separated by commas; `true` requires, `false` refuses them.
    pub decimal_comma: Option<bool>,
    /// How orientations are written: `quaternion` (default, `qw,qx,qy,qz`),
    /// `rpy`, `euler-xyz`, `euler-zyz` or `rotation-vector` (`rx,ry,rz` in
    /// the angle unit; [`gecaro_io::RotationFormat`]).
    #[serde(default)]
    pub rotation: Option<String>,
}

impl DataFormatSpec {
    /// Whether nothing is said (the file is in gecaro's own columns and units).
    pub fn is_default(&self) -> bool {
        *self == DataFormatSpec::default()
    }

    /// The format of the file.
    ///
    /// # Errors
    /// An unknown unit or a malformed column map, naming the setting.
    pub fn format(&self) -> Result<DataFormat, AppError> {
        Ok(DataFormat {
            units: DataUnits {
                length: length_unit(self.length_unit.as_deref())?.unwrap_or_default(),
                angle: angle_unit(self.angle_unit.as_deref())?.unwrap_or_default(),
            },
            columns: match self.columns.as_deref().map(str::trim) {
                None | Some("") => ColumnMap::default(),
                Some(text) => ColumnMap::parse(text)
                    .map_err(|message| AppError::setting("columns", message))?,
            },
            delimiter: delimiter(self.delimiter.as_deref())?,
            decimal_comma: self.decimal_comma,
            rotation: rotation_format(self.rotation.as_deref())?,
        })
    }
}

/// How orientations are written, by name (`quaternion`, `rpy`,
/// `euler-xyz`, …; [`gecaro_io::RotationFormat`]); none: quaternions.
///
/// # Errors
/// An unknown name, naming the `rotation` setting.
pub fn rotation_format(name: Option<&str>) -> Result<gecaro_io::RotationFormat, AppError> {
    match name {
        None => Ok(gecaro_io::RotationFormat::Quaternion),
        Some(name) => gecaro_io::RotationFormat::from_name(name).ok_or_else(|| {
            AppError::setting(
                "rotation",
                format!(
                    "{name:?} is not a form of orientations: {}",
                    gecaro_io::RotationFormat::NAMES.join(", ")
                ),
            )
        }),
    }
}

/// A field separator by name (`auto`, `comma`, `semicolon`, `tab`; `;` and
/// the like too); none: found from the header.
///
/// # Errors
/// An unknown name, naming the `delimiter` setting.
pub fn delimiter(name: Option<&str>) -> Result<Delimiter, AppError> {
    match name {
        None => Ok(Delimiter::Detect),
        Some(name) => Delimiter::from_name(name).ok_or_else(|| {
            AppError::setting(
                "delimiter",
                format!(
                    "{name:?} is not a separator: {}",
                    Delimiter::NAMES.join(", ")
                ),
            )
        }),
    }
}

/// A length unit by name (`m`, `mm`).
///
/// # Errors
/// An unknown name, naming the `length_unit` setting.
pub fn length_unit(name: Option<&str>) -> Result<Option<LengthUnit>, AppError> {
    name.map(|name| {
        LengthUnit::parse(name).map_err(|message| AppError::setting("length_unit", message))
    })
    .transpose()
}

/// An angle unit by name (`rad`, `deg`).
///
/// # Errors
/// An unknown name, naming the `angle_unit` setting.
pub fn angle_unit(name: Option<&str>) -> Result<Option<AngleUnit>, AppError> {
    name.map(|name| {
        AngleUnit::parse(name).map_err(|message| AppError::setting("angle_unit", message))
    })
    .transpose()
}
