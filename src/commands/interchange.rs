//! `gecaro robot import` and `gecaro robot export`: robots from and to URDF,
//! DH tables and SYMORO files (the rules are in `docs/interchange.md`).

use gecaro_io::{
    AngleUnit, ChainEnds, Exported, ImportOptions, LengthUnit, RobotFormat, TableUnits,
    export_robot, format_robot_file, import_robot, load_robot, write_atomically,
};

use super::options::output_policy;
use crate::cli::{AngleUnitArg, ExportArgs, FormatArg, ImportArgs, LengthUnitArg, UnitArgs};
use crate::failure::Failure;

fn format_of(argument: FormatArg) -> RobotFormat {
    match argument {
        FormatArg::Urdf => RobotFormat::Urdf,
        FormatArg::Dh => RobotFormat::Dh,
        FormatArg::Mdh => RobotFormat::Mdh,
        FormatArg::Symoro => RobotFormat::Symoro,
    }
}

/// The units the command line gives for files that do not state theirs.
pub(crate) fn table_units(units: &UnitArgs) -> TableUnits {
    TableUnits {
        angle: units.angle_unit.map(|unit| match unit {
            AngleUnitArg::Rad => AngleUnit::Radians,
            AngleUnitArg::Deg => AngleUnit::Degrees,
        }),
        length: units.length_unit.map(|unit| match unit {
            LengthUnitArg::M => LengthUnit::Metres,
            LengthUnitArg::Mm => LengthUnit::Millimetres,
        }),
    }
}

fn print_notes(notes: &[String]) {
    for note in notes {
        eprintln!("note: {note}");
    }
}

pub(crate) fn import(args: &ImportArgs) -> Result<(), Failure> {
    let imported = import_robot(
        &args.file,
        &ImportOptions {
            format: args.from.map(format_of),
            chain: ChainEnds {
                base: args.base.clone(),
                tip: args.tip.clone(),
                name: args.name.clone(),
            },
            units: table_units(&args.units),
        },
    )?;
    write_atomically(
        &args.output,
        format_robot_file(&imported.file).as_bytes(),
        output_policy(args.force),
    )?;
    let robot = &imported.file.robot;
    print_notes(&imported.notes);
    println!(
        "wrote {}: {} — {} joints ({}), {}",
        args.output.display(),
        robot.name(),
        robot.joint_count(),
        robot.joint_letters(),
        imported.file.description.as_deref().unwrap_or("imported")
    );
    println!(
        "see its table with: gecaro robot show {}",
        args.output.display()
    );
    Ok(())
}

fn format_name(format: RobotFormat) -> &'static str {
    match format {
        RobotFormat::Urdf => "a URDF",
        RobotFormat::Dh => "a standard DH table",
        RobotFormat::Mdh => "a modified DH table",
        RobotFormat::Symoro => "a SYMORO file",
    }
}

pub(crate) fn export(args: &ExportArgs) -> Result<(), Failure> {
    let file = load_robot(&args.robot)?;
    let format = format_of(args.to);
    let exported = export_robot(&file, format).map_err(|message| {
        Failure::usage(
            format!(
                "{} cannot be written as {}: {message}",
                file.robot.name(),
                format_name(format)
            ),
            None,
        )
    })?;
    let calibration_path = Exported::joint_calibration_path(&args.output);
    exported.write(&args.output, output_policy(args.force))?;
    print_notes(&exported.notes);
    if exported.joint_calibration.is_some() {
        eprintln!(
            "note: wrote the joint calibration to {}: the joint values of {} are not the motor values",
            calibration_path.display(),
            args.output.display()
        );
    } else if calibration_path.exists() {
        eprintln!(
            "warning: {} is left from an earlier export and does not apply to this one: delete it",
            calibration_path.display()
        );
    }
    let names = match (&file.urdf, format) {
        (Some(names), RobotFormat::Urdf) => format!(", names of the URDF `{}`", names.robot),
        _ => String::new(),
    };
    println!(
        "wrote {} ({}, {} joints{names})",
        args.output.display(),
        format_name(format),
        file.robot.joint_count()
    );
    Ok(())
}
