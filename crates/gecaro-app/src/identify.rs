//! The "Identification" function (paper §4, eq. 10–11) as a job, with the
//! jobs that judge it on held-out data: K-fold cross-validation, the
//! comparison of models, and the evaluation of a (calibrated) robot.
//!
//! A request is prepared first ([`IdentifyRequest::prepare`]: the robot and
//! data are read and checked, the settings parsed), so that a front end can
//! answer bad input at once and run the identification later, in the
//! background, with progress ([`PreparedIdentification::run`]).

use gecaro_calib::Observer;
use gecaro_calib::identification::{
    ErrorSummary, Identification, IdentificationOptions, ObservationErrors, evaluate_errors,
    identify,
};
use gecaro_calib::study::DataColumn;
use gecaro_calib::validation::{
    CrossValidation, Folds, ModelScore, compare_models, cross_validate_by,
};
use gecaro_io::RobotFile;
use gecaro_report::{
    ReportInput, errors_per_configuration_svg, html_report, identification_svgs,
    labelled_error_histograms_svg, observation_names,
};
use serde::{Deserialize, Serialize};

use crate::documents::{CrossValidationJson, IdentificationJson, ModelScoreJson, RegistrationJson};
use crate::error::{AppError, ErrorKind, Part};
use crate::evaluation_frame::{self, RegisterShare};
use crate::files::Files;
use crate::limits::MAX_FOLDS;
use crate::measurements::{Data, Loaded, Measurements, Note, Unknown};
use crate::model_advice::{ModelAdvice, ModelCheck};
use crate::robot_files::calibrated_robot_file;
use crate::settings::{FitSettings, model};
use crate::sources::RobotSource;

/// An identification; see the module docs.
#[derive(Clone, Debug, Default, Deserialize)]
pub struct IdentifyRequest {
    /// What is identified from what.
    #[serde(flatten)]
    pub measurements: Measurements,
    /// How.
    #[serde(flatten)]
    pub settings: FitSettings,
    /// Also cross-validate, with this many folds (2–20).
    pub cv: Option<usize>,
    /// Seed of the folds (default 1).
    pub seed: Option<u64>,
    /// How the folds hold observations out: `random` (default:
    /// interpolation) or `regions` (the ends of each joint's range:
    /// extrapolation).
    pub folds_by: Option<String>,
    /// Compare the model with the next smaller and larger ones by region
    /// folds, and suggest one that predicts better ([`ModelAdvice`]):
    /// `true` always, `false` never, unset (default) when the data are small
    /// enough for it to be cheap (at most [`crate::CHEAP_EQUATIONS`]).
    pub check_model: Option<bool>,
    #[serde(flatten)]
    unknown: Unknown,
}

/// An identification ready to run: its input read and checked.
#[derive(Clone, Debug)]
pub struct PreparedIdentification {
    /// The robot, study and notes.
    pub loaded: Loaded,
    /// The library's settings.
    pub options: IdentificationOptions,
    /// The folds of the cross-validation, if asked for.
    pub cross_validation: Option<Folds>,
    /// The comparison of the model with its neighbours, when it runs
    /// ([`IdentifyRequest::check_model`]).
    pub check_model: Option<ModelCheck>,
}

/// The folds `folds_by` names (`default` when not given), `count` of them,
/// with `seed`.
fn folds_by(
    folds_by: Option<&str>,
    default: &str,
    count: usize,
    seed: u64,
) -> Result<Folds, AppError> {
    let name = folds_by.map_or(default, str::trim);
    Folds::from_name(name, folds(count)?, seed).ok_or_else(|| {
        AppError::setting_value(
            "folds_by",
            name,
            format!("one of {}", Folds::NAMES.join(", ")),
        )
    })
}

/// Checks a number of folds.
fn folds(folds: usize) -> Result<usize, AppError> {
    if (2..=MAX_FOLDS).contains(&folds) {
        Ok(folds)
    } else {
        Err(AppError::setting_value(
            "cv",
            folds,
            format!("between 2 and {MAX_FOLDS} folds"),
        ))
    }
}

