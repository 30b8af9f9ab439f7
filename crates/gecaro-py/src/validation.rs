//! Held-out error as the judge (docs/methods.md): `gecaro.cross_validate`.

use gecaro_app::{IdentifyRequest, LocalFiles};
use pyo3::prelude::*;

use crate::data::PyData;
use crate::documents::to_python;
use crate::errors::IntoPyResult;
use crate::interrupt::watched;
use crate::robot::PyRobot;
use crate::source::{Fit, fit_settings, measurements};
use crate::warnings::warn_notes;

/// K-fold cross-validation of an identification (folds by configuration,
/// set or pair, seeded; or `folds_by="regions"`, the ends of each joint's
/// measured range), as `gecaro identify --cv K`: the document of
/// `"cross_validation"` (held-out RMS per fold and overall, metres and
/// radians). Options as `identify`.
#[pyfunction]
#[pyo3(signature = (robot, method, data = None, *, folds = 5, seed = 1, folds_by = "random", solver = "gauss-newton", max_iterations = 30, priority = None, loss = "l2", loss_scale = None, prior = None, model = "full", strict_limits = false))]
pub(crate) fn cross_validate<'py>(
    py: Python<'py>,
    robot: PyRef<'_, PyRobot>,
    method: &Bound<'py, PyAny>,
    data: Option<PyRef<'_, PyData>>,
    folds: usize,
    seed: u64,
    folds_by: &str,
    solver: &str,
    max_iterations: usize,
    priority: Option<&Bound<'py, PyAny>>,
    loss: &str,
    loss_scale: Option<f64>,
    prior: Option<&str>,
    model: &str,
    strict_limits: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let mut request =
        IdentifyRequest::new(measurements(&robot, method, data, false, strict_limits)?);
    request.settings = fit_settings(
        &robot,
        Fit {
            priority,
            model,
            solver,
            max_iterations,
            loss,
            loss_scale,
            prior,
        },
    )?;
    request.cv = Some(folds);
    request.seed = Some(seed);
    request.folds_by = Some(folds_by.to_owned());
    let prepared = request.prepare(&LocalFiles).py()?;
    warn_notes(py, &prepared.loaded.notes)?;
    let validation = watched(py, |observer| prepared.cross_validate(observer))?;
    to_python(
        py,
        &gecaro_app::documents::CrossValidationJson::new(&validation),
    )
}
