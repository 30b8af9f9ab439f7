//! How accurate the calibrated robot will be, before measuring: the
//! precision of every identifiable parameter and the error of the calibrated
//! robot at test poses, predicted from the planned configurations and the
//! sensor's σ — and the same figures measured by Monte Carlo.
//!
//! With W_b the base columns at the nominal robot (Appendix III) of the
//! planned configurations, and independent sensor noise of standard
//! deviation σ on every row, the identified base parameters have covariance
//! C = σ² (W_bᵀW_b)⁻¹ (eq. 11). At a test configuration q the calibrated
//! robot's remaining position error is J_p(q) δη_b (J_p: the position rows of
//! the Jacobian, base columns; the regrouped parameters act through the base
//! ones at every configuration), with covariance J_p C J_pᵀ, so its expected
//! squared norm is trace(J_p C J_pᵀ). Reported: the RMS over the test poses
//! and the largest per-pose RMS, and likewise for orientation (rows 3–5) for
//! methods that measure it.
//!
//! The test-pose errors concern what the data can identify: link, plane and
//! distance data do not see the robot's world frame (nor, alone, its scale),
//! so the real robot's error there stays in a calibrated robot's absolute
//! errors and is not in the prediction.
//!
//! What the prediction assumes: first order (errors small enough that W_b at
//! the nominal robot stands for W_b at the real one, and the regrouped
//! parameters' second-order effect negligible — docs/performance.md#python),
//! independent noise of equal σ on every row (the rows of link sets are
//! centred, which correlates them: the prediction is then approximate), and
//! an identification that converges.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, PoisonError};

use gecaro_core::{ChainBuffer, JacobianRows, KinematicModel, PriorityMatrix, Robot};
use nalgebra::DMatrix;

use crate::Error;
use crate::identification::{IdentificationOptions, identify_fit};
use crate::method::CalibrationMethod;
use crate::observation::ObservationSystem;
use crate::parallel::run_parts;
use crate::planning::{BaseColumns, nominal_study};
use crate::progress::{Observer, Progress, Quiet, report};
use crate::sampler::Sampler;
use crate::samples::SampleSlice;
use crate::simulation::{perturbed_robot, simulate_at};
use crate::study::Study;

/// Test poses are drawn from their own stream, apart from a pool's.
const TEST_POSE_STREAM: u64 = 0x7e57_7e57;

/// `count` test poses (motor variables) drawn uniformly within the joint
/// limits, from a stream of their own for `seed` (so they are not the
/// configurations of a pool generated with the same seed).
pub fn random_test_poses(robot: &Robot, count: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut sampler = Sampler::new(seed ^ TEST_POSE_STREAM);
    (0..count).map(|_| sampler.configuration(robot)).collect()
}

/// Errors of a calibrated robot at test poses (metres; radians).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct PoseErrors {
    /// RMS of the position error over the test poses.
    pub position_rms: f64,
    /// The largest per-pose RMS position error.
    pub position_max: f64,
    /// RMS of the orientation error, for methods that measure orientation.
    pub rotation_rms: Option<f64>,
    /// The largest per-pose RMS orientation error.
    pub rotation_max: Option<f64>,
}

/// The predicted precision of a plan.
#[derive(Clone, Debug)]
pub struct Prediction {
    /// Every identifiable parameter (auxiliary unknowns first) with its
    /// predicted standard deviation (eq. 11 with the sensor's σ).
    pub parameters: Vec<(String, f64)>,
    /// The predicted errors of the calibrated robot at the test poses.
    pub errors: PoseErrors,
}

/// Per-pose squared errors, summed: position, orientation.
fn pose_errors(position: &[f64], rotation: Option<&[f64]>, runs: f64) -> PoseErrors {
    let summary = |squares: &[f64]| {
        let mean = squares.iter().sum::<f64>() / (squares.len().max(1) as f64 * runs);
        let worst = squares.iter().copied().fold(0.0, f64::max) / runs;
        (mean.sqrt(), worst.sqrt())
    };
    let (position_rms, position_max) = summary(position);
    let rotation = rotation.map(summary);
    PoseErrors {
        position_rms,
        position_max,
        rotation_rms: rotation.map(|r| r.0),
        rotation_max: rotation.map(|r| r.1),
    }
}