impl IdentifyRequest {
    /// A request on `measurements` with default settings.
    pub fn new(measurements: Measurements) -> Self {
        IdentifyRequest {
            measurements,
            ..IdentifyRequest::default()
        }
    }

    /// Reads the robot and data, checks them, and parses the settings.
    ///
    /// # Errors
    /// Bad input or settings (see [`Measurements::load`], [`FitSettings::options`]).
    pub fn prepare(&self, files: &dyn Files) -> Result<PreparedIdentification, AppError> {
        self.unknown.check()?;
        let cross_validation = match self.cv {
            Some(count) => Some(folds_by(
                self.folds_by.as_deref(),
                "random",
                count,
                self.seed.unwrap_or(gecaro_calib::simulation::DEFAULT_SEED),
            )?),
            None => None,
        };
        let mut loaded = self.measurements.load(files, Data::Required)?;
        if crate::settings::names_elastic(loaded.model(self.settings.model.as_deref())) {
            loaded.make_elastic()?;
        }
        loaded.study.check(&loaded.robot.robot)?;
        let options = self.settings.options(&loaded, files)?;
        let check_model = match self.check_model {
            Some(asked) => asked,
            None => crate::model_advice::is_cheap(&loaded.study),
        }
        .then(|| {
            Ok::<_, AppError>(ModelCheck {
                model: loaded
                    .model(self.settings.model.as_deref())
                    .unwrap_or("full")
                    .trim()
                    .to_owned(),
                given: self.settings.given_priority(&loaded, files)?,
                asked: self.check_model == Some(true),
            })
        })
        .transpose()?;
        Ok(PreparedIdentification {
            loaded,
            options,
            cross_validation,
            check_model,
        })
    }

    /// [`prepare`](Self::prepare) and [`run`](PreparedIdentification::run).
    ///
    /// # Errors
    /// As both.
    pub fn run(
        &self,
        files: &dyn Files,
        observer: &mut dyn Observer,
    ) -> Result<Identified, AppError> {
        self.prepare(files)?.run(observer)
    }
}

/// Bytes a streamed identification holds per row of its system: the
/// residual, kind and observation (13 bytes) in the current and the trial
/// iterate, the per-observation statistics and errors of the verdict, and
/// the allocator's slack.
const STREAMED_BYTES_PER_ROW: usize = 160;

impl PreparedIdentification {
    /// About how many bytes the identification holds at its peak, on the
    /// safe side; a server admits jobs by it. A held system: five
    /// observation matrices (W, its QR, the weighted copies and the second
    /// pass's), `rows × unknowns` numbers each (all the robot's parameters,
    /// an upper bound of the base set). A streamed one (tall, every set's
    /// configurations independent: [`IdentificationOptions::streamed_rows`](gecaro_calib::identification::IdentificationOptions))
    /// holds no W, only `STREAMED_BYTES_PER_ROW` a row. And the samples'
    /// columns ([`Samples::bytes`](gecaro_calib::study::Samples::bytes)).
    /// Measured: 200,000 Stanford position configurations held peaked at
    /// 720 MB (this says 1.0 GB; systems are streamed from 1,000 rows now);
    /// 10⁶ streamed at 218–223 MB (this says 560 MB).
    pub fn memory_need(&self) -> usize {
        let study = &self.loaded.study;
        let rows: usize = study
            .sets
            .iter()
            .map(|set| set.method.row_count(set.samples.as_slice()))
            .sum();
        let unknowns = self.loaded.robot.robot.parameters().len()
            + study.frame_unknowns()
            + study
                .sets
                .iter()
                .map(|set| set.method.auxiliary_names().len())
                .sum::<usize>();
        let samples: usize = study.sets.iter().map(|set| set.samples.bytes()).sum();
        let per_row = if study.is_streamed(self.options.streamed_rows) {
            STREAMED_BYTES_PER_ROW
        } else {
            unknowns.saturating_mul(5 * std::mem::size_of::<f64>())
        };
        rows.saturating_mul(per_row).saturating_add(samples)
    }

