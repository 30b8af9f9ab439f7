//! Points generation for a parallel robot: a "real" platform drawn about
//! the nominal one (or given), measured at reachable poses with noise.

use std::path::PathBuf;

use gecaro_calib::parallel_robots::{
    MeasuringLeg, PlatformNoise, PlatformWorkspace, perturbed_platform, random_platform_poses,
    simulate_leg, simulate_platform,
};
use gecaro_calib::simulation::{DEFAULT_ERROR_LEVEL, DEFAULT_SEED, Sampler};
use gecaro_calib::study::{Sample, Samples};
use gecaro_core::parallel_model::ParallelModel;
use gecaro_io::ParallelRobotFile;
use serde::Deserialize;

use super::leg::measuring_leg;
use super::{load_parallel_robot, measure_for};
use crate::error::AppError;
use crate::files::Files;
use crate::limits::MAX_GENERATE;
use crate::output::Output;
use crate::sources::{DataFormatSpec, DataSource};

/// A points generation for a parallel robot.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParallelGenerateRequest {
    /// The nominal platform (a file, or a ready parallel robot's name).
    pub robot: String,
    /// `frame` (the platform's pose), `position` (its tool point),
    /// `distance` (between the tool points of consecutive poses) or `leg`
    /// (a measuring leg's readings).
    pub method: String,
    /// Measured poses (1 to [`MAX_GENERATE`]); not with `configurations`.
    pub count: usize,
    /// Measure at these actuator values instead (a plan's file): the real
    /// robot's direct model puts it where they take it.
    #[serde(default)]
    pub configurations: Option<DataSource>,
    /// Units and columns of the configurations file.
    #[serde(default)]
    pub format: DataFormatSpec,
    /// The real platform's errors: ±L mm on every joint centre, length and
    /// tool coordinate, ±L·10⁻³ on every gain (default 1); not with `real`.
    pub error_level: Option<f64>,
    /// The real platform, instead of one with random errors.
    pub real: Option<String>,
    /// The sensor's noise σ: metres, radians for orientations.
    #[serde(default)]
    pub noise: f64,
    /// Seed of every draw (default [`DEFAULT_SEED`]).
    pub seed: Option<u64>,
    /// The data file.
    #[serde(flatten)]
    pub output: Output,
    /// Where the real platform is written (TOML), if anywhere.
    pub real_save_as: Option<String>,
    /// The `leg` method's measuring leg, mounted where stated (its reading
    /// 0 at the real platform's home): its base socket, a point with its
    /// units.
    #[serde(default)]
    pub leg_base: Option<String>,
    /// Its platform socket, likewise.
    #[serde(default)]
    pub leg_platform: Option<String>,
    /// Its gain (default 1).
    #[serde(default)]
    pub leg_gain: Option<f64>,
}

/// What a generation made.
#[derive(Clone, Debug)]
pub struct ParallelGenerated {
    /// The measurements.
    pub samples: Vec<Sample>,
    /// The real platform.
    pub real: ParallelRobotFile,
    /// The data file's text.
    pub text: String,
    /// The files written.
    pub written: Vec<PathBuf>,
}

