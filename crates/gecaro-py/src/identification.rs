//! Identification (paper §4, eq. 10–11) and evaluation: `gecaro.identify`,
//! `gecaro.evaluate` and their results. Each computes what the command
//! line's `gecaro identify` / `evaluate` computes, through the same
//! application layer, so the numbers are equal bit for bit; the results'
//! `to_dict()` is the command's `--json` document.

use gecaro_app::documents::{FrameJson, ObservabilityJson, OutlierJson, SummaryJson, VerdictJson};
use gecaro_app::{EvaluateRequest, FitSettings, Identified, IdentifyRequest, LocalFiles};
use gecaro_calib::identification::{
    ErrorSummary, IdentifiedParameter, ObservationErrors, StopReason,
};
use numpy::PyArrayDyn;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{array, columns};
use crate::data::PyData;
use crate::documents::{to_json, to_python};
use crate::errors::{IntoPyResult, NotConvergedError};
use crate::files::write_text;
use crate::interrupt::Watch;
use crate::robot::PyRobot;
use crate::sigma::Sigma;
use crate::source::{Fit, fit_settings, measurements};
use crate::warnings::warn_notes;

/// One identified parameter.
#[pyclass(name = "Parameter", module = "gecaro", frozen, get_all)]
pub(crate) struct PyParameter {
    /// Its name (`theta2`, `K1`, or an auxiliary unknown such as `a`).
    name: String,
    /// Its nominal value (metres, radians, or a gain).
    nominal: f64,
    /// Its identified value.
    identified: f64,
    /// Its standard deviation (eq. 11; posterior with a prior).
    std: f64,
    /// The part of `std` the measurement noise makes (below it where a prior
    /// holds the parameter).
    noise_std: f64,
    /// Its prior standard deviation, with a prior.
    prior_std: Option<f64>,
}

#[pymethods]
impl PyParameter {
    /// identified − nominal.
    #[getter]
    fn deviation(&self) -> f64 {
        self.identified - self.nominal
    }

    fn __repr__(&self) -> String {
        format!(
            "Parameter({:?}, nominal={}, identified={}, std={:.3e})",
            self.name, self.nominal, self.identified, self.std
        )
    }
}

fn parameter_list(parameters: &[IdentifiedParameter]) -> Vec<PyParameter> {
    parameters
        .iter()
        .map(|p| PyParameter {
            name: p.name.clone(),
            nominal: p.nominal,
            identified: p.identified,
            std: p.std,
            noise_std: p.noise_std,
            prior_std: p.prior_std,
        })
        .collect()
}

/// Error statistics over observations (metres; radians for orientations).
#[pyclass(name = "ErrorSummary", module = "gecaro", frozen)]
pub(crate) struct PyErrorSummary {
    summary: ErrorSummary,
}

#[pymethods]
impl PyErrorSummary {
    /// Root mean square of the position errors.
    #[getter]
    fn rms(&self) -> f64 {
        self.summary.rms
    }

    /// Mean of the position errors.
    #[getter]
    fn mean(&self) -> f64 {
        self.summary.mean
    }

    /// Largest position error.
    #[getter]
    fn max(&self) -> f64 {
        self.summary.max
    }

    /// Number of observations.
    #[getter]
    fn count(&self) -> usize {
        self.summary.count
    }

    /// RMS of the orientation errors, for methods that measure orientation.
    #[getter]
    fn rms_rotation(&self) -> Option<f64> {
        self.summary.rms_rotation
    }

    /// Largest orientation error, for methods that measure orientation.
    #[getter]
    fn max_rotation(&self) -> Option<f64> {
        self.summary.max_rotation
    }

    /// The document `gecaro evaluate --json` prints, as a dict.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &SummaryJson::from(&self.summary))
    }

    fn __repr__(&self) -> String {
        format!(
            "ErrorSummary(rms={:.4} mm, max={:.4} mm over {})",
            self.summary.rms * 1e3,
            self.summary.max * 1e3,
            self.summary.count
        )
    }
}

/// Names and the square array of a value per pair of them (a correlation matrix).
type NamedMatrix<'py> = (Vec<String>, Bound<'py, PyArrayDyn<f64>>);

/// The result of an identification.
#[pyclass(name = "Identification", module = "gecaro", frozen)]
pub(crate) struct PyIdentification {
    identified: Identified,
    calibrated: Py<PyRobot>,
}

fn errors_array<'py>(
    py: Python<'py>,
    errors: &ObservationErrors,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let values = errors
        .iter()
        .flat_map(|(length, angle)| [length, angle])
        .collect();
    array(py, &[errors.len(), 2], values)
}

#[pymethods]
impl PyIdentification {
    /// The calibrated robot, named `"<name> (calibrated)"`, as `identify -o`
    /// writes it.
    #[getter]
    fn calibrated(&self, py: Python<'_>) -> Py<PyRobot> {
        self.calibrated.clone_ref(py)
    }

