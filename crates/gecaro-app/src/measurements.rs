//! The measurements a job works on: one method with its data file
//! (`robot`, `method`, `data`, `format`), or a study file of several
//! measurement sets (`study`); loaded into a [`Loaded`] with the notes a user
//! should read (unused columns, joints outside their limits).

use std::collections::BTreeMap;

use crate::StudySpec;
use gecaro_calib::identification::Prior;
use gecaro_calib::study::Study;
use gecaro_core::PriorityMatrix;
use gecaro_io::{RobotFile, StandardDeviation};
use serde::Deserialize;
use serde::de::IgnoredAny;

use crate::error::{AppError, ErrorKind, Hint, Part};
use crate::files::Files;
use crate::method::MethodSpec;
use crate::sources::{DataFormatSpec, DataSource, RobotSource};

/// Where a job's measurements come from; see the module docs.
#[derive(Clone, Debug, Default, Deserialize)]
pub struct Measurements {
    /// The robot (not with a study file, which names its own).
    pub robot: Option<RobotSource>,
    /// The method of the data.
    pub method: Option<MethodSpec>,
    /// The data; some jobs work on random configurations without.
    pub data: Option<DataSource>,
    /// Units and column names of the data file.
    #[serde(default)]
    pub format: DataFormatSpec,
    /// The sensor's standard deviation for the data: a number in the data's
    /// length unit (`format`'s, metres by default), or a text with its unit
    /// (`"20um"`); also the orientations' unless `sigma_rotation` is given.
    /// The identification's verdict tests the residuals against it. Not
    /// with a study, whose sets state their own.
    pub sigma: Option<StandardDeviation>,
    /// A separate σ for the orientation rows: a number in the data's angle
    /// unit, or a text with its unit (`"0.01deg"`).
    pub sigma_rotation: Option<StandardDeviation>,
    /// A study file: several measurement sets (method, data, σ each).
    pub study: Option<StudySource>,
    /// Refuse data with joints outside their limits (by default a warning).
    #[serde(default)]
    pub strict_limits: bool,
}

/// A study of several measurement sets: a request gives a study file's name
/// (a string) or the study itself (an object, a study file's keys in JSON:
/// [`StudySpec`]).
#[derive(Clone, Debug)]
pub enum StudySource {
    /// A study file (TOML; its data files are read beside it).
    File(String),
    /// A study as stated in a request (the web API's JSON); its files are
    /// names of the front end's ([`Files`]).
    Spec(Box<StudySpec>),
    /// A study built already (a Python `Study`).
    Loaded(Box<LoadedStudy>),
}

impl<'de> Deserialize<'de> for StudySource {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Source;
        impl<'de> serde::de::Visitor<'de> for Source {
            type Value = StudySource;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(
                    "a study file's name or a study (an object with its robot and measurements)",
                )
            }
            fn visit_str<E: serde::de::Error>(self, name: &str) -> Result<StudySource, E> {
                Ok(StudySource::File(name.to_owned()))
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                map: A,
            ) -> Result<StudySource, A::Error> {
                StudySpec::deserialize(serde::de::value::MapAccessDeserializer::new(map))
                    .map(|spec| StudySource::Spec(Box::new(spec)))
            }
        }
        deserializer.deserialize_any(Source)
    }
}

/// A study with what a study file adds to its sets.
#[derive(Clone, Debug)]
pub struct LoadedStudy {
    /// The nominal robot.
    pub robot: RobotFile,
    /// The measurement sets.
    pub study: Study,
    /// The study's priority matrix.
    pub priority: Option<PriorityMatrix>,
    /// The study's prior.
    pub prior: Option<Prior>,
    /// The study's model (`model = "elastic"`), which a job's own overrides.
    pub model: Option<String>,
    /// What names the study in messages and reports.
    pub label: String,
}

