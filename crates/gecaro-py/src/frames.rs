//! The owner's tool point and user frames (issue 74): `gecaro.tool_point`
//! and `gecaro.user_frame`, through the application layer's requests.

use gecaro_app::{
    DataSource, FramePointsSource, LocalFiles, RobotSource, ToolPointRequest, UserFrameRequest,
};
use pyo3::prelude::*;

use crate::arrays::{named_points, points};
use crate::data::PyData;
use crate::documents::to_python;
use crate::errors::IntoPyResult;
use crate::robot::PyRobot;

/// A tool point taught by pivoting, as `gecaro tcp --json` gives it: the
/// joint values `qm` ((m, n) array or `Data`) of m ≥ 4 orientations of
/// `robot` with the tool's tip on one fixed point → `{"tool": [x, y, z]}`
/// in frame n+1 (m), the fixed point in the world frame, every
/// orientation's residual, σ, and the orientations' spread (rad), with
/// `warnings` when it is small. Orientations about one axis only raise
/// InputError.
#[pyfunction]
pub(crate) fn tool_point<'py>(
    py: Python<'py>,
    robot: PyRef<'_, PyRobot>,
    qm: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    let data = match qm.cast::<PyData>() {
        Ok(data) => data.clone(),
        Err(_) => py
            .get_type::<PyData>()
            .call1((qm,))?
            .cast_into::<PyData>()?,
    };
    let data = data.borrow();
    let request = ToolPointRequest::new(
        RobotSource::Loaded(Box::new(robot.file.clone())),
        DataSource::Samples {
            samples: data.samples.clone(),
            label: data.label.clone(),
        },
    );
    let taught = request.run(&LocalFiles).py()?;
    to_python(py, &taught.document())
}

/// A user frame from measured points, as `gecaro frame --json` gives it:
/// `measured` (N, 3) points (m) named `names` — `origin`, `x` (on the +x
/// axis) and `xy` (in the xy plane) — or, with `frame` (N, 3), the same
/// points' coordinates in the frame (least squares, with σ) →
/// `{"position", "quaternion" (w, x, y, z), "rpy", …}`.
#[pyfunction]
#[pyo3(signature = (measured, *, names = None, frame = None))]
pub(crate) fn user_frame<'py>(
    py: Python<'py>,
    measured: &Bound<'py, PyAny>,
    names: Option<Vec<String>>,
    frame: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let (names, measured) = named_points(measured, names)?;
    let frame = frame
        .map(|frame| points(frame, "frame", Some(measured.len())))
        .transpose()?;
    let points = names
        .into_iter()
        .zip(measured)
        .enumerate()
        .map(|(i, (name, measured))| gecaro_io::FramePoint {
            name,
            measured,
            frame: frame.as_ref().map(|frame| frame[i]),
            line: i,
        })
        .collect();
    let made = UserFrameRequest::new(FramePointsSource::Points(points))
        .run(&LocalFiles)
        .py()?;
    to_python(py, &made.document())
}
