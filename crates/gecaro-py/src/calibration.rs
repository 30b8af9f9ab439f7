//! The paper's three functions per method, and evaluation: `generate`
//! (points generation), `identifiable` (Appendix III), `identify` (eq. 10–11,
//! the iterative linearised least squares), `evaluate`. Each computes what the
//! command line's `gecaro generate / identifiable / identify / evaluate`
//! computes, with the same defaults and seeds, so the numbers are equal bit
//! for bit; the results' `to_dict()` is the command's `--json` document.

use gecaro_calib::{
    Progress,
    identifiability::identifiability,
    identification::{
        ErrorSummary, Identification, IdentificationOptions, IdentifiedParameter, Solver,
        StopReason, evaluate as evaluate_study,
    },
    simulation::{Sampler, perturbed_robot, simulate_measurements, terminal_displacement},
    study::Study,
};
use gecaro_core::{PriorityMatrix, Robot};
use gecaro_io::RobotFile;
use gecaro_report::json::{IdentifiableJson, IdentificationJson, OutlierJson, SummaryJson};
use numpy::PyArrayDyn;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::ffi::CString;

use crate::arrays::{array, columns, priority_array};
use crate::data::PyData;
use crate::errors::{IntoPyResult, LimitWarning, NotConvergedError, input};
use crate::interrupt::Watch;
use crate::methods::PyMethod;
use crate::robot::{PyRobot, output_policy, priority_matrix};
use crate::study::PyStudy;

/// A `Method`, or a method's name with default options.
pub(crate) fn method_of<'py>(value: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyMethod>> {
    if let Ok(method) = value.cast::<PyMethod>() {
        return Ok(method.clone());
    }
    if let Ok(name) = value.extract::<String>() {
        return Bound::new(value.py(), PyMethod::named(&name)?);
    }
    Err(input(format!(
        "expected a gecaro.Method or a method's name, got {}",
        value.get_type().name()?
    )))
}

/// What a calibration function works on: the study, its priority matrix (if
/// the study file has one) and its label.
pub(crate) struct Source {
    pub(crate) study: Study,
    pub(crate) priority: Option<PriorityMatrix>,
    /// The study file's prior, if it has one.
    pub(crate) prior: Option<gecaro_calib::identification::Prior>,
    pub(crate) label: String,
}

/// The study named by `(method, data)` or `(study, None)`; `data` may be
/// missing only when `random_allowed` (identifiability on random data).
pub(crate) fn source(
    method_or_study: &Bound<'_, PyAny>,
    data: Option<PyRef<'_, PyData>>,
    random_allowed: bool,
) -> PyResult<Source> {
    if let Ok(study) = method_or_study.cast::<PyStudy>() {
        if data.is_some() {
            return Err(input(
                "a Study holds its data: give `data` only with a Method",
            ));
        }
        let study = study.borrow();
        return Ok(Source {
            study: study.study.clone(),
            priority: study.priority.clone(),
            prior: study.prior.clone(),
            label: study
                .label
                .clone()
                .unwrap_or_else(|| study.study.method_names()),
        });
    }
    let method = method_of(method_or_study)?;
    let method = method.get().method.clone_method();
    match data {
        Some(data) => Ok(Source {
            study: Study::single(method, data.samples.clone(), data.label.clone()),
            priority: None,
            prior: None,
            label: data.label.clone(),
        }),
        None if random_allowed => Ok(Source {
            study: Study::single(method, Vec::new(), "random configurations"),
            priority: None,
            prior: None,
            label: "random configurations".into(),
        }),
        None => Err(input(
            "no data: give `data` (a gecaro.Data) with the method, or a Study",
        )),
    }
}

/// Joint values outside the limits: a `LimitWarning`, or with `strict` an
/// `InputError`, as the command line's `--strict-limits`.
pub(crate) fn check_limits(
    py: Python<'_>,
    robot: &Robot,
    study: &Study,
    strict: bool,
) -> PyResult<()> {
    let Some(message) = study.limit_summary(robot) else {
        return Ok(());
    };
    if strict {
        return Err(input(format!(
            "{message} (strict_limits=True refuses such data)"
        )));
    }
    let message = CString::new(format!(
        "{message} (the data are used as they are; strict_limits=True refuses them)"
    ))
    .map_err(|error| input(error.to_string()))?;
    PyErr::warn(py, &py.get_type::<LimitWarning>(), &message, 2)
}

