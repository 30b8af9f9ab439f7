//! Before measuring: `plan` (the configurations to measure, chosen from a
//! pool by a criterion), `plan_study` (a whole cell as one design),
//! `predict` (the precision a plan gives) and
//! `accuracy_curve` (how many configurations are enough), as `gecaro plan`,
//! `gecaro predict` and `gecaro plan --curve`: the same requests of the
//! application layer, the same numbers; results as the documents their
//! `--json` prints.

use gecaro_app::{
    CellSpec, DataSource, MethodSpec, PlanRequest, PredictRequest, RobotSource, TestPoses,
};
use pyo3::prelude::*;

use crate::data::PyData;
use crate::documents::{to_json, to_python};
use crate::errors::{IntoPyResult, input};
use crate::interrupt::watched;
use crate::methods::method_of;
use crate::robot::PyRobot;

/// The method of a call, with its options.
fn spec(method: &Bound<'_, PyAny>) -> PyResult<MethodSpec> {
    let method = method_of(method)?;
    let method = method.get();
    Ok(method
        .spec
        .clone()
        .unwrap_or_else(|| MethodSpec::named(method.method.name())))
}

/// Samples of a `Data` as a request's data.
fn samples(data: &PyData) -> DataSource {
    DataSource::Samples {
        samples: data.samples.clone(),
        label: data.label.clone(),
    }
}

/// Random test poses (`count`, default 200) for the accuracy at test poses.
fn test_poses(count: Option<usize>) -> TestPoses {
    TestPoses {
        test_poses: None,
        test_pose_count: count,
    }
}

/// The request of a plan or a curve: the shared settings.
fn plan_request(
    robot: &PyRobot,
    method: &Bound<'_, PyAny>,
    criterion: &str,
    pool: Option<usize>,
    seed: u64,
    test_pose_count: Option<usize>,
    cell: CellSpec,
) -> PyResult<PlanRequest> {
    let mut request = PlanRequest::new(
        RobotSource::Loaded(Box::new(robot.file.clone())),
        spec(method)?,
        0,
    );
    request.criterion = Some(criterion.to_owned());
    request.pool = pool;
    request.seed = Some(seed);
    request.test_poses = test_poses(test_pose_count);
    request.cell = cell;
    Ok(request)
}

/// A plan: the configurations to measure (`data`) and the document of
/// `gecaro plan --json` (`to_dict()`).
#[pyclass(name = "Plan", module = "gecaro", frozen)]
pub(crate) struct PyPlan {
    data: Py<PyData>,
    document: gecaro_app::documents::PlanJson,
}

#[pymethods]
impl PyPlan {
    /// The planned configurations (qm, and set or pair ids), to measure.
    #[getter]
    fn data(&self, py: Python<'_>) -> Py<PyData> {
        self.data.clone_ref(py)
    }

    /// The plan as `gecaro plan --json` prints it (criterion, value, the
    /// random choice's value, log det, observability indices, columns, …).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.document)
    }

    /// The same as JSON text.
    fn to_json(&self) -> PyResult<String> {
        to_json(&self.document)
    }
}

