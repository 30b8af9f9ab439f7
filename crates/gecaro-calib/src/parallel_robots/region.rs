//! Where a parallel robot's calibration holds: its predicted tool-point
//! error at the measured poses and over the whole work region, as a serial
//! robot's (`crate::identification`'s region verdict, `RegionPrediction`).
//!
//! A fit explains its data where they were taken; parameters the data
//! excite over a small part of the workspace only (poses within a few
//! millimetres of home, which barely move the legs) are extrapolated over
//! the rest. The identification's posterior covariance of the base
//! parameters, `C = σ̂²·(W_bᵀW_b)⁻¹` (σ̂ the unit weight's), gives at a pose
//! x the calibrated robot's remaining tool-point error `J_y(x)·δξ_b`
//! (J_y: the tool point's derivative, [`point_derivative`]), whose
//! expected squared norm is `trace(J_y C J_yᵀ)`. It is evaluated
//!
//! - **at the measured poses**: up to [`REGION_POSES`] of the data's own,
//!   spread over them;
//! - **over the work region**: [`WORK_POSES`] poses drawn from a fixed seed
//!   in the box of the moves the actuators' ranges allow alone from home
//!   ([`PlatformWorkspace::whole`]), each with every actuator within range;
//!   or, in a work region the user states (a range of each actuator's
//!   values, as a serial robot's joint ranges), the poses of actuator
//!   values drawn uniformly in it: the direct model from the pose at its
//!   centre (the ranges' middles), a draw it does not solve drawn again.
//!
//! The rule is the serial robots': the result holds in the measured region
//! only when the work region's RMS exceeds both [`FLOOR_FACTOR`] times the
//! noise floor (√3 σ̂ of a position coordinate) and [`REGION_FACTOR`] times
//! the measured poses', or when an actuator never moved. The measured
//! region is then the box of actuator values the data covered, which the
//! calibrated robot's file carries and compensation checks.

use gecaro_core::JointRegion;
use gecaro_core::parallel_model::{ParallelModel, ParameterUnit};
use gecaro_data::sample::Sample;
use nalgebra::{DMatrix, Isometry3, Vector3};

use super::measure::PlatformMeasure;
use super::observation::{actuator_values, point_derivative};
use super::simulation::{PlatformWorkspace, random_platform_poses};
use crate::identification::{FLOOR_FACTOR, REGION_FACTOR, REGION_POSES, WORK_POSES};
use crate::sampler::{Sampler, spread_indices};

/// The work region's poses are drawn from their own stream.
const WORK_POSE_SEED: u64 = 0x7e61_0a5f;

/// An actuator whose measured values span less than this (m or rad) never
/// moved.
const STILL_SPAN: f64 = 1e-9;

/// A measured range below this part of its actuator's range is named as
/// one to measure over more of.
const NARROW_FRACTION: f64 = crate::identification::NARROW_FRACTION;

/// Where a platform's calibration holds; see the module docs.
#[derive(Clone, Debug, PartialEq)]
pub struct PlatformRegion {
    /// The smallest box of actuator values holding every measured
    /// configuration (m for a leg, rad for an arm's motor).
    pub measured: JointRegion,
    /// The region the platform is used in: the actuators' ranges, or the
    /// one stated.
    pub work: JointRegion,
    /// Whether [`work`](Self::work) is the actuators' ranges (not a
    /// stated region).
    pub work_is_ranges: bool,
    /// Whether the actuators turn (their values in degrees in words).
    pub angular: bool,
    /// Whether the errors are a distance's from the home pose's tool point
    /// (the data measured distances, which see no base frame), not the
    /// tool point's.
    pub distances: bool,
    /// RMS of the predicted tool-point error at the measured poses (m).
    pub inside: f64,
    /// RMS of the predicted tool-point error over the work region (m).
    pub work_rms: f64,
    /// The largest predicted tool-point error at a pose of the work region
    /// (m, the RMS of its distribution).
    pub work_max: f64,
    /// What a held-out position measurement of a perfect platform shows:
    /// √3 σ̂ of a position coordinate (m).
    pub floor: f64,
    /// Actuators (1-based) whose value never changed in the data.
    pub still_actuators: Vec<usize>,
    /// Whether the result holds over the work region.
    pub holds_everywhere: bool,
}

impl PlatformRegion {
    /// Actuators (1-based) whose measured range covers less than half of
    /// their work range.
    pub fn narrow_actuators(&self) -> Vec<usize> {
        (0..self.measured.joints())
            .filter(|k| self.measured.fraction_of(&self.work, *k) < NARROW_FRACTION)
            .map(|k| k + 1)
            .collect()
    }

