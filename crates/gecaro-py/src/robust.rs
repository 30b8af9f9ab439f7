//! The Python face of measurements as they are (docs/methods.md): the loss,
//! prior, outlier and model options of `identify`, and `cross_validate`.
use gecaro_calib::{
    identification::{IdentificationOptions, Loss, LossKind, Prior},
    validation::Model,
};
use gecaro_core::Robot;
use pyo3::prelude::*;

use crate::errors::{IntoPyResult, input};
use crate::interrupt::Watch;

/// The keyword options shared by `identify` and `cross_validate` beyond the
/// solver's.
pub(crate) struct RobustArguments<'a> {
    pub(crate) loss: &'a str,
    pub(crate) loss_scale: Option<f64>,
    pub(crate) prior: Option<&'a str>,
    pub(crate) outlier_threshold: f64,
    pub(crate) reject: bool,
    pub(crate) model: &'a str,
}

impl RobustArguments<'_> {
    /// The identification options they give, on top of `base` (solver,
    /// iterations, priority), with the study file's prior if `prior` is not given.
    pub(crate) fn options(
        &self,
        robot: &Robot,
        base: IdentificationOptions,
        study_prior: Option<Prior>,
    ) -> PyResult<IdentificationOptions> {
        let kind: LossKind = self.loss.parse().py()?;
        let loss = Loss::from_parts(kind, self.loss_scale).py()?;
        let prior = match self.prior {
            Some(text) => {
                let mut prior = gecaro_io::parse_prior(text)
                    .map_err(|message| input(format!("prior: {message}")))?;
                prior.overrides = study_prior.map(|p| p.overrides).unwrap_or_default();
                Some(prior)
            }
            None => study_prior,
        };
        let priority = self
            .model
            .parse::<Model>()
            .py()?
            .priority(robot, base.priority.as_ref());
        Ok(IdentificationOptions {
            loss,
            prior,
            outlier_threshold: self.outlier_threshold,
            reject: self.reject,
            priority: Some(priority),
            ..base
        })
    }
}

/// K-fold cross-validation of an identification (folds by configuration,
/// set or pair, seeded), as `gecaro identify --cv K`: the document of
/// `"cross_validation"` (held-out RMS per fold and overall, metres and
/// radians). Options as `identify`.
#[pyfunction]
#[pyo3(signature = (robot, method, data = None, *, folds = 5, seed = 1, solver = "gauss-newton", max_iterations = 30, priority = None, loss = "l2", loss_scale = None, prior = None, model = "full", strict_limits = false))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn cross_validate<'py>(
    py: Python<'py>,
    robot: PyRef<'_, crate::robot::PyRobot>,
    method: &Bound<'py, PyAny>,
    data: Option<PyRef<'_, crate::data::PyData>>,
    folds: usize,
    seed: u64,
    solver: &str,
    max_iterations: usize,
    priority: Option<&Bound<'py, PyAny>>,
    loss: &str,
    loss_scale: Option<f64>,
    prior: Option<&str>,
    model: &str,
    strict_limits: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let nominal = robot.robot();
    let source = crate::calibration::source(method, data, false)?;
    crate::calibration::check_limits(py, nominal, &source.study, strict_limits)?;
    let base = crate::calibration::solver_options(
        nominal,
        solver,
        max_iterations,
        priority,
        source.priority,
    )?;
    let arguments = RobustArguments {
        loss,
        loss_scale,
        prior,
        outlier_threshold: gecaro_calib::identification::DEFAULT_OUTLIER_THRESHOLD,
        reject: false,
        model,
    };
    let options = arguments.options(nominal, base, source.prior)?;
    let study = &source.study;
    let validation = py.detach(|| {
        let mut watch = Watch::new();
        let result = gecaro_calib::validation::cross_validate(
            nominal,
            study,
            &options,
            folds,
            seed,
            &mut |_: gecaro_calib::Progress<'_>| watch.poll(),
        );
        watch.finish(result)
    })?;
    let document = gecaro_report::json::CrossValidationJson::new(&validation, seed);
    crate::calibration::json_to_python(py, &crate::calibration::to_json(&document)?)
}
