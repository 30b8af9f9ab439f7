//! Planning before measuring (docs/planning.md) as jobs: the configurations
//! to measure, chosen from a pool by a criterion ([`PlanRequest`]); how many
//! are enough (its accuracy curve); and the precision a plan will give
//! ([`PredictRequest`]).

use gecaro_calib::curve::{CurvePoint, RANDOM_DRAWS, accuracy_curve};
use gecaro_calib::identification::IdentificationOptions;
use gecaro_calib::methods::CalibrationMethod;
use gecaro_calib::planning::{
    CandidatePool, Criterion, DesignQuality, Plan, PlanRequest as Design,
};
use gecaro_calib::prediction::{
    MonteCarlo, Prediction, SimulatedRuns, monte_carlo, predict, random_test_poses,
};
use gecaro_calib::simulation::{MAX_NOISE, Sampler};
use gecaro_calib::study::{DataColumn, Samples};
use gecaro_calib::validation::Model;
use gecaro_calib::{Observer, report_phase};
use gecaro_core::Robot;
use gecaro_io::{DataFormat, RobotFile};
use serde::Deserialize;

use crate::cell::{CellSpec, refuse_misses};
use crate::documents::{CurveJson, CurvePointJson, PlanJson, PredictJson};
use crate::error::AppError;
use crate::files::Files;
use crate::limits::{MAX_CURVE_POINTS, MAX_GENERATE};
use crate::measurements::Unknown;
use crate::method::{MethodSpec, parse_name};
use crate::output::Output;
use crate::sources::{DataFormatSpec, DataSource, RobotSource};

/// The sensor's σ of an accuracy curve when none is given: 0.1 mm.
const DEFAULT_CURVE_NOISE: f64 = 1e-4;

/// Random test poses when no file gives them.
const TEST_POSES: usize = 200;

/// The poses a calibrated robot is judged at.
#[derive(Clone, Debug, Default, Deserialize)]
pub struct TestPoses {
    /// A data file's configurations; else random ones within the limits.
    pub test_poses: Option<DataSource>,
    /// Random test poses when no file is given (default 200).
    pub test_pose_count: Option<usize>,
}

impl TestPoses {
    pub(crate) fn load(
        &self,
        robot: &Robot,
        seed: u64,
        format: &DataFormat,
        files: &dyn Files,
    ) -> Result<Vec<Vec<f64>>, AppError> {
        match &self.test_poses {
            Some(source) => Ok(configurations(robot, source, &[], format, files)?
                .iter()
                .map(|sample| sample.motor_positions().to_vec())
                .collect()),
            None => {
                let count = self.test_pose_count.unwrap_or(TEST_POSES);
                if !(1..=MAX_GENERATE).contains(&count) {
                    return Err(AppError::setting_value(
                        "test_pose_count",
                        count,
                        format!("between 1 and {MAX_GENERATE}"),
                    ));
                }
                Ok(random_test_poses(robot, count, seed))
            }
        }
    }
}

/// The configurations of a data file in `format` (measurement columns, if
/// any, ignored).
fn configurations(
    robot: &Robot,
    source: &DataSource,
    columns: &[DataColumn],
    format: &DataFormat,
    files: &dyn Files,
) -> Result<Samples, AppError> {
    Ok(source
        .read(files, &gecaro_io::joint_types(robot), columns, format)?
        .samples)
}

