//! `gecaro.Method`: one of the seven calibration methods of paper §3 with its
//! options (the command line's `--method` and its options).

use gecaro_app::MethodSpec;
use gecaro_calib::methods::{CalibrationMethod, METHODS};
use pyo3::prelude::*;

use crate::arrays::Real;
use crate::errors::{IntoPyResult, input};

/// A calibration method: "position", "frame", "point-link", "frame-link",
/// "plane1" (plane equation), "plane2" (plane normal) or "distance".
#[pyclass(name = "Method", module = "gecaro", frozen)]
pub(crate) struct PyMethod {
    pub(crate) method: Box<dyn CalibrationMethod>,
    /// What it was built from (none for a study file's method).
    pub(crate) spec: Option<MethodSpec>,
}

impl PyMethod {
    /// The method of `spec`.
    pub(crate) fn of(spec: MethodSpec) -> PyResult<Self> {
        Ok(PyMethod {
            method: spec.build().py()?,
            spec: Some(spec),
        })
    }

    /// A method as built elsewhere (a study file's).
    pub(crate) fn from_method(method: Box<dyn CalibrationMethod>) -> Self {
        PyMethod { method, spec: None }
    }
}

/// A `Method`, or a method's name with default options.
pub(crate) fn method_of<'py>(value: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyMethod>> {
    if let Ok(method) = value.cast::<PyMethod>() {
        return Ok(method.clone());
    }
    if let Ok(name) = value.extract::<String>() {
        return Bound::new(value.py(), PyMethod::of(MethodSpec::named(name))?);
    }
    Err(input(format!(
        "expected a gecaro.Method or a method's name, got {}",
        value.get_type().name()?
    )))
}

fn triple(value: Option<&Bound<'_, PyAny>>, what: &str) -> PyResult<Option<[f64; 3]>> {
    value
        .map(|value| {
            let values = Real::shaped(value, what, &[Some(3)])?.values;
            Ok([values[0], values[1], values[2]])
        })
        .transpose()
}

#[pymethods]
impl PyMethod {
    /// The method `name` with its options: for the plane methods the plane
    /// (`plane_normal` and `plane_point`, metres) and whether it is "known" or
    /// "unknown" (default: known when given); for frame and frame-link the
    /// orientation difference of Appendix I ("axis-angle" or
    /// "cross-products"); for the link methods the configurations per set
    /// when generating (`set_size`, default 4 for point-link, 2 for frame-link).
    #[new]
    #[pyo3(signature = (name, *, plane_normal = None, plane_point = None, plane = None, orientation = "axis-angle", set_size = None))]
    fn new(
        name: &str,
        plane_normal: Option<&Bound<'_, PyAny>>,
        plane_point: Option<&Bound<'_, PyAny>>,
        plane: Option<&str>,
        orientation: &str,
        set_size: Option<usize>,
    ) -> PyResult<Self> {
        let plane_unknown = match plane {
            None => None,
            Some("known") => Some(false),
            Some("unknown") => Some(true),
            Some(other) => {
                return Err(input(format!(
                    "plane: `{other}` is neither \"known\" nor \"unknown\""
                )));
            }
        };
        PyMethod::of(MethodSpec {
            name: name.to_owned(),
            plane_normal: triple(plane_normal, "plane_normal")?,
            plane_point: triple(plane_point, "plane_point")?,
            plane_unknown,
            orientation: Some(orientation.to_owned()),
            set_size,
        })
    }

    /// The method's name, as on the command line.
    #[getter]
    fn name(&self) -> &'static str {
        self.method.name()
    }

    /// The method's title in the paper's menus.
    #[getter]
    fn title(&self) -> &'static str {
        self.method.title()
    }

    /// The columns of its data files beyond qm1..qmn.
    #[getter]
    fn columns(&self) -> Vec<&'static str> {
        self.method
            .data_columns()
            .iter()
            .flat_map(|column| column.headers().iter().copied())
            .collect()
    }

    /// Names of the method's own unknowns (plane coefficients).
    #[getter]
    fn auxiliary_names(&self) -> Vec<String> {
        self.method.auxiliary_names()
    }

    fn __repr__(&self) -> String {
        let mut options = Vec::new();
        let given = self.spec.clone().unwrap_or_default();
        if let (Some(normal), Some(point)) = (given.plane_normal, given.plane_point) {
            options.push(format!(
                "plane_normal={:?}, plane_point={:?}",
                normal.as_slice(),
                point.as_slice()
            ));
        }
        if given.plane_unknown == Some(true) {
            options.push("plane=\"unknown\"".into());
        }
        if given.orientation.as_deref() == Some("cross-products") {
            options.push("orientation=\"cross-products\"".into());
        }
        if let Some(size) = given.set_size {
            options.push(format!("set_size={size}"));
        }
        let mut text = format!("Method({:?}", self.method.name());
        for option in options {
            text.push_str(", ");
            text.push_str(&option);
        }
        text + ")"
    }
}

/// The names of the seven methods, in the order of the paper's menus.
#[pyfunction]
pub(crate) fn methods() -> Vec<&'static str> {
    METHODS.iter().map(|info| info.name).collect()
}
