//! `gecaro.compensate`: a robot program corrected for the calibrated robot
//! (`gecaro compensate`): the motor values with which the calibrated robot
//! reaches what the nominal program meant.
use gecaro_app::{CompensateRequest, DataFormatSpec, LocalFiles, ProgramSource, RobotSource};
use gecaro_calib::compensation::{
    CompensatedPoint, CompensationStatus, ProgramPoint, ProgramTarget,
};
use nalgebra::Vector3;
use numpy::PyArrayDyn;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

use crate::arrays::{Real, array};
use crate::documents::to_python;
use crate::errors::{NotConvergedError, input};
use crate::interrupt::watched;
use crate::robot::PyRobot;
use crate::robot_inputs::pose;

/// A corrected program.
#[pyclass(name = "Compensation", module = "gecaro", frozen)]
pub(crate) struct PyCompensation {
    points: Vec<CompensatedPoint>,
    joint_count: usize,
}

#[pymethods]
impl PyCompensation {
    /// The motor values to send, (m, n); a target not reached keeps the
    /// program's joints (or the previous solution).
    #[getter]
    fn qm<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let values = self
            .points
            .iter()
            .flat_map(|point| point.motor_positions.iter().copied())
            .collect();
        array(py, &[self.points.len(), self.joint_count], values)
    }

    /// Distance (m) between each target point and where the calibrated robot
    /// puts frame n+1 at `qm`, (m,).
    #[getter]
    fn position_error<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let values = self
            .points
            .iter()
            .map(|point| point.position_error)
            .collect();
        array(py, &[self.points.len()], values)
    }

    /// Angle (rad) between each target orientation and the calibrated
    /// robot's, (m,); NaN for point targets.
    #[getter]
    fn rotation_error<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let values = self
            .points
            .iter()
            .map(|point| point.rotation_error.unwrap_or(f64::NAN))
            .collect();
        array(py, &[self.points.len()], values)
    }

    /// Angle (rad) by which a position match leaves the tool turned from
    /// the orientation the program's joints meant, (m,); NaN for a pose
    /// match, a Cartesian target or a target not reached.
    #[getter]
    fn tool_turn<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let values = self
            .points
            .iter()
            .map(|point| point.tool_turn.unwrap_or(f64::NAN))
            .collect();
        array(py, &[self.points.len()], values)
    }

    /// Per target: "ok", "reconfigured" (reached in another configuration,
    /// a joint moved by more than 1 rad), "outside-region" (reached outside
    /// the joint ranges the calibration measured), "outside-limits" (reached
    /// only beyond a joint limit, even turned by whole turns) or
    /// "not-reached".
    #[getter]
    fn status(&self) -> Vec<&'static str> {
        self.points
            .iter()
            .map(|point| point.status.word())
            .collect()
    }

    /// Rows (0-based) whose target is flagged (reconfigured, outside-region,
    /// outside-limits or not-reached).
    #[getter]
    fn flagged(&self) -> Vec<usize> {
        self.points
            .iter()
            .enumerate()
            .filter(|(_, point)| point.status != CompensationStatus::Reached)
            .map(|(row, _)| row)
            .collect()
    }

    fn __len__(&self) -> usize {
        self.points.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "Compensation({} targets, {} flagged)",
            self.points.len(),
            self.flagged().len()
        )
    }
}

/// The program's targets from the arguments: joint targets, or points or
/// poses with the program's joints as optional starts.
fn program(
    joint_count: usize,
    joints: Option<&Bound<'_, PyAny>>,
    positions: Option<&Bound<'_, PyAny>>,
    poses: Option<&Bound<'_, PyAny>>,
) -> PyResult<Vec<ProgramPoint>> {
    let joints = joints
        .map(|joints| Real::shaped(joints, "joints", &[None, Some(joint_count)]))
        .transpose()?;
    let rows = |values: &Real| -> Vec<Vec<f64>> {
        values
            .values
            .chunks_exact(joint_count)
            .map(<[f64]>::to_vec)
            .collect()
    };
    let targets: Vec<ProgramTarget> = match (positions, poses) {
        (Some(_), Some(_)) => return Err(input("give `positions` or `poses`, not both")),
        (Some(positions), None) => Real::shaped(positions, "positions", &[None, Some(3)])?
            .values
            .chunks_exact(3)
            .map(|xyz| ProgramTarget::Position(Vector3::from_column_slice(xyz)))
            .collect(),
        (None, Some(poses)) => {
            let count = poses.len()?;
            (0..count)
                .map(|row| {
                    Ok(ProgramTarget::Pose(pose(
                        &poses.get_item(row)?,
                        &format!("poses[{row}]"),
                    )?))
                })
                .collect::<PyResult<_>>()?
        }
        (None, None) => match &joints {
            Some(joints) => {
                let targets = rows(joints)
                    .into_iter()
                    .map(ProgramTarget::Joints)
                    .collect();
                return Ok(targets_with_starts(targets, None));
            }
            None => return Err(input("no targets: give `joints`, `positions` or `poses`")),
        },
    };
    let starts = joints.as_ref().map(rows);
    if let Some(starts) = &starts
        && starts.len() != targets.len()
    {
        return Err(input(format!(
            "joints: {} rows for {} targets; the program's joints go one per target",
            starts.len(),
            targets.len()
        )));
    }
    Ok(targets_with_starts(targets, starts))
}

