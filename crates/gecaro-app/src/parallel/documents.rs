//! The JSON documents of the parallel robots' jobs (m, rad; gains
//! dimensionless), for `--json`, the web page and Python.

use gecaro_calib::parallel_robots::{
    PlatformErrors, PlatformIdentification, PlatformRankReport, PlatformRegion,
};
use gecaro_core::parallel_model::{ParallelModel, ParameterUnit};
use gecaro_core::parallel_robot::ParallelRobot;
use serde::Serialize;

use crate::documents::PoseJson;

/// The identifiable parameters of a platform.
#[derive(Clone, Debug, Serialize)]
pub struct PlatformRankDocument {
    /// `frame`, `position` or `distance`.
    pub method: &'static str,
    /// Equations (rows of W).
    pub equations: usize,
    /// How many parameters are identifiable.
    pub rank: usize,
    /// Every parameter's name and status (`identifiable`, `regrouped`,
    /// `no_effect`, `excluded`).
    pub parameters: Vec<(String, &'static str)>,
    /// What each regrouped parameter's effect is carried by.
    pub regrouped: Vec<PlatformRelationDocument>,
    /// The condition number of the identifiable columns.
    pub condition_number: f64,
    /// Where the equations were formed.
    pub source: String,
}

/// A regrouping relation.
#[derive(Clone, Debug, Serialize)]
pub struct PlatformRelationDocument {
    /// The regrouped parameter.
    pub parameter: String,
    /// `(identifiable parameter, coefficient)`.
    pub into: Vec<(String, f64)>,
}

impl PlatformRankDocument {
    /// The document of a report on equations from `source`.
    pub fn new(report: &PlatformRankReport, source: String) -> Self {
        Self {
            method: report.measure.name(),
            equations: report.rows,
            rank: report.rank(),
            parameters: report
                .names
                .iter()
                .zip(&report.statuses)
                .map(|(name, status)| (name.clone(), status.as_str()))
                .collect(),
            regrouped: report
                .relations
                .iter()
                .map(|relation| PlatformRelationDocument {
                    parameter: report.names[relation.parameter].clone(),
                    into: relation
                        .terms
                        .iter()
                        .map(|(index, coefficient)| (report.names[*index].clone(), *coefficient))
                        .collect(),
                })
                .collect(),
            condition_number: report.condition_number,
            source,
        }
    }
}

/// A platform's errors at measured configurations.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct PlatformErrorsDocument {
    /// RMS of the position errors (m; of the distances for measured
    /// distances).
    pub position_rms: f64,
    /// The largest position error (m).
    pub position_max: f64,
    /// RMS of the orientation errors (rad), for measured poses.
    pub angle_rms: Option<f64>,
    /// The largest orientation error (rad), for measured poses.
    pub angle_max: Option<f64>,
}

impl From<&PlatformErrors> for PlatformErrorsDocument {
    fn from(errors: &PlatformErrors) -> Self {
        Self {
            position_rms: errors.position_rms,
            position_max: errors.position_max,
            angle_rms: errors.angle_rms,
            angle_max: errors.angle_max,
        }
    }
}

/// One identified parameter.
#[derive(Clone, Debug, Serialize)]
pub struct PlatformParameterDocument {
    /// `a1x`, `l3`, `K6`, `tz`.
    pub name: String,
    /// `m`, `rad`, or `""` for a gain.
    pub unit: &'static str,
    /// `identifiable`, `regrouped`, `no_effect` or `excluded`.
    pub status: &'static str,
    /// The nominal value.
    pub nominal: f64,
    /// The identified value.
    pub identified: f64,
    /// Its standard deviation, when identified.
    pub sigma: Option<f64>,
}

