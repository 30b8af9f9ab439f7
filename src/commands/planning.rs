//! `gecaro plan`: the configurations to measure, chosen before measuring
//! (docs/planning.md).

use std::ops::ControlFlow;

use gecaro_calib::{DataColumn, Sample, Sampler, design_log_det, method, plan_d_optimal, units};
use gecaro_io::{DataFormat, format_samples, joint_types, load_robot, read_samples};
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;

use super::calibration::{check_output, grouping_columns};
use super::options::{method_options, output_policy};
use crate::cli::PlanArgs;
use crate::failure::Failure;
use crate::format::number;

#[derive(Serialize)]
struct PlanJson<'a> {
    method: &'static str,
    configurations: usize,
    units: usize,
    pool: usize,
    kept: usize,
    log_det: f64,
    random_log_det: f64,
    observability: gecaro_report::json::ObservabilityJson,
    exchanges: usize,
    columns: &'a [String],
    output: String,
}

pub(crate) fn plan(args: &PlanArgs) -> Result<(), Failure> {
    let file = load_robot(&args.robot)?;
    let robot = &file.robot;
    check_output(&args.output, args.force)?;
    let chosen = method(&args.method.method, &method_options(&args.method.options)?)?;
    let columns = grouping_columns(chosen.data_columns());
    let read = |path: &std::path::Path| -> Result<Vec<Sample>, Failure> {
        Ok(read_samples(path, &joint_types(robot), &columns, &DataFormat::default())?.samples)
    };
    let pool = match &args.candidates {
        Some(path) => read(path)?,
        None => {
            let count = args.pool.unwrap_or(20 * args.count);
            chosen.generate(robot, count, 0.0, &mut Sampler::new(args.seed))?
        }
    };
    let kept = match &args.keep {
        Some(path) => read(path)?,
        None => Vec::new(),
    };
    let bar = ProgressBar::new(1);
    bar.set_style(
        ProgressStyle::with_template("planning {bar:30} {pos}/{len} [{elapsed}]")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let planned = plan_d_optimal(
        robot,
        chosen.as_ref(),
        &pool,
        args.count,
        &kept,
        &robot.priority(),
        |done, total| {
            bar.set_length(total as u64);
            bar.set_position(done as u64);
            ControlFlow::Continue(())
        },
    );
    bar.finish_and_clear();
    let planned = planned?;
    // A random choice of as many units from the same pool, for comparison.
    let pool_units = units(chosen.as_ref(), &pool);
    let mut random = kept.clone();
    for unit in Sampler::new(args.seed).subset(pool_units.len(), planned.chosen.len()) {
        random.extend(pool_units[unit].iter().map(|index| pool[*index].clone()));
    }
    let random_log_det = design_log_det(robot, chosen.as_ref(), &pool, &random, &robot.priority())?;
    gecaro_io::write_atomically(
        &args.output,
        format_samples(robot.joint_count(), &columns, &planned.samples).as_bytes(),
        output_policy(args.force),
    )?;
    if args.json {
        return super::print_json(&PlanJson {
            method: chosen.name(),
            configurations: planned.samples.len(),
            units: planned.chosen.len(),
            pool: pool.len(),
            kept: kept.len(),
            log_det: planned.log_det,
            random_log_det,
            observability: planned.observability.into(),
            exchanges: planned.exchanges,
            columns: &planned.columns,
            output: args.output.display().to_string(),
        });
    }
    let width = planned.columns.len().max(1) as f64;
    let o1 = |log_det: f64| (log_det / (2.0 * width)).exp() / (planned.samples.len() as f64).sqrt();
    let grouping = match columns.first() {
        Some(DataColumn::Set) => format!(" ({} sets)", planned.chosen.len()),
        Some(DataColumn::Pair) => format!(" ({} pairs)", planned.chosen.len()),
        _ => String::new(),
    };
    println!(
        "Planned {} configurations{grouping} of {} for {} ({} method), D-optimal over {} base \
         parameters; {} exchanges after the greedy pass",
        planned.samples.len(),
        pool.len(),
        robot.name(),
        chosen.name(),
        planned.columns.len(),
        planned.exchanges
    );
    println!(
        "D = log det(W_bᵀW_b) {} (O1 {:.3e}); a random choice from the same pool: {} (O1 {:.3e})",
        number(planned.log_det, 2),
        o1(planned.log_det),
        number(random_log_det, 2),
        o1(random_log_det)
    );
    println!(
        "{}",
        crate::format::observability(&planned.observability, "the plan")
    );
    if !kept.is_empty() {
        println!("kept {} configurations measured already", kept.len());
    }
    println!("wrote {}", args.output.display());
    Ok(())
}
