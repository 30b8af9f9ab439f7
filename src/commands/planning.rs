//! `gecaro plan` and `gecaro predict`: the configurations to measure, and how
//! accurate their calibration will be, before measuring (docs/planning.md).

use gecaro_app::{
    DataSource, LocalFiles, PlanRequest, Planning, PredictRequest, Predicted, RobotSource,
    TestPoses,
};
use gecaro_calib::curve::{CurvePoint, RANDOM_DRAWS};
use gecaro_calib::planning::Criterion;
use gecaro_calib::prediction::PoseErrors;
use gecaro_calib::study::DataColumn;
use serde::Serialize;

use super::options::{data_format, method_spec, name, written};
use super::progress::with_steps;
use crate::cli::{PlanArgs, PredictArgs, TestPoseArgs};
use crate::failure::Failure;
use crate::format::{number, table};

/// The test poses of the command line.
fn test_poses(args: &TestPoseArgs) -> TestPoses {
    TestPoses {
        test_poses: args
            .test_poses
            .as_deref()
            .map(|path| DataSource::File(name(path))),
        test_pose_count: Some(args.test_pose_count),
    }
}

#[derive(Serialize)]
struct PlanOutputJson {
    #[serde(flatten)]
    plan: gecaro_app::documents::PlanJson,
    output: String,
}

pub(crate) fn plan(args: &PlanArgs) -> Result<(), Failure> {
    if let Some(study) = &args.study {
        return plan_study(args, study);
    }
    let (Some(robot), Some(method)) = (&args.robot, &args.method) else {
        unreachable!("clap requires them without --study");
    };
    let method = method_spec(method, &args.options)?;
    let mut request = PlanRequest::new(RobotSource::Named(robot.clone()), method, 0);
    request.count = args.count;
    request.criterion = Some(args.criterion.clone());
    request.format = super::options::data_format(&args.format);
    request.candidates = args
        .candidates
        .as_deref()
        .map(|path| DataSource::File(name(path)));
    request.pool = args.pool;
    request.cell = super::options::cell_spec(&args.cell)?;
    request.seed = Some(args.seed);
    request.payloads = args.payloads.clone();
    request.keep = args
        .keep
        .as_deref()
        .map(|path| DataSource::File(name(path)));
    request.min_distance = args.min_distance;
    request.test_poses = test_poses(&args.test_poses);
    request.curve = args.curve.clone().unwrap_or_default();
    request.noise = args.noise;
    request.plot_save_as = args.plot.as_deref().map(name);
    request.output.overwrite = args.force;
    if args.curve.is_none() {
        let output = args
            .output
            .as_deref()
            .ok_or_else(|| Failure::usage("give the output file: -o PLANNED.csv", None))?;
        request.output.save_as = Some(name(output));
    }
    let planning = with_steps(
        if args.curve.is_some() {
            "curve"
        } else {
            "planning"
        },
        |observer| request.run(&LocalFiles, observer),
    );
    let planning = planning?;
    if planning.curve.is_some() {
        return print_curve(args, &planning);
    }
    print_plan(args, &planning)
}

/// `plan --study`: the whole cell as one design, written as a planned study.
fn plan_study(args: &PlanArgs, study: &std::path::Path) -> Result<(), Failure> {
    let Some(count) = args.count else {
        return Err(Failure::usage(
            "give the number of configurations: --count N",
            None,
        ));
    };
    let output = args
        .output
        .as_deref()
        .ok_or_else(|| Failure::usage("give the planned study: -o PLANNED.toml", None))?;
    let mut request =
        gecaro_app::PlanStudyRequest::new(gecaro_app::StudySource::File(name(study)), count);
    request.pool = args.pool;
    request.seed = Some(args.seed);
    request.cell = super::options::cell_spec(&args.cell)?;
    request.format = data_format(&args.format);
    request.output = written(output, args.force);
    let planned = with_steps("planning", |observer| request.run(&LocalFiles, observer));
    let planned = planned?;
    super::options::print_notes(&planned.loaded.notes);
    let plan = &planned.plan;
    if args.json {
        return super::output::print_json(&planned.document());
    }
    println!(
        "Planned {} configurations of {} for the cell of {} ({} sets, D-optimal over {} base \
         parameters and frame unknowns, {} candidates per set; {} exchanges after the greedy pass):",
        plan.sets.iter().map(Vec::len).sum::<usize>(),
        planned.loaded.robot.robot.name(),
        study.display(),
        plan.sets.len(),
        plan.columns.len(),
        planned.pool,
        plan.exchanges
    );
    let mut rows = table(&["set", "configurations", "file written"], 1);
    for ((set, samples), path) in planned
        .loaded
        .study
        .sets
        .iter()
        .zip(&plan.sets)
        .zip(planned.saved.iter().skip(1))
    {
        rows.add_row(vec![
            set.label.clone(),
            samples.len().to_string(),
            path.display().to_string(),
        ]);
    }
    println!("{rows}");
    println!(
        "log det(W_bᵀW_b): the plan {:.4e}, a random choice from the same pools {:.4e}",
        plan.quality.log_det, plan.random.log_det
    );
    println!(
        "wrote {}: `gecaro predict --study {}` predicts it; measured, `identify --study` calibrates from it",
        output.display(),
        output.display()
    );
    Ok(())
}

