//! Parallel robots (issue 79): `gecaro.parallel_generate`,
//! `parallel_identifiable`, `parallel_identify` and `parallel_evaluate`,
//! through the application layer's requests — the documents the command
//! line's `--json` prints. A robot is a parallel robot file's path or a
//! ready parallel robot's name (`"hexapod"`); data are files.

use std::path::{Path, PathBuf};

use gecaro_app::parallel::{
    ParallelCompensateRequest, ParallelEvaluateRequest, ParallelGenerateRequest,
    ParallelIdentifiableRequest, ParallelIdentifyRequest, ParallelPredictRequest,
};
use gecaro_app::{DataFormatSpec, DataSource, LocalFiles, Output};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::documents::to_python;
use crate::errors::IntoPyResult;
use crate::sigma::Sigma;

fn name(path: &Path) -> String {
    path.display().to_string()
}

fn output(path: Option<&Path>, overwrite: bool) -> Output {
    Output {
        save_as: path.map(name),
        overwrite,
    }
}

fn format(length_unit: Option<String>, angle_unit: Option<String>) -> DataFormatSpec {
    DataFormatSpec {
        length_unit,
        angle_unit,
        ..DataFormatSpec::default()
    }
}

/// Simulates `count` measurements (or measurements at the actuator values
/// of the file `configurations`, a plan's) of a "real" platform drawn about `robot`
/// at error level `error_level` (±L mm, gains ±L·10⁻³; or the platform file
/// `real`), at random reachable poses, by `method` (`"frame"`: the
/// platform's pose; `"position"`: its tool point; `"leg"`: a measuring
/// leg's readings, its sockets `leg_base` and `leg_platform` as mounted,
/// points with their units, `"250mm,-100mm,0"`), noise σ `noise` (m; rad
/// for orientations) → `{"configurations", "data": the CSV text, "real":
/// the real platform's file text}`; written to `path` (and `real_path`)
/// when given.
#[pyfunction]
#[pyo3(signature = (
    robot, method, count = 0, *, configurations = None, noise = 0.0, error_level = None,
    real = None, seed = 1, path = None, real_path = None, length_unit = None,
    angle_unit = None, leg_base = None, leg_platform = None, leg_gain = None, overwrite = false,
))]
pub(crate) fn parallel_generate<'py>(
    py: Python<'py>,
    robot: String,
    method: String,
    count: usize,
    configurations: Option<PathBuf>,
    noise: f64,
    error_level: Option<f64>,
    real: Option<PathBuf>,
    seed: u64,
    path: Option<PathBuf>,
    real_path: Option<PathBuf>,
    length_unit: Option<String>,
    angle_unit: Option<String>,
    leg_base: Option<String>,
    leg_platform: Option<String>,
    leg_gain: Option<f64>,
    overwrite: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let request = ParallelGenerateRequest {
        robot,
        method,
        count,
        configurations: configurations
            .as_deref()
            .map(|path| DataSource::File(name(path))),
        format: format(length_unit, angle_unit),
        error_level,
        real: real.as_deref().map(name),
        noise,
        seed: Some(seed),
        output: output(path.as_deref(), overwrite),
        real_save_as: real_path.as_deref().map(name),
        leg_base,
        leg_platform,
        leg_gain,
    };
    let generated = py.detach(|| request.run(&LocalFiles)).py()?;
    let document = pyo3::types::PyDict::new(py);
    document.set_item("configurations", generated.samples.len())?;
    document.set_item("data", generated.text)?;
    document.set_item(
        "real",
        gecaro_io::format_parallel_robot_file(&generated.real),
    )?;
    Ok(document.into_any())
}

