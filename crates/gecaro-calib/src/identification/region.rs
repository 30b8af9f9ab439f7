//! Where the result holds: the calibrated robot's predicted error over the
//! region its data covered and over the region it will be used in.
//!
//! A fit explains its data wherever they were taken; its parameters are
//! known only as well as those data excite them. With 120 poses within ±15°
//! of a home pose, σ = 20 µm, the fit passes the global test and its
//! condition number raises no warning, yet a gain or an angle that only
//! interpolates over ±15° is far off over the whole workspace: held out
//! there the calibrated robot was 32× the noise floor (1.12 mm), within the
//! region 1.06×.
//!
//! The prediction is the one of [`crate::prediction`] (eq. 11), with the
//! identification's own posterior covariance `C = σ̂² (W_bᵀW_b)⁻¹`
//! ([`Identification::covariance`], the prior's rows included): at a
//! configuration q the calibrated robot's remaining position error is
//! `J_p(q) δη_b` (J_p: rows 0–2 of the Jacobian of frame n+1, base columns),
//! whose expected squared norm is `trace(J_p C J_pᵀ)`. It is evaluated
//!
//! - **in the measured region**: at up to [`REGION_POSES`] of the data's own
//!   configurations, spread over them;
//! - **over the work region**: at [`WORK_POSES`] configurations drawn
//!   uniformly within the joint limits, or within the work region the user
//!   states ([`IdentificationOptions::work_region`](super::IdentificationOptions::work_region)),
//!   from a fixed seed.
//!
//! The result does not hold everywhere when the work region's RMS exceeds
//! both [`FLOOR_FACTOR`] times the noise floor (`√3 σ̂` of the length rows:
//! what a held-out position measurement of a perfect robot shows; a
//! held-out measurement over the work region then shows more than √5 times
//! it) and [`REGION_FACTOR`] times the measured region's, or when a joint
//! never moved (its parameters are not identified at all, which no
//! covariance shows). Between the floor and twice it, a warning gives both
//! figures: the laser-tracker example's 80 poses within ±68° of joint 1
//! predict 0.059 mm over the joint limits against a floor of 0.037 mm,
//! a calibration good for its work region. The
//! measured region is then the smallest box of joint ranges that holds the
//! data (eq. 4's joint variables of the calibrated robot), which the
//! calibrated robot file carries and compensation and evaluation check.
//!
//! Not predicted: studies that do not measure the robot's scale (link and
//! plane methods alone; their verdict is `incomplete` already), and errors
//! the model does not hold (an unmodelled compliance grows away from the
//! data too, and no covariance sees it).

use gecaro_core::{ChainBuffer, JacobianRows, JointRegion, KinematicModel, Robot};

use super::findings::RegionPrediction;
use super::result::Identification;
use crate::sampler::{Sampler, spread_indices};
use crate::study::Study;

/// Configurations of the work region the error is predicted at.
pub const WORK_POSES: usize = 100;

/// The data's configurations, at most, the error is predicted at.
pub const REGION_POSES: usize = 100;

/// How many times the measured region's predicted error the work region's
/// may be before the result holds in the measured region only (and above
/// [`FLOOR_FACTOR`] times the noise floor).
pub const REGION_FACTOR: f64 = 3.0;

/// How many times the noise floor the work region's predicted error may be
/// before the result holds in the measured region only (and above
/// [`REGION_FACTOR`] times the measured region's).
pub const FLOOR_FACTOR: f64 = 2.0;

/// The work region's configurations are drawn from their own stream.
const WORK_POSE_SEED: u64 = 0x7e61_0a5e;

/// Where `result`, identified from `study`, holds (module docs); `work`
/// the stated work region, else the calibrated robot's joint limits.
/// `None` where no prediction is made: a study that does not measure the
/// scale, no length rows, no covariance, or configurations the robot
/// cannot evaluate.
pub(super) fn where_it_holds(
    study: &Study,
    result: &Identification,
    work: Option<&JointRegion>,
) -> Option<RegionPrediction> {
    if !study.observes_scale() || !result.verdict.outcome.solved() {
        return None;
    }
    let robot = &result.calibrated;
    let covariance = result.covariance.as_ref()?;
    let floor = 3.0_f64.sqrt() * result.verdict.residual_length?;
    let measured = measured_region(robot, study)?;
    let total = study.sets.iter().map(|set| set.samples.len()).sum();
    let mut picked = spread_indices(total, REGION_POSES).into_iter().peekable();
    let inside_poses: Vec<Vec<f64>> = study
        .sets
        .iter()
        .flat_map(|set| set.samples.as_slice().iter())
        .enumerate()
        .filter(|(index, _)| picked.next_if_eq(index).is_some())
        .map(|(_, sample)| sample.motor_positions().to_vec())
        .collect();
    let (work, work_is_limits) = match work {
        Some(region) => (region.clone(), false),
        None => (JointRegion::of_limits(robot), true),
    };
    let mut sampler = Sampler::new(WORK_POSE_SEED);
    let work_poses: Vec<Vec<f64>> = (0..WORK_POSES)
        .map(|_| {
            let q: Vec<f64> = work
                .ranges()
                .iter()
                .map(|(min, max)| sampler.uniform(*min, *max))
                .collect();
            robot.motor_positions(&q).map(|qm| qm.as_slice().to_vec())
        })
        .collect::<Result<_, _>>()
        .ok()?;
    let columns: Vec<usize> = result
        .parameters
        .iter()
        .map(|p| p.parameter.and_then(|id| robot.parameters().index_of(id)))
        .collect::<Option<_>>()?;
    let offset = result.auxiliary.len();
    let width = columns.len();
    let block = covariance
        .view((offset, offset), (width, width))
        .clone_owned();
    let predicted = PointVariance {
        model: KinematicModel::new(robot),
        columns: &columns,
        factor: block.cholesky()?.l(),
    };
    // The two regions' predictions on two cores (0.1 ms each at 500 poses).
    let (inside, work_prediction) = crate::parallel::beside_if_free(
        || predicted.rms(&inside_poses),
        || predicted.rms(&work_poses),
    );
    let inside = inside?.0;
    let (work_rms, work_max) = work_prediction?;
    let still_joints = result.verdict.coverage.still_joints.clone();
    let joints = robot.joint_count();
    let holds_everywhere = still_joints.is_empty()
        && !(work_rms > FLOOR_FACTOR * floor && work_rms > REGION_FACTOR * inside);
    Some(RegionPrediction {
        measured,
        work,
        work_is_limits,
        revolute: robot
            .frames()
            .iter()
            .skip(1)
            .take(joints)
            .map(|frame| frame.frame_type == gecaro_core::FrameType::Revolute)
            .collect(),
        inside,
        work_rms,
        work_max,
        floor,
        still_joints,
        holds_everywhere,
    })
}

