//! A study as it is stated ([`StudySpec`]): the robot, the measurement sets
//! with their methods, data, units and σ, the named tools and stations, the
//! prior — before any file it names is read.
//!
//! Every front end fills this one description and builds the study through
//! [`StudySpec::build`], so a study follows the same rules however it was
//! written:
//!
//! - a study file is this structure in TOML ([`crate::read_study_file`]:
//!   errors name the file's line);
//! - the web API's JSON is this structure in JSON (errors name the field,
//!   `measurements[0].sigma`, counting sets from 0 as JSON arrays do);
//! - Python's `gecaro.Study` fills it set by set (`Study.add`, `add_tool`),
//!   its data given as arrays ([`SetData::Samples`]) and its methods built
//!   ([`MethodChoice::Built`]).
//!
//! The rules of a study's statement (σ, named frames) live in
//! [`gecaro_calib::study::Study::statement_problem`]; this module reads units, σ
//! texts, poses and method options, and names the field at fault.
//!
//! Units: a number is in its set's `length_unit`/`angle_unit` (metres and
//! radians unless said; both may also stand at the top, for every set); a
//! σ may carry its own unit (`"20um"`, `"0.01deg"`). A tool's pose is
//! stated in the robot's tool frame n+1 (a URDF's `tool0`), a station's in
//! the world frame; `rpy` are roll, pitch, yaw about the fixed x, y, z
//! axes (as URDF writes them), `quaternion` is `[w, x, y, z]`.

use std::collections::BTreeMap;
use std::fmt;

use gecaro_calib::frames::{FrameRole, NamedFrame};
use gecaro_calib::identification::Prior;
use gecaro_calib::methods::CalibrationMethod;
use gecaro_calib::methods::{MethodOptions, Plane};
use gecaro_calib::study::{DataColumn, MeasurementSet, Samples, Study, StudySite};
use gecaro_core::{FrameType, OrientationDifference, PriorityMatrix, Robot};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::study_parts::{FrameSpec, PriorSpec, angle_unit, length_unit};

use gecaro_io::Error;
use gecaro_io::LengthUnit;
use gecaro_io::RotationFormat;
use gecaro_io::StandardDeviation;
use gecaro_io::{AngleUnit, RobotFile};
use gecaro_io::{ColumnMap, DataUnits, Delimiter, joint_types};
use gecaro_io::{DataFile, DataFormat};

/// A study as stated (see the module docs).
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct StudySpec {
    /// The nominal robot: a robot file (relative to the study file) or a
    /// ready robot's name. A study file must name it; Python's study takes
    /// the robot of the call.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub robot: Option<String>,
    /// A priority-matrix file, as for `--priority`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub priority: Option<String>,
    /// Which parameters may be identified, as for `--model` (`full`,
    /// `elastic`, …, or a priority file); a job's own model overrides it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model: Option<String>,
    /// `m` or `mm` for every set that does not say.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub length_unit: Option<String>,
    /// `rad` or `deg` for every set that does not say.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub angle_unit: Option<String>,
    /// Columns under other names for every set (`qm1 = "A1"`): stated once
    /// for files written alike; a set's own `columns` add to them and win.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub columns: Option<BTreeMap<String, String>>,
    /// The field separator of every set's file that does not say.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub delimiter: Option<String>,
    /// Whether every set's numbers have a decimal comma, where the set does
    /// not say.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub decimal_comma: Option<bool>,
    /// How every set's file writes orientations, where the set does not say
    /// ([`RotationFormat`]'s names: `quaternion`, `rpy`, `euler-xyz`, …).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotation: Option<String>,
    /// A Gaussian prior on the parameters.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub prior: Option<PriorSpec>,
    /// The named tools (reflectors), by name.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub tools: BTreeMap<String, FrameSpec>,
    /// The named stations (measurement frames), by name.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub stations: BTreeMap<String, FrameSpec>,
    /// The measurement sets.
    #[serde(default)]
    pub measurements: Vec<SetSpec>,
}

/// A set's method: its name (with the set's options), or built already.
/// Written and read as its name; a built method has no written form.
#[derive(Debug)]
pub enum MethodChoice {
    /// `point-link`, `position`, … with the set's plane and orientation options.
    Named(String),
    /// A method built already (Python's `Method`).
    Built(Box<dyn CalibrationMethod>),
}