fn print_plan(args: &PlanArgs, planning: &Planning) -> Result<(), Failure> {
    let (Some(planned), Some(document), Some(output)) =
        (&planning.planned, planning.plan_document(), &args.output)
    else {
        return Err(Failure::input("no plan was made"));
    };
    if args.json {
        return super::output::print_json(&PlanOutputJson {
            plan: document,
            output: output.display().to_string(),
        });
    }
    let (plan, quality, random) = (&planned.plan, &planned.plan.quality, &planned.random);
    let grouping = match DataColumn::grouping(planning.method.data_columns()).first() {
        Some(DataColumn::Set) => format!(" ({} sets)", plan.chosen.len()),
        Some(DataColumn::Pair) => format!(" ({} pairs)", plan.chosen.len()),
        _ => String::new(),
    };
    println!(
        "Planned {} configurations{grouping} of {} for {} ({} method), criterion {} over {} base \
         parameters; {} exchanges after the greedy pass",
        plan.samples.len(),
        planning.pool,
        planning.robot.robot.name(),
        planning.method.name(),
        planned.criterion.name().to_uppercase(),
        plan.columns.len(),
        plan.exchanges
    );
    println!(
        "{}: the plan {:.4e}, a random choice from the same pool {:.4e}",
        planned.criterion.meaning(),
        quality.value,
        random.value
    );
    if planned.criterion != Criterion::D {
        println!(
            "D = log det(W_bᵀW_b): the plan {}, random {}",
            number(quality.log_det, 2),
            number(random.log_det, 2)
        );
    }
    println!(
        "{}",
        crate::format::observability(&quality.observability, "the plan")
    );
    if planning.kept > 0 {
        println!("kept {} configurations measured already", planning.kept);
    }
    println!("wrote {}", output.display());
    Ok(())
}

fn print_curve(args: &PlanArgs, planning: &Planning) -> Result<(), Failure> {
    let (Some(curve), Some(document)) = (&planning.curve, planning.curve_document()) else {
        return Err(Failure::input("no curve was drawn"));
    };
    if args.json {
        return super::output::print_json(&document);
    }
    println!(
        "Predicted RMS position error of the calibrated {} at {} test poses ({} method, σ {} mm; \
         plans by criterion {} from a pool of {}, random: mean of {} draws)",
        planning.robot.robot.name(),
        planning.test_poses,
        planning.method.name(),
        number(curve.noise * 1e3, 6),
        planning.criterion.to_uppercase(),
        planning.pool,
        RANDOM_DRAWS
    );
    println!("{}", curve_table(&curve.points));
    if let Some(plot) = &args.plot {
        println!("wrote {}", plot.display());
    }
    Ok(())
}

fn curve_table(points: &[CurvePoint]) -> comfy_table::Table {
    let millimetres = |value: Option<f64>| match value {
        Some(value) => format!("{:.4}", value * 1e3),
        None => "not determined".into(),
    };
    let mut rows = table(
        &[
            "configurations",
            "planned (mm)",
            "random (mm)",
            "random / planned",
        ],
        0,
    );
    for point in points {
        let ratio = match (point.planned, point.random) {
            (Some(planned), Some(random)) if planned > 0.0 => format!("{:.2}", random / planned),
            _ => "—".into(),
        };
        rows.add_row(vec![
            point.count.to_string(),
            millimetres(point.planned),
            millimetres(point.random),
            ratio,
        ]);
    }
    rows
}

pub(crate) fn predict_accuracy(args: &PredictArgs) -> Result<(), Failure> {
    if let Some(study) = &args.study {
        return predict_study(args, study);
    }
    let (Some(robot), Some(method), Some(data), Some(noise)) =
        (&args.robot, &args.method, &args.data, args.noise)
    else {
        unreachable!("clap requires them without --study");
    };
    if args.work_region.is_some() {
        return Err(Failure::usage(
            "--work-region of `predict` is a parallel robot's: a serial robot's prediction is \
             judged at its test poses"
                .to_owned(),
            Some("give configurations in the region with --test-poses FILE".to_owned()),
        ));
    }
    let mut request = PredictRequest::new(
        RobotSource::Named(robot.clone()),
        method_spec(method, &args.options)?,
        DataSource::File(name(data)),
        noise,
    );
    request.test_poses = test_poses(&args.test_poses);
    request.format = super::options::data_format(&args.format);
    request.monte_carlo = args.monte_carlo;
    request.error_level = Some(args.error_level);
    request.seed = Some(args.seed);
    request.model = args.model.clone();
    let predicted = with_steps("simulated calibrations", |observer| {
        request.run(&LocalFiles, observer)
    });
    let predicted = predicted?;
    if args.json {
        return super::output::print_json(&predicted.document());
    }
    print_prediction(args, &predicted);
    Ok(())
}

