//! `gecaro generate`, `identify`, `evaluate` and `demo`: the paper's "Points
//! generation" and "Identification" functions, and the evaluation of a
//! calibrated robot.

use gecaro_calib::{
    Quiet, each_iteration,
    identification::{
        ErrorSummary, Identification, IdentificationOptions, Loss, LossKind, Solver, StopReason,
        evaluate as evaluate_study,
    },
    methods::{CalibrationMethod, MethodOptions, Plane, method},
    simulation::{Sampler, perturbed_robot, simulate_measurements},
    study::Study,
    validation::Model,
};
use gecaro_core::Robot;
use gecaro_io::{
    RobotFile, format_robot_file, load_robot, read_priority_file, read_robot_file,
    write_atomically, write_samples,
};
use gecaro_report::json::{CrossValidationJson, IdentificationJson, SummaryJson};
use indicatif::{ProgressBar, ProgressStyle};
use nalgebra::Vector3;
use std::path::{Path, PathBuf};
use std::time::Instant;

use super::options::{load_study, method_options, output_policy};
use crate::cli::{
    DemoArgs, EvaluateArgs, GenerateArgs, IdentificationRunArgs, IdentifyArgs, LossArg, ReportArgs,
    SolverArg,
};
use crate::failure::Failure;
use crate::format::{number, table};

/// Millimetres, for human output of lengths.
fn mm(metres: f64) -> String {
    number(metres * 1000.0, 3)
}

/// Degrees, for human output of angles.
fn degrees(radians: f64) -> String {
    number(radians.to_degrees(), 4)
}

/// Refuses early, before any work or any file is written, an output that
/// exists (without --force) or whose folder is missing.
pub(crate) fn check_output(path: &Path, force: bool) -> Result<(), Failure> {
    if !force && path.exists() {
        return Err(gecaro_io::Error::OutputExists {
            path: path.to_owned(),
        }
        .into());
    }
    let folder = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    if !folder.is_dir() {
        return Err(gecaro_io::Error::Write {
            path: path.to_owned(),
            message: format!("the folder {} does not exist", folder.display()),
        }
        .into());
    }
    Ok(())
}

/// A spinner on stderr (hidden when stderr is not a terminal).
fn spinner(message: impl Into<String>) -> ProgressBar {
    let bar = ProgressBar::new_spinner();
    bar.set_style(
        ProgressStyle::with_template("{spinner} {msg} [{elapsed}]")
            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
    );
    bar.set_message(message.into());
    bar.enable_steady_tick(std::time::Duration::from_millis(120));
    bar
}

