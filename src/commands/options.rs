//! Command-line arguments as the application layer's requests, and what
//! several commands print of them.

use std::path::{Path, PathBuf};

use gecaro_app::{
    DataFormatSpec, DataSource, Dialect, FitSettings, Measurements, MethodSpec, Note,
    PrioritySource, RobotSource, StudySource,
};
use gecaro_calib::methods::Plane;
use gecaro_io::OutputPolicy;
use nalgebra::{IsometryMatrix3, Rotation3, Vector3};

use crate::cli::{
    CellArgs, DataFormatArgs, IdentificationRunArgs, MethodOptionArgs, StudySource as Source,
};
use crate::failure::Failure;

/// What `--force` says of an existing output file.
pub(crate) fn output_policy(force: bool) -> OutputPolicy {
    if force {
        OutputPolicy::Overwrite
    } else {
        OutputPolicy::KeepExisting
    }
}

/// Three comma-separated numbers from an option.
pub(crate) fn vector3(values: &[f64], option: &str) -> Result<Vector3<f64>, Failure> {
    match values {
        [x, y, z] => Ok(Vector3::new(*x, *y, *z)),
        _ => Err(Failure::usage(
            format!(
                "{option} needs three comma-separated numbers, got {}",
                values.len()
            ),
            Some(format!("for example: {option} 0.3,0.5,0.81")),
        )),
    }
}

/// A rotation from four comma-separated numbers: a unit quaternion qw,qx,qy,qz.
pub(crate) fn rotation(values: &[f64], option: &str) -> Result<Rotation3<f64>, Failure> {
    let [w, x, y, z] = values[..] else {
        return Err(Failure::usage(
            format!(
                "{option} needs four numbers (qw,qx,qy,qz), got {}",
                values.len()
            ),
            Some(format!("for example: {option} 1,0,0,0")),
        ));
    };
    gecaro_io::unit_quaternion(w, x, y, z)
        .map(|quaternion| quaternion.to_rotation_matrix())
        .map_err(|message| Failure::usage(format!("{option}: {message}"), None))
}

/// A rigid transform from seven comma-separated numbers: position x,y,z
/// (metres), then a unit quaternion qw,qx,qy,qz; or the 16 numbers of a
/// 4×4 homogeneous matrix, row by row.
pub(crate) fn pose(values: &[f64], option: &str) -> Result<IsometryMatrix3<f64>, Failure> {
    if values.len() == 16 {
        return gecaro_io::pose_from_matrix(values)
            .map_err(|message| Failure::usage(format!("{option}: {message}"), None));
    }
    if values.len() != 7 {
        return Err(Failure::usage(
            format!(
                "{option} needs seven numbers (x,y,z,qw,qx,qy,qz) or the 16 of a 4×4 matrix, \
                 got {}",
                values.len()
            ),
            Some(format!("for example: {option} 0.1,0,0.5,1,0,0,0")),
        ));
    }
    gecaro_io::pose_from_seven(values)
        .map_err(|message| Failure::usage(format!("{option}: {message}"), None))
}

/// The plane given by `--plane-normal` and `--plane-point`, if any.
pub(crate) fn plane(
    normal: Option<&[f64]>,
    point: Option<&[f64]>,
) -> Result<Option<Plane>, Failure> {
    match (normal, point) {
        (None, None) => Ok(None),
        (Some(normal), Some(point)) => Ok(Some(Plane::new(
            vector3(normal, "--plane-normal")?,
            vector3(point, "--plane-point")?,
        )?)),
        _ => Err(Failure::usage(
            "a plane needs both --plane-normal and --plane-point",
            Some("for example: --plane-normal 0.3,0.5,0.81 --plane-point 0.3,0.2,0.6".to_owned()),
        )),
    }
}

/// Three numbers of an option, as an array.
fn triple(values: Option<&[f64]>, option: &str) -> Result<Option<[f64; 3]>, Failure> {
    values
        .map(|values| vector3(values, option).map(Into::into))
        .transpose()
}

/// The method `name` with the options of the command line.
pub(crate) fn method_spec(name: &str, args: &MethodOptionArgs) -> Result<MethodSpec, Failure> {
    Ok(MethodSpec {
        name: name.to_owned(),
        plane_normal: triple(args.plane.plane_normal.as_deref(), "--plane-normal")?,
        plane_point: triple(args.plane.plane_point.as_deref(), "--plane-point")?,
        plane_unknown: args.plane.plane.as_deref().map(|plane| plane == "unknown"),
        orientation: Some(args.orientation.clone()),
        set_size: args.set_size,
    })
}