impl<'de> Deserialize<'de> for MethodChoice {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        String::deserialize(deserializer).map(MethodChoice::Named)
    }
}

impl Serialize for MethodChoice {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self {
            MethodChoice::Named(name) => serializer.serialize_str(name),
            MethodChoice::Built(method) => Err(serde::ser::Error::custom(format!(
                "the {} method was built in memory: a study file names its method",
                method.name()
            ))),
        }
    }
}

impl Clone for MethodChoice {
    fn clone(&self) -> Self {
        match self {
            MethodChoice::Named(name) => MethodChoice::Named(name.clone()),
            MethodChoice::Built(method) => MethodChoice::Built(method.clone_method()),
        }
    }
}

impl Default for MethodChoice {
    fn default() -> Self {
        MethodChoice::Named(String::new())
    }
}

/// A set's data: a file, or samples given already. Written and read as the
/// file's name; samples have no written form.
#[derive(Clone, Debug)]
pub enum SetData {
    /// A data file (CSV), relative to the study file (or the served folder).
    File(String),
    /// Samples in metres and radians (Python's arrays), with a label.
    Samples {
        /// The configurations and what was measured there, shared with
        /// whoever made them (a Python `Data`, whose arrays they may read
        /// in place): a set that changes them copies the column it changes.
        samples: Box<Samples>,
        /// What names them in messages.
        label: String,
    },
}

impl<'de> Deserialize<'de> for SetData {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        String::deserialize(deserializer).map(SetData::File)
    }
}

impl Serialize for SetData {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self {
            SetData::File(name) => serializer.serialize_str(name),
            SetData::Samples { label, .. } => Err(serde::ser::Error::custom(format!(
                "{label}: data given in memory have no file to name"
            ))),
        }
    }
}

impl Default for SetData {
    fn default() -> Self {
        SetData::File(String::new())
    }
}

/// A `[[measurements]]` table: one measurement set.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SetSpec {
    /// How the data constrain the robot.
    pub method: MethodChoice,
    /// The measurements.
    pub data: SetData,
    /// The sensor's σ: a number in the set's units, or a text with its unit.
    /// Required for data read from files (it weights the set and is what the
    /// verdict tests the residuals against).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sigma: Option<StandardDeviation>,
    /// A separate σ for orientation rows.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sigma_rotation: Option<StandardDeviation>,
    /// Instead of `sigma`: a file of poses revisited (`pose` and the
    /// attained `x,y,z`, in the set's format), whose pooled scatter is the
    /// set's σ (issue 78; `crate::repeatability`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub repeatability: Option<String>,
    /// `known` or `unknown` (plane methods).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plane: Option<String>,
    /// A known plane's normal.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plane_normal: Option<Vec<f64>>,
    /// A known plane's point (metres).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plane_point: Option<Vec<f64>>,
    /// Configurations per set of the point-link method.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub set_size: Option<usize>,
    /// `axis-angle` (default) or `cross-products`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub orientation: Option<String>,
    /// `m` or `mm` (the study's by default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub length_unit: Option<String>,
    /// `rad` or `deg` (the study's by default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub angle_unit: Option<String>,
    /// Columns under other names (`x = "X"`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub columns: Option<BTreeMap<String, String>>,
    /// The field separator (found from the header by default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub delimiter: Option<String>,
    /// Whether numbers have a decimal comma.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub decimal_comma: Option<bool>,
    /// How the file writes orientations (the study's by default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotation: Option<String>,
    /// The named tool the set measures.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tool: Option<String>,
    /// The station it measures from.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub station: Option<String>,
    /// A name for messages (the data file's by default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub label: Option<String>,
    /// The payload the robot carried for the whole set, as on the command
    /// line: `"20kg"`, or `"20kg,0,0,120mm"` with its centre in the tool
    /// frame, or as a table, `{ mass = "20kg", com = [0, 0, "120mm"] }`
    /// (elastic joints, issue 38); not with a data file's payload columns.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub payload: Option<gecaro_io::PayloadSpec>,
}