/// The identifiable parameters of `robot` measured by `method`, at the
/// configurations of the data file `data` or at `count` random reachable
/// poses → `{"rank", "parameters": [(name, status)], "regrouped":
/// [{"parameter", "into": [(name, coefficient)]}], "condition_number", …}`.
#[pyfunction]
#[pyo3(signature = (robot, method, *, data = None, count = None, seed = 1, length_unit = None))]
pub(crate) fn parallel_identifiable<'py>(
    py: Python<'py>,
    robot: String,
    method: String,
    data: Option<PathBuf>,
    count: Option<usize>,
    seed: u64,
    length_unit: Option<String>,
) -> PyResult<Bound<'py, PyAny>> {
    let request = ParallelIdentifiableRequest {
        robot,
        method,
        data: data.as_deref().map(|path| DataSource::File(name(path))),
        format: format(length_unit, None),
        count,
        seed: Some(seed),
    };
    let report = py.detach(|| request.run(&LocalFiles)).py()?;
    to_python(py, &report)
}

/// Identifies `robot`'s parameters from the data file `data` (or a list
/// of files, each measured from its own tracker station: each station's
/// frame identified with the platform, `"stations"` in the document)
/// measured by `method`, σ `sigma` (a number in the data's length unit or a text with
/// its unit, `"20um"`; `sigma_rotation` for orientations) → `{"outcome",
/// "summary", "sigma_ratio", "parameters": [{"name", "status", "nominal",
/// "identified", "sigma"}], "errors_before", "errors_after", "region" (where
/// the result holds: `"measured"` actuator ranges, `"predicted_work"` m,
/// `"holds_everywhere"`; over `work_region` when given, actuator ranges
/// with their units as `"qm1=-10..10mm,qm4=-5..5mm"`, else over the
/// actuators' ranges), "warnings", …,
/// "calibrated": the calibrated platform's file text}`, written to `path`
/// when given, and `"trusted"`: whether the verdict trusts the fit (as
/// `Identification.verdict` says for a serial robot). `loss` `"huber"`,
/// `"cauchy"` or `"tukey"` (scale `loss_scale` robust σ̂) weighs each
/// measurement down by its residual after the least-squares fit: the
/// document's `"loss"`, `"reweightings"`, `"robust_sigma"`,
/// `"weighed_down"`; `reject` drops the measurements that stand out and
/// identifies the rest again, once (`"rejected"`); `prior` (`"1mm,0.05deg,0.1%"`)
/// holds the parameters about their nominal values. `report` names the
/// file the self-contained HTML report is written to (`gecaro report`;
/// `"report"` in the document), trusted or not; `residuals` the CSV file
/// of every measurement's errors and residual (`gecaro identify
/// --residuals`; `"residuals"`). A fit that did not converge raises
/// `NotConvergedError` (its report and residuals written first). The
/// `"leg"` method calibrates a Gough–Stewart platform from its own
/// actuators and a measuring leg's readings, its sockets `leg_base` and
/// `leg_platform` (points with their units) and gain `leg_gain` (1 by
/// default): `"leg"` in the document, the leg identified.
/// One data file, or several (one a tracker station).
#[derive(FromPyObject)]
pub(crate) enum DataPaths {
    One(PathBuf),
    Several(Vec<PathBuf>),
}

impl DataPaths {
    fn paths(self) -> Vec<PathBuf> {
        match self {
            DataPaths::One(path) => vec![path],
            DataPaths::Several(paths) => paths,
        }
    }
}