/// `predict --study`: the whole cell's predicted precision.
fn predict_study(args: &PredictArgs, study: &std::path::Path) -> Result<(), Failure> {
    let mut request =
        gecaro_app::PredictStudyRequest::new(gecaro_app::StudySource::File(name(study)));
    request.test_poses = test_poses(&args.test_poses);
    request.seed = Some(args.seed);
    let predicted = request.run(&LocalFiles)?;
    super::options::print_notes(&predicted.loaded.notes);
    if args.json {
        return super::output::print_json(&predicted.document());
    }
    let document = predicted.document();
    println!(
        "Predicted precision of {} from the cell of {} ({} sets; eq. 11, first order, each set \
         weighted by its σ):",
        predicted.loaded.robot.robot.name(),
        study.display(),
        document.sets.len()
    );
    let mut sets = table(
        &[
            "set",
            "method",
            "configurations",
            "σ (mm)",
            "tool",
            "station",
        ],
        2,
    );
    for set in &document.sets {
        sets.add_row(vec![
            set.data.clone(),
            set.method.to_owned(),
            set.configurations.to_string(),
            set.sigma.map_or("—".into(), |s| number(s * 1e3, 6)),
            set.tool.clone().unwrap_or_else(|| "frame n+1".into()),
            set.station.clone().unwrap_or_else(|| "world".into()),
        ]);
    }
    println!("{sets}");
    print_parameters_and_errors(&predicted.prediction, None);
    println!(
        "{} test poses ({}); errors of the robot's own frame n+1",
        predicted.test_poses,
        args.test_poses.test_poses.as_ref().map_or_else(
            || "random within the joint limits".into(),
            |path| path.display().to_string()
        )
    );
    Ok(())
}

/// The parameters' predicted σ and the errors at the test poses (and the
/// Monte Carlo's, when run), as tables.
fn print_parameters_and_errors(
    prediction: &gecaro_calib::prediction::Prediction,
    measured: Option<&gecaro_calib::prediction::MonteCarlo>,
) {
    let mut parameters = table(&["parameter", "predicted σ"], 1);
    for (name, sigma) in &prediction.parameters {
        parameters.add_row(vec![name.clone(), format!("{sigma:.3e}")]);
    }
    println!("{parameters}");
    println!("(metres for lengths, radians for angles, relative for gains)");
    let mut errors = table(
        &[
            "at test poses",
            "RMS position (mm)",
            "max position (mm)",
            "RMS orientation (mrad)",
            "max orientation (mrad)",
        ],
        1,
    );
    let mut row = |label: &str, errors_at: &PoseErrors| {
        let milli = |value: Option<f64>| value.map_or("—".into(), |v| format!("{:.4}", v * 1e3));
        errors.add_row(vec![
            label.to_owned(),
            format!("{:.4}", errors_at.position_rms * 1e3),
            format!("{:.4}", errors_at.position_max * 1e3),
            milli(errors_at.rotation_rms),
            milli(errors_at.rotation_max),
        ]);
    };
    row("predicted", &prediction.errors);
    if let Some(measured) = measured {
        row(
            &format!("Monte Carlo ({} runs)", measured.runs),
            &measured.errors,
        );
    }
    println!("{errors}");
}

fn print_prediction(args: &PredictArgs, predicted: &Predicted) {
    let (prediction, chosen) = (&predicted.prediction, &predicted.method);
    println!(
        "Predicted precision of {} ({} method) from {} configurations of {}, sensor σ {} mm \
         (eq. 11; first order, before measuring):",
        predicted.robot.robot.name(),
        chosen.name(),
        predicted.configurations,
        args.data
            .as_deref()
            .unwrap_or(std::path::Path::new(""))
            .display(),
        number(predicted.noise * 1e3, 6)
    );
    print_parameters_and_errors(prediction, predicted.measured.as_ref());
    let predicted_errors = prediction.errors;
    println!(
        "{} test poses ({})",
        predicted.test_poses,
        args.test_poses.test_poses.as_ref().map_or_else(
            || "random within the joint limits".into(),
            |path| path.display().to_string()
        )
    );
    if let Some(measured) = &predicted.measured {
        println!(
            "Monte Carlo: real robots drawn at error level {}, measured / predicted RMS position \
             error {:.3}{}",
            predicted.error_level,
            measured.errors.position_rms / predicted_errors.position_rms,
            if measured.not_converged > 0 {
                format!("; {} calibrations did not converge", measured.not_converged)
            } else {
                String::new()
            }
        );
    }
    if !matches!(chosen.name(), "position" | "frame") {
        println!(
            "note: {} data do not see the robot's world frame; the test-pose errors concern what \
             the data identify (docs/planning.md)",
            chosen.name()
        );
    }
}
