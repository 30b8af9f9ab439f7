//! `gecaro compensate`: a robot program corrected for the calibrated robot.

use gecaro_app::{CompensateRequest, LocalFiles, ProgramSource, RobotSource};
use gecaro_calib::compensation::CompensationStatus;
use gecaro_calib::each_step;
use gecaro_io::ProgramKind;
use indicatif::ProgressBar;

use super::options::{data_format, name};
use crate::cli::CompensateArgs;
use crate::failure::Failure;

/// Targets below which no progress bar is drawn.
const QUIET_BELOW: u64 = 2000;

pub(crate) fn compensate(args: &CompensateArgs) -> Result<(), Failure> {
    let mut request = CompensateRequest::new(
        RobotSource::Named(args.nominal.clone()),
        RobotSource::Named(args.calibrated.clone()),
        ProgramSource::File(name(&args.program)),
    );
    request.format = data_format(&args.format);
    request.matching = Some(args.matching.clone());
    request.rebase = args.rebase;
    request.payload = args.payload.clone();
    request.save_as = Some(name(&args.output));
    request.overwrite = args.force;
    let mut bar: Option<ProgressBar> = None;
    let compensated = request.run(
        &LocalFiles,
        &mut each_step(|done, total| {
            let total = total as u64;
            if total >= QUIET_BELOW && done % 256 == 0 {
                let bar = bar.get_or_insert_with(|| {
                    let bar = super::progress::progress_bar("compensating");
                    bar.set_length(total);
                    bar
                });
                bar.set_position(done as u64);
            }
        }),
    );
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    let compensated = compensated?;
    let program = compensated
        .program
        .as_ref()
        .ok_or_else(|| Failure::input("no program file was read"))?;
    if !program.unused_columns.is_empty() && !args.json {
        eprintln!(
            "note: columns kept as they are (not read): {}",
            program.unused_columns.join(", ")
        );
    }
    if args.json {
        super::output::print_json(&compensated.document())?;
    } else {
        let units = program.units();
        let kind = match program.kind() {
            ProgramKind::Joints => "joint targets",
            ProgramKind::Position => "point targets",
            ProgramKind::Pose => "pose targets",
        };
        let outside = compensated
            .lines_with(CompensationStatus::OutsideLimits)
            .len();
        let unreached = compensated.lines_with(CompensationStatus::NotReached).len();
        let reconfigured = compensated
            .lines_with(CompensationStatus::Reconfigured)
            .len();
        println!(
            "{} {kind}: {} reached by the calibrated robot (largest residual {:.1e} {})",
            compensated.results.len(),
            compensated.results.len() - outside - unreached - reconfigured,
            compensated.largest_position_error() / units.length.to_metres(),
            units.length.name()
        );
        if let Some((value, unit, joint, line)) = compensated.largest_correction() {
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
    let reconfigured = compensated.lines_with(CompensationStatus::Reconfigured);
    if !reconfigured.is_empty() {
        eprintln!(
            "warning: {} target(s) reached only in another configuration, a joint moving by more than {} rad (status reconfigured: another branch, or a wrist turned about a singularity), lines {}",
            reconfigured.len(),
            gecaro_calib::compensation::RECONFIGURATION,
            list(&reconfigured)
        );
    }
    let outside = compensated.lines_with(CompensationStatus::OutsideLimits);
    if !outside.is_empty() {
        eprintln!(
            "warning: {} target(s) reached only beyond a joint limit (status outside-limits), lines {}",
            outside.len(),
            list(&outside)
        );
    }
    let unreached = compensated.lines_with(CompensationStatus::NotReached);
    if !unreached.is_empty() {
        eprintln!(
            "warning: {} target(s) not reached: their joints are left as in the program (status not-reached), lines {}",
            unreached.len(),
            list(&unreached)
        );
    }
    match compensated.failure() {
        Some(failure) => Err(failure.into()),
        None => Ok(()),
    }
}