pub(crate) fn generate(args: &GenerateArgs) -> Result<(), Failure> {
    let nominal = load_robot(&args.robot)?;
    let robot = &nominal.robot;
    check_output(&args.output, args.force)?;
    if let Some(real_out) = &args.real_out {
        check_output(real_out, args.force)?;
    }
    let options = method_options(&args.method.options)?;
    let chosen = method(&args.method.method, &options)?;
    let mut sampler = Sampler::new(args.seed);
    let real = match &args.real {
        Some(path) => {
            let real = read_robot_file(path)?.robot;
            if real.joint_letters() != robot.joint_letters() {
                return Err(Failure::Input(format!(
                    "{}: the real robot has joints {}, the nominal one {}",
                    path.display(),
                    real.joint_letters(),
                    robot.joint_letters()
                )));
            }
            real
        }
        None => perturbed_robot(robot, args.error_level, &mut sampler)?,
    };
    let samples = match (&args.configurations, args.count) {
        (Some(path), _) => {
            let planned = gecaro_io::read_samples(
                path,
                &gecaro_io::joint_types(robot),
                &gecaro_calib::study::DataColumn::grouping(chosen.data_columns()),
                &gecaro_io::DataFormat::default(),
            )?
            .samples;
            let bar = spinner(format!(
                "measuring at {} planned configurations ({})",
                planned.len(),
                chosen.title()
            ));
            let samples = gecaro_calib::simulation::simulate_at(
                &real,
                chosen.as_ref(),
                &planned,
                args.noise,
                &mut sampler,
            );
            bar.finish_and_clear();
            samples?
        }
        (None, count) => {
            let count = count.unwrap_or_default();
            let bar = spinner(format!(
                "generating {count} configurations ({})",
                chosen.title()
            ));
            let samples =
                simulate_measurements(&real, chosen.as_ref(), count, args.noise, &mut sampler);
            bar.finish_and_clear();
            samples?
        }
    };
    write_samples(
        &args.output,
        robot.joint_count(),
        chosen.data_columns(),
        &samples,
        output_policy(args.force),
    )?;
    println!(
        "wrote {} configurations ({}) to {}",
        samples.len(),
        chosen.title(),
        args.output.display()
    );
    let displacement = gecaro_calib::simulation::terminal_displacement(robot, &real, &samples)?;
    match &args.real {
        Some(path) => println!("real robot: {}", path.display()),
        None => println!(
            "real robot: {} at error level {} (seed {}); its terminal point differs from the nominal by RMS {} mm, max {} mm",
            robot.name(),
            number(args.error_level, 3),
            args.seed,
            mm(displacement.0),
            mm(displacement.1)
        ),
    }
    if args.noise > 0.0 {
        println!(
            "sensor noise: σ = {} mm ({} rad for orientations)",
            mm(args.noise),
            number(args.noise, 9)
        );
    }
    if let Some(real_out) = &args.real_out {
        let file = gecaro_report::simulated_robot_file(&nominal, real, args.error_level, args.seed);
        write_atomically(
            real_out,
            format_robot_file(&file).as_bytes(),
            output_policy(args.force),
        )?;
        println!("wrote the real robot to {}", real_out.display());
    }
    Ok(())
}

/// Reads a single-method study from the command line's method and data file.
fn single_study(
    robot: &Robot,
    method_args: &crate::cli::MethodArgs,
    data: &Path,
    format: &crate::cli::DataFormatArgs,
) -> Result<Study, Failure> {
    let options = method_options(&method_args.options)?;
    let chosen = method(&method_args.method, &options)?;
    let samples = super::options::read_data(data, robot, chosen.as_ref(), format)?;
    Ok(Study::single(chosen, samples, data.display().to_string()))
}

/// An identification run from the command line, with what produced it.
struct Run {
    file: RobotFile,
    study: Study,
    result: Identification,
    data_label: PathBuf,
    options: IdentificationOptions,
}

/// What an identification needs, read from the command line.
pub(super) struct Prepared {
    pub(super) file: RobotFile,
    pub(super) study: Study,
    pub(super) options: IdentificationOptions,
    pub(super) data_label: PathBuf,
}

/// Loads the robot and data and reads the identification options.
pub(super) fn prepare(args: &IdentificationRunArgs) -> Result<Prepared, Failure> {
    let super::options::LoadedStudy {
        file,
        study,
        priority: study_priority,
        prior: study_prior,
    } = load_study(&args.source, args.data.as_deref())?;
    let robot = &file.robot;
    let priority = match &args.priority {
        Some(path) => Some(read_priority_file(path, robot)?),
        None => study_priority,
    };
    let priority = model(&args.model, robot)?.priority(robot, priority.as_ref());
    let data_label = args
        .data
        .clone()
        .or_else(|| args.source.study.clone())
        .unwrap_or_default();
    let options = IdentificationOptions {
        solver: match args.solver {
            SolverArg::GaussNewton => Solver::GaussNewton,
            SolverArg::Lm => Solver::LevenbergMarquardt,
        },
        max_iterations: args.max_iterations,
        priority: Some(priority),
        ..robust_options(args, study_prior)?
    };
    Ok(Prepared {
        file,
        study,
        options,
        data_label,
    })
}

