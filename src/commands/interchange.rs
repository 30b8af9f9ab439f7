//! `gecaro robot import` and `gecaro robot export`: robots from and to URDF,
//! DH tables and SYMORO files (the rules are in `docs/interchange.md`).

use gecaro_app::{ExportRequest, ImportRequest, LocalFiles, RobotSource, format_name};
use gecaro_io::RobotFormat;

use super::options::name;
use crate::cli::{ExportArgs, ImportArgs};
use crate::failure::Failure;
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
    request.save_as = Some(name(&args.output));
    request.overwrite = args.force;
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
    request.save_as = Some(name(&args.output));
    request.overwrite = args.force;
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