/// The field of a [`StudySpec`] at fault.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SpecField {
    /// A top-level key (`robot`, `priority`, `measurements`, `prior`, …).
    Top(&'static str),
    /// A key of `measurements[i]`.
    Set(usize, &'static str),
    /// A key of a named tool or station.
    Frame(FrameRole, String, &'static str),
}

impl fmt::Display for SpecField {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SpecField::Top(key) => f.write_str(key),
            SpecField::Set(index, key) => write!(f, "measurements[{index}].{key}"),
            SpecField::Frame(role, name, key) => write!(f, "{}s.{name}.{key}", role.as_str()),
        }
    }
}

/// What a front end reads for a [`StudySpec`]: the files it names, through
/// the front end's own file access, and how it names a field at fault.
pub trait StudyFiles {
    /// The front end's error.
    type Error: From<Error>;

    /// The robot named `name`.
    ///
    /// # Errors
    /// A file that cannot be read, or an unknown name.
    fn robot(&self, name: &str) -> Result<RobotFile, Self::Error>;

    /// The priority matrix file `name` for `robot`.
    ///
    /// # Errors
    /// A file that cannot be read or does not fit the robot.
    fn priority(&self, name: &str, robot: &Robot) -> Result<PriorityMatrix, Self::Error>;

    /// The data file `name`, its `columns` after `qm1..qmn` in `format`, and
    /// the label messages give it.
    ///
    /// # Errors
    /// A file that cannot be read or whose content does not fit.
    fn samples(
        &self,
        name: &str,
        joint_types: &[FrameType],
        columns: &[DataColumn],
        format: &DataFormat,
    ) -> Result<(DataFile, String), Self::Error>;

    /// The error for `field`, which is wrong as `message` says.
    fn misplaced(&self, field: &SpecField, message: String) -> Self::Error;

    /// The text of the CSV file `name` (a repeatability file) and the label
    /// messages give it; a front end without files refuses it.
    ///
    /// # Errors
    /// A file that cannot be read.
    fn text(&self, name: &str) -> Result<(String, String), Self::Error> {
        Err(Error::Format {
            path: name.into(),
            message: "files are not read here: state the set's sigma".into(),
        }
        .into())
    }

    /// The robot the front end gives a study that does not name one (the
    /// web page's table); none by default.
    fn given_robot(&self) -> Option<RobotFile> {
        None
    }

    /// The most configurations a study's sets may hold together (four sets
    /// naming one large file hold four times its rows).
    fn max_configurations(&self) -> usize {
        gecaro_io::MAX_CONFIGURATIONS
    }

    /// The error for sets holding more than
    /// [`max_configurations`](Self::max_configurations) together; `label`
    /// names the set that passed the bound.
    fn too_large(&self, label: &str, message: String) -> Self::Error {
        Error::Format {
            path: label.into(),
            message,
        }
        .into()
    }
}

/// What a study's data files are read for.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum StudyData {
    /// The measurements: every column of each set's method.
    #[default]
    Measured,
    /// The configurations only (joint values, and set or pair ids): a plan
    /// before it is measured, for a prediction. Measurement columns, if
    /// present, are left alone.
    Configurations,
    /// Nothing of the sets' files (a cell planned before it is measured,
    /// whose plan writes them: they need not exist): every set is empty.
    Unmeasured,
}

/// A study built from its statement, with its robot.
#[derive(Debug)]
pub struct StudyFile {
    /// The nominal robot.
    pub robot: RobotFile,
    /// The measurement sets.
    pub study: Study,
    /// The priority matrix given by the study, if any.
    pub priority: Option<PriorityMatrix>,
    /// The prior of its `[prior]` table, if any.
    pub prior: Option<Prior>,
    /// What the user should know: columns of data files left unused.
    pub notes: Vec<String>,
    /// The statement it was built from.
    pub spec: StudySpec,
}

