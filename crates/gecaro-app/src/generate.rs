//! The "Points generation" function (paper §4) as a job: a simulated "real"
//! robot (the nominal one with random errors, or a given one) measured by
//! the method's sensor with noise, at random configurations or at planned
//! ones.
//!
//! ## Elastic joints (issue 38)
//!
//! `compliance_level` L gives the drawn real robot a compliance on every
//! joint, uniform in L·[2e-6, 1e-5] rad/(N·m) (L·[2e-7, 1e-6] m/N for a
//! prismatic joint), the range of industrial arms; `payload` (`20kg`,
//! `20kg,0,0,120mm`) is carried at every configuration and written to the
//! data file's payload columns. An elastic real robot is measured where it
//! settles under the gravity of its links (the robot file's masses) and of
//! the payload ([`gecaro_calib::elastic::settled_torques`]). The methods
//! whose sensors see the sag ([`gecaro_calib::methods::Sensor::yields_to_loads`]:
//! position, frame) simulate it; the others are refused.

use gecaro_calib::elastic::settled_torques;
use gecaro_calib::methods::CalibrationMethod;
use gecaro_calib::simulation::{
    Sampler, perturbed_robot, simulate_at, simulate_measurements, terminal_displacement,
    within_nominal_limits,
};
use gecaro_calib::study::{DataColumn, Sample, Samples};
use gecaro_calib::{Observer, report_step};
use gecaro_io::RobotFile;
use serde::Deserialize;

use crate::cell::{CellSpec, refuse_misses};
use crate::error::{AppError, ErrorKind, Part};
use crate::files::Files;
use crate::limits::MAX_GENERATE;
use crate::loads::COMPLIANCE_RANGE;
use crate::measurements::Unknown;
use crate::method::MethodSpec;
use crate::output::Output;
use crate::robot_files::simulated_robot_file;
use crate::sources::{DataFormatSpec, DataSource, RobotSource};

/// A points generation; see the module docs.
#[derive(Clone, Debug, Deserialize)]
pub struct GenerateRequest {
    /// The nominal robot.
    pub robot: RobotSource,
    /// The method whose data are simulated.
    pub method: MethodSpec,
    /// Configurations to generate (1 to [`MAX_GENERATE`]); not with
    /// `configurations`.
    pub count: Option<usize>,
    /// Measure at these configurations instead (a planned file's qm, and
    /// set or pair ids).
    pub configurations: Option<DataSource>,
    /// Units, column names and separator of the configurations file (a plan
    /// written in degrees for a teach pendant is read in degrees).
    #[serde(default)]
    pub format: DataFormatSpec,
    /// Errors of the simulated real robot: ±L cm, ±L°, ±L % (default 1); not
    /// with `real`.
    pub error_level: Option<f64>,
    /// The real robot, instead of one with random errors.
    pub real: Option<RobotSource>,
    /// Compliances of the drawn real robot: L·[2e-6, 1e-5] rad/(N·m) per
    /// joint (module docs); not with `real`, whose own are used.
    pub compliance_level: Option<f64>,
    /// The payload carried at every configuration: `20kg`, or
    /// `20kg,0,0,120mm` with its centre in the tool frame (else each planned
    /// row's own).
    pub payload: Option<String>,
    /// A measurement frame that is not levelled: the real robot's gravity
    /// leans by these two angles (`"2deg,-1.5deg"`, tilt1 and tilt2 of
    /// `gecaro_core::MassModel::tilted`) from the direction its file states.
    /// Only elastic joints see it (`--model elastic-gravity` finds it).
    pub gravity_tilt: Option<String>,
    /// Sensor noise, standard deviation (metres; radians for orientations).
    #[serde(default)]
    pub noise: f64,
    /// The cell: only configurations it can measure are drawn.
    #[serde(default)]
    pub cell: CellSpec,
    /// Seed of every random draw (default 1).
    pub seed: Option<u64>,
    /// Where the output is written (`save_as`) and whether it may replace a
    /// file (`overwrite`).
    #[serde(flatten)]
    pub output: Output,
    /// Write the simulated real robot here, so that the truth is known.
    pub real_save_as: Option<String>,
    #[serde(flatten)]
    unknown: Unknown,
}