/// Plans `count` configurations of `method` on `robot`, as `gecaro plan`:
/// chosen from `candidates` (a Data) or a pool of `pool` generated ones
/// (default 20 × count; in the cell of `floor`, `station`, `max_incidence`,
/// `clearance`), by `criterion` ("d", "a", "e", "o4", "o5", "test"), keeping
/// `keep` (configurations measured already). Elastic joints: `payloads`
/// (`["0kg", "20kg,0,0,100mm"]`) offers each candidate with each, the
/// compliances join the design, and the plan's Data states each row's
/// payload.
#[pyfunction]
#[pyo3(signature = (robot, method, count, *, criterion = "d", candidates = None, pool = None, keep = None, min_distance = 0.0, seed = 1, test_pose_count = None, floor = None, station = None, max_incidence = None, clearance = None, payloads = None))]
pub(crate) fn plan(
    py: Python<'_>,
    robot: PyRef<'_, PyRobot>,
    method: &Bound<'_, PyAny>,
    count: usize,
    criterion: &str,
    candidates: Option<PyRef<'_, PyData>>,
    pool: Option<usize>,
    keep: Option<PyRef<'_, PyData>>,
    min_distance: f64,
    seed: u64,
    test_pose_count: Option<usize>,
    floor: Option<f64>,
    station: Option<[f64; 3]>,
    max_incidence: Option<String>,
    clearance: Option<f64>,
    payloads: Option<Vec<String>>,
) -> PyResult<PyPlan> {
    let joint_count = robot.file.robot.joint_count();
    let cell = CellSpec {
        floor,
        station,
        max_incidence,
        clearance,
    };
    let mut request = plan_request(&robot, method, criterion, pool, seed, test_pose_count, cell)?;
    request.count = Some(count);
    request.candidates = candidates.as_deref().map(samples);
    request.keep = keep.as_deref().map(samples);
    request.min_distance = min_distance;
    request.payloads = payloads.unwrap_or_default();
    let planning = watched(py, |observer| {
        request.run(&gecaro_app::LocalFiles, observer)
    })?;
    let (Some(planned), Some(document)) = (&planning.planned, planning.plan_document()) else {
        return Err(input("no plan was made"));
    };
    Ok(PyPlan {
        data: Py::new(
            py,
            PyData::from_samples(planned.plan.samples.clone(), joint_count, "<plan>".into()),
        )?,
        document,
    })
}

/// Plans a whole cell, as `gecaro plan --study`: `count` configurations in
/// all, chosen as one D-optimal design over every set of `study` (each set
/// read through its tool and station, weighted by its σ) from `pool`
/// candidates drawn per set (default 20 × count ÷ sets, at least 200).
/// The cell as `plan`'s: `floor` (m), and the incidence (`"30deg"`) and
/// `clearance` (m) of each set's reflector seen from its named station, or
/// from `station` (world frame, m) for the sets that name none.
/// Returns a dict: `sets` (one Data of configurations per set, in the
/// study's order), `log_det` and `random_log_det` (a random choice of as
/// many from the same pools), `exchanges`, `pool`.
#[pyfunction]
#[pyo3(signature = (robot, study, count, *, pool = None, seed = 1, floor = None, station = None, max_incidence = None, clearance = None))]
pub(crate) fn plan_study<'py>(
    py: Python<'py>,
    robot: PyRef<'_, PyRobot>,
    study: &Bound<'_, PyAny>,
    count: usize,
    pool: Option<usize>,
    seed: u64,
    floor: Option<f64>,
    station: Option<[f64; 3]>,
    max_incidence: Option<String>,
    clearance: Option<f64>,
) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
    if study.cast::<crate::study::PyStudy>().is_err() {
        return Err(input("plan_study plans a Study"));
    }
    let measurements = crate::source::measurements(&robot, study, None, false, false)?;
    let Some(source) = measurements.study else {
        return Err(input("a Study is needed"));
    };
    let mut request = gecaro_app::PlanStudyRequest::new(source, count);
    request.pool = pool;
    request.seed = Some(seed);
    request.cell = CellSpec {
        floor,
        station,
        max_incidence,
        clearance,
    };
    let planned = watched(py, |observer| {
        request.run(&gecaro_app::LocalFiles, observer)
    })?;
    let joint_count = robot.file.robot.joint_count();
    let sets = pyo3::types::PyList::empty(py);
    for (set, samples) in planned.loaded.study.sets.iter().zip(&planned.plan.sets) {
        sets.append(Py::new(
            py,
            PyData::from_samples(
                samples.clone(),
                joint_count,
                format!("plan of {}", set.label),
            ),
        )?)?;
    }
    let result = pyo3::types::PyDict::new(py);
    result.set_item("sets", sets)?;
    result.set_item("log_det", planned.plan.quality.log_det)?;
    result.set_item("random_log_det", planned.plan.random.log_det)?;
    result.set_item("exchanges", planned.plan.exchanges)?;
    result.set_item("pool", planned.pool)?;
    Ok(result)
}