/// A plan and/or its accuracy curve; see the module docs.
#[derive(Clone, Debug, Deserialize)]
pub struct PlanRequest {
    /// The nominal robot.
    pub robot: RobotSource,
    /// The method to plan for.
    pub method: MethodSpec,
    /// Configurations to choose (rows of the plan; sets and pairs whole).
    pub count: Option<usize>,
    /// Elastic joints: the payloads a configuration may be measured with
    /// (`"0kg"`, `"20kg,0,0,100mm"`). Each candidate is offered with each,
    /// the compliances join the columns, and the plan states the payload of
    /// each row (docs/elastic.md). Empty: a geometric plan.
    #[serde(default)]
    pub payloads: Vec<String>,
    /// `d` (default), `a`, `e`, `o4`, `o5` or `test`.
    pub criterion: Option<String>,
    /// Candidates: a data file's configurations.
    pub candidates: Option<DataSource>,
    /// Or this many generated candidates (default 20 × the largest count).
    pub pool: Option<usize>,
    /// The cell: generated candidates are configurations it can measure.
    #[serde(default)]
    pub cell: CellSpec,
    /// Seed of the pool, the test poses and the random designs (default 1).
    pub seed: Option<u64>,
    /// Configurations measured already: part of the design.
    pub keep: Option<DataSource>,
    /// Units, column names and separator of the configuration files read
    /// (candidates, kept, test poses) and of the plan written (degrees for a
    /// teach pendant).
    #[serde(default)]
    pub format: DataFormatSpec,
    /// Smallest joint-space distance between chosen configurations.
    #[serde(default)]
    pub min_distance: f64,
    /// Where the accuracy is judged (the `test` criterion and the curve).
    #[serde(flatten)]
    pub test_poses: TestPoses,
    /// Counts of the accuracy curve (none: no curve).
    #[serde(default)]
    pub curve: Vec<usize>,
    /// The sensor's σ for the curve (metres; default 0.1 mm).
    pub noise: Option<f64>,
    /// Where the output is written (`save_as`) and whether it may replace a
    /// file (`overwrite`).
    #[serde(flatten)]
    pub output: Output,
    /// Write the curve's plot (SVG) here.
    pub plot_save_as: Option<String>,
    #[serde(flatten)]
    unknown: Unknown,
}

/// A plan: the chosen configurations, and a random choice to compare with.
#[derive(Clone, Debug)]
pub struct Planned {
    /// The plan.
    pub plan: Plan,
    /// The criterion it optimises.
    pub criterion: Criterion,
    /// A random choice of as many units from the same pool.
    pub random: DesignQuality,
    /// The plan as a data file (configurations, set or pair ids).
    pub csv: String,
    /// Where it was written, if asked for.
    pub saved: Option<std::path::PathBuf>,
}

/// How the predicted accuracy falls with the number of configurations.
#[derive(Clone, Debug)]
pub struct AccuracyCurve {
    /// Per count: planned and random designs' predicted RMS position error.
    pub points: Vec<CurvePoint>,
    /// The sensor's σ.
    pub noise: f64,
    /// The plot, as SVG.
    pub svg: String,
    /// Where the plot was written, if asked for.
    pub saved: Option<std::path::PathBuf>,
}

/// What a planning request gave.
#[derive(Debug)]
pub struct Planning {
    /// The nominal robot.
    pub robot: RobotFile,
    /// The method.
    pub method: Box<dyn CalibrationMethod>,
    /// The criterion's name.
    pub criterion: &'static str,
    /// Candidates in the pool.
    pub pool: usize,
    /// Configurations kept.
    pub kept: usize,
    /// Test poses used.
    pub test_poses: usize,
    /// The plan, when a count was given.
    pub planned: Option<Planned>,
    /// The curve, when counts were given.
    pub curve: Option<AccuracyCurve>,
}

impl PlanRequest {
    /// A D-optimal plan of `count` configurations of `method` on `robot`.
    pub fn new(robot: RobotSource, method: MethodSpec, count: usize) -> Self {
        PlanRequest {
            robot,
            method,
            count: Some(count),
            payloads: Vec::new(),
            criterion: None,
            candidates: None,
            pool: None,
            cell: CellSpec::default(),
            seed: None,
            keep: None,
            format: DataFormatSpec::default(),
            min_distance: 0.0,
            test_poses: TestPoses::default(),
            curve: Vec::new(),
            noise: None,
            output: Output::default(),
            plot_save_as: None,
            unknown: Unknown::default(),
        }
    }

