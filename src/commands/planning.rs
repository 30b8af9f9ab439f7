//! `gecaro plan` and `gecaro predict`: the configurations to measure, and how
//! accurate their calibration will be, before measuring (docs/planning.md).

use gecaro_calib::{
    curve::{CurvePoint, accuracy_curve},
    identification::IdentificationOptions,
    methods::method,
    planning::{CandidatePool, Criterion, PlanRequest},
    prediction::{PoseErrors, monte_carlo, predict, random_test_poses},
    simulation::Sampler,
    study::{DataColumn, Sample},
};
use gecaro_core::Robot;
use gecaro_io::{DataFormat, format_samples, joint_types, load_robot, read_samples};
use gecaro_report::json::{CurvePointJson, PlanJson};
use indicatif::ProgressBar;
use serde::Serialize;
use std::path::Path;

use super::calibration::check_output;
use super::options::{method_options, output_policy};
use super::progress_bar;
use crate::cli::{CriterionArg, PlanArgs, PredictArgs, TestPoseArgs};
use crate::failure::Failure;
use crate::format::{number, table};

/// Shows the steps of the work on `bar`.
fn shown_on(bar: &ProgressBar) -> impl gecaro_calib::Observer + '_ {
    gecaro_calib::each_step(|done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    })
}

/// The configurations of a data file (measurement columns, if any, ignored).
fn configurations(
    robot: &Robot,
    path: &Path,
    columns: &[DataColumn],
) -> Result<Vec<Sample>, Failure> {
    Ok(read_samples(path, &joint_types(robot), columns, &DataFormat::default())?.samples)
}

/// The test poses: a file's configurations, or random ones within the limits.
fn test_poses(robot: &Robot, args: &TestPoseArgs, seed: u64) -> Result<Vec<Vec<f64>>, Failure> {
    match &args.test_poses {
        Some(path) => Ok(configurations(robot, path, &[])?
            .into_iter()
            .map(|sample| sample.motor_positions)
            .collect()),
        None => Ok(random_test_poses(robot, args.test_pose_count, seed)),
    }
}

#[derive(Serialize)]
struct PlanOutputJson {
    #[serde(flatten)]
    plan: PlanJson,
    output: String,
}

#[derive(Serialize)]
struct CurveJson {
    method: &'static str,
    criterion: &'static str,
    noise: f64,
    pool: usize,
    test_poses: usize,
    random_draws: usize,
    /// Predicted RMS position error (metres) per count.
    points: Vec<CurvePointJson>,
}

