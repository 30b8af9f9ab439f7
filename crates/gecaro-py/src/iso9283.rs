//! ISO 9283's acceptance test (issue 78): `gecaro.iso9283_plan` and
//! `gecaro.iso9283_evaluate`, through the application layer's requests —
//! the documents `gecaro iso9283 plan --json` and `evaluate --json` print.

use std::path::{Path, PathBuf};

use gecaro_app::{
    CellSpec, DataFormatSpec, Iso9283EvaluateRequest, Iso9283PlanRequest, LocalFiles,
    ProgramSource, RobotSource, TestConditions,
};
use pyo3::prelude::*;

use crate::documents::to_python;
use crate::errors::IntoPyResult;
use crate::robot::PyRobot;

fn name(path: &Path) -> String {
    path.display().to_string()
}

/// Plans ISO 9283's test on `robot` (its nominal model): the cube (`"auto"`
/// — the largest found inside the working space — or `"CX,CY,CZ,SIDE"`
/// with units, `"800mm,0,600mm,400mm"`), its five poses P1–P5 and the
/// cycles, written as a program to `path` (CSV: pose, cycle, direction,
/// measure, qm1..qmn, `x,y,z[,qw,qx,qy,qz]`) in `length_unit`/`angle_unit`
/// → `{"centre", "side" (m), "poses": [{"pose", "position", "quaternion",
/// "qm"}], "rows", …, "program": the CSV text}`. `floor` (m) keeps every
/// joint above it.
#[pyfunction]
#[pyo3(signature = (
    robot, *, cube = "auto", cycles = 30, directions = 1,
    floor = None, path = None, length_unit = None, angle_unit = None, overwrite = false,
))]
pub(crate) fn iso9283_plan<'py>(
    py: Python<'py>,
    robot: PyRef<'_, PyRobot>,
    cube: &str,
    cycles: usize,
    directions: usize,
    floor: Option<f64>,
    path: Option<PathBuf>,
    length_unit: Option<String>,
    angle_unit: Option<String>,
    overwrite: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let mut request = Iso9283PlanRequest::new(RobotSource::Loaded(Box::new(robot.file.clone())));
    request.cube = Some(cube.to_owned());
    request.cycles = Some(cycles);
    request.directions = Some(directions);
    request.cell = CellSpec {
        floor,
        ..CellSpec::default()
    };
    request.format = DataFormatSpec {
        length_unit,
        angle_unit,
        ..DataFormatSpec::default()
    };
    request.output.save_as = path.as_deref().map(name);
    request.output.overwrite = overwrite;
    let planned = py.detach(|| request.run(&LocalFiles)).py()?;
    let document = to_python(py, &planned.document())?;
    document.set_item("program", planned.program)?;
    Ok(document)
}

/// Evaluates ISO 9283's test: `program` (`iso9283_plan`'s file), `data`
/// (what was measured: pose, cycle[, direction] and the attained
/// `x,y,z[,qw,qx,qy,qz]`, in `length_unit`), optionally `after` (measured
/// running the compensated program) → `{"before": {"poses": [{"ap": {"p",
/// "x", "y", "z"[, "a", "b", "c"]}, "rp": {"l"[, "a", "b", "c"]}, "vap"}],
/// "distance": {"ad", "rd", …}, …}, "after", "warnings"}` in metres and
/// radians. `frame`: `"base"` (default), `"best-fit"`, or the measurement
/// frame's pose in the base frame with units. `robot` checks the program's
/// targets against its model. `conditions`: load, speed, warm_up,
/// instrument, uncertainty (text, reported as given). `report`: write the
/// self-contained HTML report there (`overwrite` to replace one).
#[pyfunction]
#[pyo3(signature = (
    program, data, *, after = None, robot = None, frame = None, length_unit = None,
    angle_unit = None, rotation = None, conditions = None, report = None, overwrite = false,
))]
pub(crate) fn iso9283_evaluate<'py>(
    py: Python<'py>,
    program: PathBuf,
    data: PathBuf,
    after: Option<PathBuf>,
    robot: Option<PyRef<'_, PyRobot>>,
    frame: Option<String>,
    length_unit: Option<String>,
    angle_unit: Option<String>,
    rotation: Option<String>,
    conditions: Option<std::collections::HashMap<String, String>>,
    report: Option<PathBuf>,
    overwrite: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let mut request = Iso9283EvaluateRequest::new(
        ProgramSource::File(name(&program)),
        ProgramSource::File(name(&data)),
    );
    request.after = after.as_deref().map(|path| ProgramSource::File(name(path)));
    request.robot = robot.map(|robot| RobotSource::Loaded(Box::new(robot.file.clone())));
    request.frame = frame;
    request.format = DataFormatSpec {
        length_unit,
        angle_unit,
        rotation,
        ..DataFormatSpec::default()
    };
    if let Some(conditions) = conditions {
        let value = serde_json::to_value(conditions)
            .map_err(|error| crate::errors::input(format!("conditions: {error}")))?;
        request.conditions = serde_json::from_value::<TestConditions>(value).map_err(|error| {
            crate::errors::input(format!(
                "conditions: {error} (load, speed, warm_up, instrument, uncertainty)"
            ))
        })?;
    }
    request.output.save_as = report.as_deref().map(name);
    request.output.overwrite = overwrite;
    let evaluated = py.detach(|| request.run(&LocalFiles)).py()?;
    to_python(py, &evaluated.document())
}