/// The format of a data or program file as the command line gives it.
pub(crate) fn data_format(args: &DataFormatArgs) -> DataFormatSpec {
    DataFormatSpec {
        length_unit: args.units.length_unit.clone(),
        angle_unit: args.units.angle_unit.clone(),
        columns: args.columns.clone(),
        delimiter: args.delimiter.clone(),
        decimal_comma: args.decimal_comma.then_some(true),
        rotation: args.rotation.clone(),
    }
}

/// The units the command line states (`--length-unit`, `--angle-unit`).
pub(crate) fn data_units(args: &crate::cli::UnitArgs) -> Result<gecaro_io::DataUnits, Failure> {
    let spec = DataFormatSpec {
        length_unit: args.length_unit.clone(),
        angle_unit: args.angle_unit.clone(),
        ..DataFormatSpec::default()
    };
    Ok(spec.format()?.units)
}

/// A path as the application layer names files.
pub(crate) fn name(path: &Path) -> String {
    path.display().to_string()
}

/// The output file `path`, replacing one that exists when `force`.
pub(crate) fn written(path: &Path, force: bool) -> gecaro_app::Output {
    gecaro_app::Output {
        save_as: Some(name(path)),
        overwrite: force,
    }
}

/// What a command's measurements are: one method with its data file, or a study file.
pub(crate) fn measurements(source: &Source, data: Option<&Path>) -> Result<Measurements, Failure> {
    Ok(Measurements {
        robot: source.robot.clone().map(RobotSource::Named),
        method: source
            .method
            .as_deref()
            .map(|method| method_spec(method, &source.options))
            .transpose()?,
        data: data.map(|path| DataSource::File(name(path))),
        format: data_format(&source.format),
        study: source
            .study
            .as_deref()
            .map(|path| StudySource::File(name(path))),
        strict_limits: source.strict_limits,
        sigma: None,
        sigma_rotation: None,
    })
}

/// A serial robot has no measuring leg: `--method leg` and the `--leg-*`
/// options are a parallel robot's (docs/parallel.md), refused by name.
pub(crate) fn no_measuring_leg(
    leg: &crate::cli::LegArgs,
    method: Option<&str>,
) -> Result<(), Failure> {
    let given = leg.given();
    let option = given
        .iter()
        .find(|(_, given)| *given)
        .map(|(option, _)| *option)
        .or((method == Some("leg")).then_some("--method leg"));
    match option {
        Some(option) => Err(Failure::usage(
            format!("{option} is a parallel robot's measuring leg: a serial robot has none"),
            Some(
                "a serial robot is measured by an instrument outside it (--method position, \
                 frame, distance, …); a measuring leg calibrates a Gough–Stewart platform \
                 (docs/parallel.md)"
                    .to_owned(),
            ),
        )),
        None => Ok(()),
    }
}

/// A serial robot's one data file of `--data`, given at most once: its
/// several sets are a study file's.
pub(crate) fn one_data_file(data: &[PathBuf]) -> Result<Option<&Path>, Failure> {
    match data {
        [] => Ok(None),
        [one] => Ok(Some(one)),
        _ => Err(Failure::usage(
            "a serial robot takes one --data file: its several sets go in a study file \
             (--study; each set with its method, σ, reflector and station, docs/studies.md)",
            None,
        )),
    }
}

/// The identification settings of the command line.
pub(crate) fn fit_settings(args: &IdentificationRunArgs) -> FitSettings {
    FitSettings {
        priority: args
            .priority
            .as_deref()
            .map(|path| PrioritySource::File(name(path))),
        model: args.model.clone(),
        solver: Some(args.solver.clone()),
        max_iterations: Some(args.max_iterations),
        loss: Some(args.loss.clone()),
        loss_scale: args.loss_scale,
        prior: args.prior.clone(),
        outlier_threshold: Some(args.outlier_threshold),
        reject: args.reject,
        work_region: args.work_region.clone(),
    }
}

/// Prints notes and warnings on standard error.
pub(crate) fn print_notes(notes: &[Note]) {
    for note in notes {
        eprintln!(
            "{}: {}",
            if note.warning { "warning" } else { "note" },
            crate::format::shown(&note.text(Dialect::CommandLine))
        );
    }
}

/// The measuring cell as the command line gives it.
pub(crate) fn cell_spec(args: &CellArgs) -> Result<gecaro_app::CellSpec, Failure> {
    Ok(gecaro_app::CellSpec {
        floor: args.floor,
        station: triple(args.station.as_deref(), "--station")?,
        max_incidence: args.max_incidence.clone(),
        clearance: args.clearance,
    })
}
