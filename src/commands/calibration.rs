//! `gecaro generate`, `identify`, `report`, `evaluate` and `demo`: the
//! paper's "Points generation" and "Identification" functions, and the
//! evaluation of a calibrated robot.

use std::path::{Path, PathBuf};

use gecaro_app::{
    DEMO_COUNTS, DEMO_HELD_OUT, DataSource, DemoRequest, EvaluateRequest, GenerateRequest,
    Identified, IdentifyRequest, LocalFiles, Measurements, RobotSource,
};
use gecaro_calib::identification::{ErrorSummary, Identification, StopReason};
use gecaro_calib::{Progress, each_iteration};
use indicatif::{ProgressBar, ProgressStyle};

use super::options::{
    fit_settings, measurements, method_spec, name, one_data_file, output_policy, print_notes,
};
use super::progress::with_steps;
use crate::cli::{
    DemoArgs, EvaluateArgs, GenerateArgs, IdentificationRunArgs, IdentifyArgs, ReportArgs,
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
    let extension = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    Ok(gecaro_app::Files::check_output(
        &LocalFiles,
        &name(path),
        extension,
        force,
    )?)
}

/// A spinner on stderr (hidden when stderr is not a terminal).
fn spinner(message: impl Into<String>) -> ProgressBar {
    let bar = ProgressBar::new_spinner();
    bar.set_style(
        ProgressStyle::with_template("{spinner} {msg} [{elapsed}]")
            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
    );
    bar.set_message(message.into());
    // The ticking thread only where the spinner is drawn (a terminal): a
    // script's or a pipe's run gains a thread's start and end for nothing.
    if !bar.is_hidden() {
        bar.enable_steady_tick(std::time::Duration::from_millis(120));
    }
    bar
}