/// Simulated measurements and the robot they were measured on.
#[derive(Debug)]
pub struct Generated {
    /// The nominal robot.
    pub nominal: RobotFile,
    /// The method.
    pub method: Box<dyn CalibrationMethod>,
    /// The simulated measurements.
    pub samples: Samples,
    /// The real robot they were measured on.
    pub real: RobotFile,
    /// Whether the real robot was given (else drawn at `error_level`).
    pub real_given: bool,
    /// RMS and largest distance (m) between the nominal and the real
    /// terminal points over the configurations.
    pub displacement: (f64, f64),
    /// The data file's text (CSV).
    pub csv: String,
    /// Where the data file was written, if asked for.
    pub saved: Option<std::path::PathBuf>,
    /// Where the real robot was written, if asked for.
    pub real_saved: Option<std::path::PathBuf>,
    /// The error level of a drawn real robot.
    pub error_level: f64,
    /// The seed.
    pub seed: u64,
}

impl GenerateRequest {
    /// A generation of `count` configurations of `method` on `robot`, with
    /// the default settings.
    pub fn new(robot: RobotSource, method: MethodSpec, count: usize) -> Self {
        GenerateRequest {
            robot,
            method,
            count: Some(count),
            configurations: None,
            format: DataFormatSpec::default(),
            error_level: None,
            real: None,
            compliance_level: None,
            payload: None,
            gravity_tilt: None,
            noise: 0.0,
            cell: CellSpec::default(),
            seed: None,
            output: Output::default(),
            real_save_as: None,
            unknown: Unknown::default(),
        }
    }