/// The priority matrix given as an argument, else the study file's.
fn chosen_priority(
    robot: &Robot,
    priority: Option<&Bound<'_, PyAny>>,
    study: Option<PriorityMatrix>,
) -> PyResult<Option<PriorityMatrix>> {
    match priority {
        Some(value) => priority_matrix(robot, value).map(Some),
        None => Ok(study),
    }
}

/// A JSON document as Python objects.
pub(crate) fn json_to_python<'py>(py: Python<'py>, text: &str) -> PyResult<Bound<'py, PyAny>> {
    py.import("json")?.call_method1("loads", (text,))
}

pub(crate) fn to_json(value: &impl serde::Serialize) -> PyResult<String> {
    serde_json::to_string_pretty(value).map_err(|error| input(error.to_string()))
}

// ---------------------------------------------------------------------------
// Points generation

/// Data simulated on a "real" robot, and that robot.
#[pyclass(name = "Generation", module = "gecaro", frozen)]
pub(crate) struct Generation {
    data: Py<PyData>,
    real: Py<PyRobot>,
    displacement: (f64, f64),
}

#[pymethods]
impl Generation {
    /// The simulated measurements.
    #[getter]
    fn data(&self, py: Python<'_>) -> Py<PyData> {
        self.data.clone_ref(py)
    }

    /// The simulated real robot (the truth the identification should find).
    #[getter]
    fn real(&self, py: Python<'_>) -> Py<PyRobot> {
        self.real.clone_ref(py)
    }

    /// RMS and largest distance (metres) between the terminal points of the
    /// nominal and the real robot over the generated configurations.
    #[getter]
    fn displacement(&self) -> (f64, f64) {
        self.displacement
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        format!(
            "Generation({} configurations; real robot {:.3} mm RMS from the nominal)",
            self.data.borrow(py).samples.len(),
            self.displacement.0 * 1e3
        )
    }
}

/// Points generation (paper §4): `count` configurations that satisfy the
/// method's constraint on a simulated real robot — `real`, or the nominal
/// robot with every parameter of non-zero priority moved uniformly within
/// ±`error_level` units (1 cm, 1°, 1 %) — measured with Gaussian noise of σ =
/// `noise` (metres; radians for orientations). Seeded: equal to
/// `gecaro generate` with the same arguments.
#[pyfunction]
#[pyo3(signature = (robot, method, count, *, error_level = 1.0, noise = 0.0, seed = 1, real = None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn generate(
    py: Python<'_>,
    robot: PyRef<'_, PyRobot>,
    method: &Bound<'_, PyAny>,
    count: usize,
    error_level: f64,
    noise: f64,
    seed: u64,
    real: Option<PyRef<'_, PyRobot>>,
) -> PyResult<Generation> {
    let method = method_of(method)?;
    let method = method.get().method.as_ref();
    let nominal = robot.robot();
    let mut sampler = Sampler::new(seed);
    let real_file = match &real {
        Some(real) => {
            if real.robot().joint_letters() != nominal.joint_letters() {
                return Err(input(format!(
                    "real: the real robot has joints {}, the nominal one {}",
                    real.robot().joint_letters(),
                    nominal.joint_letters()
                )));
            }
            real.file.clone()
        }
        None => {
            let drawn = perturbed_robot(nominal, error_level, &mut sampler).py()?;
            gecaro_report::simulated_robot_file(&robot.file, drawn, error_level, seed)
        }
    };
    let real_robot = &real_file.robot;
    let (samples, displacement) = py
        .detach(|| {
            let samples = simulate_measurements(real_robot, method, count, noise, &mut sampler)?;
            let displacement = terminal_displacement(nominal, real_robot, &samples)?;
            Ok::<_, gecaro_calib::Error>((samples, displacement))
        })
        .py()?;
    Ok(Generation {
        data: Py::new(
            py,
            PyData::from_samples(samples, nominal.joint_count(), "<generated>".into()),
        )?,
        real: Py::new(py, PyRobot::new(real_file))?,
        displacement,
    })
}

// ---------------------------------------------------------------------------
// Identifiable parameters

/// The identifiable parameters of a study (Appendix III).
#[pyclass(name = "Identifiability", module = "gecaro", frozen)]
pub(crate) struct PyIdentifiability {
    json: IdentifiableJson,
}

#[pymethods]
impl PyIdentifiability {
    /// Number of identifiable robot parameters.
    #[getter]
    fn count(&self) -> usize {
        self.json.count
    }

    /// Condition number of W_b, the columns of the base parameters.
    #[getter]
    fn condition_number(&self) -> f64 {
        self.json.condition_number
    }

