//! The commands of a parallel robot (a Gough–Stewart platform, a Delta):
//! `robot show | check`, `generate`, `identifiable`, `plan`, `predict`,
//! `identify`, `report`, `evaluate` and `compensate` run the
//! `gecaro_app::parallel` jobs when the robot named is a parallel one;
//! an option that means something for serial robots only is refused by
//! name.

use gecaro_app::parallel::{
    ParallelCompensateRequest, ParallelEvaluateRequest, ParallelGenerateRequest,
    ParallelIdentifiableRequest, ParallelIdentifyRequest, ParallelPlanRequest,
    ParallelPredictRequest, PlatformErrorsDocument, load_parallel_robot,
};
use gecaro_app::{DataSource, LocalFiles};
use gecaro_core::parallel_model::ParallelModel;
use gecaro_core::parallel_robot::ParallelRobot;

use super::options::{data_format, name, output_policy, written};
use crate::cli::{
    CompensateArgs, EvaluateArgs, GenerateArgs, IdentifiableArgs, IdentificationRunArgs,
    IdentifyArgs, MethodOptionArgs, PlanArgs, PredictArgs, ReportArgs,
};
use crate::failure::Failure;
use crate::format::{number, shown, table};

/// Refuses the first of `given` (an option's name and whether it was
/// given) that has no meaning for a parallel robot.
fn serial_only(given: &[(&str, bool)]) -> Result<(), Failure> {
    match given.iter().find(|(_, given)| *given) {
        Some((option, _)) => Err(Failure::usage(
            format!("{option} has no meaning for a parallel robot"),
            Some(
                "a parallel robot takes --method frame|position|distance, its data, σ, work \
                 region, loss, --reject and --prior, and the data file's units and columns \
                 (docs/parallel.md)"
                    .to_owned(),
            ),
        )),
        None => Ok(()),
    }
}

/// The serial methods' options of `options` (planes, the orientation
/// difference, link sets), each with whether it was given: none has a
/// meaning for a parallel robot.
fn method_options(options: &MethodOptionArgs) -> [(&'static str, bool); 5] {
    [
        ("--plane", options.plane.plane.is_some()),
        ("--plane-normal", options.plane.plane_normal.is_some()),
        ("--plane-point", options.plane.plane_point.is_some()),
        ("--orientation", options.orientation != "axis-angle"),
        ("--set-size", options.set_size.is_some()),
    ]
}

fn mm(metres: f64) -> String {
    number(metres * 1e3, 4)
}

/// `gecaro robot show` of a parallel robot.
pub(crate) fn show(robot: &str) -> Result<(), Failure> {
    let file = load_parallel_robot(robot, &LocalFiles)?;
    let model = &file.robot;
    println!(
        "{} — {}, {} actuators, {} parameters (mm, degrees)",
        shown(model.name()),
        structure_words(model),
        model.actuator_count(),
        model.parameters().len()
    );
    if let Some(description) = &file.description {
        println!("{}", shown(description));
    }
    let degrees = |radians: f64| number(radians.to_degrees(), 4);
    let rows = match model {
        ParallelRobot::GoughStewart(platform) => {
            let mut legs = table(
                &[
                    "leg",
                    "base x",
                    "base y",
                    "base z",
                    "platform x",
                    "platform y",
                    "platform z",
                    "length",
                    "gain",
                    "min",
                    "max",
                ],
                1,
            );
            for (index, leg) in platform.legs().iter().enumerate() {
                let mut row = vec![(index + 1).to_string()];
                row.extend(leg.base.iter().chain(leg.platform.iter()).map(|v| mm(*v)));
                row.extend([
                    mm(leg.length),
                    number(leg.gain, 6),
                    mm(leg.min),
                    mm(leg.max),
                ]);
                legs.add_row(row);
            }
            legs
        }
        ParallelRobot::Delta(delta) => {
            let mut arms = table(
                &[
                    "arm",
                    "base x",
                    "base y",
                    "base z",
                    "azimuth",
                    "offset",
                    "gain",
                    "upper arm",
                    "forearm",
                    "plate x",
                    "plate y",
                    "plate z",
                    "min",
                    "max",
                ],
                1,
            );
            for (index, arm) in delta.arms().iter().enumerate() {
                let mut row = vec![(index + 1).to_string()];
                row.extend(arm.base.iter().map(|v| mm(*v)));
                row.extend([
                    degrees(arm.azimuth),
                    degrees(arm.offset),
                    number(arm.gain, 6),
                    mm(arm.upper_arm),
                    mm(arm.forearm),
                ]);
                row.extend(arm.platform.iter().map(|v| mm(*v)));
                row.extend([degrees(arm.min), degrees(arm.max)]);
                arms.add_row(row);
            }
            arms
        }
    };
    println!("{rows}");
    let tool = model.tool();
    let home = model.home().translation.vector;
    println!(
        "tool point (platform frame): {}, {}, {} mm; home pose: level at {}, {}, {} mm",
        mm(tool.x),
        mm(tool.y),
        mm(tool.z),
        mm(home.x),
        mm(home.y),
        mm(home.z)
    );
    Ok(())
}

/// The structure in words.
fn structure_words(model: &ParallelRobot) -> &'static str {
    match model {
        ParallelRobot::GoughStewart(_) => "Gough–Stewart platform",
        ParallelRobot::Delta(_) => "Delta robot",
    }
}