    /// The K-fold cross-validation asked for (two folds when none was);
    /// `observer` hears of every fold.
    ///
    /// # Errors
    /// A fold that cannot be identified, an interruption.
    pub fn cross_validate(&self, observer: &mut dyn Observer) -> Result<CrossValidation, AppError> {
        let folds = self
            .cross_validation
            .unwrap_or(Folds::Random { count: 2, seed: 1 });
        Ok(cross_validate_by(
            &self.loaded.robot.robot,
            &self.loaded.study,
            &self.options,
            folds,
            observer,
        )?)
    }

    /// Identifies, then cross-validates if asked; `observer` hears of every
    /// iterate of the identification and of every fold (so that it can stop
    /// the cross-validation too).
    ///
    /// # Errors
    /// Too few equations, numerical failures, an interruption.
    pub fn run(mut self, observer: &mut dyn Observer) -> Result<Identified, AppError> {
        let Loaded { robot, study, .. } = &self.loaded;
        let result = identify(&robot.robot, study, &self.options, observer)?;
        if let Some(masses) = &self.options.masses
            && result.verdict.outcome.solved()
        {
            // The data with the calibrated robot's loads, as the
            // identification followed them there (docs/elastic.md).
            self.loaded.study =
                gecaro_calib::elastic::weighed_at(&self.loaded.study, &result.calibrated, masses)?
                    .0;
        }
        let cross_validation = match self.cross_validation {
            Some(_) => Some(self.cross_validate(observer)?),
            None => None,
        };
        // Another model that would do better, with its figures.
        let mut advice = Vec::new();
        if result.verdict.outcome.solved() {
            advice.extend(crate::model_advice::elastic_advice(
                &self.loaded,
                &self.options,
                &result,
                observer,
            )?);
            if let Some(check) = &self.check_model {
                advice.extend(crate::model_advice::neighbour_advice(
                    &self.loaded,
                    &self.options,
                    check,
                    observer,
                )?);
            }
        }
        Ok(Identified {
            loaded: self.loaded,
            options: self.options,
            result,
            cross_validation,
            advice,
        })
    }
}

/// A finished identification with what produced it.
#[derive(Clone, Debug)]
pub struct Identified {
    /// The robot, study and notes it ran on.
    pub loaded: Loaded,
    /// Its settings.
    pub options: IdentificationOptions,
    /// The library's result.
    pub result: Identification,
    /// The cross-validation, if asked for.
    pub cross_validation: Option<CrossValidation>,
    /// Other models that would do better, with their figures.
    pub advice: Vec<ModelAdvice>,
}

/// The plots of an identification, as SVG.
#[derive(Clone, Debug, Serialize)]
pub struct Plots {
    /// Residual RMS per iteration.
    pub convergence: String,
    /// Errors before and after, as histograms.
    pub errors_histogram: String,
    /// Errors before and after, per configuration, outliers ringed.
    pub errors_per_configuration: String,
}

impl Identified {
    /// The advice of other models as notes, in each front end's words.
    pub fn advice_notes(&self) -> Vec<Note> {
        self.advice.iter().map(ModelAdvice::note).collect()
    }

    /// The JSON document (`gecaro identify --json`, the web page's result,
    /// Python's `to_dict()`).
    pub fn document(&self) -> IdentificationJson {
        let mut document = IdentificationJson::new(&self.loaded.study, &self.result);
        document.cross_validation = self.cross_validation.as_ref().map(CrossValidationJson::new);
        document.registration = Some(self.registration());
        document.model_advice = self.advice.clone();
        document
    }

    /// Where the calibrated robot puts its base and its tool, against the
    /// robot file (the document's `registration`).
    pub fn registration(&self) -> RegistrationJson {
        RegistrationJson::of(&self.loaded.robot.robot, &self.result.calibrated)
    }

    /// The calibrated robot as a robot file.
    pub fn calibrated(&self) -> RobotFile {
        calibrated_robot_file(
            &self.loaded.robot,
            &self.loaded.study,
            &self.result,
            &self.loaded.label,
        )
    }