/// Predicts the precision of measuring `planned` with `method` on `robot`
/// with a sensor of standard deviation `noise`, and the calibrated robot's
/// errors at `test_poses` (motor variables); see the module docs.
///
/// # Errors
/// Invalid configurations, too few equations for the base set, or a
/// singular W_b.
pub fn predict(
    robot: &Robot,
    method: &dyn CalibrationMethod,
    planned: SampleSlice<'_>,
    noise: f64,
    test_poses: &[Vec<f64>],
    priority: &PriorityMatrix,
) -> Result<Prediction, Error> {
    let base = BaseColumns::of(robot, method, planned, priority)?;
    predict_in(&base, robot, method, planned, noise, test_poses)
}

/// [`predict`] in base columns already known (a candidate pool's).
pub(crate) fn predict_in(
    base: &BaseColumns,
    robot: &Robot,
    method: &dyn CalibrationMethod,
    planned: SampleSlice<'_>,
    noise: f64,
    test_poses: &[Vec<f64>],
) -> Result<Prediction, Error> {
    let system = base.system(robot, method, planned)?;
    let full = method.jacobian_rows() == JacobianRows::Full;
    predicted(base, robot, &system, noise, full, test_poses)
}

/// Predicts the precision of a study — several sets, each with its method,
/// sensor σ, tool and station ([`crate::frames`]), measured at the
/// configurations of its samples — and the calibrated robot's errors at
/// `test_poses`: as [`predict`], every set's rows weighted by 1/σ of its
/// sensor (eq. 11 for a weighted W_b: C = (W_bᵀW_b)⁻¹), the named frames'
/// unknowns among the columns. The configurations are what counts: the
/// samples' readings, if any, are replaced by the nominal robot's.
///
/// # Errors
/// A set without σ, invalid configurations, too few equations for the base
/// set, or a singular W_b.
pub fn predict_study(
    robot: &Robot,
    study: &Study,
    test_poses: &[Vec<f64>],
    priority: &PriorityMatrix,
) -> Result<Prediction, Error> {
    if let Some(set) = study.sets.iter().find(|set| !set.states_sigma()) {
        return Err(Error::InvalidData {
            line: None,
            message: format!(
                "{}: a prediction needs the sensor's σ of every measurement set",
                set.label
            ),
        });
    }
    let study = nominal_study(robot, study)?;
    study.check(robot)?;
    let base = BaseColumns::of_study(robot, &study, priority)?;
    let system = base.system_of_study(robot, &study)?;
    let full = study
        .sets
        .iter()
        .any(|set| set.method.jacobian_rows() == JacobianRows::Full);
    predicted(&base, robot, &system, 1.0, full, test_poses)
}

/// The prediction from W_b (`system`, rows weighted or not) and the σ of
/// its rows (`noise`; 1 for rows weighted by 1/σ); orientation errors when
/// `full`.
fn predicted(
    base: &BaseColumns,
    robot: &Robot,
    system: &ObservationSystem,
    noise: f64,
    full: bool,
    test_poses: &[Vec<f64>],
) -> Result<Prediction, Error> {
    let w = DMatrix::from_row_slice(system.rows(), base.layout.columns(), system.matrix());
    let information = w.transpose() * &w;
    // Conditioning judged in the error units, where a well-posed W_b has a
    // condition number of 10²–10⁴: beyond 10⁸ it determines nothing.
    let scaled = DMatrix::from_fn(information.nrows(), information.ncols(), |i, j| {
        information[(i, j)] * base.scale[i] * base.scale[j]
    })
    .symmetric_eigenvalues();
    let singular = || Error::Numerical {
        message: "the planned configurations do not determine the identifiable parameters \
                  (W_bᵀW_b is singular): plan more or other configurations"
            .into(),
    };
    let (smallest, largest) = (scaled.min(), scaled.max());
    if smallest.is_nan() || smallest <= 1e-16 * largest {
        return Err(singular());
    }
    let covariance = information.cholesky().ok_or_else(singular)?.inverse() * (noise * noise);
    let parameters = base
        .names
        .iter()
        .cloned()
        .enumerate()
        .map(|(column, name)| (name, covariance[(column, column)].max(0.0).sqrt()))
        .collect();
    let mut position = Vec::with_capacity(test_poses.len());
    let mut rotation = Vec::with_capacity(test_poses.len());
    for jacobian in base.pose_jacobians(robot, test_poses, false)? {
        let propagated = &jacobian * &covariance * jacobian.transpose();
        position.push((0..3).map(|i| propagated[(i, i)]).sum::<f64>());
        rotation.push((3..6).map(|i| propagated[(i, i)]).sum::<f64>());
    }
    Ok(Prediction {
        parameters,
        errors: pose_errors(&position, full.then_some(&rotation[..]), 1.0),
    })
}