    /// Simulates the measurements and writes the files asked for (checked
    /// before any work); `observer` hears of the configurations done and
    /// may stop the work, before anything is written.
    ///
    /// # Errors
    /// Bad settings, a real robot of other joints, configurations that
    /// cannot be generated, files that cannot be written, an interruption.
    pub fn run(
        &self,
        files: &dyn Files,
        observer: &mut dyn Observer,
    ) -> Result<Generated, AppError> {
        self.unknown.check()?;
        let nominal = self.robot.load(files)?;
        let robot = &nominal.robot;
        for (name, extension) in [(&self.output.save_as, "csv"), (&self.real_save_as, "toml")] {
            if let Some(name) = name {
                files.check_output(name, extension, self.output.overwrite)?;
            }
        }
        let method = self.method.build()?;
        let seed = self.seed.unwrap_or(gecaro_calib::simulation::DEFAULT_SEED);
        let error_level = self
            .error_level
            .unwrap_or(gecaro_calib::simulation::DEFAULT_ERROR_LEVEL);
        let cell = self.cell.cell()?;
        let payload = self
            .payload
            .as_deref()
            .map(|text| crate::loads::payload(&nominal, text, "payload"))
            .transpose()?;
        let mut sampler = Sampler::new(seed);
        let mut real = match &self.real {
            Some(source) => {
                if self.error_level.is_some() {
                    return Err(AppError::new(
                        ErrorKind::Usage,
                        vec![
                            Part::Setting("real".into()),
                            Part::Text(" is the real robot; ".into()),
                            Part::Setting("error_level".into()),
                            Part::Text(" draws one: give one of them".into()),
                        ],
                    ));
                }
                let real = source.load(files)?;
                if real.robot.joint_letters() != robot.joint_letters() {
                    return Err(AppError::plain(
                        ErrorKind::Input,
                        format!(
                            "the real robot has joints {}, the nominal one {}",
                            real.robot.joint_letters(),
                            robot.joint_letters()
                        ),
                    ));
                }
                real
            }
            None => simulated_robot_file(
                &nominal,
                perturbed_robot(robot, error_level, &mut sampler)?,
                error_level,
                seed,
            ),
        };
        if let Some(level) = self.compliance_level {
            let payload_given = payload.is_some();
            draw_compliances(
                &mut real,
                level,
                (self.real.is_some(), payload_given),
                &mut sampler,
            )?;
        }
        if let Some(text) = &self.gravity_tilt {
            let tilt = gravity_tilt(text)?;
            if !real.robot.is_elastic() {
                return Err(AppError::setting(
                    "gravity_tilt",
                    "gravity's tilt loads elastic joints only: give the real robot compliances \
                     (a compliance level, or a real robot file that states them)",
                ));
            }
            real.masses = real.masses.tilted(tilt);
        }
        if real.robot.is_elastic() {
            crate::loads::require_loading_sensor(method.as_ref(), "compliance_level")?;
        }
        let samples = match (&self.configurations, self.count) {
            (Some(_), Some(_)) => {
                return Err(AppError::setting(
                    "configurations",
                    "give configurations to measure at, or a count of random ones, not both",
                ));
            }
            (Some(source), None) => {
                let planned = source.read(
                    files,
                    &gecaro_io::joint_types(robot),
                    &DataColumn::grouping(method.data_columns()),
                    &self.format.format()?,
                )?;
                simulate_at(
                    &real.robot,
                    method.as_ref(),
                    planned.samples.as_slice(),
                    self.noise,
                    &mut sampler,
                    observer,
                )?
            }
            (None, count) => {
                let count = count.ok_or_else(|| {
                    AppError::setting("count", "give the number of configurations")
                })?;
                if !(1..=MAX_GENERATE).contains(&count) {
                    return Err(AppError::setting_value(
                        "count",
                        count,
                        format!("between 1 and {MAX_GENERATE} configurations"),
                    ));
                }
                // The real robot stands in the cell, and its controller keeps
                // the nominal model's joint values within their limits: the
                // configurations drawn are those it can measure.
                let measured = within_nominal_limits(robot, &real.robot)?;
                let mut measuring = sampler.clone().with_cell(cell.clone());
                let samples = simulate_measurements(
                    &measured,
                    method.as_ref(),
                    count,
                    self.noise,
                    &mut measuring,
                    observer,
                )?;
                refuse_misses(measuring.cell_misses(), "configuration(s)")?;
                samples
            }
        };
        // Each row carries the request's payload, else the planned row's.
        let samples = samples.into_iter().map(|mut sample| {
            if payload.is_some() {
                sample.set_payload(payload);
            }
            sample
        });
        // An elastic robot is measured again where it settles under its
        // weight and the payload's; a rigid one's readings stand.
        let samples = if real.robot.is_elastic() {
            let planned = samples
                .map(|mut sample| {
                    let torques = settled_torques(
                        &real.robot,
                        &real.masses,
                        sample.payload(),
                        &sample.motor_positions,
                    )?;
                    sample.loads_mut().torques = Some(torques);
                    Ok(sample)
                })
                .collect::<Result<Vec<Sample>, AppError>>()?;
            simulate_at(
                &real.robot,
                method.as_ref(),
                Samples::from(planned.as_slice()).as_slice(),
                self.noise,
                &mut sampler,
                observer,
            )?
        } else {
            samples.collect()
        };
        let samples = Samples::from(samples);
        // Whoever asked may have gone while the data were drawn (a closed
        // page, Ctrl-C): then nothing is written.
        report_step(observer, samples.len(), samples.len())?;
        let displacement = terminal_displacement(robot, &real.robot, samples.as_slice())?;
        // The file says where its data came from (a comment line, which the
        // data reader skips).
        let csv = format!(
            "{}\n{}",
            self.origin_line(robot, method.name(), samples.len(), (seed, error_level)),
            gecaro_io::format_samples(
                robot.joint_count(),
                method.data_columns(),
                samples.as_slice()
            )
        );
        let saved = self.output.write(files, "csv", csv.as_bytes())?;
        let real_saved = match &self.real_save_as {
            Some(name) => Some(files.write(
                name,
                "toml",
                gecaro_io::robot_file_text(&real, std::path::Path::new(name))?.as_bytes(),
                self.output.overwrite,
            )?),
            None => None,
        };
        Ok(Generated {
            nominal,
            method,
            samples,
            real,
            real_given: self.real.is_some(),
            displacement,
            csv,
            saved,
            real_saved,
            error_level,
            seed,
        })
    }
}

/// The largest tilt of gravity a simulated cell takes (radians): 45°.
const MAX_GRAVITY_TILT: f64 = std::f64::consts::FRAC_PI_4;