    /// The calibrated robot's file text, read back before it is written:
    /// an iteration that ran away (a value beyond what a robot file holds,
    /// which the verdict names implausible) writes no file gecaro could not
    /// read.
    ///
    /// # Errors
    /// [`ErrorKind::Untrusted`] naming the value the file would refuse.
    pub fn calibrated_text(&self) -> Result<String, AppError> {
        let text = gecaro_io::robot_file_text(
            &self.calibrated(),
            std::path::Path::new("calibrated robot"),
        )
        .map_err(|error| {
            AppError::plain(
                ErrorKind::Untrusted,
                format!("the calibrated robot was not written, no robot file holds it: {error}"),
            )
        })?;
        Ok(text)
    }

    /// Whether the result is a solution: the iteration converged, on data
    /// that determine it (see the verdict).
    pub fn converged(&self) -> bool {
        self.result.failure().is_none()
    }

    /// Why the result is no solution: the iteration did not converge, or
    /// the data are degenerate.
    pub fn failure(&self) -> Option<AppError> {
        self.result
            .failure()
            .map(|message| AppError::plain(ErrorKind::NotConverged, message))
    }

    /// The verdict's objection to a solution it does not trust: residuals
    /// beyond or far below the stated noise, implausible values, data that
    /// do not determine the robot, a scale or tool not measured.
    pub fn misfit(&self) -> Option<AppError> {
        let outcome = self.result.verdict.outcome;
        (outcome.solved() && !outcome.trusted()).then(|| {
            AppError::plain(
                ErrorKind::Untrusted,
                format!("the identification {}", self.result.verdict.summary),
            )
        })
    }

    /// Every observation's error before and after, located in its file, as
    /// CSV text (columns in [`residuals_csv`](crate::residuals_csv)).
    ///
    /// # Errors
    /// Only if the text cannot be written.
    pub fn residuals_csv(&self) -> Result<String, AppError> {
        self.residuals_csv_with(self.point_deviations().as_deref())
    }

    /// The errors set by set and station by station (`identification.sets`
    /// and `.stations` of the document; both empty for a single set).
    pub fn group_errors(&self) -> (Vec<crate::GroupErrorsJson>, Vec<crate::GroupErrorsJson>) {
        crate::set_errors::group_errors(&self.loaded.study, &self.result)
    }

    /// [`residuals_csv`](Self::residuals_csv) with the deviations already
    /// taken ([`point_deviations`](Self::point_deviations)).
    ///
    /// # Errors
    /// As [`residuals_csv`](Self::residuals_csv).
    pub fn residuals_csv_with(
        &self,
        deviations: Option<&[crate::PointDeviation]>,
    ) -> Result<String, AppError> {
        crate::residuals::residuals_csv(&self.loaded.study, &self.result, deviations)
    }

    /// The deviation of every measured point from the calibrated robot's
    /// ([`point_deviations`](crate::point_deviations)), or `None` where the
    /// study measures no points or the robot is elastic.
    pub fn point_deviations(&self) -> Option<Vec<crate::PointDeviation>> {
        crate::deviations::point_deviations(
            &self.loaded.robot.robot,
            &self.loaded.study,
            &self.result,
        )
    }

    /// The three plots (lengths in millimetres).
    ///
    /// # Errors
    /// A plot that cannot be drawn.
    pub fn plots(&self) -> Result<Plots, AppError> {
        let svgs = identification_svgs(&self.loaded.study, &self.result)?;
        Ok(Plots {
            convergence: svgs.convergence,
            errors_histogram: svgs.errors_histogram,
            errors_per_configuration: svgs.errors_per_configuration,
        })
    }

    /// The self-contained HTML report; `command` says what produced it.
    ///
    /// # Errors
    /// A plot that cannot be drawn.
    pub fn report(&self, command: &str) -> Result<String, AppError> {
        Ok(html_report(&ReportInput {
            robot: &self.loaded.robot.robot,
            study: &self.loaded.study,
            identification: &self.result,
            command,
        })?)
    }
}

