//! `gecaro compensate`: a robot program corrected for the calibrated robot.

use gecaro_app::{CompensateRequest, LocalFiles, ProgramSource, RobotSource};
use gecaro_calib::compensation::CompensationStatus;
use gecaro_calib::each_step;
use gecaro_io::ProgramKind;
use indicatif::ProgressBar;

use super::options::{data_format, name, written};
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
    request.tool = args.tool.clone();
    request.base_points = args
        .base_points
        .as_ref()
        .map(|path| gecaro_app::BasePointsSource::File(name(path)));
    request.base_circles = args
        .base_circles
        .as_ref()
        .map(|path| gecaro_app::DataSource::File(name(path)));
    request.base_points_format.length_unit = args.base_points_unit.clone();
    request.max_tool_turn = args.max_tool_turn.clone();
    request.output = written(&args.output, args.force);
    let mut bar: Option<ProgressBar> = None;
    let mut observer = each_step(|done, total| {
        let total = total as u64;
        if total >= QUIET_BELOW {
            let bar = bar.get_or_insert_with(|| super::progress::progress_bar("compensating"));
            bar.set_length(total);
            bar.set_position(done as u64);
        }
    });
    // `--json` lists every target: the program is held whole. Otherwise it
    // is corrected as it is read, in memory that does not grow with it.
    let outcome = if args.json {
        request.run(&LocalFiles, &mut observer).map(|compensated| {
            let layout = compensated
                .program
                .as_ref()
                .map(|program| program.layout().clone());
            (
                Some(compensated.document()),
                compensated.summary,
                layout,
                None,
            )
        })
    } else {
        request
            .run_streamed(&LocalFiles, &mut observer)
            .map(|compensated| {
                let registered = compensated.registration.as_ref().map(|r| r.summary());
                (
                    None,
                    compensated.summary,
                    Some(compensated.layout),
                    registered,
                )
            })
    };
    drop(observer);
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    let (document, summary, layout, registered) = outcome?;
    if let Some(registered) = registered {
        println!("the calibrated robot in the owner's base: {registered}");
    }
    let layout = layout.ok_or_else(|| Failure::input("no program file was read"))?;
    if !layout.unused_columns().is_empty() && !args.json {
        eprintln!(
            "note: columns kept as they are (not read): {}",
            layout.unused_columns().join(", ")
        );
    }
    if let Some(document) = document {
        super::output::print_json(&document)?;
    } else {
        let units = layout.units();
        let kind = match layout.kind() {
            ProgramKind::Joints => "joint targets",
            ProgramKind::Position => "point targets",
            ProgramKind::Pose => "pose targets",
        };
        println!(
            "{} {kind}: {} reached by the calibrated robot (largest residual {:.1e} {})",
            summary.targets,
            summary.reached(),
            summary.largest_position_error / units.length.to_metres(),
            units.length.name()
        );
        if let Some(largest) = summary.largest_correction {
            println!(
                "largest joint correction: {:.4} {} (joint {}, line {})",
                largest.value, largest.unit, largest.joint, largest.line
            );
        }
        if let Some((turn, line)) = summary.largest_tool_turn {
            println!(
                "largest tool turn left by the position match: {:.3}° (line {line})",
                turn.to_degrees()
            );
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
    let reconfigured = summary.lines_with(CompensationStatus::Reconfigured);
    if !reconfigured.is_empty() {
        eprintln!(
            "warning: {} target(s) reached only in another configuration, a joint moving by more than {} rad (status reconfigured: another branch, or a wrist turned about a singularity), lines {}",
            reconfigured.len(),
            gecaro_calib::compensation::RECONFIGURATION,
            list(reconfigured)
        );
    }
    let extrapolated = summary.lines_with(CompensationStatus::OutsideRegion);
    if !extrapolated.is_empty() {
        eprintln!(
            "warning: {} target(s) reached outside the joint ranges the calibration's data covered (status outside-region: the calibrated model is extrapolated there, and may be far off; the calibrated robot file's `measured` ranges), lines {}",
            extrapolated.len(),
            list(extrapolated)
        );
    }
    let outside = summary.lines_with(CompensationStatus::OutsideLimits);
    if !outside.is_empty() {
        eprintln!(
            "warning: {} target(s) reached only beyond a joint limit (status outside-limits), lines {}",
            outside.len(),
            list(outside)
        );
    }
    let unreached = summary.lines_with(CompensationStatus::NotReached);
    if !unreached.is_empty() {
        eprintln!(
            "warning: {} target(s) not reached: their joints are left as in the program (status not-reached), lines {}",
            unreached.len(),
            list(unreached)
        );
    }
    if !summary.turned.is_empty() {
        eprintln!(
            "warning: {} target(s) reached with the tool turned beyond the tolerance (position match), lines {}",
            summary.turned.len(),
            list(&summary.turned)
        );
    }
    match summary.failure(Some(&args.output)) {
        Some(failure) => Err(failure.into()),
        None => Ok(()),
    }
}
