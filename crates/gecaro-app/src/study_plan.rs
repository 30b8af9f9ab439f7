//! A whole cell planned as one design ([`PlanStudyRequest`]): a candidate
//! pool drawn for every set of a study (through its reflector and station),
//! the configurations of all sets chosen together, D-optimal
//! ([`gecaro_calib::planning::plan_study`]), and written as a planned study:
//! one configuration file per set beside a copy of the study file whose sets
//! name them. `predict --study` reads it before it is measured; filled with
//! the measurements, `identify --study` calibrates from it.

use std::path::{Path, PathBuf};

use gecaro_calib::frames::measuring_robot;
use gecaro_calib::planning::{StudyPlan, plan_study};
use gecaro_calib::simulation::Sampler;
use gecaro_calib::study::{DataColumn, Samples};
use gecaro_calib::{Observer, report_phase};
use gecaro_io::{DataFormat, StandardDeviation};
use serde::{Deserialize, Serialize};

use crate::cell::{CellSpec, refuse_misses};
use crate::error::{AppError, ErrorKind};
use crate::files::Files;
use crate::limits::MAX_GENERATE;
use crate::measurements::{Data, Loaded, Measurements, StudySource, Unknown};
use crate::output::Output;
use crate::sources::{DataFormatSpec, RobotSource};

/// A cell to plan; see the module docs.
#[derive(Clone, Debug, Deserialize)]
pub struct PlanStudyRequest {
    /// The study file (its robot, sets, σ, named frames).
    pub study: StudySource,
    /// The robot of a stated study that names none (the web page's table).
    /// A planned study written for it names it, so it must be a name then
    /// (a robot file of the folder, or a ready robot).
    pub robot: Option<RobotSource>,
    /// Configurations to choose in all.
    pub count: usize,
    /// Candidates drawn per set (default 20 × count ÷ sets, at least 200).
    pub pool: Option<usize>,
    /// Seed of the pools and of the random comparison (default 1).
    pub seed: Option<u64>,
    /// The cell: floor, and the incidence and clearance of each set's
    /// reflector seen from its station (a set's named station, else the
    /// cell's `station`: the tracker that measures in the world frame).
    #[serde(default)]
    pub cell: CellSpec,
    /// Units, separator and decimal mark of the sets' files written (a
    /// teach pendant's degrees): each file states its units in a units
    /// line, and the planned study's sets say them.
    #[serde(default)]
    pub format: DataFormatSpec,
    /// Where the output is written (`save_as`) and whether it may replace a
    /// file (`overwrite`).
    #[serde(flatten)]
    pub output: Output,
    #[serde(flatten)]
    unknown: Unknown,
}

/// A request checked and its study read ([`PlanStudyRequest::prepare`]):
/// the study loaded, the candidates per set, the planned study's name and
/// its sets' file names when it is saved. [`run`](Self::run) plans it.
#[derive(Debug)]
pub struct PreparedStudyPlan {
    request: PlanStudyRequest,
    loaded: Loaded,
    pool: usize,
    outputs: Option<(String, Vec<String>)>,
}

/// A planned cell.
#[derive(Clone, Debug)]
pub struct PlannedStudy {
    /// The study planned for.
    pub loaded: Loaded,
    /// The plan: each set's configurations.
    pub plan: StudyPlan,
    /// Candidates drawn per set.
    pub pool: usize,
    /// The files written: the planned study, then each set's file.
    pub saved: Vec<PathBuf>,
    /// How the sets' files are written (units, separator, decimal mark).
    pub format: DataFormat,
}

impl PlanStudyRequest {
    /// A plan of `count` configurations for `study`.
    pub fn new(study: StudySource, count: usize) -> Self {
        PlanStudyRequest {
            study,
            robot: None,
            count,
            pool: None,
            seed: None,
            cell: CellSpec::default(),
            format: DataFormatSpec::default(),
            output: Output::default(),
            unknown: Unknown::default(),
        }
    }