#[pyfunction]
#[pyo3(signature = (
    robot, method, data, *, sigma = None, sigma_rotation = None, length_unit = None,
    angle_unit = None, max_iterations = 30, work_region = None, loss = "l2", loss_scale = None,
    reject = false, prior = None, path = None, report = None, residuals = None,
    leg_base = None, leg_platform = None, leg_gain = None, overwrite = false,
))]
pub(crate) fn parallel_identify<'py>(
    py: Python<'py>,
    robot: String,
    method: String,
    data: DataPaths,
    sigma: Option<Sigma>,
    sigma_rotation: Option<Sigma>,
    length_unit: Option<String>,
    angle_unit: Option<String>,
    max_iterations: usize,
    work_region: Option<String>,
    loss: &str,
    loss_scale: Option<f64>,
    reject: bool,
    prior: Option<String>,
    path: Option<PathBuf>,
    report: Option<PathBuf>,
    residuals: Option<PathBuf>,
    leg_base: Option<String>,
    leg_platform: Option<String>,
    leg_gain: Option<f64>,
    overwrite: bool,
) -> PyResult<Bound<'py, PyAny>> {
    // Refused before the work, as the platform's own file is.
    output(report.as_deref(), overwrite)
        .check(&LocalFiles, "html")
        .py()?;
    output(residuals.as_deref(), overwrite)
        .check(&LocalFiles, "csv")
        .py()?;
    let paths = data.paths();
    let Some((first, stations)) = paths.split_first() else {
        return Err(PyValueError::new_err(
            "data: give a data file, or a list of them (one a tracker station)",
        ));
    };
    let request = ParallelIdentifyRequest {
        robot,
        method,
        data: DataSource::File(name(first)),
        stations: stations
            .iter()
            .map(|path| DataSource::File(name(path)))
            .collect(),
        leg_base,
        leg_platform,
        leg_gain,
        format: format(length_unit, angle_unit),
        sigma: sigma.map(Into::into),
        sigma_rotation: sigma_rotation.map(Into::into),
        max_iterations: Some(max_iterations),
        work_region,
        loss: Some(loss.to_owned()),
        loss_scale,
        reject: Some(reject),
        prior,
        output: output(path.as_deref(), overwrite),
    };
    let identified = py.detach(|| request.run(&LocalFiles)).py()?;
    if let Some(report) = &report {
        let html = py
            .detach(|| identified.report("gecaro.parallel_identify (Python)"))
            .py()?;
        output(Some(report), overwrite)
            .write(&LocalFiles, "html", html.as_bytes())
            .py()?;
    }
    if let Some(residuals) = &residuals {
        let csv = identified.residuals_csv().py()?;
        output(Some(residuals), overwrite)
            .write(&LocalFiles, "csv", csv.as_bytes())
            .py()?;
    }
    if !identified.converged()
        && let Some(error) = identified.failure()
    {
        return Err(error).py();
    }
    let document = to_python(py, &identified.document)?;
    document.set_item("trusted", identified.failure().is_none())?;
    document.set_item(
        "report",
        report.as_deref().map(|report| report.display().to_string()),
    )?;
    document.set_item(
        "residuals",
        residuals
            .as_deref()
            .map(|residuals| residuals.display().to_string()),
    )?;
    document.set_item(
        "calibrated",
        gecaro_io::format_parallel_robot_file(&identified.calibrated),
    )?;
    Ok(document)
}

/// The errors of `robot`'s direct model at the configurations of the data
/// file `data` (measured by `method`) → `{"errors": {"position_rms",
/// "position_max", "angle_rms", "angle_max"}, …}` in metres and radians.
#[pyfunction]
#[pyo3(signature = (robot, method, data, *, length_unit = None, angle_unit = None))]
pub(crate) fn parallel_evaluate<'py>(
    py: Python<'py>,
    robot: String,
    method: String,
    data: PathBuf,
    length_unit: Option<String>,
    angle_unit: Option<String>,
) -> PyResult<Bound<'py, PyAny>> {
    let request = ParallelEvaluateRequest {
        robot,
        method,
        data: DataSource::File(name(&data)),
        format: format(length_unit, angle_unit),
    };
    let evaluated = py.detach(|| request.run(&LocalFiles)).py()?;
    to_python(py, &evaluated)
}

/// A program of platform poses (`x,y,z,qw,qx,qy,qz`, base frame; other
/// columns left aside) turned into the actuator values of the calibrated
/// platform `calibrated` (exact: its inverse model) and written to `path`
/// (`qm1…qm6` and the targets) → `{"targets", "largest_correction" (from
/// the nominal platform's values), "outside_range": [(line, legs)],
/// "outside_measured": [(line, actuators)] (outside the ranges a regional
/// calibration measured), "written", "program": the CSV text, "matched",
/// "note"}`. `match = "position"` reads the targets as tool points
/// (`x,y,z`; the platform turned as the program's `qw,qx,qy,qz` say, else
/// level), what a platform calibrated from one point is compensated for;
/// its poses are refused (its platform frame is not observed).
#[pyfunction]
#[pyo3(signature = (
    nominal, calibrated, program, *, path = None, length_unit = None, angle_unit = None,
    r#match = "pose", overwrite = false,
))]
pub(crate) fn parallel_compensate<'py>(
    py: Python<'py>,
    nominal: String,
    calibrated: String,
    program: PathBuf,
    path: Option<PathBuf>,
    length_unit: Option<String>,
    angle_unit: Option<String>,
    r#match: &str,
    overwrite: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let request = ParallelCompensateRequest {
        nominal,
        calibrated,
        program: DataSource::File(name(&program)),
        format: format(length_unit, angle_unit),
        matching: Some(r#match.to_owned()),
        output: output(path.as_deref(), overwrite),
    };
    let compensated = py.detach(|| request.run(&LocalFiles)).py()?;
    let document = to_python(py, &compensated)?;
    document.set_item("program", compensated.text)?;
    Ok(document)
}