    /// Whether the iteration converged.
    #[getter]
    fn converged(&self) -> bool {
        self.identified.result.stop_reason == StopReason::Converged
    }

    /// "converged", "iteration_limit" or "diverged".
    #[getter]
    fn stop_reason(&self) -> &'static str {
        self.identified.result.stop_reason.as_str()
    }

    /// The step rule that produced the result ("gauss_newton", "minimum_norm",
    /// "levenberg_marquardt").
    #[getter]
    fn route(&self) -> &'static str {
        self.identified.result.route.as_str()
    }

    /// Parameter updates done.
    #[getter]
    fn iterations(&self) -> usize {
        self.identified.result.iterations()
    }

    /// Every iterate from the nominal robot on: {"rms": residual RMS, "step":
    /// ‖Δη‖, "damping": λ (0 for Gauss–Newton)}, arrays of iterations + 1.
    #[getter]
    fn history<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        columns(
            py,
            &self.identified.result.history,
            &[
                ("rms", |r| r.rms),
                ("step", |r| r.step),
                ("damping", |r| r.damping),
            ],
        )
    }

    /// The identified base parameters (nominal, identified, σ).
    #[getter]
    fn parameters(&self) -> Vec<PyParameter> {
        parameter_list(&self.identified.result.parameters)
    }

    /// The identified auxiliary unknowns (plane coefficients).
    #[getter]
    fn auxiliary(&self) -> Vec<PyParameter> {
        parameter_list(&self.identified.result.auxiliary)
    }

    /// Parameters outside the base set that had to move.
    #[getter]
    fn moved(&self) -> Vec<PyParameter> {
        parameter_list(&self.identified.result.moved)
    }

    /// Errors at the nominal robot.
    #[getter]
    fn before(&self) -> PyErrorSummary {
        PyErrorSummary {
            summary: self.identified.result.before,
        }
    }

    /// Errors at the calibrated robot.
    #[getter]
    fn after(&self) -> PyErrorSummary {
        PyErrorSummary {
            summary: self.identified.result.after,
        }
    }

    /// Per-observation errors at the nominal robot, (observations, 2):
    /// position error (metres) and orientation error (radians, 0 when not
    /// measured).
    #[getter]
    fn errors_before<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        errors_array(py, &self.identified.result.errors_before)
    }

    /// Per-observation errors at the calibrated robot, as `errors_before`.
    #[getter]
    fn errors_after<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        errors_array(py, &self.identified.result.errors_after)
    }

    /// Each measured point's deviation from the calibrated robot's point,
    /// (observations, 3): measured minus calibrated (metres) along the
    /// robot's base frame 0 axes; NaN on observations that are not a
    /// measured point (links, planes, distances); `None` when the study
    /// measures no points or the robot is elastic (its sag is not in the
    /// rigid model these are taken with). The residuals CSV's `dx_mm`,
    /// `dy_mm`, `dz_mm`.
    #[getter]
    fn deviations<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArrayDyn<f64>>>> {
        let Some(points) = self.identified.point_deviations() else {
            return Ok(None);
        };
        let count = self.identified.result.errors_after.len();
        let mut values = vec![f64::NAN; count * 3];
        for point in points {
            values[point.index * 3..point.index * 3 + 3].copy_from_slice(&point.deviation);
        }
        array(py, &[count, 3], values).map(Some)
    }

    /// The correlation matrix of the identified unknowns, `(names, values)`:
    /// the auxiliary unknowns then the base parameters, `values` (k, k)
    /// symmetric with 1 on its diagonal (eq. 11's covariance scaled);
    /// `None` without a covariance.
    #[getter]
    fn correlation<'py>(&self, py: Python<'py>) -> PyResult<Option<NamedMatrix<'py>>> {
        let Some(correlation) = gecaro_app::correlation(&self.identified.result) else {
            return Ok(None);
        };
        let count = correlation.names.len();
        let values = correlation.values.into_iter().flatten().collect();
        Ok(Some((
            correlation.names,
            array(py, &[count, count], values)?,
        )))
    }

    /// Each named frame's identified origin covariance (m²), by its name, a
    /// (3, 3) array: its uncertainty ellipsoid (the page rings each station
    /// with it); frames whose origin was not identified are left out.
    #[getter]
    fn frame_covariances<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let covariances = PyDict::new(py);
        for (name, block) in gecaro_app::frame_covariances(&self.identified.result) {
            covariances.set_item(name, array(py, &[3, 3], block.concat())?)?;
        }
        Ok(covariances)
    }

    /// Condition number of W_b at the solution.
    #[getter]
    fn condition_number(&self) -> f64 {
        self.identified.result.condition_number
    }

    /// Observability indices {"o1", …, "o5"} of the data's W_b at the
    /// nominal robot (docs/planning.md).
    #[getter]
    fn observability<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(
            py,
            &ObservabilityJson::from(self.identified.result.observability()),
        )
    }

    /// Whether the result can be trusted: a dict with outcome ("fits_noise",
    /// "untested", "exceeds_noise", "below_noise", "incomplete",
    /// "implausible", "underdetermined", "repeated", "degenerate",
    /// "not_converged", "diverged"), trusted, summary, noise_test
    /// (chi_square, degrees_of_freedom, critical, critical_low, level,
    /// sigma_margin, sigma_ratio, passed; None without a stated sigma),
    /// residual_length (m), residual_angle (rad), configurations,
    /// distinct_configurations and copies (as `--json`).
    #[getter]
    fn verdict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &VerdictJson::from(&self.identified.result.verdict))
    }

    /// The study's named tools and stations at their identified poses: a
    /// list of dicts with name, role ("tool" or "station"), position (m),
    /// rpy (rad, about the fixed x, y, z axes) and quaternion [w, x, y, z],
    /// as `--json`'s `frames`.
    #[getter]
    fn frames<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let frames: Vec<FrameJson> = self
            .identified
            .result
            .frames
            .iter()
            .map(FrameJson::from)
            .collect();
        to_python(py, &frames)
    }

    /// Where the calibrated robot puts its base and its tool against the
    /// robot file: `base` (the base in the measurement frame: position m,
    /// rpy rad), `base_moved` ([distance m, angle rad] from the file's),
    /// `tool` (frame n+1 in the flange frame) and `tool_moved`, as
    /// `--json`'s `registration`.
    #[getter]
    fn registration<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.identified.registration())
    }

    /// Parameters the second pass added to the base set chosen at the
    /// nominal robot (docs/methods.md).
    #[getter]
    fn second_pass(&self) -> Vec<String> {
        self.identified.result.second_pass.clone()
    }

    /// Parameters outside the base set that the data set (the closed-form
    /// start, the continuation or the damped descent moved them) and that
    /// base parameters absorb: identified beside the base set under the
    /// second pass's weak prior (docs/methods.md, "Precision").
    #[getter]
    fn joined(&self) -> Vec<String> {
        self.identified.result.joined.clone()
    }

    /// Standard deviation of the residual (eq. 11).
    #[getter]
    fn residual_sigma(&self) -> f64 {
        self.identified.result.residual_sigma
    }

    /// Structural base parameters that the data do not excite.
    #[getter]
    fn not_excited(&self) -> Vec<String> {
        self.identified.result.not_excited.clone()
    }

    /// What the user should know about the result.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.identified
            .result
            .warnings
            .iter()
            .map(ToString::to_string)
            .collect()
    }

    /// The loss minimised: "l2", "huber", "cauchy" or "tukey".
    #[getter]
    fn loss(&self) -> &'static str {
        self.identified.result.loss.kind.as_str()
    }

    /// The robust σ̂ of the residuals at the solution (units of the sensor σ).
    #[getter]
    fn robust_sigma(&self) -> f64 {
        self.identified.result.robust_sigma
    }

    /// Observations beyond the outlier threshold, worst first: dicts with
    /// set, file, kind, observation (1-based), lines, error (m),
    /// rotation_error, residual_sigmas and weight (as `--json`).
    #[getter]
    fn outliers<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &OutlierJson::list(&self.identified.result.outliers))
    }

    /// Observations dropped before this fit (`reject=True`), as `outliers`.
    #[getter]
    fn rejected<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &OutlierJson::list(&self.identified.result.rejected))
    }

    /// The document `gecaro identify --json` prints, as a dict.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.identified.document())
    }

    /// The document `gecaro identify --json` prints.
    fn to_json(&self) -> PyResult<String> {
        to_json(&self.identified.document())
    }

    /// The self-contained HTML report (`gecaro report`); written atomically
    /// to `path` too when given.
    #[pyo3(signature = (path = None, *, overwrite = false))]
    fn report(
        &self,
        py: Python<'_>,
        path: Option<std::path::PathBuf>,
        overwrite: bool,
    ) -> PyResult<String> {
        let html = py
            .detach(|| self.identified.report("gecaro.identify (Python)"))
            .py()?;
        if let Some(path) = path {
            write_text(&path, "html", &html, overwrite)?;
        }
        Ok(html)
    }

    /// Every observation's error before and after, with its file and lines,
    /// as CSV text (`gecaro identify --residuals`; columns in
    /// docs/methods.md); written atomically to `path` too when given.
    #[pyo3(signature = (path = None, *, overwrite = false))]
    fn residuals_csv(&self, path: Option<std::path::PathBuf>, overwrite: bool) -> PyResult<String> {
        let text = self.identified.residuals_csv().py()?;
        if let Some(path) = path {
            write_text(&path, "csv", &text, overwrite)?;
        }
        Ok(text)
    }

    fn __repr__(&self) -> String {
        format!(
            "Identification({}, {} parameters, {} after {} iterations, RMS {:.4} → {:.4} mm)",
            self.identified.loaded.study.method_names(),
            self.identified.result.parameters.len(),
            self.identified.result.stop_reason.as_str(),
            self.identified.result.iterations(),
            self.identified.result.before.rms * 1e3,
            self.identified.result.after.rms * 1e3
        )
    }
}