impl StudyFile {
    /// Its statement with every set's data in memory — the samples read,
    /// σ in metres and radians (a measured σ as the number it measured),
    /// the set's label — and the named frames in the units they were stated
    /// in: a statement that builds again without files, to which sets may
    /// be added (Python's `Study.read`).
    pub fn spec_in_memory(&mut self) -> StudySpec {
        let mut spec = std::mem::take(&mut self.spec);
        for (entry, set) in spec.measurements.iter_mut().zip(&self.study.sets) {
            entry.data = SetData::Samples {
                samples: Box::new(set.samples.clone()),
                label: set.label.clone(),
            };
            entry.sigma = set.sigma.map(StandardDeviation::Number);
            entry.sigma_rotation = set.sigma_rotation.map(StandardDeviation::Number);
            entry.repeatability = None;
            entry.length_unit = None;
            entry.angle_unit = None;
            entry.label = Some(set.label.clone());
        }
        let length_unit = spec.length_unit.take();
        let angle_unit = spec.angle_unit.take();
        for frame in spec.tools.values_mut().chain(spec.stations.values_mut()) {
            if frame.length_unit.is_none() {
                frame.length_unit.clone_from(&length_unit);
            }
            if frame.angle_unit.is_none() {
                frame.angle_unit.clone_from(&angle_unit);
            }
        }
        spec
    }
}

impl StudySpec {
    /// The study with its robot, priority matrix and prior, every file read
    /// through `files` for `data`, and every named frame measured.
    ///
    /// # Errors
    /// The field at fault ([`StudyFiles::misplaced`]), or the errors of the
    /// files it names.
    pub fn build<F: StudyFiles>(&self, files: &F, data: StudyData) -> Result<StudyFile, F::Error> {
        let robot = match (&self.robot, files.given_robot()) {
            (Some(name), None) => files.robot(name)?,
            (None, Some(robot)) => robot,
            (Some(_), Some(_)) => {
                return Err(files.misplaced(
                    &SpecField::Top("robot"),
                    "the study names its robot and the request gives one: give one of them".into(),
                ));
            }
            (None, None) => {
                return Err(files.misplaced(
                    &SpecField::Top("robot"),
                    "a study names its robot (robot = \"panda.toml\" or a ready robot's name)"
                        .into(),
                ));
            }
        };
        let priority = match &self.priority {
            Some(name) => Some(files.priority(name, &robot.robot)?),
            None => None,
        };
        let prior = self
            .prior
            .as_ref()
            .map(|prior| prior.build(&robot.robot))
            .transpose()
            .map_err(|(key, message)| files.misplaced(&SpecField::Top(key), message))?;
        if self.measurements.is_empty() {
            return Err(files.misplaced(
                &SpecField::Top("measurements"),
                "a study needs at least one [[measurements]] table".into(),
            ));
        }
        let (study, notes) =
            self.build_study(files, Some(&joint_types(&robot.robot)), data, true)?;
        Ok(StudyFile {
            robot,
            study,
            priority,
            prior,
            notes,
            spec: self.clone(),
        })
    }

    /// The sets and named frames alone, with the notes of their data files.
    /// `joint_types` (the robot's) are needed to read data files; `complete`
    /// asks every named frame to be measured by some set (a study being
    /// filled set by set is not yet).
    ///
    /// # Errors
    /// As [`build`](Self::build).
    pub fn build_study<F: StudyFiles>(
        &self,
        files: &F,
        joint_types: Option<&[FrameType]>,
        data: StudyData,
        complete: bool,
    ) -> Result<(Study, Vec<String>), F::Error> {
        let study_units = DataUnits {
            length: length_unit(self.length_unit.as_deref(), LengthUnit::Metres)
                .map_err(|message| files.misplaced(&SpecField::Top("length_unit"), message))?,
            angle: angle_unit(self.angle_unit.as_deref(), AngleUnit::Radians)
                .map_err(|message| files.misplaced(&SpecField::Top("angle_unit"), message))?,
        };
        let mut study = Study::default();
        for (frames, role) in [
            (&self.tools, FrameRole::Tool),
            (&self.stations, FrameRole::Station),
        ] {
            for (name, frame) in frames {
                let pose = frame.pose(study_units).map_err(|(key, message)| {
                    files.misplaced(&SpecField::Frame(role, name.clone(), key), message)
                })?;
                if study.frames.iter().any(|frame| frame.name == *name) {
                    return Err(files.misplaced(
                        &SpecField::Frame(role, name.clone(), "name"),
                        format!(
                            "`{name}` names both a tool and a station; give them different names"
                        ),
                    ));
                }
                study.frames.push(NamedFrame {
                    name: name.clone(),
                    role,
                    pose,
                });
            }
        }
        let mut formats = Vec::new();
        for (index, set) in self.measurements.iter().enumerate() {
            let misplaced = |key: &'static str, message: String| {
                files.misplaced(&SpecField::Set(index, key), message)
            };
            let defaults = SetDefaults {
                units: study_units,
                columns: self.columns.as_ref(),
                delimiter: self.delimiter.as_deref(),
                decimal_comma: self.decimal_comma,
                rotation: self.rotation.as_deref(),
            };
            let (stated, format) = set.statement(&study, &defaults, &misplaced)?;
            study.sets.push(stated);
            formats.push(format);
        }
        // Every rule of the statement holds before any data file is read.
        if let Some(problem) = study.statement_problem(complete) {
            let field = match problem.site {
                StudySite::Frame(index) => {
                    let frame = &study.frames[index];
                    SpecField::Frame(frame.role, frame.name.clone(), "position")
                }
                StudySite::Set(index, key) => SpecField::Set(index, key),
            };
            return Err(files.misplaced(&field, problem.message));
        }
        let mut notes = Vec::new();
        for (index, (spec, format)) in self.measurements.iter().zip(&formats).enumerate() {
            let misplaced = |key: &'static str, message: String| {
                files.misplaced(&SpecField::Set(index, key), message)
            };
            let set = &mut study.sets[index];
            notes.extend(spec.read(set, format.as_ref(), files, joint_types, data, &misplaced)?);
            let total: usize = study.sets[..=index]
                .iter()
                .map(|set| set.samples.len())
                .sum();
            let most = files.max_configurations();
            if total > most {
                let label = &study.sets[index].label;
                return Err(files.too_large(
                    label,
                    format!(
                        "the study's sets hold {total} configurations together (counting \
                         {label}); up to {most} are taken here"
                    ),
                ));
            }
        }
        Ok((study, notes))
    }
}