    /// Checks the request before any work, as [`run`](Self::run) does
    /// first: its settings, the robot, the method, the data format and the
    /// files it would write (a front end answers these at once, before it
    /// starts the work as a job). What only the work finds (a pool with too
    /// few admissible candidates, too few equations) is
    /// [`run`](Self::run)'s.
    ///
    /// # Errors
    /// Bad settings, a robot that cannot be read, outputs that exist.
    pub fn check(&self, files: &dyn Files) -> Result<(), AppError> {
        self.check_settings()?;
        self.robot.load(files)?;
        self.method.build()?;
        self.format.format()?;
        for (name, extension) in [(&self.output.save_as, "csv"), (&self.plot_save_as, "svg")] {
            if let Some(name) = name {
                files.check_output(name, extension, self.output.overwrite)?;
            }
        }
        Ok(())
    }

    /// The largest count planned: the plan's or the curve's.
    fn largest_count(&self) -> usize {
        self.curve
            .iter()
            .copied()
            .chain(self.count)
            .max()
            .unwrap_or(0)
    }

    /// The candidates drawn when the request names no candidates file.
    fn pool_size(&self) -> usize {
        self.pool
            .unwrap_or_else(|| default_pool(self.largest_count()))
    }

    /// About the bytes the work holds at its largest: the candidates'
    /// observation rows (six per configuration at most, about sixty
    /// unknowns, twice over) for the pool drawn, or the most a candidates
    /// file may hold.
    pub fn memory_need(&self) -> usize {
        let pool = match &self.candidates {
            Some(_) => MAX_GENERATE,
            None => self.pool_size(),
        };
        pool.saturating_mul(6 * 60 * 2 * std::mem::size_of::<f64>())
    }

    /// Checks the settings alone.
    fn check_settings(&self) -> Result<(), AppError> {
        self.unknown.check()?;
        if self.count.is_none() && self.curve.is_empty() {
            return Err(AppError::setting(
                "count",
                "give the number of configurations to plan, or the counts of a curve",
            ));
        }
        if self.count == Some(0) {
            return Err(AppError::setting("count", "at least one configuration"));
        }
        if let Some(count) = self.count
            && count > MAX_GENERATE
        {
            return Err(AppError::setting_value(
                "count",
                count,
                format!("at most {MAX_GENERATE} configurations"),
            ));
        }
        if let Some(too_many) = self.curve.iter().find(|count| **count > MAX_GENERATE) {
            return Err(AppError::setting_value(
                "curve",
                too_many,
                format!("counts of at most {MAX_GENERATE} configurations"),
            ));
        }
        if self.candidates.is_none() && !(1..=MAX_GENERATE).contains(&self.pool_size()) {
            return Err(AppError::setting_value(
                "pool",
                self.pool_size(),
                format!("between 1 and {MAX_GENERATE} candidates"),
            ));
        }
        let criterion = self.criterion.as_deref().map(str::trim);
        if let Some(name) = criterion
            && !Criterion::NAMES.contains(&name)
        {
            return Err(AppError::setting(
                "criterion",
                format!("`{name}` is not one of {}", Criterion::NAMES.join(", ")),
            ));
        }
        if !self.curve.is_empty() {
            if self.curve.len() > MAX_CURVE_POINTS || self.curve.contains(&0) {
                return Err(AppError::setting(
                    "curve",
                    format!("up to {MAX_CURVE_POINTS} positive counts, e.g. 10,20,40,80"),
                ));
            }
            match self.noise {
                Some(noise) if noise > 0.0 && noise <= MAX_NOISE => {}
                Some(noise) => {
                    return Err(AppError::setting(
                        "noise",
                        format!(
                            "{noise:e} is not a standard deviation (> 0 and at most \
                             {MAX_NOISE} metres)"
                        ),
                    ));
                }
                None => {}
            }
        }
        Ok(())
    }