    /// What is predicted, in words: the tool point's error, or a
    /// distance's from the home pose (for measured distances).
    pub fn error_words(&self) -> &'static str {
        if self.distances {
            "error of a distance from the home pose"
        } else {
            "tool-point error"
        }
    }

    /// Where the platform is used, in words: `the workspace` (the
    /// actuators' ranges allow), or `the stated work region`.
    pub fn work_words(&self) -> &'static str {
        if self.work_is_ranges {
            "the workspace"
        } else {
            "the stated work region"
        }
    }

    /// The measured range of actuator `actuator` (1-based) in words:
    /// `qm2 −15.0…30.0 mm`.
    pub fn range_words(&self, actuator: usize) -> String {
        let (min, max) = self.measured.range(actuator - 1);
        if self.angular {
            format!(
                "qm{actuator} {:.1}…{:.1}°",
                min.to_degrees(),
                max.to_degrees()
            )
        } else {
            format!("qm{actuator} {:.1}…{:.1} mm", min * 1e3, max * 1e3)
        }
    }

    /// A warning when the result holds everywhere but its predicted error
    /// over the work region is above the noise floor: both figures.
    pub fn warning(&self) -> Option<String> {
        (self.holds_everywhere && self.work_rms > self.floor).then(|| {
            format!(
                "the calibrated platform is predicted to {:.4} mm over {} ({:.1}× the noise \
                 floor of {:.4} mm), {:.4} mm at the measured poses: measure poses over more of \
                 it to bring it down",
                self.work_rms * 1e3,
                self.work_words(),
                self.work_rms / self.floor,
                self.floor * 1e3,
                self.inside * 1e3,
            )
        })
    }

    /// The verdict's clause when the result does not hold everywhere.
    pub fn words(&self) -> String {
        let narrow = self.narrow_actuators();
        let shown: Vec<usize> = if narrow.is_empty() {
            (1..=self.measured.joints()).collect()
        } else {
            narrow
        };
        let ranges: Vec<String> = shown.iter().map(|k| self.range_words(*k)).collect();
        let still = if self.still_actuators.is_empty() {
            String::new()
        } else {
            let list: Vec<String> = self
                .still_actuators
                .iter()
                .map(ToString::to_string)
                .collect();
            format!(
                "; actuator {} never moved, whose parameters no prediction sees",
                list.join(", ")
            )
        };
        format!(
            "holds only where the data were taken ({}): predicted {:.4} mm over {} (largest \
             {:.4} mm) against {:.4} mm at the measured poses and a noise floor of {:.4} \
             mm{still}; measure poses spread over {}",
            ranges.join(", "),
            self.work_rms * 1e3,
            self.work_words(),
            self.work_max * 1e3,
            self.inside * 1e3,
            self.floor * 1e3,
            if self.work_is_ranges {
                "the whole workspace"
            } else {
                "all of the stated work region"
            },
        )
    }
}

/// Where `calibrated`, identified from `samples`, holds (module docs);
/// `pose_of` gives the platform's pose at a sample (measured or solved), for
/// the covariance `covariance` of the base parameters `base` (the fit) and
/// the noise floor `floor` (m); `work` the stated work region, else the
/// actuators' ranges. Distances observe no base frame, so for them the
/// error predicted is a distance's, from the home pose's tool point:
/// `uᵀ·(J_y(x) − J_y(home))` with u the direction between the two points.
/// `None` when a pose has no derivative (a singular one), the covariance
/// is not positive definite, or the direct model solves too few of the
/// stated work region's actuator values ([`region_poses`]).
pub(super) fn where_it_holds<M: ParallelModel>(
    calibrated: &M,
    measure: PlatformMeasure,
    samples: &[Sample],
    pose_of: impl Fn(usize) -> Option<Isometry3<f64>>,
    (base, covariance): (&[usize], &DMatrix<f64>),
    floor: f64,
    work: Option<&JointRegion>,
) -> Option<PlatformRegion> {
    let count = calibrated.actuator_count();
    let measured = JointRegion::covering(
        count,
        samples
            .iter()
            .filter_map(|sample| actuator_values(calibrated, sample).ok()),
    );
    let ranges =
        JointRegion::new((0..count).map(|k| calibrated.actuator_range(k)).collect()).ok()?;
    let work_is_ranges = work.is_none();
    let work = work.cloned().unwrap_or(ranges);
    let factor = covariance.clone().cholesky()?.l();
    let errors = ErrorRows::new(calibrated, measure)?;
    // trace(J_b C J_bᵀ) = ‖J_b·L‖² (Frobenius) for C = L·Lᵀ.
    let spread = |pose: &Isometry3<f64>, actuators: &[f64]| -> Option<f64> {
        Some((errors.at(pose, actuators, base)? * &factor).norm_squared())
    };
    let rms =
        |variances: &[f64]| (variances.iter().sum::<f64>() / variances.len().max(1) as f64).sqrt();
    let inside: Vec<f64> = spread_indices(samples.len(), REGION_POSES)
        .into_iter()
        .map(|index| {
            let actuators = actuator_values(calibrated, &samples[index]).ok()?;
            spread(&pose_of(index)?, actuators)
        })
        .collect::<Option<_>>()?;
    let mut sampler = Sampler::new(WORK_POSE_SEED);
    let work_poses = if work_is_ranges {
        random_platform_poses(
            calibrated,
            WORK_POSES,
            PlatformWorkspace::whole(calibrated),
            &mut sampler,
        )
        .ok()?
    } else {
        region_poses(calibrated, &work, &mut sampler)?
    };
    let spreads: Vec<f64> = work_poses
        .iter()
        .map(|pose| {
            let actuators = calibrated.actuator_values(pose).ok()?;
            spread(pose, &actuators)
        })
        .collect::<Option<_>>()?;
    let (inside, work_rms) = (rms(&inside), rms(&spreads));
    let work_max = spreads.iter().copied().fold(0.0, f64::max).sqrt();
    let still_actuators: Vec<usize> = (0..count)
        .filter(|k| {
            // An actuator with no measured value (an empty range) is still.
            let (min, max) = measured.range(*k);
            (max - min).partial_cmp(&STILL_SPAN) != Some(std::cmp::Ordering::Greater)
        })
        .map(|k| k + 1)
        .collect();
    let holds_everywhere = still_actuators.is_empty()
        && !(work_rms > FLOOR_FACTOR * floor && work_rms > REGION_FACTOR * inside);
    Some(PlatformRegion {
        measured,
        work,
        work_is_ranges,
        angular: calibrated.actuator_unit() == ParameterUnit::Angle,
        distances: measure == PlatformMeasure::Distance,
        inside,
        work_rms,
        work_max,
        floor,
        still_actuators,
        holds_everywhere,
    })
}

