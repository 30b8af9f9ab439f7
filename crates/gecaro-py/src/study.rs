//! `gecaro.Study`: several measurement sets calibrated together, each with its
//! method, data and sensor σ (rows weighted by 1/σ), as a study file holds them.

use gecaro_app::documents::FrameJson;
use gecaro_calib::frames::{FrameRole, NamedFrame};
use gecaro_calib::study::{MeasurementSet, Study};
use gecaro_core::PriorityMatrix;
use nalgebra::{IsometryMatrix3, Rotation3, Translation3, Vector3};
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

impl PyStudy {
    /// The index of the named frame `name` of `role`, or `None`.
    fn frame_index(&self, name: Option<&str>, role: FrameRole) -> PyResult<Option<usize>> {
        let Some(name) = name else { return Ok(None) };
        self.study
            .frames
            .iter()
            .position(|frame| frame.name == name && frame.role == role)
            .map(Some)
            .ok_or_else(|| {
                PyValueError::new_err(format!(
                    "no {} named {name:?}: add it with add_{}",
                    role.as_str(),
                    role.as_str()
                ))
            })
    }

    fn add_frame(
        &mut self,
        name: String,
        role: FrameRole,
        position: [f64; 3],
        rpy: Option<[f64; 3]>,
        quaternion: Option<[f64; 4]>,
    ) -> PyResult<()> {
        if self.study.frames.iter().any(|frame| frame.name == name) {
            return Err(PyValueError::new_err(format!(
                "a tool or station is already named {name:?}"
            )));
        }
        if !position.iter().all(|v| v.is_finite()) {
            return Err(PyValueError::new_err(format!(
                "position of {name:?} must be finite, not {position:?}"
            )));
        }
        let rotation = match (rpy, quaternion) {
            (Some(_), Some(_)) => {
                return Err(PyValueError::new_err(
                    "give the orientation as rpy or as a quaternion, not both",
                ));
            }
            (Some([roll, pitch, yaw]), None) => {
                if ![roll, pitch, yaw].iter().all(|v| v.is_finite()) {
                    return Err(PyValueError::new_err(format!(
                        "rpy of {name:?} must be finite"
                    )));
                }
                Rotation3::from_euler_angles(roll, pitch, yaw)
            }
            (None, Some([w, x, y, z])) => gecaro_io::unit_quaternion(w, x, y, z)
                .map_err(PyValueError::new_err)?
                .to_rotation_matrix(),
            (None, None) => Rotation3::identity(),
        };
        self.study.frames.push(NamedFrame {
            name,
            role,
            pose: IsometryMatrix3::from_parts(
                Translation3::from(Vector3::from(position)),
                rotation,
            ),
        });
        Ok(())
    }
}

#[pymethods]
impl PyStudy {
    /// An empty study; fill it with `add`.
    #[new]
    fn new() -> Self {
        PyStudy {
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
    #[allow(clippy::too_many_arguments)]
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
        let tool = self.frame_index(tool.as_deref(), FrameRole::Tool)?;
        let station = self.frame_index(station.as_deref(), FrameRole::Station)?;
        if (tool.is_some() || station.is_some())
            && !method
                .get()
                .method
                .data_columns()
                .contains(&gecaro_calib::study::DataColumn::Position)
        {
            return Err(PyValueError::new_err(format!(
                "the {} method measures no pose in a measurement frame; tools and stations go \
                 with position and frame measures",
                method.get().method.name()
            )));
        }
        // The rule of every front end (a Data holds metres and radians).
        let value = |name: &str, sigma: Option<Sigma>, rotation: bool| {
            sigma
                .map(|sigma| {
                    gecaro_io::StandardDeviation::from(sigma)
                        .value(rotation, gecaro_io::DataUnits::default())
                        .map_err(|message| crate::errors::input(format!("{name}: {message}")))
                })
                .transpose()
        };
        let sigma = value("sigma", sigma, false)?;
        let sigma_rotation = value("sigma_rotation", sigma_rotation, true)?;
        self.study.sets.push(MeasurementSet {
            method: method.get().method.clone_method(),
            samples: data.samples.clone(),
            sigma,
            sigma_rotation,
            label: label.unwrap_or_else(|| data.label.clone()),
            tool,
            station,
        });
        Ok(())
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
        let file = gecaro_io::read_study_file(&path).py()?;
        Ok(PyStudy {
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
                let joint_count = set.samples.first().map_or(0, |s| s.motor_positions.len());
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