/// What repeated simulated calibrations measured.
#[derive(Clone, Debug)]
pub struct MonteCarlo {
    /// Calibrations run (converged or not).
    pub runs: usize,
    /// Calibrations that did not converge (their best iterate is counted).
    pub not_converged: usize,
    /// The calibrated robots' errors against their real robots at the test poses.
    pub errors: PoseErrors,
}

/// The simulated calibrations of a [`monte_carlo`] check.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimulatedRuns {
    /// How many calibrations.
    pub runs: usize,
    /// Run r's real robot and noise are drawn from seed `seed + r`.
    pub seed: u64,
    /// The measurements' noise σ (metres; radians for orientations).
    pub noise: f64,
    /// How far each real robot is drawn from the nominal one
    /// ([`perturbed_robot`]'s level).
    pub error_level: f64,
}

/// Monte Carlo check of [`predict`]: `runs.runs` calibrations, each of a real
/// robot drawn at `runs.error_level` (seeded by `runs.seed` + run), measured
/// at `planned` with noise σ = `runs.noise` and identified; their errors at
/// `test_poses` against the real robot. Runs on all cores; the result does
/// not depend on their number. Each finished run is reported to `observer`,
/// which may stop the work.
///
/// # Errors
/// The first failed simulation or identification, or [`Error::Interrupted`].
pub fn monte_carlo(
    robot: &Robot,
    method: &dyn CalibrationMethod,
    planned: SampleSlice<'_>,
    test_poses: &[Vec<f64>],
    simulated: SimulatedRuns,
    options: &IdentificationOptions,
    observer: &mut dyn Observer,
) -> Result<MonteCarlo, Error> {
    let SimulatedRuns {
        runs,
        seed,
        noise,
        error_level,
    } = simulated;
    let full = method.jacobian_rows() == JacobianRows::Full;
    let one = |run: usize| -> Result<(Vec<f64>, Vec<f64>, bool), Error> {
        let mut sampler = Sampler::new(seed.wrapping_add(run as u64));
        let real = perturbed_robot(robot, error_level, &mut sampler)?;
        let data = simulate_at(&real, method, planned, noise, &mut sampler, &mut Quiet)?;
        let study = Study::single(method.clone_method(), data, "simulated");
        let result = identify_fit(robot, &study, options, &mut Quiet)?;
        let (calibrated, real) = (
            KinematicModel::new(&result.calibrated),
            KinematicModel::new(&real),
        );
        let (mut a, mut b) = (ChainBuffer::default(), ChainBuffer::default());
        let mut position = Vec::with_capacity(test_poses.len());
        let mut rotation = Vec::with_capacity(test_poses.len());
        for pose in test_poses {
            let (p, q) = (
                calibrated.terminal_pose(pose, &mut a)?,
                real.terminal_pose(pose, &mut b)?,
            );
            position.push((p.translation.vector - q.translation.vector).norm_squared());
            rotation.push((p.rotation.inverse() * q.rotation).angle().powi(2));
        }
        Ok((position, rotation, result.failure().is_some()))
    };
    // Runs go in parallel; the observer hears of each finished one in turn.
    let observer = Mutex::new(observer);
    let finished = AtomicUsize::new(0);
    let outcomes = run_parts((0..runs).collect(), |run| -> Result<_, Error> {
        let outcome = one(run)?;
        let done = finished.fetch_add(1, Ordering::Relaxed) + 1;
        let mut observer = observer.lock().unwrap_or_else(PoisonError::into_inner);
        report(&mut **observer, Progress::Step { done, total: runs })?;
        Ok(outcome)
    });
    let mut position = vec![0.0; test_poses.len()];
    let mut rotation = vec![0.0; test_poses.len()];
    let mut not_converged = 0;
    for outcome in outcomes {
        let (p, r, failed) = outcome?;
        for (sum, value) in position.iter_mut().zip(p) {
            *sum += value;
        }
        for (sum, value) in rotation.iter_mut().zip(r) {
            *sum += value;
        }
        not_converged += usize::from(failed);
    }
    Ok(MonteCarlo {
        runs,
        not_converged,
        errors: pose_errors(&position, full.then_some(&rotation[..]), runs.max(1) as f64),
    })
}
