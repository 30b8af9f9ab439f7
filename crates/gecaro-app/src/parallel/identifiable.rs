//! The identifiable parameters of a parallel robot: at the configurations
//! of a data file, or at random reachable poses.

use gecaro_calib::parallel_robots::{
    PlatformMeasure, PlatformNoise, PlatformWorkspace, platform_identifiability,
    random_platform_poses, simulate_platform,
};
use gecaro_calib::simulation::{DEFAULT_SEED, Sampler};
use gecaro_core::parallel_model::ParallelModel;
use serde::Deserialize;

use super::documents::PlatformRankDocument;
use super::{actuator_types, load_parallel_robot, measure_without_leg};
use crate::error::AppError;
use crate::files::Files;
use crate::sources::{DataFormatSpec, DataSource};

/// Random poses drawn when no data are given (for distances, one equation a
/// pair, four a parameter when that is more).
pub const DEFAULT_POSES: usize = 60;

/// The identifiable parameters of a parallel robot.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParallelIdentifiableRequest {
    /// The platform (a file, or a ready parallel robot's name).
    pub robot: String,
    /// `frame`, `position` or `distance`.
    pub method: String,
    /// The configurations (a data file); random reachable poses without.
    pub data: Option<DataSource>,
    /// Units and columns of the data file.
    #[serde(default)]
    pub format: DataFormatSpec,
    /// Random poses when no data are given (default [`DEFAULT_POSES`]).
    pub count: Option<usize>,
    /// Seed of the random poses (default [`DEFAULT_SEED`]).
    pub seed: Option<u64>,
}

impl ParallelIdentifiableRequest {
    /// Runs the analysis.
    ///
    /// # Errors
    /// A robot or data file that cannot be read, too few equations.
    pub fn run(&self, files: &dyn Files) -> Result<PlatformRankDocument, AppError> {
        let file = load_parallel_robot(&self.robot, files)?;
        let measure = measure_without_leg(&self.method, &file.robot, "identifiable")?;
        let (samples, source) = match &self.data {
            Some(data) => {
                let read = data.read(
                    files,
                    &actuator_types(&file.robot),
                    measure.columns(),
                    &self.format.format()?,
                )?;
                let count = read.samples.len();
                (
                    read.samples.to_rows(),
                    format!("the {count} configurations of {}", read.label),
                )
            }
            None => {
                let count = self.count.unwrap_or(match measure {
                    PlatformMeasure::Distance => {
                        DEFAULT_POSES.max(4 * file.robot.parameters().len())
                    }
                    _ => DEFAULT_POSES,
                });
                let seed = self.seed.unwrap_or(DEFAULT_SEED);
                let mut sampler = Sampler::new(seed);
                let poses = random_platform_poses(
                    &file.robot,
                    count,
                    PlatformWorkspace::of(&file.robot),
                    &mut sampler,
                )?;
                let exact = PlatformNoise {
                    length: 0.0,
                    angle: 0.0,
                };
                (
                    simulate_platform(&file.robot, measure, &poses, exact, &mut sampler)?,
                    format!("{count} random reachable poses (seed {seed})"),
                )
            }
        };
        let report = platform_identifiability(&file.robot, &samples, measure)?;
        Ok(PlatformRankDocument::new(&report, source))
    }
}