    /// Plans and/or draws the curve, and writes the files asked for
    /// (checked before any work); `observer` hears of the steps.
    ///
    /// # Errors
    /// Bad settings or files, a pool too small, too few equations.
    pub fn run(
        &self,
        files: &dyn Files,
        observer: &mut dyn Observer,
    ) -> Result<Planning, AppError> {
        self.check_settings()?;
        let file = self.robot.load(files)?;
        for (name, extension) in [(&self.output.save_as, "csv"), (&self.plot_save_as, "svg")] {
            if let Some(name) = name {
                files.check_output(name, extension, self.output.overwrite)?;
            }
        }
        let robot = &file.robot;
        let method = self.method.build()?;
        let seed = self.seed.unwrap_or(gecaro_calib::simulation::DEFAULT_SEED);
        let columns = DataColumn::grouping(method.data_columns());
        let largest = self.largest_count();
        let format = self.format.format()?;
        let pool = match &self.candidates {
            Some(source) => configurations(robot, source, &columns, &format, files)?,
            None => {
                let size = self.pool_size();
                let mut sampler = Sampler::new(seed).with_cell(self.cell.cell()?);
                report_phase(observer, "drawing the candidates")?;
                let pool = method
                    .sensor()
                    .generate(robot, size, 0.0, &mut sampler, observer)?;
                refuse_misses(sampler.cell_misses(), "candidate(s)")?;
                Samples::from(pool)
            }
        };
        let kept = match &self.keep {
            Some(source) => configurations(robot, source, &columns, &format, files)?,
            None => Samples::empty(),
        };
        let name = self.criterion.as_deref().unwrap_or("d");
        let needs_poses = name == "test" || !self.curve.is_empty();
        let poses = if needs_poses {
            self.test_poses.load(robot, seed, &format, files)?
        } else {
            Vec::new()
        };
        let criterion = parse_name("criterion", Some(name), &Criterion::NAMES, |name| {
            Criterion::from_name(name, || poses.clone())
        })?
        .unwrap_or(Criterion::D);
        // Elastic: each candidate with each payload, loaded, and the
        // compliances among the columns.
        let (elastic, pool, kept, priority) = if self.payloads.is_empty() {
            (None, pool, kept, robot.priority())
        } else {
            crate::loads::require_loading_sensor(method.as_ref(), "payloads")?;
            let payloads = crate::loads::payloads(&file, &self.payloads, "payloads")?;
            let elastic = crate::loads::elastic_file(&file, true, "payloads")?;
            let priority = Model::Elastic.priority(&elastic.robot, None);
            let pool = crate::loads::loaded(&elastic, pool.as_slice(), &payloads)?;
            let kept = crate::loads::loaded(&elastic, kept.as_slice(), &[])?;
            (Some(elastic), pool, kept, priority)
        };
        let robot = elastic.as_ref().map_or(robot, |file| &file.robot);
        let design = Design {
            count: largest,
            kept: kept.as_slice(),
            criterion,
            min_distance: self.min_distance,
        };
        let candidates = CandidatePool::new(robot, method.as_ref(), pool.as_slice(), &priority)?;
        let curve = if self.curve.is_empty() {
            None
        } else {
            let noise = self.noise.unwrap_or(DEFAULT_CURVE_NOISE);
            report_phase(observer, "predicting the accuracy curve")?;
            let points = accuracy_curve(
                &candidates,
                &self.curve,
                &design,
                noise,
                &poses,
                seed,
                observer,
            )?;
            Some(AccuracyCurve {
                svg: gecaro_report::accuracy_curve_svg(&points)?,
                points,
                noise,
                saved: None,
            })
        };
        let planned = match self.count {
            Some(count) => {
                let design = Design {
                    count,
                    ..design.clone()
                };
                report_phase(observer, "choosing the configurations")?;
                let plan = candidates.plan(&design, observer)?;
                // A random choice of as many units from the same pool, for comparison.
                let random = candidates.random_design(
                    kept.as_slice(),
                    plan.chosen.len(),
                    &mut Sampler::new(seed),
                );
                let random = candidates.assess(random.as_slice(), &design.criterion)?;
                let csv = gecaro_io::format_configurations(
                    &gecaro_io::joint_types(robot),
                    &columns,
                    Samples::from(plan.samples.as_slice()).as_slice(),
                    &format,
                );
                Some(Planned {
                    plan,
                    criterion: design.criterion.clone(),
                    random,
                    csv,
                    saved: None,
                })
            }
            None => None,
        };
        let mut planning = Planning {
            criterion: design.criterion.name(),
            pool: candidates.len(),
            kept: kept.len(),
            test_poses: poses.len(),
            planned,
            curve,
            robot: file.clone(),
            method: method.clone_method(),
        };
        // Written last: a failed request leaves no file.
        if let (Some(name), Some(planned)) = (&self.output.save_as, &mut planning.planned) {
            planned.saved =
                Some(files.write(name, "csv", planned.csv.as_bytes(), self.output.overwrite)?);
        }
        if let (Some(name), Some(curve)) = (&self.plot_save_as, &mut planning.curve) {
            curve.saved =
                Some(files.write(name, "svg", curve.svg.as_bytes(), self.output.overwrite)?);
        }
        Ok(planning)
    }
}

