//! How many configurations are enough: the predicted error of the calibrated
//! robot against the number of configurations, planned versus random.
//!
//! For each count N, a plan of N configurations from the pool
//! ([`CandidatePool::plan`]) and [`RANDOM_DRAWS`] random choices of as many
//! units from the same pool are each given to [`crate::prediction::predict`] (in the
//! pool's base columns, found once); the
//! curve holds the planned design's predicted RMS position error at the test
//! poses and the mean of the random ones'. A count whose design does not
//! determine the identifiable parameters has no value.

use crate::Error;
use crate::planning::{CandidatePool, PlanRequest};
use crate::prediction::predict_in;
use crate::progress::{Observer, Progress, Quiet, report};
use crate::sampler::Sampler;
use crate::samples::Samples;

/// Random choices averaged per count.
pub const RANDOM_DRAWS: usize = 5;

/// One count of the curve.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct CurvePoint {
    /// Configurations measured (rows of the data file).
    pub count: usize,
    /// Predicted RMS position error at the test poses of the planned design
    /// (metres); None when it does not determine the parameters.
    pub planned: Option<f64>,
    /// The mean over [`RANDOM_DRAWS`] random choices of as many units; None
    /// when any of them does not determine the parameters.
    pub random: Option<f64>,
}

/// The curve at `counts` (see the module docs), for a sensor of standard
/// deviation `noise`, plans made as `request` says (its count replaced by
/// each of `counts`). `observer` hears of the counts done and may stop
/// the work.
///
/// # Errors
/// A pool too small for the largest count, invalid samples, or
/// [`Error::Interrupted`].
pub fn accuracy_curve(
    pool: &CandidatePool<'_>,
    counts: &[usize],
    request: &PlanRequest<'_>,
    noise: f64,
    test_poses: &[Vec<f64>],
    seed: u64,
    observer: &mut dyn Observer,
) -> Result<Vec<CurvePoint>, Error> {
    let (robot, method, columns) = pool.parts();
    let mut sampler = Sampler::new(seed);
    let predicted = |design: &Samples| match predict_in(
        columns,
        robot,
        method,
        design.as_slice(),
        noise,
        test_poses,
    ) {
        Ok(prediction) => Ok(Some(prediction.errors.position_rms)),
        Err(Error::Numerical { .. } | Error::TooFewEquations { .. }) => Ok(None),
        Err(error) => Err(error),
    };
    let mut curve = Vec::with_capacity(counts.len());
    for (done, count) in counts.iter().enumerate() {
        report(
            observer,
            Progress::Step {
                done,
                total: counts.len(),
            },
        )?;
        let request = PlanRequest {
            count: *count,
            ..request.clone()
        };
        let plan = match pool.plan(&request, &mut Quiet) {
            Err(Error::TooFewEquations { .. }) => {
                curve.push(CurvePoint {
                    count: *count,
                    planned: None,
                    random: None,
                });
                continue;
            }
            other => other?,
        };
        let planned = predicted(&Samples::from(plan.samples.as_slice()))?;
        let mut random = Some(0.0);
        for _ in 0..RANDOM_DRAWS {
            let design = pool.random_design(request.kept, plan.chosen.len(), &mut sampler);
            random = match (random, predicted(&design)?) {
                (Some(sum), Some(value)) => Some(sum + value / RANDOM_DRAWS as f64),
                _ => None,
            };
        }
        curve.push(CurvePoint {
            count: plan.samples.len(),
            planned,
            random,
        });
    }
    report(
        observer,
        Progress::Step {
            done: counts.len(),
            total: counts.len(),
        },
    )?;
    Ok(curve)
}