/// What a study's top level states for every set that does not say: the
/// units, column names, separator and decimal mark of its file.
struct SetDefaults<'a> {
    units: DataUnits,
    columns: Option<&'a BTreeMap<String, String>>,
    delimiter: Option<&'a str>,
    decimal_comma: Option<bool>,
    rotation: Option<&'a str>,
}

impl SetSpec {
    /// The set as stated, its samples not read yet, with the format of its
    /// data file (`None` for samples given in memory).
    fn statement<E>(
        &self,
        study: &Study,
        defaults: &SetDefaults<'_>,
        misplaced: &dyn Fn(&'static str, String) -> E,
    ) -> Result<(MeasurementSet, Option<DataFormat>), E> {
        let study_units = defaults.units;
        let units = DataUnits {
            length: length_unit(self.length_unit.as_deref(), study_units.length)
                .map_err(|message| misplaced("length_unit", message))?,
            angle: angle_unit(self.angle_unit.as_deref(), study_units.angle)
                .map_err(|message| misplaced("angle_unit", message))?,
        };
        let sigma = |value: &Option<StandardDeviation>, key: &'static str, rotation: bool| {
            value
                .as_ref()
                .map(|value| value.value(rotation, units))
                .transpose()
                .map_err(|message| misplaced(key, message))
        };
        let sigma_value = sigma(&self.sigma, "sigma", false)?;
        if self.sigma.is_some() && self.repeatability.is_some() {
            return Err(misplaced(
                "repeatability",
                "a set's σ is stated (sigma) or measured (repeatability), not both".into(),
            ));
        }
        let sigma_rotation = sigma(&self.sigma_rotation, "sigma_rotation", true)?;
        let method = self.method(misplaced)?;
        let frame = |name: &Option<String>, role: FrameRole, key: &'static str| {
            name.as_ref()
                .map(|name| study.frame_index(name, role))
                .transpose()
                .map_err(|message| misplaced(key, message))
        };
        let tool = frame(&self.tool, FrameRole::Tool, "tool")?;
        let station = frame(&self.station, FrameRole::Station, "station")?;
        let (label, format) = match &self.data {
            SetData::Samples { label, .. } => (label.clone(), None),
            SetData::File(name) => {
                if self.sigma.is_none() && self.repeatability.is_none() {
                    return Err(misplaced(
                        "sigma",
                        "a set read from a file states its sensor's σ (sigma = 0.02 in the set's \
                         length unit, or \"20um\"), or a repeatability file that measures it"
                            .into(),
                    ));
                }
                let delimiter = match self.delimiter.as_deref().or(defaults.delimiter) {
                    None => Delimiter::Detect,
                    Some(name) => Delimiter::from_name(name).ok_or_else(|| {
                        misplaced(
                            "delimiter",
                            format!(
                                "must be one of {}, not {name:?}",
                                Delimiter::NAMES.join(", ")
                            ),
                        )
                    })?,
                };
                // The study's columns, then the set's (which win).
                let columns = defaults
                    .columns
                    .into_iter()
                    .chain(self.columns.as_ref())
                    .flat_map(|map| map.iter().map(|(k, v)| (k.clone(), v.clone())))
                    .collect::<BTreeMap<String, String>>();
                let rotation = match self.rotation.as_deref().or(defaults.rotation) {
                    None => RotationFormat::Quaternion,
                    Some(name) => RotationFormat::from_name(name).ok_or_else(|| {
                        misplaced(
                            "rotation",
                            format!(
                                "must be one of {}, not {name:?}",
                                RotationFormat::NAMES.join(", ")
                            ),
                        )
                    })?,
                };
                let format = DataFormat {
                    units,
                    columns: ColumnMap::from_pairs(columns),
                    delimiter,
                    decimal_comma: self.decimal_comma.or(defaults.decimal_comma),
                    rotation,
                };
                (name.clone(), Some(format))
            }
        };
        let set = MeasurementSet {
            sigma: sigma_value,
            sigma_rotation,
            sigma_source: None,
            method,
            samples: Samples::empty(),
            label: self.label.clone().unwrap_or(label),
            tool,
            station,
        };
        Ok((set, format))
    }

    /// Reads the set's samples into `set` (stated by [`Self::statement`]),
    /// with the notes on its file.
    fn read<F: StudyFiles>(
        &self,
        set: &mut MeasurementSet,
        format: Option<&DataFormat>,
        files: &F,
        joint_types: Option<&[FrameType]>,
        data: StudyData,
        misplaced: &dyn Fn(&'static str, String) -> F::Error,
    ) -> Result<Vec<String>, F::Error> {
        let mut notes = Vec::new();
        if let Some(name) = &self.repeatability {
            let (text, label) = files.text(name)?;
            let noise = crate::repeatability::repeatability_noise(
                &text,
                &label,
                format.unwrap_or(&DataFormat::default()),
            )?;
            set.sigma = Some(noise.sigma);
            set.sigma_source = Some(name.clone());
            notes.push(format!(
                "{}: σ {:.4} mm measured from {label} ({} poses, {} visits; the largest RP_l \
                 {:.4} mm)",
                set.label,
                noise.sigma * 1e3,
                noise.poses,
                noise.positions,
                noise.repeatability * 1e3
            ));
        }
        let (name, format) = match (&self.data, format) {
            (SetData::File(_), _) if data == StudyData::Unmeasured => return Ok(notes),
            (SetData::File(name), Some(format)) => (name, format),
            (SetData::Samples { samples, .. }, _) => {
                // Shared with the arrays' `Data`: copied only if changed.
                set.samples = Samples::clone(samples);
                self.carried(set, misplaced)?;
                return Ok(notes);
            }
            (SetData::File(_), None) => return Ok(notes),
        };
        let Some(joint_types) = joint_types else {
            return Err(misplaced(
                "data",
                "a data file is read for a robot: give the study's robot".into(),
            ));
        };
        let columns = match data {
            StudyData::Measured => set.method.data_columns().to_vec(),
            StudyData::Configurations | StudyData::Unmeasured => {
                DataColumn::grouping(set.method.data_columns())
            }
        };
        let (read, label) = files.samples(name, joint_types, &columns, format)?;
        if !read.unused_columns.is_empty() && data == StudyData::Measured {
            notes.push(format!(
                "{label}: columns {} are not used by the {} method (left alone)",
                read.unused_columns.join(", "),
                set.method.name()
            ));
        }
        notes.extend(read.notes);
        set.samples = read.samples;
        if self.label.is_none() {
            set.label = label;
        }
        self.carried(set, misplaced)?;
        Ok(notes)
    }

    /// Gives every sample the set's `payload`, when it states one.
    fn carried<E>(
        &self,
        set: &mut MeasurementSet,
        misplaced: &dyn Fn(&'static str, String) -> E,
    ) -> Result<(), E> {
        let Some(stated) = &self.payload else {
            return Ok(());
        };
        let payload = stated
            .payload()
            .map_err(|message| misplaced("payload", message))?;
        if let Some(line) = set
            .samples
            .iter()
            .find(|sample| sample.payload().is_some())
            .map(|sample| sample.line())
        {
            return Err(misplaced(
                "payload",
                format!(
                    "the set states a payload and its data state one per row too{}: give one \
                     of them",
                    line.map(|line| format!(" (line {line})"))
                        .unwrap_or_default()
                ),
            ));
        }
        for loads in set.samples.loads_mut() {
            loads.get_or_insert_with(Box::default).payload = Some(payload);
        }
        Ok(())
    }

    /// The set's method with its options.
    fn method<E>(
        &self,
        misplaced: &dyn Fn(&'static str, String) -> E,
    ) -> Result<Box<dyn CalibrationMethod>, E> {
        let name = match &self.method {
            MethodChoice::Built(method) => return Ok(method.clone_method()),
            MethodChoice::Named(name) => name,
        };
        let vector = |values: &Option<Vec<f64>>, key: &'static str| match values.as_deref() {
            None => Ok(None),
            Some([x, y, z]) => Ok(Some(Vector3::new(*x, *y, *z))),
            Some(other) => Err(misplaced(
                key,
                format!("needs three numbers, got {}", other.len()),
            )),
        };
        let plane = match (
            vector(&self.plane_normal, "plane_normal")?,
            vector(&self.plane_point, "plane_point")?,
        ) {
            (Some(normal), Some(point)) => Some(
                Plane::new(normal, point)
                    .map_err(|error| misplaced("plane_normal", error.to_string()))?,
            ),
            (None, None) => None,
            _ => {
                return Err(misplaced(
                    "plane_normal",
                    "a plane needs both plane_normal and plane_point".into(),
                ));
            }
        };
        let plane_unknown = match self.plane.as_deref() {
            None => plane.is_none(),
            Some("known") if plane.is_none() => {
                return Err(misplaced(
                    "plane",
                    "plane = \"known\" needs plane_normal and plane_point".into(),
                ));
            }
            Some("known") => false,
            Some("unknown") => true,
            Some(other) => {
                return Err(misplaced(
                    "plane",
                    format!("must be \"known\" or \"unknown\", not {other:?}"),
                ));
            }
        };
        let orientation = match self.orientation.as_deref() {
            None | Some("axis-angle") => OrientationDifference::AxisAngle,
            Some("cross-products") => OrientationDifference::CrossProducts,
            Some(other) => {
                return Err(misplaced(
                    "orientation",
                    format!("must be \"axis-angle\" or \"cross-products\", not {other:?}"),
                ));
            }
        };
        let options = MethodOptions {
            plane,
            plane_unknown,
            orientation,
            set_size: self.set_size,
        };
        gecaro_calib::methods::method(name, &options)
            .map_err(|error| misplaced("method", error.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Files of nothing: every field error is its message with its field.
    struct NoFiles;

    /// An error of [`NoFiles`]: its message.
    #[derive(Debug, PartialEq)]
    struct Message(String);

    impl StudyFiles for NoFiles {
        type Error = Message;
        fn robot(&self, name: &str) -> Result<RobotFile, Message> {
            Err(Message(format!("no robot {name}")))
        }
        fn priority(&self, name: &str, _: &Robot) -> Result<PriorityMatrix, Message> {
            Err(Message(format!("no priority {name}")))
        }
        fn samples(
            &self,
            name: &str,
            _: &[FrameType],
            _: &[DataColumn],
            _: &DataFormat,
        ) -> Result<(DataFile, String), Message> {
            Err(Message(format!("no data {name}")))
        }
        fn misplaced(&self, field: &SpecField, message: String) -> Message {
            Message(format!("{field}: {message}"))
        }
    }

    impl From<Error> for Message {
        fn from(error: Error) -> Message {
            Message(error.to_string())
        }
    }

    fn position_set(samples: usize) -> SetSpec {
        let robot = gecaro_io::ready_robot("stanford")
            .expect("ready")
            .expect("stanford")
            .robot;
        let mut sampler = gecaro_calib::prelude::Sampler::new(3);
        let method =
            gecaro_calib::methods::method("position", &MethodOptions::default()).expect("position");
        let samples = method
            .sensor()
            .generate(&robot, samples, 0.0, &mut sampler, &mut gecaro_calib::Quiet)
            .expect("samples");
        SetSpec {
            method: MethodChoice::Named("position".into()),
            data: SetData::Samples {
                samples: Box::new(samples.into()),
                label: "arrays".into(),
            },
            sigma: Some(StandardDeviation::WithUnit("20um".into())),
            ..SetSpec::default()
        }
    }

    #[test]
    fn json_names_the_field_at_fault() {
        let json = r#"{"robot": "stanford", "tools": {"ball": {"position": [0, 0, 2000], "length_unit": "m"}},
                       "measurements": [{"method": "position", "data": "a.csv", "sigma": "20um", "tool": "ball"}]}"#;
        let spec: StudySpec = serde_json::from_str(json).expect("json");
        let mut filled = spec.clone();
        filled.measurements[0] = SetSpec {
            tool: Some("ball".into()),
            ..position_set(5)
        };
        let error = filled
            .build_study(&NoFiles, None, StudyData::Measured, true)
            .expect_err("2 km")
            .0;
        assert!(
            error.starts_with("tools.ball.position: tool `ball` is stated 2000 m"),
            "{error}"
        );
        filled.tools.get_mut("ball").expect("ball").position = vec![0.0, 0.0, 0.1];
        let (study, _) = filled
            .build_study(&NoFiles, None, StudyData::Measured, true)
            .expect("a study");
        assert_eq!(study.sets[0].tool, Some(0));
        assert!((study.sets[0].sigma.expect("σ") - 2e-5).abs() < 1e-18);
        filled.measurements[0].sigma = Some(StandardDeviation::Number(-1.0));
        let error = filled
            .build_study(&NoFiles, None, StudyData::Measured, true)
            .expect_err("negative")
            .0;
        assert_eq!(
            error,
            "measurements[0].sigma: must be a positive standard deviation, not -1"
        );
        filled.measurements[0].sigma = None;
        filled.measurements[0].tool = Some("bal".into());
        let error = filled
            .build_study(&NoFiles, None, StudyData::Measured, true)
            .expect_err("no such tool")
            .0;
        assert_eq!(
            error,
            "measurements[0].tool: no tool named `bal` in this study"
        );
    }

    #[test]
    fn a_study_filled_set_by_set_waits_for_its_frames_to_be_measured() {
        let mut spec = StudySpec::default();
        spec.stations.insert(
            "far".into(),
            FrameSpec {
                position: vec![2.5, 0.0, 0.0],
                ..FrameSpec::default()
            },
        );
        spec.build_study(&NoFiles, None, StudyData::Measured, false)
            .expect("not yet complete");
        let error = spec
            .build_study(&NoFiles, None, StudyData::Measured, true)
            .expect_err("unmeasured")
            .0;
        assert!(
            error.contains("station `far` is measured by no measurement set"),
            "{error}"
        );
        spec.measurements.push(SetSpec {
            station: Some("far".into()),
            ..position_set(4)
        });
        spec.build_study(&NoFiles, None, StudyData::Measured, true)
            .expect("measured");
    }

    #[test]
    fn a_spec_reads_back_what_it_writes() {
        let text = "robot = \"stanford\"\nmodel = \"elastic\"\nlength_unit = \"mm\"\n\n[tools.ball]\nposition = [0, 0, 90]\n\
                    rpy = [0, 0, 90]\nangle_unit = \"deg\"\n\n[[measurements]]\nmethod = \"position\"\n\
                    data = \"a.csv\"\nsigma = \"20um\"\ntool = \"ball\"\ncolumns = { x = \"X\" }\n";
        let spec: StudySpec = toml::from_str(text).expect("toml");
        let written = toml::to_string(&spec).expect("written");
        let again: StudySpec = toml::from_str(&written).expect("read back");
        assert_eq!(format!("{spec:?}"), format!("{again:?}"));
        assert_eq!(again.model.as_deref(), Some("elastic"));
        let json = serde_json::to_string(&spec).expect("json");
        let again: StudySpec = serde_json::from_str(&json).expect("json back");
        assert_eq!(format!("{spec:?}"), format!("{again:?}"));
    }
}
