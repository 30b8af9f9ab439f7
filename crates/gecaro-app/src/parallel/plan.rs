//! The poses to measure on a parallel robot (D-optimal from a pool of
//! reachable poses by default; A, E, O4, O5, or the calibrated platform's
//! predicted error over its workspace), written as the actuator values to
//! command: a file `generate --configurations` simulates and a cell
//! measures.

use gecaro_calib::parallel_robots::plan_platform;
use gecaro_calib::planning::Criterion;
use gecaro_calib::simulation::DEFAULT_SEED;
use gecaro_calib::study::Samples;
use gecaro_core::parallel_model::ParallelModel;
use serde::{Deserialize, Serialize};

use super::{load_parallel_robot, measure_without_leg};
use crate::error::AppError;
use crate::files::Files;
use crate::limits::MAX_GENERATE;
use crate::method::parse_name;
use crate::output::Output;

/// Candidates per chosen pose when the pool is not stated.
pub const POOL_PER_POSE: usize = 20;

/// A plan of poses for a parallel robot.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParallelPlanRequest {
    /// The nominal robot.
    pub robot: String,
    /// `frame`, `position` or `distance`.
    pub method: String,
    /// Poses to choose.
    pub count: usize,
    /// Candidate poses drawn (default [`POOL_PER_POSE`] × count).
    pub pool: Option<usize>,
    /// Seed of the pool (default [`DEFAULT_SEED`]).
    pub seed: Option<u64>,
    /// What the poses are chosen for: `d` (default), `a`, `e`, `o4`, `o5`,
    /// or `test` (the calibrated platform's predicted error over its
    /// workspace).
    #[serde(default)]
    pub criterion: Option<String>,
    /// The planned configurations (CSV: `qm1…qmk`).
    #[serde(flatten)]
    pub output: Output,
}

/// A plan, as `gecaro plan ROBOT --json` prints it.
#[derive(Clone, Debug, Serialize)]
pub struct ParallelPlanned {
    /// Poses chosen.
    pub count: usize,
    /// Candidates they were chosen from.
    pub pool: usize,
    /// Identifiable parameters the design is for.
    pub rank: usize,
    /// The criterion the poses were chosen for (`d`, `a`, `e`, `o4`, `o5`,
    /// `test`).
    pub criterion_name: &'static str,
    /// What its value is, in words.
    pub criterion_meaning: &'static str,
    /// Its value, the plan's and as many random poses' (parameters scaled
    /// to unit column norms over the pool): D's `log det(W_bᵀW_b)` per
    /// equation; `test`'s the predicted RMS tool-point error over the
    /// workspace per unit σ.
    pub criterion: f64,
    /// See `criterion`.
    pub random_criterion: f64,
    /// The chosen poses' actuator values.
    pub configurations: Vec<Vec<f64>>,
    /// Where they were written.
    pub written: Option<String>,
    /// The file's text.
    #[serde(skip)]
    pub text: String,
}

impl ParallelPlanRequest {
    /// Runs the plan.
    ///
    /// # Errors
    /// A robot that cannot be read, a count or pool out of range or too
    /// small for the identifiable parameters, a file that cannot be written.
    pub fn run(&self, files: &dyn Files) -> Result<ParallelPlanned, AppError> {
        let file = load_parallel_robot(&self.robot, files)?;
        let measure = measure_without_leg(&self.method, &file.robot, "plan")?;
        self.output.check(files, "csv")?;
        let pool = self.pool.unwrap_or(POOL_PER_POSE * self.count);
        if !(1..=MAX_GENERATE).contains(&pool) {
            return Err(AppError::setting_value(
                "pool",
                pool,
                format!("takes 1 to {MAX_GENERATE} candidate poses"),
            ));
        }
        let criterion = parse_name(
            "criterion",
            self.criterion.as_deref(),
            &Criterion::NAMES,
            |name| Criterion::from_name(name, Vec::new),
        )?
        .unwrap_or(Criterion::D);
        let planned = plan_platform(
            &file.robot,
            measure,
            self.count,
            pool,
            self.seed.unwrap_or(DEFAULT_SEED),
            &criterion,
        )?;
        let text = gecaro_io::format_samples(
            file.robot.actuator_count(),
            &[],
            Samples::from(planned.samples.as_slice()).as_slice(),
        );
        let written = self.output.write(files, "csv", text.as_bytes())?;
        Ok(ParallelPlanned {
            count: planned.samples.len(),
            pool,
            rank: planned.rank.rank(),
            criterion_name: planned.criterion_name,
            criterion_meaning: meaning(&criterion),
            criterion: planned.criterion,
            random_criterion: planned.random_criterion,
            configurations: planned
                .samples
                .iter()
                .map(|sample| sample.motor_positions.as_slice().to_vec())
                .collect(),
            written: written.map(|path| path.display().to_string()),
            text,
        })
    }
}

/// What a parallel plan's criterion value is, in words: a serial plan's
/// meaning, but D per equation and the test poses the workspace's.
fn meaning(criterion: &Criterion) -> &'static str {
    match criterion {
        Criterion::D => "log det(W_bᵀW_b) per equation",
        Criterion::TestPoses(_) => "predicted RMS tool-point error over the workspace per unit σ",
        other => other.meaning(),
    }
}
