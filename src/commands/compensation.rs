//! `gecaro compensate`: a robot program corrected for the calibrated robot.

use super::options::output_policy;
use crate::cli::{CompensateArgs, MatchArg};
use crate::failure::Failure;
use gecaro_calib::compensation::{
    CompensatedPoint, CompensationStatus, Match, compensate as compensate_program,
};
use gecaro_io::{ProgramKind, load_robot, read_program, write_atomically};
use indicatif::ProgressBar;
use serde::Serialize;

/// Targets below which no progress bar is drawn.
const QUIET_BELOW: usize = 2000;

#[derive(Serialize)]
struct PointJson {
    line: usize,
    status: &'static str,
    motor_positions: Vec<f64>,
    position_error: f64,
    rotation_error: Option<f64>,
}

#[derive(Serialize)]
struct SummaryJson<'a> {
    targets: usize,
    reached: usize,
    outside_limits: Vec<usize>,
    not_reached: Vec<usize>,
    largest_position_error: f64,
    largest_correction: f64,
    output: &'a str,
    points: Vec<PointJson>,
}

pub(crate) fn compensate(args: &CompensateArgs) -> Result<(), Failure> {
    let nominal = load_robot(&args.nominal)?.robot;
    let calibrated = load_robot(&args.calibrated)?.robot;
    if !args.force && args.output.exists() {
        return Err(gecaro_io::Error::OutputExists {
            path: args.output.clone(),
        }
        .into());
    }
    let format = super::options::data_format(&args.format)?;
    let program = read_program(&args.program, &nominal, format.units, &format.columns)?;
    if !program.unused_columns.is_empty() && !args.json {
        eprintln!(
            "note: columns kept as they are (not read): {}",
            program.unused_columns.join(", ")
        );
    }
    let bar = if program.points.len() >= QUIET_BELOW {
        let bar = super::progress_bar("compensating");
        bar.set_length(program.points.len() as u64);
        bar
    } else {
        ProgressBar::hidden()
    };
    let matching = match args.matching {
        MatchArg::Pose => Match::Pose,
        MatchArg::Position => Match::Position,
    };
    let results = compensate_program(
        &nominal,
        &calibrated,
        &program.points,
        matching,
        &mut gecaro_calib::each_step(|done, _| {
            if done % 256 == 0 {
                bar.set_position(done as u64);
            }
        }),
    )?;
    bar.finish_and_clear();
    write_atomically(
        &args.output,
        program.format_corrected(&results).as_bytes(),
        output_policy(args.force),
    )?;
    report(args, &program, &results)
}

/// The largest change of a joint between the program and the correction, in
/// the program's unit: (value, unit, joint number, line).
fn largest_correction(
    program: &gecaro_io::ProgramFile,
    results: &[CompensatedPoint],
) -> Option<(f64, &'static str, usize, usize)> {
    let mut largest: Option<(f64, &'static str, usize, usize)> = None;
    for (index, (point, result)) in program.points.iter().zip(results).enumerate() {
        if result.status != CompensationStatus::Reached {
            continue;
        }
        let original = match &point.target {
            gecaro_calib::compensation::ProgramTarget::Joints(qm) => Some(qm),
            _ => point.joints.as_ref(),
        };
        for (j, (before, after)) in original
            .into_iter()
            .flatten()
            .zip(&result.motor_positions)
            .enumerate()
        {
            let (change, unit) = program.joint_in_file_unit(j, (after - before).abs());
            if largest.is_none_or(|(value, ..)| change > value) {
                largest = Some((change, unit, j + 1, program.line(index)));
            }
        }
    }
    largest
}

fn report(
    args: &CompensateArgs,
    program: &gecaro_io::ProgramFile,
    results: &[CompensatedPoint],
) -> Result<(), Failure> {
    let lines_with = |status: CompensationStatus| -> Vec<usize> {
        results
            .iter()
            .enumerate()
            .filter(|(_, result)| result.status == status)
            .map(|(index, _)| program.line(index))
            .collect()
    };
    let outside = lines_with(CompensationStatus::OutsideLimits);
    let unreached = lines_with(CompensationStatus::NotReached);
    let reached = results.len() - outside.len() - unreached.len();
    let largest_error = results
        .iter()
        .filter(|result| result.status != CompensationStatus::NotReached)
        .map(|result| result.position_error)
        .fold(0.0, f64::max);
    let correction = largest_correction(program, results);
    if args.json {
        super::print_json(&SummaryJson {
            targets: results.len(),
            reached,
            outside_limits: outside.clone(),
            not_reached: unreached.clone(),
            largest_position_error: largest_error,
            largest_correction: correction.map_or(0.0, |(value, ..)| value),
            output: &args.output.display().to_string(),
            points: results
                .iter()
                .enumerate()
                .map(|(index, result)| PointJson {
                    line: program.line(index),
                    status: result.status.word(),
                    motor_positions: result.motor_positions.clone(),
                    position_error: result.position_error,
                    rotation_error: result.rotation_error,
                })
                .collect(),
        })?;
    } else {
        let units = program.units();
        let kind = match program.kind() {
            ProgramKind::Joints => "joint targets",
            ProgramKind::Position => "point targets",
            ProgramKind::Pose => "pose targets",
        };
        println!(
            "{} {kind}: {reached} reached by the calibrated robot (largest residual {:.1e} {})",
            results.len(),
            largest_error / units.length.to_metres(),
            units.length.name()
        );
        if let Some((value, unit, joint, line)) = correction {
            println!("largest joint correction: {value:.4} {unit} (joint {joint}, line {line})");
        }
        println!("wrote {}", args.output.display());
    }
    let list = |lines: &[usize]| {
        let shown: Vec<String> = lines.iter().take(10).map(ToString::to_string).collect();
        format!(
            "{}{}",
            shown.join(", "),
            if lines.len() > 10 { ", …" } else { "" }
        )
    };
    if !outside.is_empty() {
        eprintln!(
            "warning: {} target(s) reached only beyond a joint limit (status outside-limits), lines {}",
            outside.len(),
            list(&outside)
        );
    }
    if !unreached.is_empty() {
        eprintln!(
            "warning: {} target(s) not reached: their joints are left as in the program (status not-reached), lines {}",
            unreached.len(),
            list(&unreached)
        );
    }
    if outside.is_empty() && unreached.is_empty() {
        Ok(())
    } else {
        Err(Failure::Numerical(format!(
            "{} of {} targets are flagged in {}; check them before running the program",
            outside.len() + unreached.len(),
            results.len(),
            args.output.display()
        )))
    }
}
