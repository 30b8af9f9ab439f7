//! How many configurations are enough: the predicted error of the calibrated
//! robot against the number of configurations, planned versus random.
//!
//! For each count N, a plan of N configurations from the pool
//! ([`crate::plan_configurations`]) and [`RANDOM_DRAWS`] random choices of as
//! many units from the same pool are each given to [`crate::predict`]; the
//! curve holds the planned design's predicted RMS position error at the test
//! poses and the mean of the random ones'. A count whose design does not
//! determine the identifiable parameters has no value.

use std::ops::ControlFlow;

use gecaro_core::{PriorityMatrix, Robot};

use crate::Error;
use crate::methods::CalibrationMethod;
use crate::planning::{PlanRequest, plan_configurations, random_design, units};
use crate::prediction::predict;
use crate::sample::Sample;
use crate::sampler::Sampler;

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
/// each of `counts`). `progress(done, total)` counts the counts and may stop
/// the work.
///
/// # Errors
/// A pool too small for the largest count, invalid samples, or
/// [`Error::Interrupted`].
#[allow(clippy::too_many_arguments)]
pub fn accuracy_curve(
    robot: &Robot,
    method: &dyn CalibrationMethod,
    pool: &[Sample],
    counts: &[usize],
    request: &PlanRequest<'_>,
    noise: f64,
    test_poses: &[Vec<f64>],
    priority: &PriorityMatrix,
    seed: u64,
    mut progress: impl FnMut(usize, usize) -> ControlFlow<()>,
) -> Result<Vec<CurvePoint>, Error> {
    let pool_units = units(method, pool);
    let unit_size = pool.len().max(1) as f64 / pool_units.len().max(1) as f64;
    let mut sampler = Sampler::new(seed);
    let predicted =
        |design: &[Sample]| match predict(robot, method, design, noise, test_poses, priority) {
            Ok(prediction) => Ok(Some(prediction.errors.position_rms)),
            Err(Error::Numerical { .. } | Error::TooFewEquations { .. }) => Ok(None),
            Err(error) => Err(error),
        };
    let mut curve = Vec::with_capacity(counts.len());
    for (done, count) in counts.iter().enumerate() {
        if progress(done, counts.len()).is_break() {
            return Err(Error::Interrupted);
        }
        let request = PlanRequest {
            count: *count,
            ..request.clone()
        };
        let plan = match plan_configurations(robot, method, pool, &request, priority, |_, _| {
            ControlFlow::Continue(())
        }) {
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
        let planned = predicted(&plan.samples)?;
        let wanted =
            ((count.saturating_sub(request.kept.len())) as f64 / unit_size).round() as usize;
        let mut random = Some(0.0);
        for _ in 0..RANDOM_DRAWS {
            let design = random_design(method, pool, request.kept, wanted, &mut sampler);
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
    let _ = progress(counts.len(), counts.len());
    Ok(curve)
}