/// The smallest box of joint ranges that holds every configuration of
/// `study` (eq. 4's joint variables of `robot`); `None` when a
/// configuration does not fit the robot. Without couplings each joint
/// variable is its motor variable's affine image, so the box is the motor
/// values' mapped (a million configurations read once, nothing converted).
fn measured_region(robot: &Robot, study: &Study) -> Option<JointRegion> {
    let joints = robot.joint_count();
    let map = robot.motor_to_joint();
    let diagonal = (0..joints).all(|i| (0..joints).all(|j| i == j || map[(i, j)] == 0.0));
    let mut joint_positions = vec![0.0; joints];
    let mut measured = JointRegion::covering(joints, std::iter::empty());
    for set in &study.sets {
        let slice = set.samples.as_slice();
        match slice.motor_values().filter(|_| diagonal) {
            Some(values) => {
                let motors = JointRegion::covering(joints, values.chunks_exact(joints));
                for (j, (min, max)) in motors.ranges().iter().enumerate() {
                    if min > max {
                        continue;
                    }
                    let offset = robot.joints()[j].offset;
                    let (a, b) = (map[(j, j)] * min + offset, map[(j, j)] * max + offset);
                    joint_positions.iter_mut().for_each(|q| *q = f64::NAN);
                    joint_positions[j] = a.min(b);
                    measured.include(&joint_positions);
                    joint_positions[j] = a.max(b);
                    measured.include(&joint_positions);
                }
            }
            None => {
                for sample in slice.iter() {
                    robot
                        .joint_positions_into(sample.motor_positions(), &mut joint_positions)
                        .ok()?;
                    measured.include(&joint_positions);
                }
            }
        }
    }
    Some(measured)
}

/// The predicted squared position error `trace(J_p C J_pᵀ)` at a
/// configuration, for the covariance `C = L Lᵀ` of the parameters at
/// `columns` (vocabulary indices): `‖Lᵀ J_pᵀ‖²`.
struct PointVariance<'a> {
    model: KinematicModel,
    columns: &'a [usize],
    /// L, lower triangular.
    factor: nalgebra::DMatrix<f64>,
}

impl PointVariance<'_> {
    /// The RMS and the largest of the predicted position errors at `poses`
    /// (m); `None` when a pose cannot be evaluated or `poses` is empty.
    fn rms(&self, poses: &[Vec<f64>]) -> Option<(f64, f64)> {
        if poses.is_empty() {
            return None;
        }
        let mut chain = ChainBuffer::default();
        let mut rows = Vec::new();
        let count = self.model.parameter_count();
        // Every pose's three rows J_p stacked, then one product with L.
        let mut jacobian = nalgebra::DMatrix::<f64>::zeros(3 * poses.len(), self.columns.len());
        for (at, pose) in poses.iter().enumerate() {
            self.model.forward(pose, &mut chain).ok()?;
            self.model
                .jacobian_rows(&chain, &mut rows, JacobianRows::Position);
            for (column, index) in self.columns.iter().enumerate() {
                for axis in 0..3 {
                    jacobian[(3 * at + axis, column)] = rows[axis * count + index];
                }
            }
        }
        // J_p L, whose squared norm is trace(J_p C J_pᵀ).
        let projected = jacobian * &self.factor;
        let (mut sum, mut largest) = (0.0, 0.0_f64);
        for at in 0..poses.len() {
            let variance = projected.rows(3 * at, 3).norm_squared();
            sum += variance;
            largest = largest.max(variance);
        }
        let rms = (sum / poses.len() as f64).sqrt();
        (rms.is_finite()).then_some((rms, largest.sqrt()))
    }
}