/// Candidate models ranked by their cross-validated held-out error.
#[derive(Clone, Debug, Deserialize)]
pub struct CompareModelsRequest {
    /// The measurements.
    #[serde(flatten)]
    pub measurements: Measurements,
    /// The settings of every fit (the model excepted).
    #[serde(flatten)]
    pub settings: FitSettings,
    /// The candidates: `offsets`, `kinematic`, `no-gains`, `no-beta`, `full`
    /// or priority files.
    pub models: Vec<String>,
    /// Folds of the cross-validation (2–20).
    pub cv: usize,
    /// Seed of the folds (the same for every model).
    pub seed: Option<u64>,
    /// How the folds hold observations out: `regions` (default: the ends
    /// of each joint's range, so that what only interpolates loses) or
    /// `random` (interpolation).
    pub folds_by: Option<String>,
    #[serde(flatten)]
    unknown: Unknown,
}

/// The models, best first, with what each adds to the next smaller one.
#[derive(Clone, Debug)]
pub struct ModelComparison {
    /// The robot, study and notes.
    pub loaded: Loaded,
    /// Each model's cross-validation, best first.
    pub scores: Vec<ModelScore>,
    /// For each score: what it identifies beyond the next smaller model, or
    /// which model it identifies the same parameters as.
    pub adds: Vec<Vec<String>>,
    /// The folds every model was judged on.
    pub folds: Folds,
}

impl CompareModelsRequest {
    /// A comparison of `models` on `measurements` by `cv` folds.
    pub fn new(measurements: Measurements, models: Vec<String>, cv: usize) -> Self {
        CompareModelsRequest {
            measurements,
            settings: FitSettings::default(),
            models,
            cv,
            seed: None,
            folds_by: None,
            unknown: Unknown::default(),
        }
    }

    /// Cross-validates every model; `observer` hears of every fold.
    ///
    /// # Errors
    /// A model given also as `model`, no model, bad input or settings, or a
    /// fold that cannot be identified.
    pub fn run(
        &self,
        files: &dyn Files,
        observer: &mut dyn Observer,
    ) -> Result<ModelComparison, AppError> {
        self.unknown.check()?;
        if self.settings.model.as_deref().is_some_and(|m| m != "full") {
            return Err(AppError::new(
                ErrorKind::Usage,
                vec![
                    Part::Setting("model".into()),
                    Part::Text(": a comparison takes its candidates from ".into()),
                    Part::Setting("models".into()),
                    Part::Text(", not ".into()),
                    Part::Setting("model".into()),
                ],
            )
            .with_help(vec![
                Part::Text("for example: ".into()),
                Part::Setting("models".into()),
                Part::Text(" kinematic,no-gains,full".into()),
            ]));
        }
        let folds = folds_by(
            self.folds_by.as_deref(),
            "regions",
            self.cv,
            self.seed.unwrap_or(gecaro_calib::simulation::DEFAULT_SEED),
        )?;
        let mut loaded = self.measurements.load(files, Data::Required)?;
        // The candidates are the models compared, not the study's.
        loaded.model = None;
        // An elastic candidate needs the robot elastic; the others leave its
        // compliances (0) alone.
        if self
            .models
            .iter()
            .any(|name| crate::settings::names_elastic(Some(name)))
        {
            loaded.make_elastic()?;
        }
        let options = self.settings.options(&loaded, files)?;
        let robot = &loaded.robot.robot;
        let models = self
            .models
            .iter()
            .map(|name| name.trim())
            .filter(|name| !name.is_empty())
            .map(|name| model(name, robot, files))
            .collect::<Result<Vec<_>, AppError>>()?;
        if models.is_empty() {
            return Err(AppError::setting("models", "no model given"));
        }
        let scores = compare_models(robot, &loaded.study, &options, &models, folds, observer)?;
        let adds = additions(&scores);
        Ok(ModelComparison {
            loaded,
            scores,
            adds,
            folds,
        })
    }
}

impl ModelComparison {
    /// The JSON document, best model first.
    pub fn documents(&self) -> Vec<ModelScoreJson> {
        self.scores
            .iter()
            .zip(&self.adds)
            .map(|(score, adds)| ModelScoreJson {
                model: score.model.to_string(),
                parameters: score.validation.parameters.clone(),
                adds: adds.clone(),
                cross_validation: CrossValidationJson::new(&score.validation),
            })
            .collect()
    }
}