    /// The status of every parameter (robot, then auxiliary): "identifiable",
    /// "regrouped" ('n'), "no_effect" ('0') or "excluded" (priority 0).
    #[getter]
    fn statuses<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let statuses = PyDict::new(py);
        for parameter in self.json.parameters.iter().chain(&self.json.auxiliary) {
            statuses.set_item(&parameter.name, parameter.status)?;
        }
        Ok(statuses)
    }

    /// Names of the identifiable (base) parameters, robot then auxiliary.
    #[getter]
    fn identifiable(&self) -> Vec<String> {
        self.json
            .parameters
            .iter()
            .chain(&self.json.auxiliary)
            .filter(|parameter| parameter.status == "identifiable")
            .map(|parameter| parameter.name.clone())
            .collect()
    }

    /// The regrouping relations of eq. 32: `(base, [(absorbed, coefficient), …])`,
    /// meaning base_b = base + Σ coefficient·absorbed.
    #[getter]
    fn relations(&self) -> Vec<(String, Vec<(String, f64)>)> {
        self.json
            .regrouping
            .iter()
            .map(|relation| {
                (
                    relation.base.clone(),
                    relation
                        .absorbed
                        .iter()
                        .map(|absorbed| (absorbed.name.clone(), absorbed.coefficient))
                        .collect(),
                )
            })
            .collect()
    }

    /// The new priority matrix ((n+2)×6; non-identifiable parameters set to 0).
    #[getter]
    fn priority<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<i64>>> {
        priority_array(py, &self.json.priority_matrix)
    }

    /// For measured data, whether they excite the structural base set:
    /// {"same_base_set", "not_excited", "condition_number"}; None for random data.
    #[getter]
    fn excitation<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        self.json
            .excitation
            .as_ref()
            .map(|excitation| json_to_python(py, &to_json(excitation)?))
            .transpose()
    }

    /// Observability indices {"o1", …, "o5"} of W_b (docs/planning.md): of
    /// the data when given, else of the random configurations.
    #[getter]
    fn observability<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_python(py, &to_json(&self.json.observability)?)
    }

    /// The document `gecaro identifiable --json` prints, as a dict.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_python(py, &self.to_json()?)
    }

    /// The document `gecaro identifiable --json` prints.
    fn to_json(&self) -> PyResult<String> {
        to_json(&self.json)
    }

    fn __repr__(&self) -> String {
        format!(
            "Identifiability({}, {} method: {} identifiable parameters, condition number {:.3e})",
            self.json.robot, self.json.method, self.json.count, self.json.condition_number
        )
    }
}

/// Identifiable parameters (Appendix III: QR of W with columns in priority
/// order, eq. 33–37): on `data` (or a Study) with the excitation check, or on
/// `count` random configurations (seeded) when no data are given. `priority`:
/// an (n+2)×6 array or a priority file; default the study file's, else the
/// robot's. As `gecaro identifiable`.
#[pyfunction]
#[pyo3(signature = (robot, method, data = None, *, count = None, seed = 1, priority = None, strict_limits = false))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn identifiable(
    py: Python<'_>,
    robot: PyRef<'_, PyRobot>,
    method: &Bound<'_, PyAny>,
    data: Option<PyRef<'_, PyData>>,
    count: Option<usize>,
    seed: u64,
    priority: Option<&Bound<'_, PyAny>>,
    strict_limits: bool,
) -> PyResult<PyIdentifiability> {
    let nominal = robot.robot();
    let source = source(method, data, true)?;
    check_limits(py, nominal, &source.study, strict_limits)?;
    let priority =
        chosen_priority(nominal, priority, source.priority)?.unwrap_or_else(|| nominal.priority());
    let study = &source.study;
    let analysis = py
        .detach(|| identifiability(nominal, study, &priority, count, seed))
        .py()?;
    Ok(PyIdentifiability {
        json: IdentifiableJson::new(nominal, &analysis),
    })
}

// ---------------------------------------------------------------------------
// Identification

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
        json_to_python(py, &to_json(&SummaryJson::from(&self.summary))?)
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

/// The result of an identification.
#[pyclass(name = "Identification", module = "gecaro", frozen)]
pub(crate) struct PyIdentification {
    nominal: RobotFile,
    study: Study,
    result: Identification,
    calibrated: Py<PyRobot>,
}

fn errors_array<'py>(
    py: Python<'py>,
    errors: &[(f64, f64)],
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let values = errors
        .iter()
        .flat_map(|(length, angle)| [*length, *angle])
        .collect();
    array(py, &[errors.len(), 2], values)
}