/// The `count` poses to measure, chosen for `criterion` (`"d"`: D-optimal,
/// `"a"`, `"e"`, `"o4"`, `"o5"`, or `"test"`: the calibrated platform's
/// predicted error over its workspace) from `pool` random reachable poses
/// of `robot` (default 20 × `count`) → `{"count", "rank",
/// "criterion_name", "criterion_meaning", "criterion", "random_criterion"
/// (the plan's value and random poses'), "configurations": actuator
/// values, "written", "configurations_csv": the file's text}`, written to
/// `path` when given.
#[pyfunction]
#[pyo3(signature = (
    robot, method, count, *, pool = None, seed = 1, criterion = "d", path = None,
    overwrite = false,
))]
pub(crate) fn parallel_plan<'py>(
    py: Python<'py>,
    robot: String,
    method: String,
    count: usize,
    pool: Option<usize>,
    seed: u64,
    criterion: &str,
    path: Option<PathBuf>,
    overwrite: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let request = gecaro_app::parallel::ParallelPlanRequest {
        robot,
        method,
        count,
        pool,
        seed: Some(seed),
        criterion: Some(criterion.to_owned()),
        output: output(path.as_deref(), overwrite),
    };
    let planned = py.detach(|| request.run(&LocalFiles)).py()?;
    let document = to_python(py, &planned)?;
    document.set_item("configurations_csv", planned.text)?;
    Ok(document)
}

/// The precision of calibrating `robot` from the configurations of the data
/// file `data` (a plan's actuator values; consecutive rows a pair for
/// distances) measured by `method` with σ `sigma` (a number in the data's
/// length unit or a text with its unit; `sigma_rotation` for orientations)
/// → `{"rank", "parameters": [{"name", "unit", "sigma"}], "region":
/// {"predicted_inside", "predicted_work", "predicted_work_max",
/// "noise_floor", "holds_everywhere", …}, "monte_carlo": {"runs",
/// "work_rms", "work_max"} when `monte_carlo` calibrations are simulated
/// (real robots drawn at `error_level`: ±mm, ±mrad)}` in metres and radians;
/// over `work_region` when given (actuator ranges with their units,
/// `"qm1=-12..12mm"`; the region's `work_name` then says so), else over
/// the whole workspace.
#[pyfunction]
#[pyo3(signature = (
    robot, method, data, *, sigma, sigma_rotation = None, length_unit = None, angle_unit = None,
    monte_carlo = None, error_level = None, seed = 1, work_region = None,
))]
pub(crate) fn parallel_predict<'py>(
    py: Python<'py>,
    robot: String,
    method: String,
    data: PathBuf,
    sigma: Sigma,
    sigma_rotation: Option<Sigma>,
    length_unit: Option<String>,
    angle_unit: Option<String>,
    monte_carlo: Option<usize>,
    error_level: Option<f64>,
    seed: u64,
    work_region: Option<String>,
) -> PyResult<Bound<'py, PyAny>> {
    let request = ParallelPredictRequest {
        robot,
        method,
        data: DataSource::File(name(&data)),
        format: format(length_unit, angle_unit),
        sigma: sigma.into(),
        sigma_rotation: sigma_rotation.map(Into::into),
        monte_carlo,
        error_level,
        seed: Some(seed),
        work_region,
    };
    let predicted = py.detach(|| request.run(&LocalFiles)).py()?;
    to_python(py, &predicted)
}
