//! The owner's tool point and user frames, and an instrument's export
//! joined with a controller's log (issue 74): `gecaro.tool_point`,
//! `gecaro.user_frame` and `gecaro.join`, through the application layer's
//! requests.

use std::ffi::CString;
use std::path::PathBuf;

use gecaro_app::{
    DataFormatSpec, DataSource, FramePointsSource, JoinRequest, LocalFiles, RobotSource,
    ToolPointRequest, UserFrameRequest,
};
use gecaro_calib::study::DataColumn;
use pyo3::prelude::*;

use crate::arrays::{named_points, points};
use crate::data::PyData;
use crate::documents::to_python;
use crate::errors::{IntoPyResult, input};
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

/// An instrument's export joined with a controller's log, as `gecaro
/// join`: `tracker` (x, y, z and, when measured, qw, qx, qy, qz per point,
/// lengths in `length_unit`) and `log` (qm1 … qmn in `angle_unit`, a
/// prismatic joint in `log_length_unit`), by the
/// `key` column of both (`log_key` in the log when its name differs) or by
/// row order; columns renamed by `tracker_columns` / `log_columns`
/// (`"x=X,y=Y,z=Z"`); the tracker's orientations as quaternions `qw … qz`,
/// or `rx, ry, rz` in the form `rotation` names (`"rpy"`, `"euler-xyz"`,
/// `"euler-zyz"`, `"rotation-vector"`) and the angle unit `rotation_unit`
/// (written as quaternions; `rx, ry, rz` without `rotation` are refused).
/// Returns the joined `Data` (metres, radians), written
/// to `output` when given. Log rows nothing measured are left out with a
/// `UserWarning`; a shifted join, a key twice, a point the log lacks raise
/// InputError.
#[pyfunction]
#[pyo3(signature = (
    robot, tracker, log, output = None, *, key = None, log_key = None, tracker_columns = None,
    log_columns = None, length_unit = None, angle_unit = None, log_length_unit = None,
    rotation = None, rotation_unit = None, overwrite = false,
))]
pub(crate) fn join(
    py: Python<'_>,
    robot: PyRef<'_, PyRobot>,
    tracker: PathBuf,
    log: PathBuf,
    output: Option<PathBuf>,
    key: Option<String>,
    log_key: Option<String>,
    tracker_columns: Option<String>,
    log_columns: Option<String>,
    length_unit: Option<String>,
    angle_unit: Option<String>,
    log_length_unit: Option<String>,
    rotation: Option<String>,
    rotation_unit: Option<String>,
    overwrite: bool,
) -> PyResult<PyData> {
    let mut request = JoinRequest::new(
        RobotSource::Loaded(Box::new(robot.file.clone())),
        DataSource::File(tracker.display().to_string()),
        DataSource::File(log.display().to_string()),
    );
    request.key = key;
    request.log_key = log_key;
    request.tracker_format = DataFormatSpec {
        length_unit,
        angle_unit: rotation_unit,
        columns: tracker_columns,
        rotation,
        ..DataFormatSpec::default()
    };
    request.log_format = DataFormatSpec {
        angle_unit,
        length_unit: log_length_unit,
        columns: log_columns,
        ..DataFormatSpec::default()
    };
    request.output.save_as = output.map(|path| path.display().to_string());
    request.output.overwrite = overwrite;
    let joined = request.run(&LocalFiles).py()?;
    if let Some(note) = joined.unmeasured_note() {
        let message = CString::new(note).map_err(|error| input(error.to_string()))?;
        PyErr::warn(
            py,
            &py.get_type::<pyo3::exceptions::PyUserWarning>(),
            &message,
            1,
        )?;
    }
    let types = gecaro_io::joint_types(robot.robot());
    let columns = if joined.joined.orientations {
        vec![DataColumn::Position, DataColumn::Orientation]
    } else {
        vec![DataColumn::Position]
    };
    let label = joined
        .saved
        .as_ref()
        .map_or_else(|| "joined".to_owned(), |path| path.display().to_string());
    let file = gecaro_io::parse_samples(
        joined.joined.text.as_bytes(),
        std::path::Path::new(&label),
        &types,
        &columns,
        &gecaro_io::DataFormat::default(),
    )
    .py()?;
    Ok(PyData::from_samples(file.samples, types.len(), label))
}