/// What a job reads: the robot, the study, what the study file adds, and
/// the notes on the data.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// The nominal robot.
    pub robot: RobotFile,
    /// The measurement sets (empty samples for random configurations).
    pub study: Study,
    /// The study file's priority matrix.
    pub priority: Option<PriorityMatrix>,
    /// The study file's prior.
    pub prior: Option<Prior>,
    /// The study file's model, which a job's own overrides.
    pub model: Option<String>,
    /// The data file or study file, for messages and reports.
    pub label: String,
    /// What a user should know about the data.
    pub notes: Vec<Note>,
}

impl Loaded {
    /// The model a job identifies: its own (`given`), else the study's.
    pub fn model<'a>(&'a self, given: Option<&'a str>) -> Option<&'a str> {
        given.or(self.model.as_deref())
    }

    /// Makes the nominal robot elastic, every compliance 0, unless it is
    /// already (issue 38: `model = "elastic"`), and loads its samples.
    ///
    /// # Errors
    /// As [`weigh`](Self::weigh).
    pub fn make_elastic(&mut self) -> Result<(), AppError> {
        crate::loads::make_elastic(&mut self.robot.robot, "model")?;
        self.weigh()
    }

    /// Gives every sample the gravity torques of its configuration when the
    /// robot is elastic: from the robot file's masses and the sample's
    /// payload ([`gecaro_calib::elastic::load_samples`]). A rigid robot's
    /// samples are left alone.
    ///
    /// # Errors
    /// An elastic robot whose joints nothing loads (no masses in its file,
    /// no payload in the data), or a configuration that does not fit it.
    pub fn weigh(&mut self) -> Result<(), AppError> {
        let robot = &self.robot.robot;
        if !robot.is_elastic() {
            return Ok(());
        }
        let payloads = self
            .study
            .sets
            .iter()
            .flat_map(|set| set.samples.iter())
            .any(|sample| sample.payload().is_some());
        crate::loads::require_loads(&self.robot, payloads, "model")?;
        let heaviest = self
            .study
            .sets
            .iter()
            .flat_map(|set| set.samples.iter())
            .filter_map(|sample| sample.payload().copied())
            .max_by(|a, b| a.mass.total_cmp(&b.mass));
        if let Some(heaviest) = heaviest {
            crate::loads::require_carried(&self.robot, &heaviest, "payload_mass")?;
        }
        for set in &mut self.study.sets {
            gecaro_calib::elastic::load_samples(robot, &self.robot.masses, &mut set.samples)?;
        }
        Ok(())
    }
}

/// Something a user should know about a job's input or result.
#[derive(Clone, Debug, PartialEq)]
pub struct Note {
    /// A warning (something may be wrong), or a note.
    pub warning: bool,
    message: Vec<Part>,
}

impl Note {
    pub(crate) fn plain(message: impl Into<String>) -> Self {
        Note {
            warning: false,
            message: vec![Part::Text(message.into())],
        }
    }

    pub(crate) fn warning(message: impl Into<String>) -> Self {
        Note::warning_parts(vec![Part::Text(message.into())])
    }

    pub(crate) fn warning_parts(message: Vec<Part>) -> Self {
        Note {
            warning: true,
            message,
        }
    }

    /// The note in a front end's words.
    pub fn text(&self, dialect: crate::Dialect) -> String {
        crate::error::render(&self.message, dialect)
    }
}

/// Whether a job can work without measured data.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Data {
    /// Data are required.
    Required,
    /// Without data, the study has no samples: the job draws random
    /// configurations (identifiable parameters).
    Optional,
    /// The configurations of the data are what counts (a plan before it is
    /// measured): measurement columns need not be there.
    Configurations,
    /// None of the study's set files is read (a cell planned before it is
    /// measured: its plan writes them).
    Unmeasured,
}

impl Measurements {
    /// One method with its data file: what the command line's `ROBOT
    /// --method M --data FILE` gives.
    pub fn single(robot: RobotSource, method: MethodSpec, data: Option<DataSource>) -> Self {
        Measurements {
            robot: Some(robot),
            method: Some(method),
            data,
            ..Measurements::default()
        }
    }