impl Planning {
    /// The plan's JSON document, when there is a plan.
    pub fn plan_document(&self) -> Option<PlanJson> {
        self.planned.as_ref().map(|planned| {
            PlanJson::new(
                self.method.name(),
                &planned.criterion,
                &planned.plan,
                &planned.random,
                self.pool,
                self.kept,
            )
        })
    }

    /// The curve's JSON document, when there is a curve.
    pub fn curve_document(&self) -> Option<CurveJson> {
        self.curve.as_ref().map(|curve| CurveJson {
            method: self.method.name(),
            criterion: self.criterion,
            noise: curve.noise,
            pool: self.pool,
            test_poses: self.test_poses,
            random_draws: RANDOM_DRAWS,
            points: curve.points.iter().map(CurvePointJson::from).collect(),
        })
    }

    /// A name to save the plan as: `stanford-position-planned-30.csv`.
    pub fn file_name(&self) -> Option<String> {
        self.planned.as_ref().map(|planned| {
            crate::generate::data_file_name(
                &self.robot.robot,
                &format!("{}-planned", self.method.name()),
                planned.plan.samples.len(),
            )
        })
    }
}

/// The precision a plan will give, before measuring (eq. 11), checked by
/// simulated calibrations if asked.
#[derive(Clone, Debug, Deserialize)]
pub struct PredictRequest {
    /// The nominal robot.
    pub robot: RobotSource,
    /// The method.
    pub method: MethodSpec,
    /// The configurations to be measured (a plan).
    pub data: DataSource,
    /// Units, column names and separator of the plan and test-pose files.
    #[serde(default)]
    pub format: DataFormatSpec,
    /// The sensor's standard deviation (metres; radians for orientation rows).
    pub noise: f64,
    /// Where the calibrated robot's accuracy is judged.
    #[serde(flatten)]
    pub test_poses: TestPoses,
    /// Also run this many simulated calibrations (Monte Carlo).
    pub monte_carlo: Option<usize>,
    /// The simulated real robots' error level (default 0.1).
    pub error_level: Option<f64>,
    /// Seed of the test poses and the simulations (default 1).
    pub seed: Option<u64>,
    /// Which parameters are predicted: a model as `identify --model` takes
    /// it (`full`, `kinematic`, …, a priority file); `"elastic"` adds the
    /// compliances, loaded by the robot's masses and the plan's payloads
    /// (docs/elastic.md). None: the robot's priority matrix.
    pub model: Option<String>,
    #[serde(flatten)]
    unknown: Unknown,
}

/// A prediction, and what simulated calibrations measured.
#[derive(Debug)]
pub struct Predicted {
    /// The nominal robot.
    pub robot: RobotFile,
    /// The method.
    pub method: Box<dyn CalibrationMethod>,
    /// The plan's configurations.
    pub configurations: usize,
    /// The sensor's σ.
    pub noise: f64,
    /// Test poses used.
    pub test_poses: usize,
    /// The predicted precision.
    pub prediction: Prediction,
    /// The simulated calibrations, if asked.
    pub measured: Option<MonteCarlo>,
    /// Their error level.
    pub error_level: f64,
}

impl PredictRequest {
    /// A prediction for the plan `data` and a sensor of σ `noise`.
    pub fn new(robot: RobotSource, method: MethodSpec, data: DataSource, noise: f64) -> Self {
        PredictRequest {
            robot,
            method,
            data,
            format: DataFormatSpec::default(),
            noise,
            test_poses: TestPoses::default(),
            monte_carlo: None,
            error_level: None,
            seed: None,
            model: None,
            unknown: Unknown::default(),
        }
    }