/// An identification of a platform.
#[derive(Clone, Debug, Serialize)]
pub struct PlatformIdentificationDocument {
    /// The robot's name.
    pub robot: String,
    /// `frame`, `position` or `distance`.
    pub method: &'static str,
    /// The data's label.
    pub data: String,
    /// Measured configurations.
    pub configurations: usize,
    /// The verdict (`fits_noise`, `exceeds_noise`, `below_noise`,
    /// `untested`, `implausible`, `not_converged`, `diverged`).
    pub outcome: &'static str,
    /// The verdict in words.
    pub summary: String,
    /// σ̂/σ of the χ² test, when σ was stated.
    pub sigma_ratio: Option<f64>,
    /// Gauss–Newton iterations.
    pub iterations: usize,
    /// RMS of the equations' residuals before and after (m).
    pub rms_before: f64,
    /// See `rms_before`.
    pub rms_after: f64,
    /// The direct model's errors at the measured configurations, nominal
    /// and calibrated.
    pub errors_before: PlatformErrorsDocument,
    /// See `errors_before`.
    pub errors_after: PlatformErrorsDocument,
    /// Identifiable parameters.
    pub rank: usize,
    /// Every parameter.
    pub parameters: Vec<PlatformParameterDocument>,
    /// Regrouped parameters and what carries them.
    pub regrouped: Vec<PlatformRelationDocument>,
    /// Where the result holds; `null` for a fit that is no solution.
    pub region: Option<PlatformRegionDocument>,
    /// The base frame in the instrument's frame, when the data were
    /// measured in another frame and registered before the fit.
    pub registered: Option<PoseJson>,
    /// The measurements that stand out from the fit (at most ten, the
    /// largest first): their line and their residual in units of the
    /// stated σ (of σ̂ without one).
    pub outliers: Vec<PlatformOutlierDocument>,
    /// What the verdict adds (a predicted error over the workspace above
    /// the noise floor).
    pub warnings: Vec<String>,
    /// The file the calibrated robot was written to.
    pub written: Option<String>,
    /// The loss the fit minimised: `l2`, or a robust one with its scale
    /// (`huber (k = 1.345 σ̂)`).
    pub loss: String,
    /// Reweightings of a robust loss (0 for least squares).
    pub reweightings: usize,
    /// The robust σ̂ of a row its weights were formed with (in units of
    /// the stated σ; m without one); `null` for least squares.
    pub robust_sigma: Option<f64>,
    /// Measurements a robust loss weighed below one half.
    pub weighed_down: usize,
    /// Of them, those it gave no weight at all (a redescending loss).
    pub ignored: usize,
    /// The measurements dropped before the fit (`reject`): their line and
    /// their residual in the fit with them.
    pub rejected: Vec<PlatformOutlierDocument>,
    /// The prior the fit was held by, in words (`1 mm, 0.05°, 0.1 %`).
    pub prior: Option<String>,
    /// The block of measurements that disagrees with the rest in the
    /// file's row order (the cell changed during the run; outcome
    /// `changed`), as a serial identification's `changes` are written.
    pub change: Option<crate::documents::CellChangeJson>,
    /// Each later data file's station (several files, each measured from
    /// its own tracker station; empty for one file): where the base frame
    /// is seen from it.
    pub stations: Vec<PlatformStationDocument>,
    /// The measuring leg of the `leg` method, identified.
    pub leg: Option<PlatformLegDocument>,
}

/// A measuring leg, identified with the platform (m).
#[derive(Clone, Debug, Serialize)]
pub struct PlatformLegDocument {
    /// Its base socket's centre, in the base frame.
    pub base: [f64; 3],
    /// Its platform socket's centre, in the platform frame.
    pub platform: [f64; 3],
    /// Its length at reading 0.
    pub length: f64,
    /// Its gain, as stated.
    pub gain: f64,
    /// σ of `base`, `platform` and `length`, in that order.
    pub sigma: [f64; 7],
    /// Its length at reading 0 as the data gave it on the nominal platform
    /// (the start of the fit).
    pub stated_length: f64,
}

/// A later data file's tracker station, identified with the platform.
#[derive(Clone, Debug, Serialize)]
pub struct PlatformStationDocument {
    /// The data file measured from it.
    pub data: String,
    /// The base frame in the station's frame (m, rad): what its data are
    /// read in.
    pub frame: PoseJson,
    /// σ of the station's position along the base frame's axes (m).
    pub sigma_position: [f64; 3],
    /// σ of its orientation about the base frame's axes (rad).
    pub sigma_rotation: [f64; 3],
}