impl ParallelGenerateRequest {
    /// Runs the generation.
    ///
    /// # Errors
    /// A robot that cannot be read, a setting out of range, a workspace
    /// with too few reachable poses, a file that cannot be written.
    pub fn run(&self, files: &dyn Files) -> Result<ParallelGenerated, AppError> {
        let nominal = load_parallel_robot(&self.robot, files)?;
        let measure = measure_for(&self.method, &nominal.robot)?;
        let leg = measuring_leg(
            measure,
            self.leg_base.as_deref(),
            self.leg_platform.as_deref(),
            self.leg_gain,
        )?;
        self.output.check(files, "csv")?;
        if let Some(name) = &self.real_save_as {
            files.check_output(name, "toml", self.output.overwrite)?;
        }
        if self.configurations.is_none() && !(1..=MAX_GENERATE).contains(&self.count) {
            return Err(AppError::setting_value(
                "count",
                self.count,
                format!("takes 1 to {MAX_GENERATE} poses"),
            ));
        }
        if !(self.noise.is_finite() && (0.0..=1.0).contains(&self.noise)) {
            return Err(AppError::setting_value(
                "noise",
                self.noise,
                "is a sensor's σ in metres (radians for orientations), from 0 to 1",
            ));
        }
        let seed = self.seed.unwrap_or(DEFAULT_SEED);
        let mut sampler = Sampler::new(seed);
        let real = match (&self.real, self.error_level) {
            (Some(_), Some(_)) => {
                return Err(AppError::setting(
                    "real",
                    "is the real platform; an error level draws one: give one of them",
                ));
            }
            (Some(name), None) => load_parallel_robot(name, files)?,
            (None, level) => {
                let level = level.unwrap_or(DEFAULT_ERROR_LEVEL);
                let platform = perturbed_platform(&nominal.robot, level, &mut sampler)?
                    .renamed(&format!("{} (simulated real)", nominal.robot.name()));
                ParallelRobotFile {
                    robot: platform,
                    description: Some(format!(
                        "{} with random errors of level {level} (seed {seed}), drawn by gecaro",
                        nominal.robot.name()
                    )),
                    calibrated_from: None,
                    measured_region: None,
                }
            }
        };
        // The actuator values commanded, when a file gives them: the
        // measured rows keep them to the bit (not as the inverse model of
        // the pose reached gives them back).
        let mut commanded: Vec<Vec<f64>> = Vec::new();
        let poses = match &self.configurations {
            Some(source) => {
                let read = source.read(
                    files,
                    &super::actuator_types(&nominal.robot),
                    &[],
                    &self.format.format()?,
                )?;
                let rows = read.samples.to_rows();
                commanded = rows
                    .iter()
                    .map(|sample| sample.motor_positions.as_slice().to_vec())
                    .collect();
                rows.iter()
                    .map(|sample| {
                        real.robot
                            .direct(sample.motor_positions.as_slice(), &real.robot.home())
                            .map_err(|cause| {
                                AppError::plain(
                                    crate::error::ErrorKind::Input,
                                    format!(
                                        "{}, line {}: {cause}",
                                        read.label,
                                        sample.line.map_or_else(|| "?".into(), |l| l.to_string())
                                    ),
                                )
                            })
                    })
                    .collect::<Result<Vec<_>, _>>()?
            }
            None => random_platform_poses(
                &real.robot,
                self.count,
                PlatformWorkspace::of(&real.robot),
                &mut sampler,
            )?,
        };
        let noise = PlatformNoise {
            length: self.noise,
            angle: self.noise,
        };
        let mut samples = match leg {
            Some(leg) => {
                // The leg where it is stated, its reading 0 at the real
                // platform's home.
                let mounted = MeasuringLeg {
                    length: leg.length_at(&real.robot.home()),
                    ..leg
                };
                simulate_leg(&real.robot, &mounted, &poses, noise, &mut sampler)?
            }
            None => simulate_platform(&real.robot, measure, &poses, noise, &mut sampler)?,
        };
        for (sample, values) in samples.iter_mut().zip(commanded) {
            sample.motor_positions = values.into();
        }
        let text = gecaro_io::format_samples(
            real.robot.actuator_count(),
            measure.columns(),
            Samples::from(samples.as_slice()).as_slice(),
        );
        let mut outputs: Vec<(&str, &str, Vec<u8>)> = Vec::new();
        if let Some(name) = &self.output.save_as {
            outputs.push((name, "csv", text.clone().into_bytes()));
        }
        if let Some(name) = &self.real_save_as {
            outputs.push((
                name,
                "toml",
                gecaro_io::format_parallel_robot_file(&real).into_bytes(),
            ));
        }
        let borrowed: Vec<(&str, &str, &[u8])> = outputs
            .iter()
            .map(|(name, extension, bytes)| (*name, *extension, bytes.as_slice()))
            .collect();
        let written = files.write_all(&borrowed, self.output.overwrite)?;
        Ok(ParallelGenerated {
            samples,
            real,
            text,
            written,
        })
    }
}
