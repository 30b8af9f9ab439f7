//! `gecaro.Study`: several measurement sets calibrated together, each with its
//! method, data and sensor σ (rows weighted by 1/σ), as a study file holds them.

use gecaro_app::documents::FrameJson;
use gecaro_app::{
    FrameSpec, MethodChoice, SetData, SetSpec, SpecField, StudyData, StudyFiles, StudySpec,
};
use gecaro_calib::frames::FrameRole;
use gecaro_calib::study::Study;
use gecaro_core::PriorityMatrix;
use gecaro_io::StandardDeviation;
use numpy::PyArrayDyn;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

use crate::arrays::priority_array;
use crate::data::PyData;
use crate::errors::IntoPyResult;
use crate::methods::PyMethod;
use crate::methods::method_of;
use crate::robot::PyRobot;
use crate::sigma::Sigma;

/// Measurement sets calibrated together (see the module docs).
#[pyclass(name = "Study", module = "gecaro")]
pub(crate) struct PyStudy {
    /// The study as stated: what `add`, `add_tool` and `add_station` fill,
    /// built by the rules of every front end ([`StudySpec`]).
    pub(crate) spec: StudySpec,
    /// The study built from `spec`.
    pub(crate) study: Study,
    /// The robot of the study file, when read from one.
    robot: Option<Py<PyRobot>>,
    /// The study file's priority matrix, if it has one.
    pub(crate) priority: Option<PriorityMatrix>,
    /// The study file's prior, if it has one.
    pub(crate) prior: Option<gecaro_calib::identification::Prior>,
    notes: Vec<String>,
    /// The study file, for messages and the calibrated robot's description.
    pub(crate) label: Option<String>,
}

/// A study's sets given as arrays: no file to read; a field at fault is
/// named by its argument.
struct InMemory;

/// A problem of a study filled from Python.
struct Problem(String);

impl From<gecaro_io::Error> for Problem {
    fn from(error: gecaro_io::Error) -> Self {
        Problem(error.to_string())
    }
}

impl StudyFiles for InMemory {
    type Error = Problem;

    fn robot(&self, name: &str) -> Result<gecaro_io::RobotFile, Problem> {
        Err(Problem(format!(
            "a Study built in Python takes no robot file ({name})"
        )))
    }

    fn priority(&self, name: &str, _: &gecaro_core::Robot) -> Result<PriorityMatrix, Problem> {
        Err(Problem(format!(
            "a Study built in Python takes no priority file ({name})"
        )))
    }

    fn samples(
        &self,
        name: &str,
        _: &[gecaro_core::FrameType],
        _: &[gecaro_calib::study::DataColumn],
        _: &gecaro_io::DataFormat,
    ) -> Result<(gecaro_io::DataFile, String), Problem> {
        Err(Problem(format!(
            "a Study built in Python takes Data, not files ({name})"
        )))
    }

    fn misplaced(&self, field: &SpecField, message: String) -> Problem {
        Problem(match field {
            SpecField::Set(_, key) | SpecField::Frame(_, _, key) | SpecField::Top(key) => {
                format!("{key}: {message}")
            }
        })
    }
}

impl PyStudy {
    /// Takes `spec` when its study can be built (every named frame need not
    /// be measured yet: `identify` checks that).
    fn restate(&mut self, spec: StudySpec) -> PyResult<()> {
        let (study, _) = spec
            .build_study(&InMemory, None, StudyData::Measured, false)
            .map_err(|Problem(message)| crate::errors::input(message))?;
        self.spec = spec;
        self.study = study;
        Ok(())
    }

    fn add_frame(
        &mut self,
        name: String,
        role: FrameRole,
        position: [f64; 3],
        rpy: Option<[f64; 3]>,
        quaternion: Option<[f64; 4]>,
    ) -> PyResult<()> {
        if self.spec.tools.contains_key(&name) || self.spec.stations.contains_key(&name) {
            return Err(crate::errors::input(format!(
                "a tool or station is already named {name:?}"
            )));
        }
        let mut spec = self.spec.clone();
        let frames = match role {
            FrameRole::Tool => &mut spec.tools,
            FrameRole::Station => &mut spec.stations,
        };
        frames.insert(
            name,
            FrameSpec {
                position: position.to_vec(),
                rpy: rpy.map(|rpy| rpy.to_vec()),
                quaternion: quaternion.map(|quaternion| quaternion.to_vec()),
                ..FrameSpec::default()
            },
        );
        self.restate(spec)
    }
}

#[pymethods]
impl PyStudy {
    /// An empty study; fill it with `add`.
    #[new]
    fn new() -> Self {
        PyStudy {
            spec: StudySpec::default(),
            study: Study::default(),
            robot: None,
            priority: None,
            prior: None,
            notes: Vec::new(),
            label: None,
        }
    }