    /// Loads the robot and the study, and checks the joint limits of the data.
    ///
    /// # Errors
    /// Missing or conflicting parts (a study with a robot, method or data;
    /// a method without robot), files that cannot be read, data that do not
    /// fit, joints outside their limits with `strict_limits`.
    pub fn load(&self, files: &dyn Files, data: Data) -> Result<Loaded, AppError> {
        let mut loaded = match &self.study {
            Some(study) => self.load_study(study, files, data)?,
            None => self.load_single(files, data)?,
        };
        if let Some(message) = loaded.study.limit_summary(&loaded.robot.robot) {
            if self.strict_limits {
                return Err(AppError::new(
                    ErrorKind::Input,
                    vec![
                        Part::Text(format!("{message} (")),
                        Part::Hint(Hint::StrictLimits),
                        Part::Text(" refuses such data)".into()),
                    ],
                ));
            }
            loaded.notes.push(Note {
                warning: true,
                message: vec![
                    Part::Text(format!("{message} (the data are used as they are; ")),
                    Part::Hint(Hint::StrictLimits),
                    Part::Text(" refuses them)".into()),
                ],
            });
        }
        loaded.weigh()?;
        Ok(loaded)
    }

    /// Loads the measurements a robot is evaluated on: with a study and a
    /// robot, the robot replaces the study's own (a calibrated robot on a
    /// held-out study of its cell); otherwise as [`load`](Self::load), data
    /// required.
    ///
    /// # Errors
    /// As [`load`](Self::load), and a robot the study's sets do not fit.
    pub fn load_evaluated(&self, files: &dyn Files) -> Result<Loaded, AppError> {
        let (Some(source), Some(robot)) = (&self.study, &self.robot) else {
            return self.load(files, Data::Required);
        };
        // A study stated in the request without a robot is read for the
        // request's robot already.
        if matches!(source, StudySource::Spec(spec) if spec.robot.is_none()) {
            return self.load(files, Data::Required);
        }
        let robot = robot.load(files)?;
        let study = Measurements {
            robot: None,
            ..self.clone()
        };
        let mut loaded = study.load(files, Data::Required)?;
        loaded.study.check(&robot.robot)?;
        loaded.robot = robot;
        loaded.weigh()?;
        Ok(loaded)
    }

    fn load_study(
        &self,
        study: &StudySource,
        files: &dyn Files,
        data: Data,
    ) -> Result<Loaded, AppError> {
        // A study stated in the request may take the request's robot (the
        // page's table); a study file names its own.
        let robot_with_spec = self.robot.is_some() && matches!(study, StudySource::Spec(_));
        if (self.robot.is_some() && !robot_with_spec)
            || self.method.is_some()
            || self.data.is_some()
        {
            return Err(AppError::setting(
                "study",
                "a study file names its robot, methods and data: give the study alone",
            ));
        }
        if self.sigma.is_some() || self.sigma_rotation.is_some() {
            return Err(AppError::setting(
                "sigma",
                "a study states the σ of each measurement set (sigma = … in its [[measurements]])",
            ));
        }
        if !self.format.is_default() {
            return Err(AppError::new(
                ErrorKind::Usage,
                vec![
                    Part::Setting("angle_unit".into()),
                    Part::Text(", ".into()),
                    Part::Setting("length_unit".into()),
                    Part::Text(" and ".into()),
                    Part::Setting("columns".into()),
                    Part::Text(" are for a data file; a study file gives them per set".into()),
                ],
            )
            .with_help(vec![Part::Text(
                "add length_unit = \"mm\", angle_unit = \"deg\" or columns = { x = \"X\" } to \
                 its [[measurements]]"
                    .into(),
            )]));
        }
        let read_for = match data {
            Data::Configurations => crate::StudyData::Configurations,
            Data::Unmeasured => crate::StudyData::Unmeasured,
            Data::Required | Data::Optional => crate::StudyData::Measured,
        };
        let (file, label) = match study {
            StudySource::File(name) => (
                crate::study_files::read_study(files, name, read_for)?,
                name.clone(),
            ),
            StudySource::Spec(spec) => {
                let given = self
                    .robot
                    .as_ref()
                    .map(|robot| robot.load(files))
                    .transpose()?;
                (
                    crate::study_files::build_study(files, spec, read_for, given.as_ref())?,
                    "study".to_owned(),
                )
            }
            StudySource::Loaded(study) => {
                return Ok(Loaded {
                    robot: study.robot.clone(),
                    study: study.study.clone(),
                    priority: study.priority.clone(),
                    prior: study.prior.clone(),
                    model: study.model.clone(),
                    label: study.label.clone(),
                    notes: Vec::new(),
                });
            }
        };
        Ok(Loaded {
            robot: file.robot,
            study: file.study,
            priority: file.priority,
            prior: file.prior,
            model: file.spec.model.clone(),
            label,
            notes: file.notes.into_iter().map(Note::plain).collect(),
        })
    }