/// The rows of the error a calibration of `model` from `measure` is
/// judged by at a pose, on the parameters' columns: the tool point's
/// derivative `J_y(x)`, or, for measured distances (which see no base
/// frame), the derivative of its distance from the home pose's tool point,
/// `uᵀ·(J_y(x) − J_y(home))` with u the direction between the two points.
pub(super) struct ErrorRows<'a, M> {
    model: &'a M,
    distances: bool,
    home_point: Vector3<f64>,
    home_derivative: DMatrix<f64>,
}

impl<'a, M: ParallelModel> ErrorRows<'a, M> {
    /// `None` when the home pose has no derivative (a singular one).
    pub(super) fn new(model: &'a M, measure: PlatformMeasure) -> Option<Self> {
        let home = model.home();
        let home_actuators = model.actuator_values(&home).ok()?;
        Some(Self {
            model,
            distances: measure == PlatformMeasure::Distance,
            home_point: model.tool_point(&home),
            home_derivative: point_derivative(model, &home, &home_actuators)?,
        })
    }

    /// The rows at `pose` (reached by `actuators`) on the columns `base`;
    /// `None` at a singular pose.
    pub(super) fn at(
        &self,
        pose: &Isometry3<f64>,
        actuators: &[f64],
        base: &[usize],
    ) -> Option<DMatrix<f64>> {
        let mut derivative = point_derivative(self.model, pose, actuators)?;
        if self.distances {
            let direction = (self.model.tool_point(pose) - self.home_point)
                .try_normalize(f64::EPSILON)
                .unwrap_or_default();
            let along = direction.transpose() * (derivative - &self.home_derivative);
            derivative = DMatrix::from_row_slice(1, along.ncols(), along.as_slice());
        }
        Some(DMatrix::from_fn(
            derivative.nrows(),
            base.len(),
            |row, k| derivative[(row, base[k])],
        ))
    }
}

/// Draws per pose kept, at most, before a stated work region is said to
/// hold too few poses the direct model solves.
const DRAWS_PER_POSE: usize = 20;

/// [`WORK_POSES`] poses of `model` with their actuator values drawn
/// uniformly in `region`: the direct model from the pose at its centre (the
/// ranges' middles), a draw it does not solve (no assembly there, or
/// another assembly mode) drawn again. `None` when the centre has no pose
/// or fewer than one draw in [`DRAWS_PER_POSE`] is solved.
pub(super) fn region_poses<M: ParallelModel>(
    model: &M,
    region: &JointRegion,
    sampler: &mut Sampler,
) -> Option<Vec<Isometry3<f64>>> {
    let centre = work_region_centre(model, region).ok()?;
    let mut poses = Vec::with_capacity(WORK_POSES);
    for _ in 0..DRAWS_PER_POSE * WORK_POSES {
        if poses.len() == WORK_POSES {
            break;
        }
        let values: Vec<f64> = region
            .ranges()
            .iter()
            .map(|(min, max)| sampler.uniform(*min, *max))
            .collect();
        if let Ok(pose) = model.direct(&values, &centre) {
            poses.push(pose);
        }
    }
    (poses.len() == WORK_POSES).then_some(poses)
}

/// The pose at the centre of a stated work region: the direct model at the
/// middles of its ranges, from the home pose.
///
/// # Errors
/// [`gecaro_core::Error::NoAssembly`] when no pose puts every actuator
/// there.
pub fn work_region_centre<M: ParallelModel>(
    model: &M,
    region: &JointRegion,
) -> Result<Isometry3<f64>, gecaro_core::Error> {
    let middles: Vec<f64> = region
        .ranges()
        .iter()
        .map(|(min, max)| 0.5 * (min + max))
        .collect();
    model.direct(&middles, &model.home())
}