    /// Checks the request and reads the study and the files it names, before
    /// any work: the settings, the files it would write (a front end answers
    /// these at once, then runs the plan as a job).
    ///
    /// # Errors
    /// As [`run`](Self::run)'s, but those only the work finds.
    pub fn prepare(&self, files: &dyn Files) -> Result<PreparedStudyPlan, AppError> {
        self.unknown.check()?;
        if !(1..=MAX_GENERATE).contains(&self.count) {
            return Err(AppError::setting_value(
                "count",
                self.count,
                format!("between 1 and {MAX_GENERATE} configurations"),
            ));
        }
        let loaded = Measurements {
            robot: self.robot.clone(),
            study: Some(self.study.clone()),
            ..Measurements::default()
        }
        // The sets' files are what the plan writes: they need not exist.
        .load(files, Data::Unmeasured)?;
        let written = self.format.format()?;
        if !written.columns.is_empty() {
            return Err(AppError::setting(
                "columns",
                "a planned study's set files are written in gecaro's column names",
            ));
        }
        let sets = loaded.study.sets.len();
        let pool = self
            .pool
            .unwrap_or_else(|| (20 * self.count / sets.max(1)).max(200));
        if !(1..=MAX_GENERATE).contains(&pool) {
            return Err(AppError::setting_value(
                "pool",
                pool,
                format!("between 1 and {MAX_GENERATE} candidates per set"),
            ));
        }
        let outputs = match &self.output.save_as {
            Some(name) => {
                if let StudySource::Loaded(_) = &self.study {
                    return Err(AppError::setting(
                        "save_as",
                        "a planned study is written for a study file or a stated study",
                    ));
                }
                if self.named_robot().is_none() {
                    return Err(AppError::setting(
                        "save_as",
                        "a planned study names its robot: give the robot by its file in the \
                         folder or a ready robot's name, not as a table",
                    ));
                }
                let outputs = set_file_names(name, sets);
                files.check_output(name, "toml", self.output.overwrite)?;
                for output in &outputs {
                    files.check_output(output, "csv", self.output.overwrite)?;
                }
                Some((name.clone(), outputs))
            }
            None => None,
        };
        Ok(PreparedStudyPlan {
            request: self.clone(),
            loaded,
            pool,
            outputs,
        })
    }

    /// Draws the pools, plans, and writes the planned study if asked (every
    /// output checked before any work, written after it).
    ///
    /// # Errors
    /// Files that cannot be read or written, bad counts, a plan that does
    /// not determine the cell, an interruption.
    pub fn run(
        &self,
        files: &dyn Files,
        observer: &mut dyn Observer,
    ) -> Result<PlannedStudy, AppError> {
        self.prepare(files)?.run(files, observer)
    }
}

impl PreparedStudyPlan {
    /// Where the planned study is written, if it is.
    pub fn save_as(&self) -> Option<&str> {
        self.request.output.save_as.as_deref()
    }

    /// About the bytes the work holds at its largest: every set's
    /// candidates' observation rows (six per configuration at most, about
    /// sixty unknowns, twice over).
    pub fn memory_need(&self) -> usize {
        self.pool
            .saturating_mul(self.loaded.study.sets.len())
            .saturating_mul(6 * 60 * 2 * std::mem::size_of::<f64>())
    }

    /// Draws the pools, plans, and writes the planned study if asked.
    ///
    /// # Errors
    /// Files that cannot be written, a plan that does not determine the
    /// cell, an interruption.
    pub fn run(
        self,
        files: &dyn Files,
        observer: &mut dyn Observer,
    ) -> Result<PlannedStudy, AppError> {
        let PreparedStudyPlan {
            request,
            loaded,
            pool,
            outputs,
        } = self;
        let robot = &loaded.robot.robot;
        let seed = request
            .seed
            .unwrap_or(gecaro_calib::simulation::DEFAULT_SEED);
        let mut sampler = Sampler::new(seed);
        let mut candidates = loaded.study.clone();
        for set in &mut candidates.sets {
            let frame = |index: Option<usize>| index.map(|i| &loaded.study.frames[i]);
            // The reflector on the robot, in the world frame: the cell
            // (floor, and the line of sight to the set's station) is judged
            // there; configurations are what the pool holds.
            let with_tool = measuring_robot(robot, frame(set.tool), None)?;
            let station = frame(set.station).map(|station| station.pose.translation.vector);
            report_phase(
                observer,
                &format!("drawing the candidates of {}", set.label),
            )?;
            let mut drawing = sampler
                .clone()
                .with_cell(request.cell.cell_seen_from(station)?);
            set.samples = set
                .method
                .sensor()
                .generate(&with_tool, pool, 0.0, &mut drawing, observer)?
                .into();
            refuse_misses(
                drawing.cell_misses(),
                &format!("candidate(s) of {}", set.label),
            )?;
            sampler = drawing;
        }
        let priority = loaded.priority.clone().unwrap_or_else(|| robot.priority());
        report_phase(observer, "choosing the configurations")?;
        let plan = plan_study(robot, &candidates, request.count, &priority, seed, observer)?;
        let mut planned = PlannedStudy {
            loaded,
            plan,
            pool,
            saved: Vec::new(),
            format: request.format.format()?,
        };
        // Written last: a failed request leaves no file.
        if let Some((name, outputs)) = outputs {
            let text = planned_study_text(
                files,
                &request.study,
                request.named_robot(),
                &name,
                (&planned.loaded, &planned.format),
                &outputs,
            )?;
            // The study and its set files together, or none of them: a
            // planned study never names files it did not write (issue 75).
            let set_files = planned.set_files();
            let mut all: Vec<(&str, &str, &[u8])> = vec![(&name, "toml", text.as_bytes())];
            all.extend(
                set_files
                    .iter()
                    .zip(&outputs)
                    .map(|(text, output)| (output.as_str(), "csv", text.as_bytes())),
            );
            planned.saved = files.write_all(&all, request.output.overwrite)?;
        }
        Ok(planned)
    }
}