/// The two angles of `text` (`"2deg,-1.5deg"`), each within
/// [`MAX_GRAVITY_TILT`].
///
/// # Errors
/// Not two angles with their units, or one beyond 45°.
fn gravity_tilt(text: &str) -> Result<[f64; 2], AppError> {
    let angles = text
        .split(',')
        .map(gecaro_io::parse_signed_angle)
        .collect::<Result<Vec<f64>, String>>()
        .map_err(|message| AppError::setting("gravity_tilt", message))?;
    match angles.as_slice() {
        [first, second] if first.abs().max(second.abs()) <= MAX_GRAVITY_TILT => {
            Ok([*first, *second])
        }
        [_, _] => Err(AppError::setting(
            "gravity_tilt",
            format!("'{text}' leans gravity by more than 45°: a tilt is a few degrees"),
        )),
        _ => Err(AppError::setting(
            "gravity_tilt",
            format!("'{text}' is not two angles: write tilt1,tilt2, e.g. 2deg,-1.5deg"),
        )),
    }
}

/// The largest compliance level: 100 × a soft joint is 1e-3 rad/(N·m).
const MAX_COMPLIANCE_LEVEL: f64 = 100.0;

/// Gives the drawn real robot compliances at `level` (module docs).
fn draw_compliances(
    real: &mut RobotFile,
    level: f64,
    (real_given, payload_given): (bool, bool),
    sampler: &mut Sampler,
) -> Result<(), AppError> {
    if real_given {
        return Err(AppError::setting(
            "compliance_level",
            "draws the compliances of a drawn real robot; a given real robot states its own",
        ));
    }
    if !(0.0..=MAX_COMPLIANCE_LEVEL).contains(&level) {
        return Err(AppError::setting_value(
            "compliance_level",
            level,
            format!("from 0 to {MAX_COMPLIANCE_LEVEL}"),
        ));
    }
    crate::loads::require_loads(real, payload_given, "compliance_level")?;
    let compliances = real.robot.frames()[1..=real.robot.joint_count()]
        .iter()
        .map(|frame| {
            let scale = match frame.frame_type {
                gecaro_core::FrameType::Prismatic => 0.1,
                _ => 1.0,
            };
            scale * level * sampler.uniform(COMPLIANCE_RANGE.0, COMPLIANCE_RANGE.1)
        })
        .collect();
    real.robot
        .set_compliances(Some(compliances))
        .map_err(|error| AppError::setting("compliance_level", error.to_string()))?;
    Ok(())
}

impl GenerateRequest {
    /// The first line of a generated data file: a comment naming the
    /// method, the real robot (drawn: the nominal one, its error level and
    /// seed; given: its file), the configurations and the sensor noise.
    fn origin_line(
        &self,
        robot: &gecaro_core::Robot,
        method: &str,
        count: usize,
        (seed, error_level): (u64, f64),
    ) -> String {
        let real = match &self.real {
            Some(RobotSource::Named(name)) => format!("the real robot {name}"),
            Some(_) => "a real robot given with the request".to_owned(),
            None => format!(
                "a real robot drawn from {} at error level {error_level} (seed {seed})",
                robot.name()
            ),
        };
        let at = match &self.configurations {
            Some(source) => format!(" at the configurations of {}", source.label()),
            None => format!(", configurations drawn with seed {seed}"),
        };
        let mut line = format!(
            "# gecaro generate: {count} {method} measurements of {real}{at}; sensor noise sigma {} m (rad for orientations)",
            self.noise
        );
        if let Some(level) = self.compliance_level {
            line.push_str(&format!("; compliance level {level}"));
        }
        if let Some(payload) = &self.payload {
            line.push_str(&format!("; payload {}", payload.trim()));
        }
        if let Some(tilt) = &self.gravity_tilt {
            line.push_str(&format!("; gravity tilted by {}", tilt.trim()));
        }
        line
    }
}

impl Generated {
    /// A name to save the data as: `stanford-position-50.csv`.
    pub fn file_name(&self) -> String {
        data_file_name(&self.nominal.robot, self.method.name(), self.samples.len())
    }
}

/// The name a data file of `robot` for `what` (a method name, ...) with
/// `count` configurations is offered under: `stanford-position-50.csv`.
pub fn data_file_name(robot: &gecaro_core::Robot, what: &str, count: usize) -> String {
    let slug = robot
        .name()
        .to_lowercase()
        .replace(|c: char| !c.is_alphanumeric(), "-");
    format!("{slug}-{what}-{count}.csv")
}