/// Identification (paper §4, eq. 10–11): iterative linearised least squares
/// on the identifiable parameters, W rebuilt at every iterate, until the step
/// is negligible; `solver` "gauss-newton" (the paper's) or "lm". As
/// `gecaro identify`: the same result for the same inputs. Runs without the
/// GIL; Ctrl-C interrupts it. `progress(iteration, rms)` is called after
/// every iterate (an exception from it stops the identification).
///
/// Raises NotConvergedError (with the best iterate in `.result`) when the
/// iteration did not converge, NotIdentifiableError with too few equations.
#[pyfunction]
#[pyo3(signature = (robot, method, data = None, *, solver = "gauss-newton", max_iterations = 30, priority = None, loss = "l2", loss_scale = None, prior = None, outlier_threshold = 3.0, reject = false, model = "full", strict_limits = false, sigma = None, sigma_rotation = None, work_region = None, check_model = None, progress = None))]
pub(crate) fn identify(
    py: Python<'_>,
    robot: PyRef<'_, PyRobot>,
    method: &Bound<'_, PyAny>,
    data: Option<PyRef<'_, PyData>>,
    solver: &str,
    max_iterations: usize,
    priority: Option<&Bound<'_, PyAny>>,
    loss: &str,
    loss_scale: Option<f64>,
    prior: Option<&str>,
    outlier_threshold: f64,
    reject: bool,
    model: &str,
    strict_limits: bool,
    sigma: Option<Sigma>,
    sigma_rotation: Option<Sigma>,
    work_region: Option<&str>,
    check_model: Option<bool>,
    progress: Option<Py<PyAny>>,
) -> PyResult<PyIdentification> {
    let mut request =
        IdentifyRequest::new(measurements(&robot, method, data, false, strict_limits)?);
    request.measurements.sigma = sigma.map(Into::into);
    request.measurements.sigma_rotation = sigma_rotation.map(Into::into);
    request.check_model = check_model;
    request.settings = FitSettings {
        outlier_threshold: Some(outlier_threshold),
        reject,
        work_region: work_region.map(str::to_owned),
        ..fit_settings(
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
        )?
    };
    let prepared = request.prepare(&LocalFiles).py()?;
    warn_notes(py, &prepared.loaded.notes)?;
    let identified = py.detach(|| {
        let mut watch = Watch::with_callback(progress);
        let result = prepared.run(&mut watch);
        watch.finish(result)
    })?;
    warn_notes(py, &identified.advice_notes())?;
    let failure = identified.failure();
    let identification = PyIdentification {
        calibrated: Py::new(py, PyRobot::new(identified.calibrated()))?,
        identified,
    };
    match failure {
        None => Ok(identification),
        Some(failure) => {
            let error = NotConvergedError::new_err(format!(
                "{}. The exception's `result` holds the best iterate; try solver=\"lm\", \
                 a larger max_iterations, or check the data.",
                failure.message(gecaro_app::Dialect::Python)
            ));
            error
                .value(py)
                .setattr("result", Py::new(py, identification)?)?;
            Err(error)
        }
    }
}

/// Errors of `robot` on measured data (a Method with Data, or a Study): the
/// distance to the measured point (position, frame), to the set's mean point
/// (links), to the plane, or the distance error (pairs). As `gecaro evaluate`.
/// `register` (`"30%"`, `"all"`): data measured in another frame, registered
/// in closed form on that share of the rows and judged on the others.
#[pyfunction]
#[pyo3(signature = (robot, method, data = None, *, strict_limits = false, register = None))]
pub(crate) fn evaluate(
    py: Python<'_>,
    robot: PyRef<'_, PyRobot>,
    method: &Bound<'_, PyAny>,
    data: Option<PyRef<'_, PyData>>,
    strict_limits: bool,
    register: Option<String>,
) -> PyResult<PyErrorSummary> {
    let mut request =
        EvaluateRequest::new(measurements(&robot, method, data, false, strict_limits)?);
    request.register = register;
    let evaluation = py.detach(|| request.run(&LocalFiles)).py()?;
    warn_notes(py, &evaluation.loaded.notes)?;
    Ok(PyErrorSummary {
        summary: evaluation.summary,
    })
}