fn targets_with_starts(
    targets: Vec<ProgramTarget>,
    starts: Option<Vec<Vec<f64>>>,
) -> Vec<ProgramPoint> {
    let mut starts = starts.map(Vec::into_iter);
    targets
        .into_iter()
        .map(|target| ProgramPoint {
            target,
            joints: starts.as_mut().and_then(Iterator::next),
        })
        .collect()
}

/// Program compensation ("program filtering"): for each target of a program
/// taught on the `nominal` model, the motor values with which the
/// `calibrated` robot reaches it, as `gecaro compensate`. Targets are joint
/// values (`joints`, (m, n): the pose the nominal model gives them, matched
/// whole or, with `match="position"`, by its point), or Cartesian targets —
/// `positions` (m, 3) or `poses` (m, 4, 4) / (m, 7) — with the program's
/// `joints` as starts when it has them. With `rebase=True` the calibrated
/// robot, calibrated in a measurement frame (a tracker's), is first
/// re-expressed in the nominal's base frame (`Robot.rebased`); without it,
/// robots in different frames are refused. An elastic calibrated robot is
/// commanded where it comes to rest on the targets with `payload`
/// (`"12kg"`, `"12kg,0,0,80mm"`) and its links' weight. `tool` is the tool
/// the targets are for: a tool the calibration identified (by name) or its
/// pose in frame n+1 (`"0,0,120mm"`); frame n+1 itself is refused where the
/// calibration never observed it. `base_points` (a file of `gecaro robot
/// rebase --base-points`, lengths in `base_points_unit`) registers the
/// owner's base first. Runs without the GIL; Ctrl-C stops it.
///
/// Raises NotConvergedError, with the whole result in `.result`, when some
/// targets are reached only beyond a joint limit or not at all, or a
/// position match turns the tool beyond `max_tool_turn` (`"1deg"`).
#[pyfunction]
#[pyo3(signature = (
    nominal, calibrated, *, joints = None, positions = None, poses = None, r#match = "pose",
    rebase = false, payload = None, tool = None, max_tool_turn = None, base_points = None,
    base_points_unit = None,
))]
pub(crate) fn compensate(
    py: Python<'_>,
    nominal: PyRef<'_, PyRobot>,
    calibrated: PyRef<'_, PyRobot>,
    joints: Option<&Bound<'_, PyAny>>,
    positions: Option<&Bound<'_, PyAny>>,
    poses: Option<&Bound<'_, PyAny>>,
    r#match: &str,
    rebase: bool,
    payload: Option<String>,
    tool: Option<String>,
    max_tool_turn: Option<String>,
    base_points: Option<PathBuf>,
    base_points_unit: Option<String>,
) -> PyResult<PyCompensation> {
    let joint_count = nominal.robot().joint_count();
    let mut request = CompensateRequest::new(
        RobotSource::Loaded(Box::new(nominal.file.clone())),
        RobotSource::Loaded(Box::new(calibrated.file.clone())),
        ProgramSource::Points(program(joint_count, joints, positions, poses)?),
    );
    request.matching = Some(r#match.to_owned());
    request.rebase = rebase;
    request.payload = payload;
    request.tool = tool;
    request.max_tool_turn = max_tool_turn;
    request.base_points =
        base_points.map(|path| gecaro_app::BasePointsSource::File(path.display().to_string()));
    request.base_points_format.length_unit = base_points_unit;
    let compensated = watched(py, |observer| request.run(&LocalFiles, observer))?;
    let failure = compensated.failure();
    let result = PyCompensation {
        points: compensated.results,
        joint_count,
    };
    let flagged = result.flagged();
    if flagged.is_empty() {
        // No target flagged, yet a position match may turn the tool beyond
        // the tolerance.
        let Some(failure) = failure else {
            return Ok(result);
        };
        let error = NotConvergedError::new_err(failure.message(gecaro_app::Dialect::Python));
        error.value(py).setattr("result", Py::new(py, result)?)?;
        return Err(error);
    }
    let shown: Vec<String> = flagged.iter().take(10).map(ToString::to_string).collect();
    let error = NotConvergedError::new_err(format!(
        "{} of {} targets are flagged (rows {}{}); check them before running the program \
         (the exception's `result` holds every target's values and status)",
        flagged.len(),
        result.points.len(),
        shown.join(", "),
        if flagged.len() > 10 { ", …" } else { "" }
    ));
    error.value(py).setattr("result", Py::new(py, result)?)?;
    Err(error)
}

/// A program file corrected into `output` as it is read, a block of targets
/// at a time, in memory that does not grow with the program — as
/// `gecaro compensate --program PROGRAM -o OUTPUT`, for programs of a
/// million targets. The program's format is said as for `Data.read`
/// (`length_unit`, `angle_unit`, `columns` as a dict {gecaro name: file
/// column} or text `"qm1=A1,…"`, `delimiter`, `decimal_comma`); `output`
/// is written atomically, and an existing one is kept unless `overwrite`.
/// Returns what `gecaro compensate --json` says of it (counts, flagged lines,
/// largest residual and correction, the file written), without listing the
/// targets, which are in the file. Runs without the GIL; Ctrl-C stops it and
/// writes nothing.
///
/// Raises NotConvergedError, with that dict in `.result`, when some targets
/// are flagged (reconfigured, beyond a joint limit, or not reached).
#[pyfunction]
#[pyo3(signature = (
    nominal, calibrated, program, output, *, r#match = "pose", rebase = false, payload = None,
    tool = None, max_tool_turn = None, length_unit = None, angle_unit = None, columns = None, delimiter = None, decimal_comma = None,
    overwrite = false,
))]
pub(crate) fn compensate_program<'py>(
    py: Python<'py>,
    nominal: PyRef<'_, PyRobot>,
    calibrated: PyRef<'_, PyRobot>,
    program: PathBuf,
    output: PathBuf,
    r#match: &str,
    rebase: bool,
    payload: Option<String>,
    tool: Option<String>,
    max_tool_turn: Option<String>,
    length_unit: Option<String>,
    angle_unit: Option<String>,
    columns: Option<&Bound<'py, PyAny>>,
    delimiter: Option<String>,
    decimal_comma: Option<bool>,
    overwrite: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let columns = columns
        .map(|columns| -> PyResult<String> {
            if let Ok(text) = columns.extract::<String>() {
                return Ok(text);
            }
            let pairs = columns.cast::<PyDict>().map_err(|_| {
                input("columns: expected a dict {gecaro name: file column} or \"qm1=A1,…\"")
            })?;
            let pairs: Vec<String> = pairs
                .iter()
                .map(|(ours, theirs)| {
                    Ok(format!(
                        "{}={}",
                        ours.extract::<String>()?,
                        theirs.extract::<String>()?
                    ))
                })
                .collect::<PyResult<_>>()?;
            Ok(pairs.join(","))
        })
        .transpose()?;
    let mut request = CompensateRequest::new(
        RobotSource::Loaded(Box::new(nominal.file.clone())),
        RobotSource::Loaded(Box::new(calibrated.file.clone())),
        ProgramSource::File(program.display().to_string()),
    );
    request.matching = Some(r#match.to_owned());
    request.rebase = rebase;
    request.payload = payload;
    request.tool = tool;
    request.max_tool_turn = max_tool_turn;
    request.output.save_as = Some(output.display().to_string());
    request.output.overwrite = overwrite;
    request.format = DataFormatSpec {
        length_unit,
        angle_unit,
        columns,
        delimiter,
        decimal_comma,
        rotation: None,
    };
    let compensated = watched(py, |observer| request.run_streamed(&LocalFiles, observer))?;
    let document = to_python(py, &compensated.document())?;
    if let Some(failure) = compensated.failure() {
        let error = NotConvergedError::new_err(failure.message(gecaro_app::Dialect::Python));
        error.value(py).setattr("result", &document)?;
        return Err(error);
    }
    Ok(document)
}