#[pymethods]
impl PyIdentification {
    /// The calibrated robot, named "<name> (calibrated)", as `identify -o`
    /// writes it.
    #[getter]
    fn calibrated(&self, py: Python<'_>) -> Py<PyRobot> {
        self.calibrated.clone_ref(py)
    }

    /// Whether the iteration converged.
    #[getter]
    fn converged(&self) -> bool {
        self.result.stop_reason == StopReason::Converged
    }

    /// "converged", "iteration_limit" or "diverged".
    #[getter]
    fn stop_reason(&self) -> &'static str {
        self.result.stop_reason.as_str()
    }

    /// The step rule that produced the result ("gauss_newton", "minimum_norm",
    /// "levenberg_marquardt").
    #[getter]
    fn route(&self) -> &'static str {
        self.result.route.as_str()
    }

    /// Parameter updates done.
    #[getter]
    fn iterations(&self) -> usize {
        self.result.iterations()
    }

    /// Every iterate from the nominal robot on: {"rms": residual RMS, "step":
    /// ‖Δη‖, "damping": λ (0 for Gauss–Newton)}, arrays of iterations + 1.
    #[getter]
    fn history<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        columns(
            py,
            &self.result.history,
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
        parameter_list(&self.result.parameters)
    }

    /// The identified auxiliary unknowns (plane coefficients).
    #[getter]
    fn auxiliary(&self) -> Vec<PyParameter> {
        parameter_list(&self.result.auxiliary)
    }

    /// Parameters outside the base set that had to move.
    #[getter]
    fn moved(&self) -> Vec<PyParameter> {
        parameter_list(&self.result.moved)
    }

    /// Errors at the nominal robot.
    #[getter]
    fn before(&self) -> PyErrorSummary {
        PyErrorSummary {
            summary: self.result.before,
        }
    }

    /// Errors at the calibrated robot.
    #[getter]
    fn after(&self) -> PyErrorSummary {
        PyErrorSummary {
            summary: self.result.after,
        }
    }

    /// Per-observation errors at the nominal robot, (observations, 2):
    /// position error (metres) and orientation error (radians, 0 when not
    /// measured).
    #[getter]
    fn errors_before<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        errors_array(py, &self.result.errors_before)
    }

    /// Per-observation errors at the calibrated robot, as `errors_before`.
    #[getter]
    fn errors_after<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        errors_array(py, &self.result.errors_after)
    }

    /// Condition number of W_b at the solution.
    #[getter]
    fn condition_number(&self) -> f64 {
        self.result.condition_number
    }

    /// Observability indices {"o1", …, "o5"} of the data's W_b at the
    /// nominal robot (docs/planning.md).
    #[getter]
    fn observability<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_python(
            py,
            &to_json(&gecaro_report::json::ObservabilityJson::from(
                self.result.observability(),
            ))?,
        )
    }

    /// Standard deviation of the residual (eq. 11).
    #[getter]
    fn residual_sigma(&self) -> f64 {
        self.result.residual_sigma
    }

    /// Structural base parameters that the data do not excite.
    #[getter]
    fn not_excited(&self) -> Vec<String> {
        self.result.not_excited.clone()
    }

    /// What the user should know about the result.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.result.warnings.clone()
    }

    /// The loss minimised: "l2", "huber", "cauchy" or "tukey".
    #[getter]
    fn loss(&self) -> &'static str {
        self.result.loss.kind.as_str()
    }

    /// The robust σ̂ of the residuals at the solution (units of the sensor σ).
    #[getter]
    fn robust_sigma(&self) -> f64 {
        self.result.robust_sigma
    }

    /// Observations beyond the outlier threshold, worst first: dicts with
    /// set, file, kind, observation (1-based), lines, error (m),
    /// rotation_error, residual_sigmas and weight (as `--json`).
    #[getter]
    fn outliers<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_python(py, &to_json(&OutlierJson::list(&self.result.outliers))?)
    }

    /// Observations dropped before this fit (`reject=True`), as `outliers`.
    #[getter]
    fn rejected<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_python(py, &to_json(&OutlierJson::list(&self.result.rejected))?)
    }

    /// The document `gecaro identify --json` prints, as a dict.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_python(py, &self.to_json()?)
    }

    /// The document `gecaro identify --json` prints.
    fn to_json(&self) -> PyResult<String> {
        to_json(&IdentificationJson::new(&self.study, &self.result))
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
            .detach(|| {
                gecaro_report::html_report(&gecaro_report::ReportInput {
                    robot: &self.nominal,
                    study: &self.study,
                    identification: &self.result,
                    command: "gecaro.identify (Python)",
                })
            })
            .py()?;
        if let Some(path) = path {
            gecaro_io::write_atomically(&path, html.as_bytes(), output_policy(overwrite)).py()?;
        }
        Ok(html)
    }

    fn __repr__(&self) -> String {
        format!(
            "Identification({}, {} parameters, {} after {} iterations, RMS {:.4} → {:.4} mm)",
            self.study.method_names(),
            self.result.parameters.len(),
            self.result.stop_reason.as_str(),
            self.result.iterations(),
            self.result.before.rms * 1e3,
            self.result.after.rms * 1e3
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
#[pyo3(signature = (robot, method, data = None, *, solver = "gauss-newton", max_iterations = 30, priority = None, loss = "l2", loss_scale = None, prior = None, outlier_threshold = 3.0, reject = false, model = "full", strict_limits = false, progress = None))]
#[allow(clippy::too_many_arguments)]
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
    progress: Option<Py<PyAny>>,
) -> PyResult<PyIdentification> {
    let nominal = robot.robot();
    let source = source(method, data, false)?;
    check_limits(py, nominal, &source.study, strict_limits)?;
    let base = solver_options(nominal, solver, max_iterations, priority, source.priority)?;
    let arguments = crate::robust::RobustArguments {
        loss,
        loss_scale,
        prior,
        outlier_threshold,
        reject,
        model,
    };
    let options = arguments.options(nominal, base, source.prior)?;
    let study = &source.study;
    let result = py.detach(|| {
        let mut watch = Watch::new();
        let mut iteration = 0;
        let result = gecaro_calib::identification::identify(
            nominal,
            study,
            &options,
            &mut |step: Progress<'_>| {
                if let (Progress::Iteration(record), Some(callback)) = (step, &progress) {
                    let called = Python::attach(|py| {
                        callback.call1(py, (iteration, record.rms)).map(|_| ())
                    });
                    iteration += 1;
                    if let Err(error) = called {
                        return watch.stop(error);
                    }
                }
                watch.poll()
            },
        );
        watch.finish(result)
    })?;
    let calibrated =
        gecaro_report::calibrated_robot_file(&robot.file, study, &result, &source.label);
    let failure = result.failure();
    let identification = PyIdentification {
        nominal: robot.file.clone(),
        study: source.study,
        result,
        calibrated: Py::new(py, PyRobot::new(calibrated))?,
    };
    match failure {
        None => Ok(identification),
        Some(message) => {
            let error = NotConvergedError::new_err(format!(
                "{message}. The exception's `result` holds the best iterate; try solver=\"lm\", \
                 a larger max_iterations, or check the data."
            ));
            error
                .value(py)
                .setattr("result", Py::new(py, identification)?)?;
            Err(error)
        }
    }
}