    /// Adds a measurement set: `data` measured by `method` (a Method or its
    /// name) with a sensor of standard deviation `sigma` (metres, or a text
    /// with its unit, `"20um"`; also the orientations' unless
    /// `sigma_rotation` is given: radians, or `"0.01deg"`).
    ///
    /// `tool` and `station` name a tool or station added with `add_tool` or
    /// `add_station`: the set measures that reflector, from that station
    /// (docs/studies.md).
    #[pyo3(signature = (method, data, *, sigma = None, sigma_rotation = None, label = None, tool = None, station = None))]
    fn add(
        &mut self,
        method: &Bound<'_, PyAny>,
        data: PyRef<'_, PyData>,
        sigma: Option<Sigma>,
        sigma_rotation: Option<Sigma>,
        label: Option<String>,
        tool: Option<String>,
        station: Option<String>,
    ) -> PyResult<()> {
        let method = method_of(method)?;
        let mut spec = self.spec.clone();
        spec.measurements.push(SetSpec {
            method: MethodChoice::Built(method.get().method.clone_method()),
            data: SetData::Samples {
                samples: Box::new(data.samples.clone()),
                label: data.label.clone(),
            },
            sigma: sigma.map(StandardDeviation::from),
            sigma_rotation: sigma_rotation.map(StandardDeviation::from),
            label,
            tool,
            station,
            ..SetSpec::default()
        });
        self.restate(spec)
    }

    /// Names a tool (a reflector): its pose in the robot's tool frame n+1 (a
    /// URDF's `tool0`), `position` in metres, `rpy` (radians, about the
    /// fixed x, y, z axes) or a unit `quaternion` [w, x, y, z]. Its pose is
    /// identified with the robot.
    #[pyo3(signature = (name, position, *, rpy = None, quaternion = None))]
    fn add_tool(
        &mut self,
        name: String,
        position: [f64; 3],
        rpy: Option<[f64; 3]>,
        quaternion: Option<[f64; 4]>,
    ) -> PyResult<()> {
        self.add_frame(name, FrameRole::Tool, position, rpy, quaternion)
    }

    /// Names a station (a measurement frame): its pose in the world frame, as
    /// `add_tool`. Sets measured from it give poses in its frame.
    #[pyo3(signature = (name, position, *, rpy = None, quaternion = None))]
    fn add_station(
        &mut self,
        name: String,
        position: [f64; 3],
        rpy: Option<[f64; 3]>,
        quaternion: Option<[f64; 4]>,
    ) -> PyResult<()> {
        self.add_frame(name, FrameRole::Station, position, rpy, quaternion)
    }

    /// The named tools and stations: a list of dicts with name, role,
    /// position (m), rpy (rad) and quaternion, as stated.
    #[getter]
    fn frames<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let frames: Vec<FrameJson> = self.study.frames.iter().map(FrameJson::from).collect();
        pythonize::pythonize(py, &frames).map_err(|error| PyValueError::new_err(error.to_string()))
    }

    /// Reads a study file (TOML: the robot, a priority matrix, and
    /// `[[measurements]]` with method, data file, σ, units), as `--study`.
    #[staticmethod]
    fn read(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let mut file = gecaro_app::read_study_file(&path).py()?;
        // The sets' data are read: later sets added in Python need no files.
        let spec = file.spec_in_memory();
        Ok(PyStudy {
            spec,
            study: file.study,
            robot: Some(Py::new(py, PyRobot::new(file.robot))?),
            priority: file.priority,
            prior: file.prior,
            notes: file.notes,
            label: Some(path.display().to_string()),
        })
    }

    /// The study file's robot (None for a study built with `add`).
    #[getter]
    fn robot(&self, py: Python<'_>) -> Option<Py<PyRobot>> {
        self.robot.as_ref().map(|robot| robot.clone_ref(py))
    }

    /// The study file's priority matrix, if it sets one (used by `identify`
    /// and `identifiable` unless they are given another).
    #[getter]
    fn priority<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArrayDyn<i64>>>> {
        self.priority
            .as_ref()
            .map(|matrix| priority_array(py, matrix.rows()))
            .transpose()
    }

    /// Notes of the study file's reading (columns left alone, …).
    #[getter]
    fn notes(&self) -> Vec<String> {
        self.notes.clone()
    }

    /// The sets: a list of dicts with `method`, `data`, `sigma`,
    /// `sigma_rotation` and `label`.
    #[getter]
    fn sets<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        self.study
            .sets
            .iter()
            .map(|set| {
                let entry = PyDict::new(py);
                let joint_count = set
                    .samples
                    .iter()
                    .next()
                    .map_or(0, |s| s.motor_positions().len());
                entry.set_item("method", PyMethod::from_method(set.method.clone_method()))?;
                entry.set_item(
                    "data",
                    PyData::from_samples(set.samples.clone(), joint_count, set.label.clone()),
                )?;
                entry.set_item("sigma", set.sigma)?;
                entry.set_item("sigma_rotation", set.sigma_rotation)?;
                entry.set_item("label", &set.label)?;
                Ok(entry)
            })
            .collect()
    }

    /// The methods of the sets, joined with `+`.
    #[getter]
    fn methods(&self) -> String {
        self.study.method_names()
    }

    fn __len__(&self) -> usize {
        self.study.sets.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "Study({} sets: {})",
            self.study.sets.len(),
            self.study
                .sets
                .iter()
                .map(|set| format!(
                    "{} ({} configurations)",
                    set.method.name(),
                    set.samples.len()
                ))
                .collect::<Vec<_>>()
                .join(", ")
        )
    }
}
