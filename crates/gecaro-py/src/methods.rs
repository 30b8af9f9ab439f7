//! `gecaro.Method`: one of the seven calibration methods of paper §3 with its
//! options (the command line's `--method` and its options).
use gecaro_calib::methods::{CalibrationMethod, METHODS, MethodOptions, Plane, method};
use gecaro_core::OrientationDifference;
use nalgebra::Vector3;
use pyo3::prelude::*;

use crate::arrays::Real;
use crate::errors::{IntoPyResult, input};

/// A calibration method: "position", "frame", "point-link", "frame-link",
/// "plane1" (plane equation), "plane2" (plane normal) or "distance".
#[pyclass(name = "Method", module = "gecaro", frozen)]
pub(crate) struct PyMethod {
    pub(crate) method: Box<dyn CalibrationMethod>,
    /// The options it was built with (unknown for a study file's method).
    options: Option<MethodOptions>,
}

impl PyMethod {
    /// The method called `name` with default options.
    pub(crate) fn named(name: &str) -> PyResult<Self> {
        let options = MethodOptions::default();
        Ok(PyMethod {
            method: method(name, &options).py()?,
            options: Some(options),
        })
    }

    /// A method as built elsewhere (a study file's).
    pub(crate) fn from_method(method: Box<dyn CalibrationMethod>) -> Self {
        PyMethod {
            method,
            options: None,
        }
    }
}

fn vector3(value: &Bound<'_, PyAny>, what: &str) -> PyResult<Vector3<f64>> {
    Ok(Vector3::from_column_slice(
        &Real::shaped(value, what, &[Some(3)])?.values,
    ))
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
        let given = match (plane_normal, plane_point) {
            (None, None) => None,
            (Some(normal), Some(point)) => Some(
                Plane::new(
                    vector3(normal, "plane_normal")?,
                    vector3(point, "plane_point")?,
                )
                .py()?,
            ),
            _ => {
                return Err(input(
                    "a plane needs both plane_normal and plane_point (for example \
                     plane_normal=[0.3, 0.5, 0.81], plane_point=[0.3, 0.2, 0.6])",
                ));
            }
        };
        let unknown = match plane {
            None => None,
            Some("known") => Some(false),
            Some("unknown") => Some(true),
            Some(other) => {
                return Err(input(format!(
                    "plane: `{other}` is neither \"known\" nor \"unknown\""
                )));
            }
        };
        let (plane, plane_unknown) = MethodOptions::plane_choice(given, unknown).py()?;
        let options = MethodOptions {
            plane,
            plane_unknown,
            orientation: match orientation {
                "axis-angle" => OrientationDifference::AxisAngle,
                "cross-products" => OrientationDifference::CrossProducts,
                other => {
                    return Err(input(format!(
                        "orientation: `{other}` is neither \"axis-angle\" nor \"cross-products\""
                    )));
                }
            },
            set_size: MethodOptions::check_set_size(set_size).py()?,
        };
        Ok(PyMethod {
            method: method(name, &options).py()?,
            options: Some(options),
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
        let given = self.options.clone().unwrap_or_default();
        if let Some(plane) = &given.plane {
            options.push(format!(
                "plane_normal={:?}, plane_point={:?}",
                plane.normal().as_slice(),
                plane.point().as_slice()
            ));
        }
        if given.plane_unknown {
            options.push("plane=\"unknown\"".into());
        }
        if given.orientation == OrientationDifference::CrossProducts {
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