/// `gecaro robot check` of a parallel robot.
pub(crate) fn check(robot: &str) -> Result<(), Failure> {
    let file = load_parallel_robot(robot, &LocalFiles)?;
    let model = &file.robot;
    let home = model.home().translation.vector;
    println!(
        "ok: {} — {}, {} actuators, {} parameters; home pose at {} mm from the base",
        shown(model.name()),
        structure_words(model),
        model.actuator_count(),
        model.parameters().len(),
        mm(home.z)
    );
    Ok(())
}

/// `gecaro generate` of a parallel robot.
pub(crate) fn generate(args: &GenerateArgs) -> Result<(), Failure> {
    serial_only(&method_options(&args.method.options))?;
    serial_only(&[
        ("--compliance-level", args.compliance_level.is_some()),
        ("--payload", args.payload.is_some()),
        ("--gravity-tilt", args.gravity_tilt.is_some()),
    ])?;
    let count = match (&args.configurations, args.count) {
        (Some(_), _) => 0,
        (None, Some(count)) => count,
        (None, None) => {
            return Err(Failure::usage(
                "give the number of poses (--count N) or the configurations to measure at \
                 (--configurations planned.csv)",
                None,
            ));
        }
    };
    let output = written(&args.output, args.force);
    let generated = ParallelGenerateRequest {
        robot: args.robot.clone(),
        method: args.method.method.clone(),
        count,
        configurations: args
            .configurations
            .as_deref()
            .map(|path| DataSource::File(name(path))),
        format: data_format(&args.format),
        error_level: args.error_level,
        real: args.real.as_deref().map(name),
        noise: args.noise,
        seed: Some(args.seed),
        output,
        real_save_as: args.real_out.as_deref().map(name),
        leg_base: args.leg.leg_base.clone(),
        leg_platform: args.leg.leg_platform.clone(),
        leg_gain: args.leg.leg_gain,
    }
    .run(&LocalFiles)?;
    println!(
        "wrote {} poses ({} measured) to {}",
        generated.samples.len(),
        args.method.method,
        args.output.display()
    );
    println!("real robot: {}", shown(generated.real.robot.name()));
    if args.noise > 0.0 {
        println!(
            "sensor noise: σ = {} mm ({} rad for orientations)",
            mm(args.noise),
            number(args.noise, 9)
        );
    }
    if let Some(real_out) = &args.real_out {
        println!("wrote the real platform to {}", real_out.display());
    }
    Ok(())
}

