//! The arguments of the calibration functions as the application layer's
//! measurements and settings: a robot with a `Method` and `Data`, or a
//! `Study`; a priority matrix as an array or a file.

use gecaro_app::{
    DataSource, FitSettings, LoadedStudy, Measurements, PrioritySource, RobotSource, StudySource,
};
use gecaro_calib::study::{Samples, Study};
use gecaro_core::Robot;
use pyo3::prelude::*;

use crate::data::PyData;
use crate::errors::input;
use crate::methods::method_of;
use crate::robot::PyRobot;
use crate::robot_inputs::priority_matrix;
use crate::study::PyStudy;

/// The measurements named by `(robot, method, data)` or `(robot, study,
/// None)`; without data only when `random_allowed` (identifiability on
/// random configurations).
pub(crate) fn measurements(
    robot: &PyRobot,
    method_or_study: &Bound<'_, PyAny>,
    data: Option<PyRef<'_, PyData>>,
    random_allowed: bool,
    strict_limits: bool,
) -> PyResult<Measurements> {
    let loaded = RobotSource::Loaded(Box::new(robot.file.clone()));
    if let Ok(study) = method_or_study.cast::<PyStudy>() {
        if data.is_some() {
            return Err(input(
                "a Study holds its data: give `data` only with a Method",
            ));
        }
        let study = study.borrow();
        return Ok(Measurements {
            study: Some(StudySource::Loaded(Box::new(LoadedStudy {
                robot: robot.file.clone(),
                study: study.study.clone(),
                priority: study.priority.clone(),
                prior: study.prior.clone(),
                model: study.spec.model.clone(),
                label: study
                    .label
                    .clone()
                    .unwrap_or_else(|| study.study.method_names()),
            }))),
            strict_limits,
            ..Measurements::default()
        });
    }
    let method = method_of(method_or_study)?;
    let method = method.get();
    let data = match data {
        Some(data) => Some(DataSource::Samples {
            samples: data.samples.clone(),
            label: data.label.clone(),
        }),
        None if random_allowed => None,
        None => {
            return Err(input(
                "no data: give `data` (a gecaro.Data) with the method, or a Study",
            ));
        }
    };
    let measurements = match &method.spec {
        Some(spec) => Measurements::single(loaded, spec.clone(), data),
        // A study file's method: its options are not known, only the method.
        None => {
            let (samples, label) = match data {
                Some(DataSource::Samples { samples, label }) => (samples, label),
                _ => (Samples::empty(), "random configurations".to_owned()),
            };
            Measurements {
                study: Some(StudySource::Loaded(Box::new(LoadedStudy {
                    robot: robot.file.clone(),
                    study: Study::single(method.method.clone_method(), samples, label.clone()),
                    priority: None,
                    prior: None,
                    model: None,
                    label,
                }))),
                ..Measurements::default()
            }
        }
    };
    Ok(Measurements {
        strict_limits,
        ..measurements
    })
}

/// A priority matrix given as an (n+2)×6 array or a priority file.
pub(crate) fn priority(
    robot: &Robot,
    value: Option<&Bound<'_, PyAny>>,
) -> PyResult<Option<PrioritySource>> {
    let Some(value) = value else {
        return Ok(None);
    };
    if let Ok(path) = value.extract::<std::path::PathBuf>() {
        return Ok(Some(PrioritySource::File(path.display().to_string())));
    }
    Ok(Some(PrioritySource::Matrix(priority_matrix(robot, value)?)))
}

/// The settings that `identify` and `cross_validate` take alike.
pub(crate) struct Fit<'a, 'py> {
    pub(crate) priority: Option<&'a Bound<'py, PyAny>>,
    pub(crate) model: &'a str,
    pub(crate) solver: &'a str,
    pub(crate) max_iterations: usize,
    pub(crate) loss: &'a str,
    pub(crate) loss_scale: Option<f64>,
    pub(crate) prior: Option<&'a str>,
}

/// The application layer's fit settings from Python's keywords.
pub(crate) fn fit_settings(robot: &PyRobot, fit: Fit<'_, '_>) -> PyResult<FitSettings> {
    Ok(FitSettings {
        priority: priority(robot.robot(), fit.priority)?,
        model: Some(fit.model.to_owned()),
        solver: Some(fit.solver.to_owned()),
        max_iterations: Some(fit.max_iterations),
        loss: Some(fit.loss.to_owned()),
        loss_scale: fit.loss_scale,
        prior: fit.prior.map(str::to_owned),
        ..FitSettings::default()
    })
}
