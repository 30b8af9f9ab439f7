//! Points generation (paper §4): `gecaro.generate` and its result.

use gecaro_app::{GenerateRequest, LocalFiles, RobotSource};
use pyo3::prelude::*;

use crate::data::PyData;
use crate::interrupt::watched;
use crate::methods::method_of;
use crate::robot::PyRobot;

/// Data simulated on a "real" robot, and that robot.
#[pyclass(name = "Generation", module = "gecaro", frozen)]
pub(crate) struct Generation {
    data: Py<PyData>,
    real: Py<PyRobot>,
    displacement: (f64, f64),
    csv: String,
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

    /// The data file `gecaro generate -o` writes: a comment line saying
    /// where the data came from (method, real robot, seed, noise), then the
    /// measurements.
    #[getter]
    fn csv(&self) -> &str {
        &self.csv
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
/// ±`error_level` units (1 cm, 1°, 1 %; default 1) — measured with Gaussian noise of σ =
/// `noise` (metres; radians for orientations). Seeded: equal to
/// `gecaro generate` with the same arguments. The cell — `floor` (z in
/// metres), a tracker `station` (x, y, z), its `max_incidence` ("30deg")
/// and `clearance` (metres) — keeps only configurations it can measure.
/// Elastic joints: `compliance_level` gives the drawn real robot compliances
/// of L·[2e-6, 1e-5] rad/(N·m), loaded by the robot's masses and `payload`
/// (`"20kg"`, `"20kg,0,0,120mm"`), carried at every configuration;
/// `gravity_tilt` (`"2deg,-1.5deg"`) leans the real robot's gravity, a
/// measurement frame that is not levelled.
#[pyfunction]
#[pyo3(signature = (robot, method, count, *, error_level = None, noise = 0.0, seed = 1, real = None, floor = None, station = None, max_incidence = None, clearance = None, compliance_level = None, payload = None, gravity_tilt = None))]
pub(crate) fn generate(
    py: Python<'_>,
    robot: PyRef<'_, PyRobot>,
    method: &Bound<'_, PyAny>,
    count: usize,
    error_level: Option<f64>,
    noise: f64,
    seed: u64,
    real: Option<PyRef<'_, PyRobot>>,
    floor: Option<f64>,
    station: Option<[f64; 3]>,
    max_incidence: Option<String>,
    clearance: Option<f64>,
    compliance_level: Option<f64>,
    payload: Option<String>,
    gravity_tilt: Option<String>,
) -> PyResult<Generation> {
    let method = method_of(method)?;
    let spec = method
        .get()
        .spec
        .clone()
        .unwrap_or_else(|| gecaro_app::MethodSpec::named(method.get().method.name()));
    let mut request = GenerateRequest::new(
        RobotSource::Loaded(Box::new(robot.file.clone())),
        spec,
        count,
    );
    request.error_level = error_level;
    request.compliance_level = compliance_level;
    request.payload = payload;
    request.gravity_tilt = gravity_tilt;
    request.noise = noise;
    request.seed = Some(seed);
    request.real = real.map(|real| RobotSource::Loaded(Box::new(real.file.clone())));
    request.cell = gecaro_app::CellSpec {
        floor,
        station,
        max_incidence,
        clearance,
    };
    let generated = watched(py, |observer| request.run(&LocalFiles, observer))?;
    Ok(Generation {
        data: Py::new(
            py,
            PyData::from_samples(
                generated.samples,
                generated.nominal.robot.joint_count(),
                "<generated>".into(),
            ),
        )?,
        real: Py::new(py, PyRobot::new(generated.real))?,
        displacement: generated.displacement,
        csv: generated.csv,
    })
}