/// `gecaro identifiable` of a parallel robot.
pub(crate) fn identifiable(args: &IdentifiableArgs, robot: &str) -> Result<(), Failure> {
    serial_only(&method_options(&args.source.options))?;
    serial_only(&[
        ("--priority", args.priority.is_some()),
        ("--model", args.model.is_some()),
        ("--study", args.source.study.is_some()),
        ("--strict-limits", args.source.strict_limits),
    ])?;
    let method = args.source.method.clone().unwrap_or_default();
    let report = ParallelIdentifiableRequest {
        robot: robot.to_owned(),
        method,
        data: args
            .data
            .as_deref()
            .map(|path| DataSource::File(name(path))),
        format: data_format(&args.source.format),
        count: args.count,
        seed: Some(args.seed),
    }
    .run(&LocalFiles)?;
    if args.json {
        return super::output::print_json(&report);
    }
    println!(
        "{} of {} parameters identifiable ({} method, {} equations from {}); condition number {}",
        report.rank,
        report.parameters.len(),
        report.method,
        report.equations,
        report.source,
        number(report.condition_number, 4)
    );
    for status in ["identifiable", "regrouped", "no_effect", "excluded"] {
        let names: Vec<&str> = report
            .parameters
            .iter()
            .filter(|(_, of)| *of == status)
            .map(|(name, _)| name.as_str())
            .collect();
        if !names.is_empty() {
            println!(
                "{} ({}): {}",
                status.replace('_', " "),
                names.len(),
                names.join(" ")
            );
        }
    }
    for relation in &report.regrouped {
        let terms: Vec<String> = relation
            .into
            .iter()
            .map(|(name, coefficient)| format!("{} {name}", number(*coefficient, 4)))
            .collect();
        println!(
            "{} is regrouped into: {}",
            relation.parameter,
            terms.join(", ")
        );
    }
    Ok(())
}

/// The identification `run` asks of the parallel robot `robot`, the
/// calibrated platform written to `output`; refuses the options of `run`
/// that mean something for serial robots only.
fn identify_request(
    run: &IdentificationRunArgs,
    robot: &str,
    output: gecaro_app::Output,
) -> Result<ParallelIdentifyRequest, Failure> {
    serial_only(&method_options(&run.source.options))?;
    serial_only(&[
        ("--priority", run.priority.is_some()),
        ("--model", run.model.is_some()),
        (
            "--outlier-threshold",
            run.outlier_threshold != gecaro_calib::identification::DEFAULT_OUTLIER_THRESHOLD,
        ),
        ("--solver", run.solver != "gauss-newton"),
        ("--study", run.source.study.is_some()),
        ("--strict-limits", run.source.strict_limits),
    ])?;
    let (data, stations) = run
        .data
        .split_first()
        .ok_or_else(|| Failure::usage("give the measurements (--data FILE.csv)", None))?;
    Ok(ParallelIdentifyRequest {
        robot: robot.to_owned(),
        method: run.source.method.clone().unwrap_or_default(),
        data: DataSource::File(name(data)),
        stations: stations
            .iter()
            .map(|path| DataSource::File(name(path)))
            .collect(),
        leg_base: run.leg.leg_base.clone(),
        leg_platform: run.leg.leg_platform.clone(),
        leg_gain: run.leg.leg_gain,
        format: data_format(&run.source.format),
        sigma: run.sigma.clone(),
        sigma_rotation: run.sigma_rotation.clone(),
        max_iterations: Some(run.max_iterations),
        work_region: run.work_region.clone(),
        loss: Some(run.loss.clone()),
        loss_scale: run.loss_scale,
        reject: Some(run.reject),
        prior: run.prior.clone(),
        output,
    })
}