/// The solver options of `identify` and `cross_validate`.
pub(crate) fn solver_options(
    robot: &Robot,
    solver: &str,
    max_iterations: usize,
    priority: Option<&Bound<'_, PyAny>>,
    study_priority: Option<PriorityMatrix>,
) -> PyResult<IdentificationOptions> {
    Ok(IdentificationOptions {
        solver: match solver {
            "gauss-newton" => Solver::GaussNewton,
            "lm" => Solver::LevenbergMarquardt,
            other => {
                return Err(input(format!(
                    "solver: `{other}` is neither \"gauss-newton\" nor \"lm\""
                )));
            }
        },
        max_iterations,
        priority: chosen_priority(robot, priority, study_priority)?,
        ..IdentificationOptions::default()
    })
}

/// Errors of `robot` on measured data (a Method with Data, or a Study): the
/// distance to the measured point (position, frame), to the set's mean point
/// (links), to the plane, or the distance error (pairs). As `gecaro evaluate`.
#[pyfunction]
#[pyo3(signature = (robot, method, data = None, *, strict_limits = false))]
pub(crate) fn evaluate(
    py: Python<'_>,
    robot: PyRef<'_, PyRobot>,
    method: &Bound<'_, PyAny>,
    data: Option<PyRef<'_, PyData>>,
    strict_limits: bool,
) -> PyResult<PyErrorSummary> {
    let nominal = robot.robot();
    let source = source(method, data, false)?;
    check_limits(py, nominal, &source.study, strict_limits)?;
    let study = &source.study;
    let summary = py.detach(|| evaluate_study(nominal, study)).py()?;
    Ok(PyErrorSummary { summary })
}