    fn load_single(&self, files: &dyn Files, data: Data) -> Result<Loaded, AppError> {
        let (Some(robot), Some(method)) = (&self.robot, &self.method) else {
            return Err(AppError::new(
                ErrorKind::Usage,
                vec![
                    Part::Text("give a robot and a method (".into()),
                    Part::Setting("method".into()),
                    Part::Text("), or a study (".into()),
                    Part::Setting("study".into()),
                    Part::Text(")".into()),
                ],
            ));
        };
        let robot = robot.load(files)?;
        let method = method.build()?;
        let mut notes = Vec::new();
        let (samples, label) = match (&self.data, data) {
            (Some(source), _) => {
                let columns = if matches!(data, Data::Configurations | Data::Unmeasured) {
                    gecaro_calib::study::DataColumn::grouping(method.data_columns())
                } else {
                    method.data_columns().to_vec()
                };
                let read = source.read(
                    files,
                    &gecaro_io::joint_types(&robot.robot),
                    &columns,
                    &self.format.format()?,
                )?;
                if !read.unused_columns.is_empty()
                    && !matches!(data, Data::Configurations | Data::Unmeasured)
                {
                    notes.push(Note::plain(format!(
                        "{}: columns {} are not used by the {} method (left alone)",
                        read.label,
                        read.unused_columns.join(", "),
                        method.name()
                    )));
                }
                notes.extend(read.notes.iter().map(Note::plain));
                (read.samples, read.label)
            }
            (None, Data::Optional) => (Default::default(), "random configurations".to_owned()),
            (None, Data::Required | Data::Configurations | Data::Unmeasured) => {
                return Err(AppError::new(
                    ErrorKind::Usage,
                    vec![
                        Part::Text("no data: give the measurements (".into()),
                        Part::Setting("data".into()),
                        Part::Text(")".into()),
                    ],
                ));
            }
        };
        let mut study = Study::single(method, samples, label.clone());
        let units = self.format.format()?.units;
        let value = |setting: &str, sigma: &Option<StandardDeviation>, rotation: bool| {
            sigma
                .as_ref()
                .map(|sigma| sigma.value(rotation, units))
                .transpose()
                .map_err(|message| AppError::setting(setting, message))
        };
        study.sets[0].sigma = value("sigma", &self.sigma, false)?;
        study.sets[0].sigma_rotation = value("sigma_rotation", &self.sigma_rotation, true)?;
        Ok(Loaded {
            robot,
            study,
            priority: None,
            prior: None,
            model: None,
            label,
            notes,
        })
    }
}

/// Fields of a request that no job knows: collected so that a typo is an
/// error, not a setting silently ignored.
#[derive(Clone, Debug, Default, Deserialize)]
pub(crate) struct Unknown(BTreeMap<String, IgnoredAny>);

impl Unknown {
    /// Refuses unknown fields.
    ///
    /// # Errors
    /// [`ErrorKind::Usage`] naming the first unknown field.
    pub(crate) fn check(&self) -> Result<(), AppError> {
        match self.0.keys().next() {
            None => Ok(()),
            Some(field) => Err(AppError::plain(
                ErrorKind::Usage,
                format!("unknown field `{field}`"),
            )),
        }
    }
}