/// What each model identifies beyond the next smaller one (by parameter
/// count), or which model it identifies the same parameters as.
fn additions(scores: &[ModelScore]) -> Vec<Vec<String>> {
    let parameters = |index: usize| &scores[index].validation.parameters;
    let mut by_size: Vec<usize> = (0..scores.len()).collect();
    by_size.sort_by_key(|index| parameters(*index).len());
    let mut adds = vec![Vec::new(); scores.len()];
    for (position, &index) in by_size.iter().enumerate() {
        let earlier = &by_size[..position];
        if let Some(same) = earlier.iter().find(|other| {
            parameters(**other).len() == parameters(index).len()
                && parameters(index)
                    .iter()
                    .all(|name| parameters(**other).contains(name))
        }) {
            adds[index] = vec![format!("(the same parameters as {})", scores[*same].model)];
        } else if let Some(smaller) = earlier
            .iter()
            .rev()
            .find(|other| parameters(**other).len() < parameters(index).len())
        {
            adds[index] = parameters(index)
                .iter()
                .filter(|name| !parameters(*smaller).contains(name))
                .cloned()
                .collect();
        }
    }
    adds
}

/// The errors of a (calibrated) robot on measurements, ideally not those it
/// was identified from.
#[derive(Clone, Debug, Default, Deserialize)]
pub struct EvaluateRequest {
    /// The robot and its measurements.
    #[serde(flatten)]
    pub measurements: Measurements,
    /// A second robot evaluated on the same data (the page's calibrated
    /// robot beside the table's): "before" is the first, "after" this one.
    pub compared: Option<RobotSource>,
    /// Register the measurement frame on this share of the rows (`all`,
    /// `30%`) and judge the robot on the others (`crate::evaluation_frame`).
    #[serde(default)]
    pub register: Option<String>,
    #[serde(flatten)]
    unknown: Unknown,
}

/// The errors of a robot on measurements.
#[derive(Clone, Debug)]
pub struct Evaluation {
    /// The robot, study and notes.
    pub loaded: Loaded,
    /// Error statistics per configuration (or pair).
    pub summary: ErrorSummary,
    /// The error of every observation: position-like (m), orientation (rad).
    pub errors: ObservationErrors,
    /// The compared robot's statistics and errors, when one was given.
    pub compared: Option<(ErrorSummary, ObservationErrors)>,
}

impl EvaluateRequest {
    /// A request on `measurements`.
    pub fn new(measurements: Measurements) -> Self {
        EvaluateRequest {
            measurements,
            compared: None,
            register: None,
            unknown: Unknown::default(),
        }
    }

    /// Evaluates the robot (and the compared one) on the data.
    ///
    /// # Errors
    /// Bad input, or auxiliary unknowns that cannot be initialised.
    pub fn run(&self, files: &dyn Files) -> Result<Evaluation, AppError> {
        self.unknown.check()?;
        let mut loaded = self.measurements.load_evaluated(files)?;
        if !loaded.study.frames.is_empty() {
            loaded.notes.push(Note::plain(
                "the study's tools and stations are taken where it states them: to judge the \
                 robot alone, state the identified ones (identify prints them as a study states \
                 them)",
            ));
        }
        if let Some(share) = &self.register {
            let share = RegisterShare::parse(share)?;
            let (registered, note) =
                evaluation_frame::register(&loaded.robot.robot, &mut loaded.study, share)?;
            loaded.robot.robot = registered;
            loaded.notes.push(note);
        }
        let (summary, errors) = evaluate_errors(&loaded.robot.robot, &loaded.study)?;
        if let Some(note) = outside_region_note(&loaded, &errors)? {
            loaded.notes.push(note);
        }
        if self.register.is_none()
            && summary.rms.is_finite()
            && loaded
                .study
                .sets
                .iter()
                .all(|set| set.method.data_columns().contains(&DataColumn::Position))
            && let Some(note) = evaluation_frame::frame_mismatch(
                summary.rms,
                evaluation_frame::reach(&loaded.robot.robot, &loaded.study),
            )
        {
            loaded.notes.push(note);
        }
        let compared = match &self.compared {
            None => None,
            Some(source) => {
                // An elastic robot yields to the loads of its own masses.
                let mut compared = loaded.clone();
                compared.robot = source.load(files)?;
                compared.weigh()?;
                Some(evaluate_errors(&compared.robot.robot, &compared.study)?)
            }
        };
        Ok(Evaluation {
            loaded,
            summary,
            errors,
            compared,
        })
    }
}