impl PlanStudyRequest {
    /// The name of the robot a planned study names: the study's own, or the
    /// request's when it is a name; `None` for a stated study given a
    /// robot's contents (a planned study cannot name those).
    fn named_robot(&self) -> Option<Option<&str>> {
        match (&self.study, &self.robot) {
            (StudySource::Spec(spec), Some(RobotSource::Named(name))) if spec.robot.is_none() => {
                Some(Some(name))
            }
            (StudySource::Spec(spec), Some(_)) if spec.robot.is_none() => None,
            _ => Some(None),
        }
    }
}

impl PlannedStudy {
    /// Every set's planned configurations as a data file's text (gecaro's
    /// column names, in the request's units with a units line where they
    /// are not metres and radians), in the study's order.
    pub fn set_files(&self) -> Vec<String> {
        let types = gecaro_io::joint_types(&self.loaded.robot.robot);
        self.loaded
            .study
            .sets
            .iter()
            .zip(&self.plan.sets)
            .map(|(set, samples)| {
                let columns = DataColumn::grouping(set.method.data_columns());
                gecaro_io::format_configurations(
                    &types,
                    &columns,
                    Samples::from(samples.as_slice()).as_slice(),
                    &self.format,
                )
            })
            .collect()
    }

    /// The JSON document (`gecaro plan --study --json`).
    pub fn document(&self) -> PlanStudyJson {
        let plan = &self.plan;
        PlanStudyJson {
            sets: self
                .loaded
                .study
                .sets
                .iter()
                .zip(&plan.sets)
                .enumerate()
                .map(|(index, (set, samples))| PlannedSetJson {
                    data: set.label.clone(),
                    method: set.method.name(),
                    configurations: samples.len(),
                    file: self
                        .saved
                        .get(index + 1)
                        .map(|path| path.display().to_string()),
                })
                .collect(),
            configurations: plan.sets.iter().map(Vec::len).sum(),
            unknowns: plan.columns.len(),
            pool: self.pool,
            log_det: plan.quality.log_det,
            random_log_det: plan.random.log_det,
            exchanges: plan.exchanges,
            output: self
                .saved
                .iter()
                .map(|path| path.display().to_string())
                .collect(),
        }
    }
}

/// One set of a planned study.
#[derive(Clone, Debug, Serialize)]
pub struct PlannedSetJson {
    /// The set's data file as the study names it.
    pub data: String,
    /// Its method.
    pub method: &'static str,
    /// Configurations planned for it.
    pub configurations: usize,
    /// The file its configurations were written to, if saved.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
}

/// `gecaro plan --study --json`.
#[derive(Clone, Debug, Serialize)]
pub struct PlanStudyJson {
    /// Every set, in the study's order.
    pub sets: Vec<PlannedSetJson>,
    /// Configurations planned in all.
    pub configurations: usize,
    /// The unknowns the design determines (base parameters and named
    /// frames' unknowns).
    pub unknowns: usize,
    /// Candidates drawn per set.
    pub pool: usize,
    /// log det(W_bᵀW_b) of the plan (D-optimal criterion).
    pub log_det: f64,
    /// The same of a random choice of as many from the same pools.
    pub random_log_det: f64,
    /// Exchanges after the greedy pass.
    pub exchanges: usize,
    /// The files written: the planned study, then each set's.
    pub output: Vec<String>,
}