/// The precision of every identifiable parameter and the calibrated robot's
/// error at test poses that measuring `data` with a sensor of σ = `noise`
/// would give, as `gecaro predict --json` prints it; `monte_carlo` simulated
/// calibrations (robots at `error_level`) check the prediction. With a
/// Study as `method` (no `data`, no `noise`: its sets state them), the whole
/// cell's prediction, as `gecaro predict --study --json`: every set weighted
/// by its σ, through its tool and station, from its configurations.
/// `model="elastic"` predicts the compliances too, loaded by the robot's
/// masses and the data's payloads.
#[pyfunction]
#[pyo3(signature = (robot, method, data = None, noise = None, *, monte_carlo = None, error_level = 0.1, seed = 1, test_pose_count = None, model = None))]
pub(crate) fn predict<'py>(
    py: Python<'py>,
    robot: PyRef<'_, PyRobot>,
    method: &Bound<'_, PyAny>,
    data: Option<PyRef<'_, PyData>>,
    noise: Option<f64>,
    monte_carlo: Option<usize>,
    error_level: f64,
    seed: u64,
    test_pose_count: Option<usize>,
    model: Option<String>,
) -> PyResult<Bound<'py, PyAny>> {
    if method.cast::<crate::study::PyStudy>().is_ok() {
        if data.is_some() || noise.is_some() || monte_carlo.is_some() {
            return Err(input(
                "a Study states its data and σ per set: give neither data, noise nor monte_carlo",
            ));
        }
        let measurements = crate::source::measurements(&robot, method, None, false, false)?;
        let Some(study) = measurements.study else {
            return Err(input("a Study is needed"));
        };
        let mut request = gecaro_app::PredictStudyRequest::new(study);
        request.seed = Some(seed);
        request.test_poses = test_poses(test_pose_count);
        let predicted = py.detach(|| request.run(&gecaro_app::LocalFiles)).py()?;
        return to_python(py, &predicted.document());
    }
    let (Some(data), Some(noise)) = (data, noise) else {
        return Err(input(
            "give the planned configurations (data) and the sensor's σ (noise), or a Study",
        ));
    };
    let mut request = PredictRequest::new(
        RobotSource::Loaded(Box::new(robot.file.clone())),
        spec(method)?,
        samples(&data),
        noise,
    );
    request.monte_carlo = monte_carlo;
    request.error_level = Some(error_level);
    request.seed = Some(seed);
    request.test_poses = test_poses(test_pose_count);
    request.model = model;
    let predicted = watched(py, |observer| {
        request.run(&gecaro_app::LocalFiles, observer)
    })?;
    to_python(py, &predicted.document())
}

/// The predicted RMS position error of the calibrated robot against the
/// number of configurations (`counts`), planned by `criterion` and drawn at
/// random, for a sensor of σ = `noise`, as `gecaro plan --curve --json`
/// prints it (without the plot).
#[pyfunction]
#[pyo3(signature = (robot, method, counts, noise, *, criterion = "d", pool = None, seed = 1, test_pose_count = None, floor = None, station = None, max_incidence = None, clearance = None))]
pub(crate) fn accuracy_curve<'py>(
    py: Python<'py>,
    robot: PyRef<'_, PyRobot>,
    method: &Bound<'_, PyAny>,
    counts: Vec<usize>,
    noise: f64,
    criterion: &str,
    pool: Option<usize>,
    seed: u64,
    test_pose_count: Option<usize>,
    floor: Option<f64>,
    station: Option<[f64; 3]>,
    max_incidence: Option<String>,
    clearance: Option<f64>,
) -> PyResult<Bound<'py, PyAny>> {
    let cell = CellSpec {
        floor,
        station,
        max_incidence,
        clearance,
    };
    let mut request = plan_request(&robot, method, criterion, pool, seed, test_pose_count, cell)?;
    request.count = None;
    request.curve = counts;
    request.noise = Some(noise);
    let planning = watched(py, |observer| {
        request.run(&gecaro_app::LocalFiles, observer)
    })?;
    let document = planning
        .curve_document()
        .ok_or_else(|| input("no curve was drawn"))?;
    to_python(py, &document)
}