/// A warning when configurations of the data lie outside the region the
/// robot's calibration measured (a calibrated robot that holds there only,
/// [`RobotFile::measured_region`]): how many, and, where every observation
/// is one configuration, the errors within and outside.
fn outside_region_note(
    loaded: &Loaded,
    errors: &ObservationErrors,
) -> Result<Option<Note>, AppError> {
    let robot = &loaded.robot.robot;
    let Some(region) = &loaded.robot.measured_region else {
        return Ok(None);
    };
    let region = region.widened(gecaro_core::MEASURED_MARGIN);
    let mut joint_positions = vec![0.0; robot.joint_count()];
    let mut outside = Vec::new();
    let mut total = 0;
    for set in &loaded.study.sets {
        for sample in set.samples.as_slice().iter() {
            robot
                .joint_positions_into(sample.motor_positions(), &mut joint_positions)
                .map_err(gecaro_calib::Error::from)?;
            outside.push(!region.contains(&joint_positions));
            total += 1;
        }
    }
    let count = outside.iter().filter(|o| **o).count();
    if count == 0 {
        return Ok(None);
    }
    let mut text = format!(
        "{count} of {total} configurations lie outside the joint ranges this robot's calibration \
         measured (its file's `measured` ranges, and a tenth of each beyond): the calibrated model \
         is extrapolated there"
    );
    if errors.len() == total {
        let rms = |keep: bool| {
            let (sum, n) = errors
                .lengths
                .iter()
                .zip(&outside)
                .filter(|(_, o)| **o != keep)
                .fold((0.0, 0usize), |(sum, n), (e, _)| (sum + e * e, n + 1));
            (n > 0).then(|| (sum / n as f64).sqrt() * 1e3)
        };
        if let (Some(inside), Some(beyond)) = (rms(true), rms(false)) {
            text.push_str(&format!(
                " (error RMS {inside:.4} mm within the ranges, {beyond:.4} mm outside)"
            ));
        }
    }
    Ok(Some(Note::warning(text)))
}

impl Evaluation {
    /// How the compared robot fares against the robot, when one was given.
    pub fn comparison(&self) -> Option<crate::documents::ComparisonJson> {
        self.compared
            .as_ref()
            .map(|(compared, _)| crate::documents::ComparisonJson::of(&self.summary, compared))
    }

    /// The errors as plots (mm): histograms and per configuration, the
    /// robot's as "before" and the compared robot's as "after" (the robot's
    /// own on both sides without one).
    ///
    /// # Errors
    /// When a plot cannot be drawn.
    pub fn plots(&self) -> Result<EvaluationPlots, AppError> {
        let millimetres = |errors: &ObservationErrors| -> Vec<f64> {
            errors.lengths.iter().map(|length| length * 1e3).collect()
        };
        let before = millimetres(&self.errors);
        let after = self
            .compared
            .as_ref()
            .map_or_else(|| before.clone(), |(_, errors)| millimetres(errors));
        // The robot evaluated is whatever it is (nominal or not): named as
        // "the robot"; alone, one panel, not the same errors twice.
        let compared = self
            .compared
            .as_ref()
            .map(|_| (after.as_slice(), "the compared robot (calibrated)"));
        Ok(EvaluationPlots {
            errors_histogram: labelled_error_histograms_svg(
                (&before, "the robot evaluated"),
                compared,
                "mm",
            )?,
            errors_per_configuration: errors_per_configuration_svg(
                &before,
                &after,
                &[],
                &observation_names(&self.loaded.study),
                "mm",
            )?,
        })
    }
}

/// The plots of an evaluation, as SVG.
#[derive(Clone, Debug, Serialize)]
pub struct EvaluationPlots {
    /// Errors of both robots, as histograms.
    pub errors_histogram: String,
    /// Errors of both robots, per configuration.
    pub errors_per_configuration: String,
}