/// `PLANNED_1.csv` … beside `PLANNED.toml`.
fn set_file_names(study: &str, sets: usize) -> Vec<String> {
    let path = Path::new(study);
    let stem = path
        .file_stem()
        .map_or_else(|| "planned".into(), |s| s.to_string_lossy().into_owned());
    (1..=sets)
        .map(|k| {
            path.with_file_name(format!("{stem}_{k}.csv"))
                .to_string_lossy()
                .into_owned()
        })
        .collect()
}

/// The study file `study` rewritten for the planned files: every set names
/// its file (by its name beside the planned study), read in metres and
/// radians with gecaro's column names, its σ stated with its unit; the
/// robot and the priority matrix named so that they are found from the
/// planned study's folder. Everything else (named frames, the prior, method
/// options) is kept as the study states it.
fn planned_study_text(
    files: &dyn Files,
    source: &StudySource,
    robot: Option<Option<&str>>,
    planned: &str,
    (loaded, format): (&Loaded, &DataFormat),
    outputs: &[String],
) -> Result<String, AppError> {
    let (study, mut spec) = match source {
        StudySource::File(study) => {
            let (path, text) = files.read_text(study, &["toml"])?;
            (study.as_str(), crate::StudyText::parse(text, &path)?.spec)
        }
        StudySource::Spec(spec) => {
            let mut spec = (**spec).clone();
            if let Some(Some(robot)) = robot {
                spec.robot = Some(robot.to_owned());
            }
            ("the stated study", spec)
        }
        StudySource::Loaded(_) => {
            return Err(AppError::setting(
                "save_as",
                "a planned study is written for a study file or a stated study",
            ));
        }
    };
    let from = match source {
        StudySource::File(study) => Path::new(study).parent().unwrap_or(Path::new("")),
        _ => Path::new(""),
    };
    let to = Path::new(planned).parent().unwrap_or(Path::new(""));
    if from != to {
        for name in [&mut spec.robot, &mut spec.priority].into_iter().flatten() {
            let beside = from.join(&*name);
            if beside.is_file() {
                let absolute = std::fs::canonicalize(&beside).unwrap_or(beside);
                *name = absolute.to_string_lossy().into_owned();
            }
        }
    }
    // The planned files are written as the request says, not as the
    // study's measured files are.
    spec.columns = None;
    spec.delimiter = None;
    spec.decimal_comma = None;
    for ((entry, set), output) in spec
        .measurements
        .iter_mut()
        .zip(&loaded.study.sets)
        .zip(outputs)
    {
        let file_name = Path::new(output)
            .file_name()
            .map_or_else(|| output.clone(), |n| n.to_string_lossy().into_owned());
        entry.data = crate::SetData::File(file_name);
        entry.columns = None;
        entry.delimiter = match format.delimiter {
            gecaro_io::Delimiter::Semicolon => Some("semicolon".into()),
            gecaro_io::Delimiter::Tab => Some("tab".into()),
            gecaro_io::Delimiter::Comma | gecaro_io::Delimiter::Detect => None,
        };
        entry.decimal_comma = format.decimal_comma.filter(|comma| *comma);
        entry.length_unit = Some(format.units.length.name().into());
        entry.angle_unit = Some(format.units.angle.name().into());
        entry.sigma = set
            .sigma
            .map(|sigma| StandardDeviation::WithUnit(format!("{sigma:e}m")));
        entry.sigma_rotation = set
            .sigma_rotation
            .map(|sigma| StandardDeviation::WithUnit(format!("{sigma:e}rad")));
    }
    let body = toml::to_string(&spec)
        .map_err(|error| AppError::plain(ErrorKind::Internal, error.to_string()))?;
    Ok(format!(
        "# planned by gecaro plan --study from {study}: each set's configurations in its file\n\
         # (qm in {} and {}); add the measurements to identify from it.\n{body}",
        format.units.angle.name(),
        format.units.length.name()
    ))
}