pub(crate) fn plan(args: &PlanArgs) -> Result<(), Failure> {
    let file = load_robot(&args.robot)?;
    let robot = &file.robot;
    if let Some(output) = &args.output {
        check_output(output, args.force)?;
    }
    if let Some(plot) = &args.plot {
        check_output(plot, args.force)?;
    }
    let chosen = method(&args.method.method, &method_options(&args.method.options)?)?;
    let columns = DataColumn::grouping(chosen.data_columns());
    if let Some(counts) = &args.curve {
        check_curve(counts, args.noise.unwrap_or_default())?;
    }
    let largest = match (&args.curve, args.count) {
        (Some(counts), _) => counts.iter().copied().max().unwrap_or(0),
        (None, count) => count.unwrap_or(0),
    };
    let pool = match &args.candidates {
        Some(path) => configurations(robot, path, &columns)?,
        None => {
            let count = args.pool.unwrap_or(20 * largest);
            chosen
                .sensor()
                .generate(robot, count, 0.0, &mut Sampler::new(args.seed))?
        }
    };
    let kept = match &args.keep {
        Some(path) => configurations(robot, path, &columns)?,
        None => Vec::new(),
    };
    let needs_poses = args.criterion == CriterionArg::Test || args.curve.is_some();
    let poses = if needs_poses {
        test_poses(robot, &args.test_poses, args.seed)?
    } else {
        Vec::new()
    };
    let criterion = match args.criterion {
        CriterionArg::D => Criterion::D,
        CriterionArg::A => Criterion::A,
        CriterionArg::E => Criterion::E,
        CriterionArg::O4 => Criterion::O4,
        CriterionArg::O5 => Criterion::O5,
        CriterionArg::Test => Criterion::TestPoses(poses.clone()),
    };
    let request = PlanRequest {
        count: largest,
        kept: &kept,
        criterion,
        min_distance: args.min_distance,
    };
    let pool = CandidatePool::new(robot, chosen.as_ref(), &pool, &robot.priority())?;
    if let Some(counts) = &args.curve {
        return curve(args, &pool, counts, &request, &poses);
    }
    let bar = progress_bar("planning");
    let planned = pool.plan(&request, &mut shown_on(&bar));
    bar.finish_and_clear();
    let planned = planned?;
    // A random choice of as many units from the same pool, for comparison.
    let random = pool.random_design(&kept, planned.chosen.len(), &mut Sampler::new(args.seed));
    let random_quality = pool.assess(&random, &request.criterion)?;
    let output = args
        .output
        .as_deref()
        .ok_or_else(|| Failure::usage("give the output file: -o PLANNED.csv", None))?;
    gecaro_io::write_atomically(
        output,
        format_samples(robot.joint_count(), &columns, &planned.samples).as_bytes(),
        output_policy(args.force),
    )?;
    let quality = &planned.quality;
    if args.json {
        return super::print_json(&PlanOutputJson {
            plan: PlanJson::new(
                chosen.name(),
                &request.criterion,
                &planned,
                &random_quality,
                pool.len(),
                kept.len(),
            ),
            output: output.display().to_string(),
        });
    }
    let grouping = match columns.first() {
        Some(DataColumn::Set) => format!(" ({} sets)", planned.chosen.len()),
        Some(DataColumn::Pair) => format!(" ({} pairs)", planned.chosen.len()),
        _ => String::new(),
    };
    println!(
        "Planned {} configurations{grouping} of {} for {} ({} method), criterion {} over {} base \
         parameters; {} exchanges after the greedy pass",
        planned.samples.len(),
        pool.len(),
        robot.name(),
        chosen.name(),
        request.criterion.name().to_uppercase(),
        planned.columns.len(),
        planned.exchanges
    );
    println!(
        "{}: the plan {:.4e}, a random choice from the same pool {:.4e}",
        request.criterion.meaning(),
        quality.value,
        random_quality.value
    );
    if request.criterion != Criterion::D {
        println!(
            "D = log det(W_bᵀW_b): the plan {}, random {}",
            number(quality.log_det, 2),
            number(random_quality.log_det, 2)
        );
    }
    println!(
        "{}",
        crate::format::observability(&quality.observability, "the plan")
    );
    if !kept.is_empty() {
        println!("kept {} configurations measured already", kept.len());
    }
    println!("wrote {}", output.display());
    Ok(())
}

/// Refuses a curve's bad counts or σ before any work.
fn check_curve(counts: &[usize], noise: f64) -> Result<(), Failure> {
    if !(noise > 0.0 && noise.is_finite()) {
        return Err(Failure::usage(
            format!("--noise: {noise} is not a standard deviation (> 0 metres)"),
            None,
        ));
    }
    if counts.is_empty() || counts.contains(&0) {
        return Err(Failure::usage(
            "--curve: give positive counts, e.g. 10,20,40,80",
            None,
        ));
    }
    Ok(())
}

fn curve(
    args: &PlanArgs,
    pool: &CandidatePool<'_>,
    counts: &[usize],
    request: &PlanRequest<'_>,
    poses: &[Vec<f64>],
) -> Result<(), Failure> {
    let (robot, chosen) = (pool.robot(), pool.method());
    let noise = args.noise.unwrap_or_default();
    let bar = progress_bar("curve");
    let points = accuracy_curve(
        pool,
        counts,
        request,
        noise,
        poses,
        args.seed,
        &mut shown_on(&bar),
    );
    bar.finish_and_clear();
    let points = points?;
    if let Some(plot) = &args.plot {
        let svg = gecaro_report::accuracy_curve_svg(&points)?;
        gecaro_io::write_atomically(plot, svg.as_bytes(), output_policy(args.force))?;
    }
    if args.json {
        return super::print_json(&CurveJson {
            method: chosen.name(),
            criterion: request.criterion.name(),
            noise,
            pool: pool.len(),
            test_poses: poses.len(),
            random_draws: gecaro_calib::curve::RANDOM_DRAWS,
            points: points.iter().map(CurvePointJson::from).collect(),
        });
    }
    println!(
        "Predicted RMS position error of the calibrated {} at {} test poses ({} method, σ {} mm; \
         plans by criterion {} from a pool of {}, random: mean of {} draws)",
        robot.name(),
        poses.len(),
        chosen.name(),
        number(noise * 1e3, 6),
        request.criterion.name().to_uppercase(),
        pool.len(),
        gecaro_calib::curve::RANDOM_DRAWS
    );
    println!("{}", curve_table(&points));
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

#[derive(Serialize)]
struct PoseErrorsJson {
    position_rms: f64,
    position_max: f64,
    rotation_rms: Option<f64>,
    rotation_max: Option<f64>,
}

impl From<PoseErrors> for PoseErrorsJson {
    fn from(errors: PoseErrors) -> Self {
        PoseErrorsJson {
            position_rms: errors.position_rms,
            position_max: errors.position_max,
            rotation_rms: errors.rotation_rms,
            rotation_max: errors.rotation_max,
        }
    }
}

#[derive(Serialize)]
struct ParameterJson<'a> {
    name: &'a str,
    sigma: f64,
}

