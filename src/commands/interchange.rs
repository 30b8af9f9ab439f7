//! `gecaro robot import`, `gecaro robot export` and `gecaro robot rebase`:
//! robots from and to URDF, DH tables and SYMORO files (the rules are in
//! `docs/interchange.md`), and a calibrated robot in its own base frame.

use gecaro_app::{
    BasePointsSource, BaseRegistration, ExportRequest, ImportRequest, LocalFiles, RebaseRequest,
    RobotSource, format_name,
};
use gecaro_io::RobotFormat;
use serde::Serialize;

use super::options::{name, written};
use crate::cli::{ExportArgs, ImportArgs, RebaseArgs};
use crate::failure::Failure;
use crate::format::number;
use crate::format::shown;

fn print_notes(notes: &[String]) {
    for note in notes {
        eprintln!("note: {}", shown(note));
    }
}

pub(crate) fn import(args: &ImportArgs) -> Result<(), Failure> {
    let mut request = ImportRequest::new(name(&args.file));
    request.format = args.from.clone();
    request.base = args.base.clone();
    request.tip = args.tip.clone();
    request.name = args.name.clone();
    request.length_unit = args.units.length_unit.clone();
    request.angle_unit = args.units.angle_unit.clone();
    request.output = written(&args.output, args.force);
    let imported = request.run(&LocalFiles)?.imported;
    let robot = &imported.file.robot;
    print_notes(&imported.notes);
    println!(
        "wrote {}: {} — {} joints ({}), {}",
        shown(&args.output.display().to_string()),
        shown(robot.name()),
        robot.joint_count(),
        robot.joint_letters(),
        shown(imported.file.description.as_deref().unwrap_or("imported"))
    );
    println!(
        "see its table with: gecaro robot show {}",
        args.output.display()
    );
    Ok(())
}

pub(crate) fn export(args: &ExportArgs) -> Result<(), Failure> {
    let mut request = ExportRequest::new(RobotSource::Named(args.robot.clone()), args.to.clone());
    request.output = written(&args.output, args.force);
    request.rebase = args.rebase.clone().map(RobotSource::Named);
    let calibration_path = gecaro_app::joint_calibration_name(&name(&args.output));
    let exported = request.run(&LocalFiles)?;
    print_notes(&exported.exported.notes);
    if exported.exported.joint_calibration.is_some() {
        eprintln!(
            "note: wrote the joint calibration to {calibration_path}: the joint values of {} are not the motor values",
            args.output.display()
        );
    } else if std::path::Path::new(&calibration_path).exists() {
        eprintln!(
            "warning: {calibration_path} is left from an earlier export and does not apply to this one: delete it",
        );
    }
    let names = match (&exported.robot.urdf, exported.format) {
        (Some(names), RobotFormat::Urdf) => format!(", names of the URDF `{}`", names.robot),
        _ => String::new(),
    };
    println!(
        "wrote {} ({}, {} joints{names})",
        args.output.display(),
        format_name(exported.format),
        exported.robot.robot.joint_count()
    );
    Ok(())
}

/// `gecaro robot rebase --json`: the measurement frame in the robot's base
/// frame (metres, radians) and the file written.
#[derive(Serialize)]
struct RebasedJson {
    /// The measurement frame's origin in the robot's base frame (m).
    position: [f64; 3],
    /// Its roll, pitch, yaw (rad, about the fixed x, y, z axes).
    rpy: [f64; 3],
    /// Its orientation as a unit quaternion `[w, x, y, z]`.
    quaternion: [f64; 4],
    /// The robot file written.
    output: String,
    /// The base registered by points (`--base-points`).
    #[serde(skip_serializing_if = "Option::is_none")]
    registration: Option<gecaro_app::BaseRegistrationJson>,
}

pub(crate) fn rebase(args: &RebaseArgs) -> Result<(), Failure> {
    let mut request = RebaseRequest::new(
        RobotSource::Named(args.robot.clone()),
        RobotSource::Named(args.nominal.clone()),
    );
    request.output = written(&args.output, args.force);
    request.base_points = args
        .base_points
        .as_ref()
        .map(|path| BasePointsSource::File(name(path)));
    request.base_circles = args
        .base_circles
        .as_ref()
        .map(|path| gecaro_app::DataSource::File(name(path)));
    request.format = super::options::data_format(&args.format);
    let rebased = request.run(&LocalFiles)?;
    let frame = rebased.measurement_frame;
    let t = frame.translation.vector;
    let (roll, pitch, yaw) = frame.rotation.euler_angles();
    let q = nalgebra::UnitQuaternion::from_rotation_matrix(&frame.rotation);
    if args.json {
        return super::output::print_json(&RebasedJson {
            position: [t.x, t.y, t.z],
            rpy: [roll, pitch, yaw],
            quaternion: [q.w, q.i, q.j, q.k],
            output: args.output.display().to_string(),
            registration: rebased
                .registration
                .as_ref()
                .map(BaseRegistration::document),
        });
    }
    if let (Some(registration), Some(convention)) =
        (&rebased.registration, &rebased.from_convention)
    {
        println!("{}", registration.summary());
        for (point, residual) in registration.points.iter().zip(&registration.fit.residuals) {
            println!(
                "  {:<12} line {:>4}: {} {} mm",
                point.name,
                point.line,
                match registration.by {
                    gecaro_app::BaseBy::Points => "residual",
                    gecaro_app::BaseBy::Circles => "from its circle",
                },
                number(residual * 1e3, 4)
            );
        }
        let (distance, angle) = (
            convention.translation.vector.norm(),
            convention.rotation.angle().to_degrees(),
        );
        let said = format!(
            "the base by {}'s convention (joint 1's axis, x towards axis 2) stands {} mm and {}° \
             from this base",
            shown(&args.nominal),
            number(distance * 1e3, 3),
            number(angle, 4)
        );
        // A robot base stands within millimetres of its drawing's.
        if distance > 0.05 || angle > 5.0 {
            eprintln!(
                "warning: {said}: more than a mounting error; check the points' names and \
                 columns, and that {}'s base is the drawing's",
                shown(&args.nominal)
            );
        } else {
            println!("{said}");
        }
    }
    let base = match (&args.base_points, &args.base_circles) {
        (Some(points), _) | (None, Some(points)) => format!("the base of {}", points.display()),
        (None, None) => format!("{}'s base frame", shown(&args.nominal)),
    };
    println!(
        "the measurement frame in {base}: x {} y {} z {} mm, rpy {} {} {}°",
        number(t.x * 1e3, 3),
        number(t.y * 1e3, 3),
        number(t.z * 1e3, 3),
        number(roll.to_degrees(), 4),
        number(pitch.to_degrees(), 4),
        number(yaw.to_degrees(), 4)
    );
    let back = frame.inverse();
    let (b, r) = (
        back.translation.vector,
        nalgebra::UnitQuaternion::from_rotation_matrix(&back.rotation),
    );
    println!(
        "wrote {}: the calibrated robot in its own base frame (`gecaro robot reframe {} --world \
         {},{},{},{},{},{},{}` gives the measured one back)",
        shown(&args.output.display().to_string()),
        args.output.display(),
        b.x,
        b.y,
        b.z,
        r.w,
        r.i,
        r.j,
        r.k
    );
    Ok(())
}
