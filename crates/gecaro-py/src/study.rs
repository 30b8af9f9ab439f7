//! `gecaro.Study`: several measurement sets calibrated together, each with its
//! method, data and sensor σ (rows weighted by 1/σ), as a study file holds them.

use gecaro_calib::study::{MeasurementSet, Study};
use gecaro_core::PriorityMatrix;
use numpy::PyArrayDyn;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

use crate::arrays::priority_array;
use crate::data::PyData;
use crate::errors::IntoPyResult;
use crate::methods::PyMethod;
use crate::methods::method_of;
use crate::robot::PyRobot;

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
    /// name) with a sensor of standard deviation `sigma` (metres; also
    /// radians for orientations unless `sigma_rotation` is given).
    #[pyo3(signature = (method, data, *, sigma = None, sigma_rotation = None, label = None))]
    fn add(
        &mut self,
        method: &Bound<'_, PyAny>,
        data: PyRef<'_, PyData>,
        sigma: Option<f64>,
        sigma_rotation: Option<f64>,
        label: Option<String>,
    ) -> PyResult<()> {
        let method = method_of(method)?;
        self.study.sets.push(MeasurementSet {
            method: method.get().method.clone_method(),
            samples: data.samples.clone(),
            sigma,
            sigma_rotation,
            label: label.unwrap_or_else(|| data.label.clone()),
            tool: None,
            station: None,
        });
        Ok(())
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
