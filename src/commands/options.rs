//! Turning command-line method options into library options.
use gecaro_calib::methods::{MethodOptions, Plane};
use gecaro_core::OrientationDifference;
use gecaro_io::OutputPolicy;
use nalgebra::{IsometryMatrix3, Rotation3, Vector3};

use crate::cli::{DataFormatArgs, MethodOptionArgs, OrientationMethod, PlaneKnowledge};
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
/// (metres), then a unit quaternion qw,qx,qy,qz.
pub(crate) fn pose(values: &[f64], option: &str) -> Result<IsometryMatrix3<f64>, Failure> {
    if values.len() != 7 {
        return Err(Failure::usage(
            format!(
                "{option} needs seven numbers (x,y,z,qw,qx,qy,qz), got {}",
                values.len()
            ),
            Some(format!("for example: {option} 0.1,0,0.5,1,0,0,0")),
        ));
    }
    Ok(IsometryMatrix3::from_parts(
        vector3(&values[..3], option)?.into(),
        rotation(&values[3..], option)?,
    ))
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

/// The library options of a method from its command-line arguments.
pub(crate) fn method_options(args: &MethodOptionArgs) -> Result<MethodOptions, Failure> {
    let given = plane(
        args.plane.plane_normal.as_deref(),
        args.plane.plane_point.as_deref(),
    )?;
    let unknown = args
        .plane
        .plane
        .map(|knowledge| knowledge == PlaneKnowledge::Unknown);
    let (plane, plane_unknown) = MethodOptions::plane_choice(given, unknown)?;
    Ok(MethodOptions {
        plane,
        plane_unknown,
        orientation: match args.orientation {
            OrientationMethod::AxisAngle => OrientationDifference::AxisAngle,
            OrientationMethod::CrossProducts => OrientationDifference::CrossProducts,
        },
        set_size: MethodOptions::check_set_size(args.set_size)?,
    })
}

/// The robot, the study and the study's priority matrix named by a command
/// line: one method with its data file, or a study file.
pub(crate) fn load_study(
    source: &crate::cli::StudySource,
    data: Option<&std::path::Path>,
) -> Result<LoadedStudy, Failure> {
    if let Some(path) = &source.study {
        if source.format.units.angle_unit.is_some()
            || source.format.units.length_unit.is_some()
            || source.format.columns.is_some()
        {
            return Err(Failure::usage(
                "--angle-unit, --length-unit and --columns are for a data file; a study file \
                 gives them per set",
                Some("add length_unit = \"mm\", angle_unit = \"deg\" or columns = { x = \"X\" } to its [[measurements]]".to_owned()),
            ));
        }
        let file = gecaro_io::read_study_file(path)?;
        for note in &file.notes {
            eprintln!("note: {note}");
        }
        check_limits(&file.robot.robot, &file.study, source.strict_limits)?;
        return Ok(LoadedStudy {
            file: file.robot,
            study: file.study,
            priority: file.priority,
            prior: file.prior,
        });
    }
    let (Some(robot), Some(method)) = (&source.robot, &source.method) else {
        return Err(Failure::usage("give ROBOT and --method, or --study", None));
    };
    let robot = gecaro_io::load_robot(robot)?;
    let chosen = gecaro_calib::methods::method(method, &method_options(&source.options)?)?;
    let samples = match data {
        Some(path) => read_data(path, &robot.robot, chosen.as_ref(), &source.format)?,
        None => Vec::new(),
    };
    let label = data.map_or_else(
        || "random configurations".to_owned(),
        |p| p.display().to_string(),
    );
    let study = gecaro_calib::study::Study::single(chosen, samples, label);
    check_limits(&robot.robot, &study, source.strict_limits)?;
    Ok(LoadedStudy {
        file: robot,
        study,
        priority: None,
        prior: None,
    })
}

/// A robot with a study, and what a study file adds.
pub(crate) struct LoadedStudy {
    pub(crate) file: gecaro_io::RobotFile,
    pub(crate) study: gecaro_calib::study::Study,
    /// The study file's priority matrix.
    pub(crate) priority: Option<gecaro_core::PriorityMatrix>,
    /// The study file's prior.
    pub(crate) prior: Option<gecaro_calib::identification::Prior>,
}

/// The format of a data file as the command line gives it.
pub(crate) fn data_format(args: &DataFormatArgs) -> Result<gecaro_io::DataFormat, Failure> {
    let units = super::interchange::table_units(&args.units);
    Ok(gecaro_io::DataFormat {
        units: gecaro_io::DataUnits {
            length: units.length.unwrap_or_default(),
            angle: units.angle.unwrap_or_default(),
        },
        columns: match &args.columns {
            Some(text) => gecaro_io::ColumnMap::parse(text).map_err(|message| {
                Failure::usage(
                    format!("--columns: {message}"),
                    Some("for example: --columns x=X_mm,y=Y_mm,z=Z_mm".to_owned()),
                )
            })?,
            None => gecaro_io::ColumnMap::default(),
        },
    })
}

/// The samples of a data file for a method, with a note on the columns
/// the method does not use.
pub(crate) fn read_data(
    path: &std::path::Path,
    robot: &gecaro_core::Robot,
    method: &dyn gecaro_calib::methods::CalibrationMethod,
    format: &DataFormatArgs,
) -> Result<Vec<gecaro_calib::study::Sample>, Failure> {
    let data = gecaro_io::read_samples(
        path,
        &gecaro_io::joint_types(robot),
        method.data_columns(),
        &data_format(format)?,
    )?;
    if !data.unused_columns.is_empty() {
        eprintln!(
            "note: {}: columns {} are not used by the {} method (left alone)",
            path.display(),
            data.unused_columns.join(", "),
            method.name()
        );
    }
    Ok(data.samples)
}

/// Joints outside their limits in the data: a warning on stderr, or with
/// `--strict-limits` an error.
pub(crate) fn check_limits(
    robot: &gecaro_core::Robot,
    study: &gecaro_calib::study::Study,
    strict: bool,
) -> Result<(), Failure> {
    let Some(message) = study.limit_summary(robot) else {
        return Ok(());
    };
    if strict {
        Err(Failure::Input(format!(
            "{message} (--strict-limits refuses such data)"
        )))
    } else {
        eprintln!(
            "warning: {message} (the data are used as they are; --strict-limits refuses them)"
        );
        Ok(())
    }
}