/// A model by name, or a priority-matrix file.
pub(super) fn model(name: &str, robot: &Robot) -> Result<Model, Failure> {
    let path = Path::new(name);
    if path.extension().is_some_and(|e| e == "toml") || path.is_file() {
        return Ok(Model::Matrix(
            name.to_owned(),
            read_priority_file(path, robot)?,
        ));
    }
    Ok(name.parse::<Model>()?)
}

/// Loads the robot and data, identifies with a spinner showing the residual.
/// `outputs` are checked before any work is done.
fn run_identification(
    args: &IdentificationRunArgs,
    outputs: &[&Path],
    force: bool,
) -> Result<Run, Failure> {
    let Prepared {
        file,
        study,
        options,
        data_label,
    } = prepare(args)?;
    let robot = &file.robot;
    for output in outputs {
        check_output(output, force)?;
    }
    let bar = spinner("identifying");
    let mut iteration = 0;
    let result = gecaro_calib::identification::identify(
        robot,
        &study,
        &options,
        &mut each_iteration(|record| {
            bar.set_message(format!(
                "iteration {iteration}: residual RMS {:.3e}",
                record.rms
            ));
            iteration += 1;
        }),
    );
    bar.finish_and_clear();
    Ok(Run {
        result: result?,
        file,
        study,
        data_label,
        options,
    })
}

/// The loss, prior and outlier options of the command line (the study
/// file's prior, if any, unless `--prior` replaces its σ per kind).
fn robust_options(
    args: &IdentificationRunArgs,
    study_prior: Option<gecaro_calib::identification::Prior>,
) -> Result<IdentificationOptions, Failure> {
    let kind = match args.loss {
        LossArg::L2 => LossKind::L2,
        LossArg::Huber => LossKind::Huber,
        LossArg::Cauchy => LossKind::Cauchy,
        LossArg::Tukey => LossKind::Tukey,
    };
    let loss = Loss::from_parts(kind, args.loss_scale)?;
    let prior = match (&args.prior, study_prior) {
        (Some(text), study) => {
            let mut prior = gecaro_io::parse_prior(text).map_err(|message| {
                Failure::usage(
                    format!("--prior: {message}"),
                    Some("for example: --prior 5mm,0.5deg,1%".to_owned()),
                )
            })?;
            prior.overrides = study.map(|p| p.overrides).unwrap_or_default();
            Some(prior)
        }
        (None, study) => study,
    };
    Ok(IdentificationOptions {
        loss,
        prior,
        outlier_threshold: args.outlier_threshold,
        reject: args.reject,
        ..IdentificationOptions::default()
    })
}

/// The error of a run that did not converge; `advice` says what was saved anyway.
fn not_converged(result: &Identification, advice: &str) -> Failure {
    Failure::Numerical(format!(
        "{}. {advice}",
        result.failure().unwrap_or_default()
    ))
}

/// Millimetre lengths of per-observation errors, for the plots.
fn millimetres(errors: &[(f64, f64)]) -> Vec<f64> {
    errors.iter().map(|error| error.0 * 1e3).collect()
}

/// Writes the three plots of `identify --plot` into `folder`.
fn write_plots(
    folder: &Path,
    result: &Identification,
    force: bool,
) -> Result<Vec<PathBuf>, Failure> {
    std::fs::create_dir_all(folder).map_err(|error| gecaro_io::Error::Write {
        path: folder.to_owned(),
        message: error.to_string(),
    })?;
    let (before, after) = (
        millimetres(&result.errors_before),
        millimetres(&result.errors_after),
    );
    let plots = [
        (
            "convergence.svg",
            gecaro_report::convergence_svg(&result.history)?,
        ),
        (
            "errors_histogram.svg",
            gecaro_report::error_histograms_svg(&before, &after, "mm")?,
        ),
        (
            "errors_per_configuration.svg",
            gecaro_report::errors_per_configuration_svg(
                &before,
                &after,
                &result.outlier_observations(),
                "mm",
            )?,
        ),
    ];
    let paths: Vec<PathBuf> = plots.iter().map(|(name, _)| folder.join(name)).collect();
    for path in &paths {
        check_output(path, force)?;
    }
    for (path, (_, svg)) in paths.iter().zip(&plots) {
        write_atomically(path, svg.as_bytes(), output_policy(force))?;
    }
    Ok(paths)
}