    /// Predicts, then simulates if asked; `observer` hears of the runs.
    ///
    /// # Errors
    /// Bad settings or files, too few equations, a failed simulation.
    pub fn run(
        &self,
        files: &dyn Files,
        observer: &mut dyn Observer,
    ) -> Result<Predicted, AppError> {
        self.unknown.check()?;
        if !(self.noise > 0.0 && self.noise <= MAX_NOISE) {
            return Err(AppError::setting(
                "noise",
                format!(
                    "{:e} is not a standard deviation (> 0 and at most {MAX_NOISE} metres)",
                    self.noise
                ),
            ));
        }
        if let Some(runs) = self.monte_carlo
            && !(1..=MAX_GENERATE).contains(&runs)
        {
            return Err(AppError::setting_value(
                "monte_carlo",
                runs,
                format!("between 1 and {MAX_GENERATE} simulated calibrations"),
            ));
        }
        let file = self.robot.load(files)?;
        let robot = &file.robot;
        let method = self.method.build()?;
        let seed = self.seed.unwrap_or(gecaro_calib::simulation::DEFAULT_SEED);
        let columns = DataColumn::grouping(method.data_columns());
        let format = self.format.format()?;
        let planned = configurations(robot, &self.data, &columns, &format, files)?;
        let poses = self.test_poses.load(robot, seed, &format, files)?;
        let model = self
            .model
            .as_deref()
            .map(|name| crate::settings::model(name, robot, files))
            .transpose()?;
        let (elastic, planned, priority) = match model {
            None => (None, planned, robot.priority()),
            Some(model) if model.is_elastic() => {
                if self.monte_carlo.is_some() {
                    return Err(AppError::setting(
                        "monte_carlo",
                        "simulated calibrations of an elastic robot are not run yet: predict \
                         without them, or simulate with generate --compliance-level",
                    ));
                }
                let payloads = planned.iter().any(|sample| sample.payload().is_some());
                let elastic = crate::loads::elastic_file(&file, payloads, "model")?;
                let planned = crate::loads::loaded(&elastic, planned.as_slice(), &[])?;
                let priority = model.priority(&elastic.robot, None);
                (Some(elastic), planned, priority)
            }
            Some(model) => (None, planned, model.priority(robot, None)),
        };
        let robot = elastic.as_ref().map_or(robot, |file| &file.robot);
        let prediction = predict(
            robot,
            method.as_ref(),
            planned.as_slice(),
            self.noise,
            &poses,
            &priority,
        )?;
        let error_level = self.error_level.unwrap_or(0.1);
        let measured = match self.monte_carlo {
            Some(runs) => Some(monte_carlo(
                robot,
                method.as_ref(),
                planned.as_slice(),
                &poses,
                SimulatedRuns {
                    runs,
                    seed,
                    noise: self.noise,
                    error_level,
                },
                &IdentificationOptions::default(),
                observer,
            )?),
            None => None,
        };
        Ok(Predicted {
            configurations: planned.len(),
            noise: self.noise,
            test_poses: poses.len(),
            robot: file,
            method,
            prediction,
            measured,
            error_level,
        })
    }
}

impl Predicted {
    /// The JSON document (`gecaro predict --json`).
    pub fn document(&self) -> PredictJson {
        PredictJson::new(
            self.method.name(),
            self.configurations,
            self.noise,
            self.test_poses,
            &self.prediction,
            self.measured
                .as_ref()
                .map(|measured| (measured, self.error_level)),
        )
    }
}

/// The pool generated when none is given: 20 candidates per configuration
/// asked, within the bound on generated configurations (docs/api.md), and
/// never fewer than asked.
fn default_pool(largest: usize) -> usize {
    largest.saturating_mul(20).min(MAX_GENERATE).max(largest)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_pool_stays_within_its_bound() {
        assert_eq!(default_pool(50), 1000);
        assert_eq!(default_pool(5000), MAX_GENERATE);
        assert_eq!(default_pool(MAX_GENERATE + 1), MAX_GENERATE + 1);
    }
}
