//! Identifiable parameters (Appendix III): `gecaro.identifiable` and its
//! result.

use gecaro_app::documents::IdentifiableJson;
use gecaro_app::{IdentifiableRequest, LocalFiles};
use numpy::PyArrayDyn;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::priority_array;
use crate::data::PyData;
use crate::documents::{to_json, to_python};
use crate::interrupt::watched;
use crate::robot::PyRobot;
use crate::source::{measurements, priority};
use crate::warnings::warn_notes;

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
            .map(|excitation| to_python(py, excitation))
            .transpose()
    }

    /// Observability indices {"o1", …, "o5"} of W_b (docs/planning.md): of
    /// the data when given, else of the random configurations.
    #[getter]
    fn observability<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.json.observability)
    }

    /// The document `gecaro identifiable --json` prints, as a dict.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.json)
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
/// robot's. `model="elastic"`: the compliances too, on the data's loads.
/// As `gecaro identifiable`.
#[pyfunction]
#[pyo3(signature = (robot, method, data = None, *, count = None, seed = 1, priority = None, strict_limits = false, model = None))]
pub(crate) fn identifiable(
    py: Python<'_>,
    robot: PyRef<'_, PyRobot>,
    method: &Bound<'_, PyAny>,
    data: Option<PyRef<'_, PyData>>,
    count: Option<usize>,
    seed: u64,
    priority: Option<&Bound<'_, PyAny>>,
    strict_limits: bool,
    model: Option<String>,
) -> PyResult<PyIdentifiability> {
    let mut request =
        IdentifiableRequest::new(measurements(&robot, method, data, true, strict_limits)?);
    request.priority = self::priority(robot.robot(), priority)?;
    request.count = count;
    request.seed = Some(seed);
    request.model = model;
    let analysis = watched(py, |observer| request.run(&LocalFiles, observer))?;
    warn_notes(py, &analysis.loaded.notes)?;
    Ok(PyIdentifiability {
        json: analysis.document(),
    })
}