/// The command line as typed, quoted where a shell would need it.
fn command_line() -> String {
    std::env::args()
        .enumerate()
        .map(|(index, argument)| {
            let argument = if index == 0 {
                "gecaro".to_owned()
            } else {
                argument
            };
            let plain = !argument.is_empty()
                && argument
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || "-_./,=:+@%".contains(c));
            if plain {
                argument
            } else {
                format!("'{}'", argument.replace('\'', "'\\''"))
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
}

pub(crate) fn report(args: &ReportArgs) -> Result<(), Failure> {
    let run = run_identification(&args.run, &[&args.output], args.force)?;
    let html = gecaro_report::html_report(&gecaro_report::ReportInput {
        robot: &run.file,
        study: &run.study,
        identification: &run.result,
        command: &command_line(),
    })?;
    write_atomically(&args.output, html.as_bytes(), output_policy(args.force))?;
    println!(
        "wrote the report of {} ({} method, {}) to {}",
        run.file.robot.name(),
        run.study.method_names(),
        run.data_label.display(),
        args.output.display()
    );
    if run.result.stop_reason == StopReason::Converged {
        Ok(())
    } else {
        Err(not_converged(
            &run.result,
            "The report shows the best iterate.",
        ))
    }
}

pub(crate) fn identify(args: &IdentifyArgs) -> Result<(), Failure> {
    let outputs: Vec<&Path> = args.output.iter().map(PathBuf::as_path).collect();
    let Run {
        file,
        study,
        result,
        data_label,
        options,
    } = run_identification(&args.run, &outputs, args.force)?;
    let robot = &file.robot;
    let converged = result.stop_reason == StopReason::Converged;
    let validation = match args.cv {
        Some(folds) => Some(super::validation::cross_validation(
            robot, &study, &options, folds, args.seed,
        )?),
        None => None,
    };
    if args.json {
        let mut document = IdentificationJson::new(&study, &result);
        document.cross_validation = validation
            .as_ref()
            .map(|validation| CrossValidationJson::new(validation, args.seed));
        super::print_json(&document)?;
    } else {
        print_identification(robot, &study, &result, &data_label);
        if let Some(validation) = &validation {
            super::validation::print_cross_validation(validation, args.seed);
        }
    }
    if let Some(output) = &args.output
        && (converged || args.write_unconverged)
    {
        let calibrated = gecaro_report::calibrated_robot_file(
            &file,
            &study,
            &result,
            &data_label.display().to_string(),
        );
        write_atomically(
            output,
            format_robot_file(&calibrated).as_bytes(),
            output_policy(args.force),
        )?;
        if !args.json {
            println!("wrote the calibrated robot to {}", output.display());
        }
    }
    if let Some(folder) = &args.plot {
        let paths = write_plots(folder, &result, args.force)?;
        if !args.json {
            println!("wrote the plots to {}", display_list(&paths));
        }
    }
    if converged {
        Ok(())
    } else {
        Err(not_converged(
            &result,
            if args.output.is_some() && !args.write_unconverged {
                "Nothing was written (--write-unconverged saves the best iterate)."
            } else {
                "Try --solver lm, more --max-iterations, or check the data."
            },
        ))
    }
}

fn display_list(paths: &[PathBuf]) -> String {
    paths
        .iter()
        .map(|path| path.display().to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

fn print_identification(robot: &Robot, study: &Study, result: &Identification, data: &Path) {
    let configurations: usize = study.sets.iter().map(|s| s.samples.len()).sum();
    println!(
        "Identification — {}, {} method, {} ({configurations} configurations, {} equations)",
        robot.name(),
        study.method_names(),
        data.display(),
        study.equation_count()
    );
    println!(
        "{} identifiable parameters{}; condition number of W_b {}",
        result.parameters.len(),
        if result.auxiliary.is_empty() {
            String::new()
        } else {
            format!(" + {} auxiliary", result.auxiliary.len())
        },
        number(result.condition_number, 2)
    );
    println!(
        "{}",
        crate::format::observability(&result.observability(), "the data")
    );
    let mut iterations = table(&["iteration", "residual RMS", "step ‖Δη‖", "damping λ"], 1);
    for (index, record) in result.history.iter().enumerate() {
        iterations.add_row(vec![
            index.to_string(),
            format!("{:.3e}", record.rms),
            if index == 0 {
                "–".into()
            } else {
                format!("{:.2e}", record.step)
            },
            if record.damping == 0.0 {
                "–".into()
            } else {
                format!("{:.0e}", record.damping)
            },
        ]);
    }
    println!("{iterations}");
    match result.stop_reason {
        StopReason::Converged => println!(
            "Converged after {} iterations ({}).",
            result.iterations(),
            match result.route {
                gecaro_calib::identification::Route::GaussNewton =>
                    "plain Gauss–Newton, as in the paper",
                gecaro_calib::identification::Route::MinimumNorm =>
                    "minimum-norm route: the plain steps did not converge",
                gecaro_calib::identification::Route::LevenbergMarquardt => "Levenberg–Marquardt",
            }
        ),
        StopReason::IterationLimit => {
            println!("NOT converged: iteration limit reached; showing the best iterate.")
        }
        StopReason::Diverged => println!(
            "NOT converged: no step lowers the residual any more; showing the best iterate."
        ),
    }
    print_errors("Errors", &result.before, Some(&result.after));
    println!(
        "Residual standard deviation σ = {:.3e}",
        result.residual_sigma
    );
    super::robustness::print_robustness(result);
    let with_prior = result.prior.is_some();
    let mut header = vec!["parameter", "nominal", "identified", "deviation", "σ"];
    if with_prior {
        header.push("prior σ");
    }
    let mut parameters = table(&header, 1);
    for parameter in result.parameters.iter().chain(&result.auxiliary) {
        let mut row = vec![
            parameter.name.clone(),
            number(parameter.nominal, 9),
            number(parameter.identified, 9),
            format!("{:+.3e}", parameter.identified - parameter.nominal),
            format!("{:.2e}", parameter.std),
        ];
        if with_prior {
            row.push(
                parameter
                    .prior_std
                    .map_or("–".into(), |s| format!("{s:.2e}")),
            );
        }
        parameters.add_row(row);
    }
    println!("Identified parameters (metres, radians):\n{parameters}");
    if !result.moved.is_empty() {
        let moved: Vec<String> = result
            .moved
            .iter()
            .map(|p| format!("{} {:+.3e}", p.name, p.identified - p.nominal))
            .collect();
        println!("Moved outside the base set: {}", moved.join(", "));
    }
    for warning in &result.warnings {
        println!("warning: {warning}");
    }
}

/// Prints RMS/mean/max errors, before → after when both are given.
fn print_errors(title: &str, before: &ErrorSummary, after: Option<&ErrorSummary>) {
    let arrow = |a: String, b: Option<String>| match b {
        Some(b) => format!("{a} → {b}"),
        None => a,
    };
    println!(
        "{title} over {} observations: RMS {} mm, mean {} mm, max {} mm",
        before.count,
        arrow(mm(before.rms), after.map(|a| mm(a.rms))),
        arrow(mm(before.mean), after.map(|a| mm(a.mean))),
        arrow(mm(before.max), after.map(|a| mm(a.max))),
    );
    if let Some(rms_rotation) = before.rms_rotation {
        println!(
            "{title} of orientation: RMS {}°, max {}°",
            arrow(
                degrees(rms_rotation),
                after.and_then(|a| a.rms_rotation).map(degrees)
            ),
            arrow(
                degrees(before.max_rotation.unwrap_or(0.0)),
                after.and_then(|a| a.max_rotation).map(degrees)
            ),
        );
    }
}

pub(crate) fn evaluate(args: &EvaluateArgs) -> Result<(), Failure> {
    let robot = load_robot(&args.robot)?.robot;
    let study = single_study(&robot, &args.method, &args.data, &args.format)?;
    super::options::check_limits(&robot, &study, args.strict_limits)?;
    let summary = evaluate_study(&robot, &study)?;
    if args.json {
        return super::print_json(&SummaryJson::from(&summary));
    }
    println!(
        "{} on {} ({} method):",
        robot.name(),
        args.data.display(),
        study.method_names()
    );
    print_errors("Errors", &summary, None);
    Ok(())
}

/// Configurations per method in the demo: enough for a clean identification.
const DEMO_COUNTS: [(&str, usize); 7] = [
    ("position", 50),
    ("frame", 30),
    ("point-link", 80),
    ("frame-link", 60),
    ("plane1", 120),
    ("plane2", 120),
    ("distance", 200),
];

pub(crate) fn demo(args: &DemoArgs) -> Result<(), Failure> {
    let robot = load_robot("stanford")?.robot;
    let plane = Plane::new(
        Vector3::from(gecaro_calib::table2::TABLE2_PLANE_NORMAL),
        Vector3::from(gecaro_calib::table2::STANFORD_PLANE_POINT),
    )?;
    let options = MethodOptions {
        plane: Some(plane),
        ..MethodOptions::default()
    };
    let mut sampler = Sampler::new(args.seed);
    let real = perturbed_robot(&robot, args.error_level, &mut sampler)?;
    println!(
        "gecaro demo — {} (Table 1); simulated real robot at error level {}, sensor noise σ = {} mm, seed {}",
        robot.name(),
        number(args.error_level, 3),
        mm(args.noise),
        args.seed
    );
    let mut summary = table(
        &[
            "method",
            "configurations",
            "parameters",
            "iterations",
            "error RMS before → after (mm)",
            "time",
        ],
        1,
    );
    let bar = ProgressBar::new(DEMO_COUNTS.len() as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let mut failures = Vec::new();
    for (name, count) in DEMO_COUNTS {
        let chosen: Box<dyn CalibrationMethod> = method(name, &options)?;
        bar.set_message(chosen.title());
        let started = Instant::now();
        let samples =
            simulate_measurements(&real, chosen.as_ref(), count, args.noise, &mut sampler)?;
        let title = chosen.title();
        let study = Study::single(chosen, samples, name);
        let result = gecaro_calib::identification::identify(
            &robot,
            &study,
            &IdentificationOptions::default(),
            &mut Quiet,
        )?;
        let elapsed = started.elapsed();
        if result.stop_reason != StopReason::Converged {
            failures.push(format!("{title}: {}", result.stop_reason.as_str()));
        }
        summary.add_row(vec![
            title.to_owned(),
            study.sets[0].samples.len().to_string(),
            result.parameters.len().to_string(),
            result.iterations().to_string(),
            format!("{} → {}", mm(result.before.rms), mm(result.after.rms)),
            format!("{:.0} ms", elapsed.as_secs_f64() * 1000.0),
        ]);
        bar.inc(1);
    }
    bar.finish_and_clear();
    println!("{summary}");
    println!(
        "Errors are per configuration: distance to the measured point (position, frame), to the set's \
         mean point (links), to the plane, or distance error (pairs). Next: `gecaro generate`, \
         `gecaro identify`, `gecaro evaluate` (see the README)."
    );
    if failures.is_empty() {
        Ok(())
    } else {
        Err(Failure::Numerical(format!(
            "not converged: {}",
            failures.join("; ")
        )))
    }
}