/// `gecaro identify` of a parallel robot.
pub(crate) fn identify(args: &IdentifyArgs, robot: &str) -> Result<(), Failure> {
    serial_only(&[
        ("--check-model", args.check_model),
        ("--no-check-model", args.no_check_model),
        ("--write-unconverged", args.write_unconverged),
        ("--cv", args.cv.is_some()),
    ])?;
    let output = args
        .output
        .as_deref()
        .map(|path| written(path, args.force))
        .unwrap_or_default();
    if let Some(path) = &args.residuals {
        super::calibration::check_output(path, args.force)?;
    }
    let identified = identify_request(&args.run, robot, output)?.run(&LocalFiles)?;
    // Written whether or not the fit converged: they say what went wrong.
    if let Some(path) = &args.residuals {
        let csv = identified.residuals_csv()?;
        gecaro_io::write_atomically(path, csv.as_bytes(), output_policy(args.force))?;
    }
    let plots = match &args.plot {
        Some(folder) => {
            let plots = identified.plots()?;
            super::calibration::write_svgs(
                folder,
                &[
                    ("errors_histogram.svg", plots.errors_histogram),
                    ("errors_per_configuration.svg", plots.errors_per_observation),
                ],
                args.force,
            )?
        }
        None => Vec::new(),
    };
    let document = &identified.document;
    if args.json {
        super::output::print_json(document)?;
    } else {
        println!(
            "{} — {} method on {} ({} poses): {}",
            shown(&document.robot),
            document.method,
            document.data,
            document.configurations,
            document.summary
        );
        let mut parameters = table(&["parameter", "nominal", "identified", "σ", "status"], 1);
        for parameter in &document.parameters {
            let shown_value = |value: f64| match parameter.unit {
                "m" => mm(value),
                "rad" => number(value.to_degrees(), 5),
                _ => number(value, 8),
            };
            parameters.add_row(vec![
                parameter.name.clone(),
                shown_value(parameter.nominal),
                shown_value(parameter.identified),
                parameter.sigma.map_or_else(|| "-".into(), shown_value),
                parameter.status.to_owned(),
            ]);
        }
        println!("{parameters}");
        println!("(mm; angles in degrees; gains dimensionless)");
        print_errors(
            "at the measured poses, nominal",
            &document.errors_before,
            document.method,
        );
        print_errors(
            "at the measured poses, calibrated",
            &document.errors_after,
            document.method,
        );
        if let Some(region) = &document.region {
            println!(
                "predicted {}: {} mm RMS at the measured poses, {} mm over {} (largest {} \
                 mm; noise floor {} mm)",
                region.error,
                mm(region.predicted_inside),
                mm(region.predicted_work),
                region.work_name,
                mm(region.predicted_work_max),
                mm(region.noise_floor)
            );
        }
        for warning in &document.warnings {
            println!("warning: {warning}");
        }
        if let Some(path) = &document.written {
            println!("wrote the calibrated platform to {path}");
        }
        if let Some(path) = &args.residuals {
            println!("wrote the residuals to {}", path.display());
        }
        if !plots.is_empty() {
            println!(
                "wrote the plots to {}",
                super::calibration::display_list(&plots)
            );
        }
    }
    identified
        .failure()
        .map_or(Ok(()), |error| Err(error.into()))
}

/// `gecaro report` of a parallel robot: the identification, and its HTML
/// report written whether the fit is trusted or not (it says which), the
/// exit status that of `identify`.
pub(crate) fn report(args: &ReportArgs, robot: &str) -> Result<(), Failure> {
    let identified =
        identify_request(&args.run, robot, gecaro_app::Output::default())?.run(&LocalFiles)?;
    let html = identified.report(&super::calibration::command_line())?;
    gecaro_io::write_atomically(&args.output, html.as_bytes(), output_policy(args.force))?;
    let document = &identified.document;
    println!(
        "wrote the report of {} ({} method, {}) to {}",
        shown(&document.robot),
        document.method,
        document.data,
        args.output.display()
    );
    println!("{}", document.summary);
    identified
        .failure()
        .map_or(Ok(()), |error| Err(error.into()))
}

/// A platform's errors in words: of its positions, its distances, or its
/// measuring leg's lengths (`method`).
fn print_errors(title: &str, errors: &PlatformErrorsDocument, method: &str) {
    let angles = match (errors.angle_rms, errors.angle_max) {
        (Some(rms), Some(max)) => format!(
            "; orientation RMS {}°, max {}°",
            number(rms.to_degrees(), 4),
            number(max.to_degrees(), 4)
        ),
        _ => String::new(),
    };
    println!(
        "{title}: {} RMS {} mm, max {} mm{angles}",
        match method {
            "distance" => "distance",
            "leg" => "leg length",
            _ => "position",
        },
        mm(errors.position_rms),
        mm(errors.position_max)
    );
}

