//! The state of a `gecaro.Data` (the class's methods are in `data`): a
//! leaf beneath every module that takes one, the robot's included.

use gecaro_calib::study::{SampleRef, Samples};
use numpy::PyArrayDyn;
use pyo3::prelude::*;

use crate::arrays::array;

/// The label of data built from arrays, in messages: `<arrays>:3: …` names
/// row 3 (0-based, as numpy indexes it).
pub(crate) const ARRAYS: &str = "<arrays>";

/// A data set (see the module docs).
#[pyclass(name = "Data", module = "gecaro", skip_from_py_object)]
#[derive(Clone)]
pub(crate) struct PyData {
    /// Shared with the requests made of it; its large columns are the
    /// arrays it was made of, read in place.
    pub(crate) samples: Samples,
    pub(crate) joint_count: usize,
    /// Names the data in messages and reports: the file, or `<arrays>`.
    pub(crate) label: String,
    pub(crate) unused_columns: Vec<String>,
}

impl PyData {
    pub(crate) fn from_samples(
        samples: impl Into<Samples>,
        joint_count: usize,
        label: String,
    ) -> Self {
        PyData {
            samples: samples.into(),
            joint_count,
            label,
            unused_columns: Vec::new(),
        }
    }

    /// The field of every sample as rows of `width` values, or None when no
    /// sample has it.
    pub(crate) fn field<'py>(
        &self,
        py: Python<'py>,
        width: usize,
        value: impl Fn(SampleRef<'_>) -> Option<Vec<f64>>,
    ) -> PyResult<Option<Bound<'py, PyArrayDyn<f64>>>> {
        if self.samples.iter().all(|sample| value(sample).is_none()) {
            return Ok(None);
        }
        let values = self
            .samples
            .iter()
            .flat_map(|sample| value(sample).unwrap_or_else(|| vec![f64::NAN; width]))
            .collect();
        let shape = if width == 1 {
            vec![self.samples.len()]
        } else {
            vec![self.samples.len(), width]
        };
        array(py, &shape, values).map(Some)
    }
}