#[derive(Serialize)]
struct MonteCarloJson {
    runs: usize,
    not_converged: usize,
    error_level: f64,
    measured: PoseErrorsJson,
    /// measured / predicted RMS position error.
    position_ratio: f64,
}

#[derive(Serialize)]
struct PredictJson<'a> {
    method: &'static str,
    configurations: usize,
    noise: f64,
    test_poses: usize,
    parameters: Vec<ParameterJson<'a>>,
    predicted: PoseErrorsJson,
    monte_carlo: Option<MonteCarloJson>,
}

pub(crate) fn predict_accuracy(args: &PredictArgs) -> Result<(), Failure> {
    let file = load_robot(&args.robot)?;
    let robot = &file.robot;
    let chosen = method(&args.method.method, &method_options(&args.method.options)?)?;
    if !(args.noise > 0.0 && args.noise.is_finite()) {
        return Err(Failure::usage(
            format!(
                "--noise: {} is not a standard deviation (> 0 metres)",
                args.noise
            ),
            None,
        ));
    }
    let columns = DataColumn::grouping(chosen.data_columns());
    let planned = configurations(robot, &args.data, &columns)?;
    let poses = test_poses(robot, &args.test_poses, args.seed)?;
    let prediction = predict(
        robot,
        chosen.as_ref(),
        &planned,
        args.noise,
        &poses,
        &robot.priority(),
    )?;
    let measured = match args.monte_carlo {
        Some(runs) => {
            let bar = progress_bar("simulated calibrations");
            bar.set_length(runs as u64);
            let result = monte_carlo(
                robot,
                chosen.as_ref(),
                &planned,
                args.noise,
                args.error_level,
                &poses,
                runs,
                args.seed,
                &IdentificationOptions::default(),
                &mut gecaro_calib::each_step(|_, _| bar.inc(1)),
            );
            bar.finish_and_clear();
            Some(result?)
        }
        None => None,
    };
    let predicted = prediction.errors;
    if args.json {
        return super::print_json(&PredictJson {
            method: chosen.name(),
            configurations: planned.len(),
            noise: args.noise,
            test_poses: poses.len(),
            parameters: prediction
                .parameters
                .iter()
                .map(|(name, sigma)| ParameterJson {
                    name,
                    sigma: *sigma,
                })
                .collect(),
            predicted: predicted.into(),
            monte_carlo: measured.map(|measured| MonteCarloJson {
                runs: measured.runs,
                not_converged: measured.not_converged,
                error_level: args.error_level,
                measured: measured.errors.into(),
                position_ratio: measured.errors.position_rms / predicted.position_rms,
            }),
        });
    }
    println!(
        "Predicted precision of {} ({} method) from {} configurations of {}, sensor σ {} mm \
         (eq. 11; first order, before measuring):",
        robot.name(),
        chosen.name(),
        planned.len(),
        args.data.display(),
        number(args.noise * 1e3, 6)
    );
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
    row("predicted", &predicted);
    if let Some(measured) = &measured {
        row(
            &format!("Monte Carlo ({} runs)", measured.runs),
            &measured.errors,
        );
    }
    println!("{errors}");
    println!(
        "{} test poses ({})",
        poses.len(),
        args.test_poses.test_poses.as_ref().map_or_else(
            || "random within the joint limits".into(),
            |path| path.display().to_string()
        )
    );
    if let Some(measured) = &measured {
        println!(
            "Monte Carlo: real robots drawn at error level {}, measured / predicted RMS position \
             error {:.3}{}",
            args.error_level,
            measured.errors.position_rms / predicted.position_rms,
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
    Ok(())
}