/// `gecaro evaluate` of a parallel robot.
pub(crate) fn evaluate(args: &EvaluateArgs) -> Result<(), Failure> {
    serial_only(&method_options(&args.options))?;
    serial_only(&[
        ("--study", args.study.is_some()),
        ("--strict-limits", args.strict_limits),
        ("--register", args.register.is_some()),
    ])?;
    let data = args
        .data
        .as_deref()
        .ok_or_else(|| Failure::usage("give the measurements (--data FILE.csv)", None))?;
    let evaluated = ParallelEvaluateRequest {
        robot: args.robot.clone(),
        method: args.method.clone().unwrap_or_default(),
        data: DataSource::File(name(data)),
        format: data_format(&args.format),
    }
    .run(&LocalFiles)?;
    if args.json {
        return super::output::print_json(&evaluated);
    }
    println!(
        "{} on {} ({} method, {} poses):",
        shown(&evaluated.robot),
        evaluated.data,
        evaluated.method,
        evaluated.configurations
    );
    if let Some(frame) = &evaluated.registered {
        println!(
            "the data were in another frame: the instrument's registered on all {} rows (the \
             base at ({}) mm in it), so the errors below are the platform's up to its base \
             frame's pose",
            evaluated.configurations,
            frame
                .position
                .iter()
                .map(|value| mm(*value))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    print_errors(
        "direct model against the measured",
        &evaluated.errors,
        evaluated.method,
    );
    Ok(())
}

/// `gecaro compensate` of a parallel robot: a program of platform poses to
/// the calibrated platform's actuator values.
pub(crate) fn compensate(args: &CompensateArgs) -> Result<(), Failure> {
    serial_only(&[
        ("--rebase", args.rebase),
        ("--base-points", args.base_points.is_some()),
        ("--base-circles", args.base_circles.is_some()),
        ("--payload", args.payload.is_some()),
        ("--tool", args.tool.is_some()),
        ("--max-tool-turn", args.max_tool_turn.is_some()),
    ])?;
    let compensated = ParallelCompensateRequest {
        nominal: args.nominal.clone(),
        calibrated: args.calibrated.clone(),
        program: DataSource::File(name(&args.program)),
        format: data_format(&args.format),
        matching: Some(args.matching.clone()),
        output: written(&args.output, args.force),
    }
    .run(&LocalFiles)?;
    if args.json {
        super::output::print_json(&compensated)?;
    } else {
        println!(
            "{} targets ({}): actuator values of the calibrated platform (the largest change \
             from the nominal one {} mm), written to {}",
            compensated.targets,
            match compensated.matched {
                "position" => "tool points",
                _ => "platform poses",
            },
            mm(compensated.largest_correction),
            args.output.display()
        );
        if let Some(note) = &compensated.note {
            println!("note: {note}");
        }
    }
    compensated
        .failure()
        .map_or(Ok(()), |error| Err(error.into()))
}

/// `gecaro plan` of a parallel robot: D-optimal poses from a pool, written
/// as the actuator values to command.
pub(crate) fn plan(args: &PlanArgs, robot: &str) -> Result<(), Failure> {
    serial_only(&method_options(&args.options))?;
    serial_only(&[
        // The test criterion's poses are the platform's workspace.
        ("--test-poses", args.test_poses.test_poses.is_some()),
        ("--test-pose-count", args.test_poses.test_pose_count != 200),
        ("--candidates", args.candidates.is_some()),
        ("--keep", args.keep.is_some()),
        ("--payload", !args.payloads.is_empty()),
        ("--min-distance", args.min_distance != 0.0),
        ("--curve", args.curve.is_some()),
    ])?;
    let count = args
        .count
        .ok_or_else(|| Failure::usage("give the number of poses to plan (--count N)", None))?;
    let output = args
        .output
        .as_deref()
        .ok_or_else(|| Failure::usage("name the planned file (-o planned.csv)", None))?;
    let planned = ParallelPlanRequest {
        robot: robot.to_owned(),
        method: args.method.clone().unwrap_or_default(),
        count,
        pool: args.pool,
        seed: Some(args.seed),
        criterion: Some(args.criterion.clone()),
        output: written(output, args.force),
    }
    .run(&LocalFiles)?;
    if args.json {
        return super::output::print_json(&planned);
    }
    println!(
        "{} poses of {} candidates chosen for the {} identifiable parameters ({}): {} {} \
         against {} for as many random poses; written to {}",
        planned.count,
        planned.pool,
        planned.rank,
        match planned.criterion_name {
            "test" => "the predicted error over the workspace".to_owned(),
            name => format!("{}-optimal", name.to_uppercase()),
        },
        planned.criterion_meaning,
        number(planned.criterion, 4),
        number(planned.random_criterion, 4),
        output.display()
    );
    Ok(())
}

/// `gecaro predict` of a parallel robot: every identifiable parameter's σ
/// and the calibrated platform's predicted error, before measuring.
pub(crate) fn predict(args: &PredictArgs, robot: &str) -> Result<(), Failure> {
    serial_only(&method_options(&args.options))?;
    serial_only(&[
        ("--model", args.model.is_some()),
        ("--test-poses", args.test_poses.test_poses.is_some()),
        ("--study", args.study.is_some()),
    ])?;
    let (Some(method), Some(data), Some(noise)) = (&args.method, &args.data, args.noise) else {
        unreachable!("clap requires them without --study");
    };
    // --noise is in metres (radians for orientations), whatever the
    // configurations' units.
    let predicted = ParallelPredictRequest {
        robot: robot.to_owned(),
        method: method.clone(),
        data: DataSource::File(name(data)),
        format: data_format(&args.format),
        sigma: gecaro_io::StandardDeviation::WithUnit(format!("{noise}m")),
        sigma_rotation: Some(gecaro_io::StandardDeviation::WithUnit(format!(
            "{noise}rad"
        ))),
        monte_carlo: args.monte_carlo,
        // A parallel robot's level, as `generate` reads it: ±L mm, ±L mrad.
        error_level: Some(args.error_level),
        seed: Some(args.seed),
        work_region: args.work_region.clone(),
    }
    .run(&LocalFiles)?;
    if args.json {
        return super::output::print_json(&predicted);
    }
    println!(
        "{} — {} method at the {} configurations of {} (σ {} mm): {} parameters identifiable",
        shown(&predicted.robot),
        predicted.method,
        predicted.configurations,
        predicted.data,
        mm(noise),
        predicted.rank
    );
    let mut parameters = table(&["parameter", "predicted σ"], 1);
    for parameter in &predicted.parameters {
        parameters.add_row(vec![
            parameter.name.clone(),
            match parameter.unit {
                "m" => mm(parameter.sigma),
                "rad" => number(parameter.sigma.to_degrees(), 5),
                _ => number(parameter.sigma, 6),
            },
        ]);
    }
    println!("{parameters}");
    println!("(mm; angles in degrees; gains dimensionless)");
    let region = &predicted.region;
    println!(
        "predicted {} of the calibrated platform: {} mm RMS at these configurations, {} mm over \
         {} (largest {} mm; a held-out measurement's noise {} mm)",
        region.error,
        mm(region.predicted_inside),
        mm(region.predicted_work),
        region.work_name,
        mm(region.predicted_work_max),
        mm(region.noise_floor)
    );
    if let Some(simulated) = &predicted.monte_carlo {
        println!(
            "{} simulated calibrations (real platforms drawn at ±{} mm): {} mm RMS over {} \
             against their real ones (largest {} mm)",
            simulated.runs,
            number(args.error_level, 3),
            mm(simulated.work_rms),
            region.work_name,
            mm(simulated.work_max)
        );
    }
    if !region.holds_everywhere {
        println!(
            "warning: these configurations calibrate the platform where they are only: \
             measure poses spread over {}",
            if region.work_is_ranges {
                "the whole workspace"
            } else {
                "the stated work region"
            }
        );
    }
    Ok(())
}