pub(crate) fn generate(args: &GenerateArgs) -> Result<(), Failure> {
    super::options::no_measuring_leg(&args.leg, Some(&args.method.method))?;
    let method = method_spec(&args.method.method, &args.method.options)?;
    let mut request = GenerateRequest::new(RobotSource::Named(args.robot.clone()), method, 0);
    request.count = args.count;
    request.configurations = args
        .configurations
        .as_deref()
        .map(|path| DataSource::File(name(path)));
    request.format = super::options::data_format(&args.format);
    request.error_level = args.error_level;
    request.compliance_level = args.compliance_level;
    request.payload = args.payload.clone();
    request.gravity_tilt = args.gravity_tilt.clone();
    request.real = args
        .real
        .as_deref()
        .map(|path| RobotSource::Named(name(path)));
    request.noise = args.noise;
    request.cell = super::options::cell_spec(&args.cell)?;
    request.seed = Some(args.seed);
    request.output.save_as = Some(name(&args.output));
    request.real_save_as = args.real_out.as_deref().map(name);
    request.output.overwrite = args.force;
    let what = match &args.configurations {
        Some(_) => "measuring",
        None => "generating",
    };
    let generated = with_steps(what, |observer| request.run(&LocalFiles, observer))?;
    println!(
        "wrote {} configurations ({}) to {}",
        generated.samples.len(),
        generated.method.title(),
        args.output.display()
    );
    let (rms, max) = generated.displacement;
    match &args.real {
        Some(path) => println!("real robot: {}", path.display()),
        None => println!(
            "real robot: {} at error level {} (seed {}); its terminal point differs from the nominal by RMS {} mm, max {} mm",
            generated.nominal.robot.name(),
            number(generated.error_level, 3),
            generated.seed,
            mm(rms),
            mm(max)
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
        println!("wrote the real robot to {}", real_out.display());
    }
    Ok(())
}

/// The identification request of a command line.
fn request(args: &IdentificationRunArgs) -> Result<IdentifyRequest, Failure> {
    super::options::no_measuring_leg(&args.leg, args.source.method.as_deref())?;
    let mut request = IdentifyRequest::new(measurements(&args.source, one_data_file(&args.data)?)?);
    request.measurements.sigma = args.sigma.clone();
    request.measurements.sigma_rotation = args.sigma_rotation.clone();
    request.settings = fit_settings(args);
    Ok(request)
}

/// Prepares the identification, checks the outputs, and identifies with a
/// spinner showing the residual.
fn run_identification(
    request: &IdentifyRequest,
    outputs: &[&Path],
    force: bool,
) -> Result<Identified, Failure> {
    let prepared = request.prepare(&LocalFiles)?;
    print_notes(&prepared.loaded.notes);
    for output in outputs {
        check_output(output, force)?;
    }
    let bar = spinner("identifying");
    let mut iteration = 0;
    let identified = prepared.run(&mut each_iteration(|record| {
        bar.set_message(format!(
            "iteration {iteration}: residual RMS {:.3e}",
            record.rms
        ));
        iteration += 1;
    }));
    bar.finish_and_clear();
    Ok(identified?)
}

/// Writes the three plots of `identify --plot` into `folder`.
fn write_plots(
    folder: &Path,
    identified: &Identified,
    force: bool,
) -> Result<Vec<PathBuf>, Failure> {
    let plots = identified.plots()?;
    write_svgs(
        folder,
        &[
            ("convergence.svg", plots.convergence),
            ("errors_histogram.svg", plots.errors_histogram),
            (
                "errors_per_configuration.svg",
                plots.errors_per_configuration,
            ),
        ],
        force,
    )
}

/// `named` SVG plots written into `folder` (created if missing), none over
/// a file without `force`: their paths.
pub(crate) fn write_svgs(
    folder: &Path,
    named: &[(&str, String)],
    force: bool,
) -> Result<Vec<PathBuf>, Failure> {
    std::fs::create_dir_all(folder).map_err(|error| gecaro_io::Error::Write {
        path: folder.to_owned(),
        message: error.to_string(),
    })?;
    let paths: Vec<PathBuf> = named.iter().map(|(file, _)| folder.join(file)).collect();
    for path in &paths {
        check_output(path, force)?;
    }
    for (path, (_, svg)) in paths.iter().zip(named) {
        gecaro_io::write_atomically(path, svg.as_bytes(), output_policy(force))?;
    }
    Ok(paths)
}

/// The command line as typed, quoted where a shell would need it.
pub(crate) fn command_line() -> String {
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

/// The error of a run that did not converge; `advice` says what was saved anyway.
/// Whether the last updates of a run that did not converge still lowered
/// the residual by more than a thousandth (more iterations would help).
fn still_descending(result: &gecaro_calib::identification::Identification) -> bool {
    let rms: Vec<f64> = result.history.iter().map(|record| record.rms).collect();
    match rms.as_slice() {
        [.., before, last] => *last < 0.999 * before,
        _ => false,
    }
}

fn not_converged(identified: &Identified, advice: &str) -> Failure {
    let failure = identified
        .result
        .failure()
        .unwrap_or_else(|| "the identification did not converge".into());
    gecaro_app::AppError::plain(
        gecaro_app::ErrorKind::NotConverged,
        if advice.is_empty() {
            format!("{failure}.")
        } else {
            format!("{failure}. {advice}")
        },
    )
    .into()
}

pub(crate) fn report(args: &ReportArgs) -> Result<(), Failure> {
    let identified = run_identification(&request(&args.run)?, &[&args.output], args.force)?;
    let html = identified.report(&command_line())?;
    gecaro_io::write_atomically(&args.output, html.as_bytes(), output_policy(args.force))?;
    println!(
        "wrote the report of {} ({} method, {}) to {}",
        identified.loaded.robot.robot.name(),
        identified.loaded.study.method_names(),
        identified.loaded.label,
        args.output.display()
    );
    if !identified.converged() {
        return Err(not_converged(
            &identified,
            "The report shows the best iterate.",
        ));
    }
    identified
        .misfit()
        .map_or(Ok(()), |misfit| Err(misfit.into()))
}

pub(crate) fn identify(args: &IdentifyArgs) -> Result<(), Failure> {
    let mut request = request(&args.run)?;
    request.cv = args.cv;
    request.seed = Some(args.seed);
    request.folds_by = Some(args.folds_by.clone());
    request.check_model = match (args.check_model, args.no_check_model) {
        (true, _) => Some(true),
        (_, true) => Some(false),
        _ => None,
    };
    let outputs: Vec<&Path> = args
        .output
        .iter()
        .chain(&args.residuals)
        .map(PathBuf::as_path)
        .collect();
    let identified = run_identification(&request, &outputs, args.force)?;
    if args.json {
        super::output::print_json(&identified.document())?;
    } else {
        print_identification(&identified);
        if let Some(validation) = &identified.cross_validation {
            super::validation::print_cross_validation(validation);
        }
    }
    super::options::print_notes(&identified.advice_notes());
    // Written atomically and together — both or neither (a full disk after
    // the robot left it without its residuals) — never over a file without
    // --force; said unless --json.
    let mut outputs: Vec<(&Path, String, &str)> = Vec::new();
    if let Some(output) = &args.output
        && (identified.converged() || args.write_unconverged)
    {
        outputs.push((
            output,
            identified.calibrated_text()?,
            "the calibrated robot",
        ));
    }
    if let Some(path) = &args.residuals {
        outputs.push((path, identified.residuals_csv()?, "the residuals"));
    }
    let bytes: Vec<(&Path, &[u8])> = outputs
        .iter()
        .map(|(path, text, _)| (*path, text.as_bytes()))
        .collect();
    gecaro_io::write_all_atomically(&bytes, output_policy(args.force))?;
    if !args.json {
        for (path, _, what) in &outputs {
            println!("wrote {what} to {}", path.display());
        }
    }
    if let Some(folder) = &args.plot {
        let paths = write_plots(folder, &identified, args.force)?;
        if !args.json {
            println!("wrote the plots to {}", display_list(&paths));
        }
    }
    if !identified.converged() {
        return Err(not_converged(
            &identified,
            if args.output.is_some() && !args.write_unconverged {
                "Nothing was written (--write-unconverged saves the best iterate)."
            } else if identified.result.verdict.shifted_join.is_some() {
                ""
            } else if still_descending(&identified.result) {
                "The residual was still falling: allow more --max-iterations."
            } else {
                // The default already falls back on Levenberg–Marquardt.
                "The residual had stopped falling far from the data: check their units \
                 (--length-unit, --angle-unit), the robot file and how the joints and the \
                 measurements were joined."
            },
        ));
    }
    identified
        .misfit()
        .map_or(Ok(()), |misfit| Err(misfit.into()))
}

pub(crate) fn display_list(paths: &[PathBuf]) -> String {
    paths
        .iter()
        .map(|path| path.display().to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

fn print_identification(identified: &Identified) {
    let (robot, study, result) = (
        &identified.loaded.robot.robot,
        &identified.loaded.study,
        &identified.result,
    );
    let configurations: usize = study.sets.iter().map(|s| s.samples.len()).sum();
    println!(
        "Identification — {}, {} method, {} ({configurations} configurations, {} equations)",
        robot.name(),
        study.method_names(),
        identified.loaded.label,
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
    print_iterations(result);
    print_errors("Errors", &result.before, Some(&result.after));
    if let Some(inliers) = result.after_inliers() {
        print_errors(
            &format!(
                "Without the {} outliers, errors after",
                result.outliers.len()
            ),
            &inliers,
            None,
        );
    }
    println!(
        "Residual standard deviation σ = {:.3e}",
        result.residual_sigma
    );
    super::robustness::print_robustness(result);
    print_parameters(result);
    print_groups(identified);
    print_registration(identified);
}

/// A study's errors set by set and station by station (mm): the set that
/// fits worse than the others stands out.
fn print_groups(identified: &Identified) {
    let (sets, stations) = identified.group_errors();
    for (title, groups) in [("set", &sets), ("station", &stations)] {
        if groups.is_empty() {
            continue;
        }
        // A set names its tool and station; a station is its own name.
        let sets = title == "set";
        let mut header = vec![title];
        if sets {
            header.extend(["tool", "station"]);
        }
        header.extend(["observations", "RMS before", "RMS after", "largest after"]);
        let mut rows = table(&header, if sets { 3 } else { 1 });
        for group in groups {
            let mut row = vec![group.name.clone()];
            if sets {
                row.push(group.tool.clone().unwrap_or_default());
                row.push(group.station.clone().unwrap_or_default());
            }
            row.extend([
                group.observations.to_string(),
                format!("{:.4}", group.rms_before * 1e3),
                format!("{:.4}", group.rms_after * 1e3),
                format!("{:.4}", group.max_after * 1e3),
            ]);
            rows.add_row(row);
        }
        println!("Errors {title} by {title} (mm):\n{rows}");
    }
}

fn print_iterations(result: &Identification) {
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
                gecaro_calib::identification::Route::GaussNewton => {
                    "plain Gauss–Newton, as in the paper"
                }
                gecaro_calib::identification::Route::MinimumNorm => {
                    "minimum-norm route: the plain steps did not converge"
                }
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
    println!("Verdict: {}.", result.verdict.summary);
}

/// The named tools and stations at their identified poses, as a study
/// file states them (ready to be pasted into the next study).
fn print_frames(result: &Identification) {
    if result.frames.is_empty() {
        return;
    }
    println!("Tools and stations identified (as a study file states them, in mm and degrees):");
    for frame in &result.frames {
        let t = frame.pose.translation.vector * 1e3;
        let (roll, pitch, yaw) = frame.pose.rotation.euler_angles();
        println!(
            "  [{}s.{}]\n  position = [{:.4}, {:.4}, {:.4}]\n  rpy = [{:.5}, {:.5}, {:.5}]\n  length_unit = \"mm\"\n  angle_unit = \"deg\"",
            frame.role.as_str(),
            crate::format::shown(&frame.name),
            t.x,
            t.y,
            t.z,
            roll.to_degrees(),
            pitch.to_degrees(),
            yaw.to_degrees()
        );
    }
}

fn print_parameters(result: &Identification) {
    let with_prior = result.prior.is_some();
    let mut header = vec!["parameter", "nominal", "identified", "deviation", "σ"];
    if with_prior {
        header.extend(["noise σ", "prior σ"]);
    }
    let mut parameters = table(&header, 1);
    for parameter in result.parameters.iter().chain(&result.auxiliary) {
        let mut row = vec![
            if parameter.is_regrouped() {
                format!("{} (regrouped)", parameter.name)
            } else {
                parameter.name.clone()
            },
            number(parameter.nominal, 9),
            number(parameter.identified, 9),
            format!("{:+.3e}", parameter.identified - parameter.nominal),
            format!("{:.2e}", parameter.std),
        ];
        if with_prior {
            row.push(format!("{:.2e}", parameter.noise_std));
            row.push(
                parameter
                    .prior_std
                    .map_or("–".into(), |s| format!("{s:.2e}")),
            );
        }
        parameters.add_row(row);
    }
    println!("Identified parameters (metres, radians):\n{parameters}");
    print_frames(result);
    let combinations: Vec<String> = result
        .parameters
        .iter()
        .filter_map(|p| p.combination())
        .collect();
    if !combinations.is_empty() {
        println!(
            "Regrouped: each of these deviations stands for a combination, not for the \
             parameter alone: {}",
            combinations.join("; ")
        );
    }
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

/// Where the calibrated robot puts its base and its tool, against the
/// robot file: the registration a cell's user reads first.
fn print_registration(identified: &Identified) {
    let registration = identified.registration();
    let pose = |pose: &gecaro_app::documents::PoseJson| {
        let position: Vec<String> = pose.position.iter().map(|v| mm(*v)).collect();
        let rpy: Vec<String> = pose.rpy.iter().map(|v| degrees(*v)).collect();
        format!("({}) mm, rpy ({})°", position.join(", "), rpy.join(", "))
    };
    let moved = |change: &[f64]| {
        format!(
            "{} mm, {}° from the robot file's",
            mm(change[0]),
            degrees(change[1])
        )
    };
    println!(
        "Registration: the base in the measurement frame at {} ({}); the tool in the flange \
         frame at {} ({})",
        pose(&registration.base),
        moved(&registration.base_moved),
        pose(&registration.tool),
        moved(&registration.tool_moved)
    );
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
    let measurements = Measurements {
        robot: Some(RobotSource::Named(args.robot.clone())),
        method: args
            .method
            .as_deref()
            .map(|method| method_spec(method, &args.options))
            .transpose()?,
        data: args
            .data
            .as_deref()
            .map(|path| DataSource::File(name(path))),
        format: super::options::data_format(&args.format),
        study: args
            .study
            .as_deref()
            .map(|path| gecaro_app::StudySource::File(name(path))),
        strict_limits: args.strict_limits,
        ..Measurements::default()
    };
    let mut request = EvaluateRequest::new(measurements);
    request.register = args.register.clone();
    let evaluation = request.run(&LocalFiles)?;
    print_notes(&evaluation.loaded.notes);
    if args.json {
        return super::output::print_json(&gecaro_app::documents::SummaryJson::from(
            &evaluation.summary,
        ));
    }
    println!(
        "{} on {} ({} method):",
        evaluation.loaded.robot.robot.name(),
        evaluation.loaded.label,
        evaluation.loaded.study.method_names()
    );
    print_errors("Errors", &evaluation.summary, None);
    Ok(())
}

pub(crate) fn demo(args: &DemoArgs) -> Result<(), Failure> {
    let request = DemoRequest {
        error_level: args.error_level,
        noise: args.noise,
        seed: args.seed,
    };
    println!(
        "gecaro demo — Stanford (Table 1); simulated real robot at error level {}, sensor noise σ = {} mm, seed {}",
        number(args.error_level, 3),
        mm(args.noise),
        args.seed
    );
    let bar = ProgressBar::new(DEMO_COUNTS.len() as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let mut observer = |progress: Progress<'_>| {
        match progress {
            Progress::Phase(title) => bar.set_message(title.to_owned()),
            Progress::Step { done, .. } => bar.set_position(done as u64),
            Progress::Iteration(_) => {}
        }
        std::ops::ControlFlow::Continue(())
    };
    let demo = request.run(&LocalFiles, &mut observer)?;
    bar.finish_and_clear();
    let mut summary = table(
        &[
            "method",
            "configurations",
            "parameters",
            "iterations",
            "fit RMS before → after (mm)",
            "held out (mm)",
            "verdict (σ̂/σ)",
            "time",
        ],
        1,
    );
    let mut failures = Vec::new();
    for run in &demo.runs {
        let result = &run.identification;
        if result.stop_reason != StopReason::Converged {
            failures.push(format!("{}: {}", run.title, result.stop_reason.as_str()));
        }
        summary.add_row(vec![
            run.title.to_owned(),
            run.configurations.to_string(),
            result.parameters.len().to_string(),
            result.iterations().to_string(),
            format!("{} → {}", mm(result.before.rms), mm(result.after.rms)),
            format!("{} → {}", mm(demo.nominal_held_out), mm(run.held_out)),
            match result.verdict.noise_test {
                Some(test) => format!(
                    "{} ({:.2})",
                    result.verdict.outcome.as_str().replace('_', " "),
                    test.sigma_ratio
                ),
                None => result.verdict.outcome.as_str().replace('_', " "),
            },
            format!("{:.0} ms", run.elapsed.as_secs_f64() * 1000.0),
        ]);
    }
    println!("{summary}");
    println!(
        "Fit: each method's own residuals per configuration (distance to the measured point, to the \
         set's mean point, to the plane, distance error). Held out: the tool points of {DEMO_HELD_OUT} \
         other configurations of the real robot, nominal → calibrated, after the rigid registration \
         that best maps them onto the real ones (link and plane methods do not observe the base). \
         Link and plane methods measure no length: their robot's size is the nominal one's, which \
         their verdict (incomplete) says; frame link does not see the tool either. Next: `gecaro \
         generate`, `gecaro identify`, `gecaro evaluate` (see the README)."
    );
    if failures.is_empty() {
        Ok(())
    } else {
        Err(Failure::numerical(format!(
            "not converged: {}",
            failures.join("; ")
        )))
    }
}