impl PlatformIdentificationDocument {
    /// The parameters of a result.
    pub(super) fn parameters(
        robot: &ParallelRobot,
        result: &PlatformIdentification<ParallelRobot>,
    ) -> Vec<PlatformParameterDocument> {
        result
            .parameters
            .iter()
            .enumerate()
            .map(|(index, parameter)| PlatformParameterDocument {
                name: parameter.name.clone(),
                unit: match robot.parameter_unit(index) {
                    ParameterUnit::Length => "m",
                    ParameterUnit::Angle => "rad",
                    ParameterUnit::Gain => "",
                },
                status: parameter.status.as_str(),
                nominal: parameter.nominal,
                identified: parameter.identified,
                sigma: parameter.sigma,
            })
            .collect()
    }
}

/// Where a platform's calibration holds (see
/// [`gecaro_calib::parallel_robots::PlatformRegion`]): actuator ranges as
/// `[min, max]` (m for a leg, rad for an arm's motor), errors in metres.
#[derive(Clone, Debug, Serialize)]
pub struct PlatformRegionDocument {
    /// The actuator values the data covered.
    pub measured: Vec<[f64; 2]>,
    /// The region the platform is used in: the actuators' ranges, or the
    /// one stated.
    pub work: Vec<[f64; 2]>,
    /// Whether `work` is the actuators' ranges (not a stated region).
    pub work_is_ranges: bool,
    /// Where the platform is used, in words (`the workspace`, or `the
    /// stated work region`).
    pub work_name: &'static str,
    /// RMS of the predicted tool-point error at the measured poses.
    pub predicted_inside: f64,
    /// RMS of the predicted tool-point error over the workspace.
    pub predicted_work: f64,
    /// The largest predicted tool-point error at a pose of the workspace.
    pub predicted_work_max: f64,
    /// What a held-out position measurement of a perfect platform shows
    /// (√3 σ̂).
    pub noise_floor: f64,
    /// Actuators (1-based) whose measured range covers less than half of
    /// their work range.
    pub narrow_actuators: Vec<usize>,
    /// Actuators (1-based) that never moved.
    pub still_actuators: Vec<usize>,
    /// Whether the result holds over the whole workspace.
    pub holds_everywhere: bool,
    /// Whether the errors are of a distance from the home pose's tool
    /// point (the data measured distances, which observe no base frame),
    /// not of the tool point.
    pub distances: bool,
    /// What is predicted, in words (`tool-point error`, or `error of a
    /// distance from the home pose`).
    pub error: &'static str,
}

impl From<&PlatformRegion> for PlatformRegionDocument {
    fn from(region: &PlatformRegion) -> Self {
        let pairs = |ranges: &[(f64, f64)]| ranges.iter().map(|(a, b)| [*a, *b]).collect();
        Self {
            measured: pairs(region.measured.ranges()),
            work: pairs(region.work.ranges()),
            work_is_ranges: region.work_is_ranges,
            work_name: region.work_words(),
            predicted_inside: region.inside,
            predicted_work: region.work_rms,
            predicted_work_max: region.work_max,
            noise_floor: region.floor,
            narrow_actuators: region.narrow_actuators(),
            still_actuators: region.still_actuators.clone(),
            holds_everywhere: region.holds_everywhere,
            distances: region.distances,
            error: region.error_words(),
        }
    }
}

/// A registered frame as a document.
pub(super) fn pose_document(pose: &nalgebra::Isometry3<f64>) -> PoseJson {
    (&nalgebra::IsometryMatrix3::from_parts(pose.translation, pose.rotation.to_rotation_matrix()))
        .into()
}

/// A measurement that stands out from a platform's fit.
#[derive(Clone, Debug, Serialize)]
pub struct PlatformOutlierDocument {
    /// Its data file, when the fit read several (`None` for one).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub data: Option<String>,
    /// Its line in the data file (a distance's pair by its first row).
    pub line: Option<usize>,
    /// The RMS of its residuals in units of the stated σ (of σ̂ without one).
    pub ratio: f64,
}
