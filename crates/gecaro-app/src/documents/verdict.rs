//! An identification's verdict as a document: what it says and where it
//! holds (the noise test, repeatability, the sets, a change, the region).

use gecaro_calib::identification::{NOISE_TEST_LEVEL, SIGMA_MARGIN, Verdict};
use serde::Serialize;

/// The verdict of an identification (see
/// [`gecaro_calib::identification::Verdict`]); lengths in metres, angles in
/// radians.
#[derive(Clone, Debug, Serialize)]
pub struct VerdictJson {
    /// `fits_noise`, `untested`, `incomplete`, `regional`, `below_noise`,
    /// `exceeds_noise`, `implausible`, `underdetermined`, `degenerate`,
    /// `not_converged` or `diverged`.
    pub outcome: &'static str,
    /// Whether the result may be used (`fits_noise` or `untested`).
    pub trusted: bool,
    /// The verdict in one sentence.
    pub summary: String,
    /// The global test, when every measurement set states its σ.
    pub noise_test: Option<NoiseTestJson>,
    /// The noise the data's repeated poses measure, and the lack-of-fit
    /// test against it (the fit's judge when there are repeats).
    pub repeatability: Option<RepeatabilityJson>,
    /// Residual standard deviation of the length rows (m).
    pub residual_length: Option<f64>,
    /// Residual standard deviation of the angle rows (rad).
    pub residual_angle: Option<f64>,
    /// Configurations in the data.
    pub configurations: usize,
    /// Distinct configurations among them.
    pub distinct_configurations: usize,
    /// Measurements that are exact copies of others (the same file twice,
    /// rows pasted again).
    pub copies: usize,
    /// Parameters with values no real robot has: `name`, `why`, `cause`.
    pub implausible: Vec<ImplausibleJson>,
    /// What the data determine and the methods observe.
    pub coverage: CoverageJson,
    /// Blocks of consecutive observations that disagree with the rest: the
    /// cell changed during the measurement.
    pub changes: Vec<CellChangeJson>,
    /// Every set's σ̂/σ at the solution (studies of several sets):
    /// `{"label", "sigma_ratio"}`.
    pub sets: Vec<SetFitJson>,
    /// The set that disagrees with the rest, when the global test fails and
    /// leaving it out makes the others fit.
    pub disagreement: Option<DisagreementJson>,
    /// A set whose measurements belong to other rows' configurations (a
    /// join off by a few rows).
    pub shifted_join: Option<ShiftedJoinJson>,
    /// Where the result holds: the calibrated robot's predicted error in
    /// the measured region and over the work region; `null` where no
    /// prediction is made (a study that does not measure the scale).
    pub region: Option<RegionJson>,
}

/// The noise repeated poses measure (see
/// [`gecaro_calib::identification::Repeatability`]).
#[derive(Clone, Debug, Serialize)]
pub struct RepeatabilityJson {
    /// Poses measured more than once.
    pub poses: usize,
    /// Their observations.
    pub observations: usize,
    /// Degrees of freedom of the pure error.
    pub degrees_of_freedom: usize,
    /// The noise they measure, in units of the stated σ (metres without one).
    pub sigma_ratio: f64,
    /// The lack-of-fit statistic F.
    pub lack_of_fit: f64,
    /// Its quantile at 1 − 1 %.
    pub critical: f64,
    /// Whether the residuals fit the measured noise.
    pub passed: bool,
}

/// One set's fit at the solution.
#[derive(Clone, Debug, Serialize)]
pub struct SetFitJson {
    /// The set's label.
    pub label: String,
    /// Its σ̂/σ.
    pub sigma_ratio: f64,
}

/// The set of a study that disagrees with the rest (see
/// [`gecaro_calib::identification::Disagreement`]).
#[derive(Clone, Debug, Serialize)]
pub struct DisagreementJson {
    /// The set (0-based).
    pub set: usize,
    /// Its label.
    pub label: String,
    /// σ̂/σ of the other sets identified without it.
    pub rest_ratio: f64,
    /// σ̂/σ of the study as a whole.
    pub whole_ratio: f64,
    /// The set's RMS error at the robot the others give (m).
    pub error: f64,
}

/// A set joined a few rows off (see
/// [`gecaro_calib::identification::ShiftedJoin`]).
#[derive(Clone, Debug, Serialize)]
pub struct ShiftedJoinJson {
    /// The set (0-based).
    pub set: usize,
    /// Its label.
    pub label: String,
    /// The measurement of row i belongs to the configuration of row i − shift.
    pub shift: isize,
    /// Residual RMS of the identification as read and with the shift.
    pub rms_as_read: f64,
    /// See `rms_as_read`.
    pub rms_shifted: f64,
}

/// A block of consecutive observations of one set that disagrees with the
/// rest (see [`gecaro_calib::identification::CellChange`]).
#[derive(Clone, Debug, Serialize)]
pub struct CellChangeJson {
    /// The set (0-based) and its label.
    pub set: usize,
    /// Its label (usually its data file).
    pub label: String,
    /// The block's first and last observations (1-based, in the set).
    pub observations: Vec<usize>,
    /// The block's first and last lines of the data file, when known.
    pub lines: Option<Vec<usize>>,
    /// Whether the block runs to the set's last observation.
    pub to_end: bool,
    /// Outliers in the block.
    pub outliers_inside: usize,
    /// Outliers of the set outside it.
    pub outliers_elsewhere: usize,
    /// The chance of so dense a block among independent outliers.
    pub chance: f64,
}

impl From<&gecaro_calib::identification::CellChange> for CellChangeJson {
    fn from(change: &gecaro_calib::identification::CellChange) -> Self {
        Self {
            set: change.set,
            label: change.label.clone(),
            observations: vec![change.first + 1, change.last + 1],
            lines: change.lines.map(|(first, last)| vec![first, last]),
            to_end: change.to_end(),
            outliers_inside: change.outliers_inside,
            outliers_elsewhere: change.outliers_elsewhere,
            chance: change.chance,
        }
    }
}

/// Where an identification's result holds (see
/// [`gecaro_calib::identification::RegionPrediction`]); joint ranges as
/// `[min, max]` per joint in radians (metres for a prismatic joint),
/// errors in metres.
#[derive(Clone, Debug, Serialize)]
pub struct RegionJson {
    /// The joint ranges the data covered.
    pub measured: Vec<Vec<f64>>,
    /// The region the robot is used in: the joint limits, or the one stated.
    pub work: Vec<Vec<f64>>,
    /// Whether `work` is the joint limits.
    pub work_is_limits: bool,
    /// RMS of the predicted position error at the measured configurations.
    pub predicted_inside: f64,
    /// RMS of the predicted position error over the work region.
    pub predicted_work: f64,
    /// The largest predicted position error at a configuration of the work region.
    pub predicted_work_max: f64,
    /// What a held-out position measurement of a perfect robot shows (√3 σ̂).
    pub noise_floor: f64,
    /// Joints (1-based) whose measured range covers less than half their
    /// work range.
    pub narrow_joints: Vec<usize>,
    /// Whether the result holds over the work region.
    pub holds_everywhere: bool,
}

/// What the data of an identification determine and its methods observe
/// (see [`gecaro_calib::identification::Coverage`]).
#[derive(Clone, Debug, Serialize)]
pub struct CoverageJson {
    /// Joints (1-based) that never moved in the data.
    pub still_joints: Vec<usize>,
    /// Base parameters the data do not excite.
    pub not_excited: Vec<String>,
    /// Independent equations of the data.
    pub equations: usize,
    /// Identified unknowns.
    pub unknowns: usize,
    /// Whether the equations are too few for the unknowns.
    pub low_redundancy: bool,
    /// The robot's scale when no set observes it: its relative σ and the
    /// size the paper's base set alone gave; `null` when measured.
    pub scale: Option<UnobservedScaleJson>,
    /// Whether the methods observe the tool (frame n+1).
    pub tool_observed: bool,
    /// Whether the methods observe the base (frame 0).
    pub base_observed: bool,
}

/// The robot's scale when no measurement set observes it.
#[derive(Clone, Debug, Serialize)]
pub struct UnobservedScaleJson {
    /// Relative standard deviation of the scale kept (0.009: ±0.9 %).
    pub std: f64,
    /// Size of the base-set solution relative to the robot kept.
    pub base_set_scale: f64,
}

/// A parameter whose identified value no real robot has.
#[derive(Clone, Debug, Serialize)]
pub struct ImplausibleJson {
    /// Its name.
    pub name: String,
    /// Why it is implausible.
    pub why: String,
    /// Its likely cause.
    pub cause: String,
}

/// Two identified parameters whose estimates are strongly correlated.
#[derive(Clone, Debug, Serialize)]
pub struct CorrelatedJson {
    /// One parameter.
    pub a: String,
    /// The other.
    pub b: String,
    /// Their correlation coefficient ρ.
    pub rho: f64,
}

/// The global test of the residuals against the stated σ.
#[derive(Clone, Debug, Serialize)]
pub struct NoiseTestJson {
    /// `Σ (r/σ)²`.
    pub chi_square: f64,
    /// Its degrees of freedom.
    pub degrees_of_freedom: usize,
    /// The χ² quantile at 1 − level times (1 + sigma_margin)²: above it the
    /// residuals exceed the noise.
    pub critical: f64,
    /// The χ² quantile at the level divided by (1 + sigma_margin)²: below it
    /// they are too small for it.
    pub critical_low: f64,
    /// The test's significance level (each side).
    pub level: f64,
    /// How well the stated σ is taken to be known (0.05: ±5 %).
    pub sigma_margin: f64,
    /// σ̂/σ.
    pub sigma_ratio: f64,
    /// Whether the residuals fit the stated noise.
    pub passed: bool,
}

impl From<&Verdict> for VerdictJson {
    fn from(verdict: &Verdict) -> Self {
        VerdictJson {
            outcome: verdict.outcome.as_str(),
            trusted: verdict.outcome.trusted(),
            summary: verdict.summary.clone(),
            noise_test: verdict.noise_test.map(|test| NoiseTestJson {
                chi_square: test.chi_square,
                degrees_of_freedom: test.degrees_of_freedom,
                critical: test.critical,
                critical_low: test.critical_low,
                level: NOISE_TEST_LEVEL,
                sigma_margin: SIGMA_MARGIN,
                sigma_ratio: test.sigma_ratio,
                passed: test.passed,
            }),
            repeatability: verdict.repeatability.as_ref().map(|r| RepeatabilityJson {
                poses: r.poses,
                observations: r.observations,
                degrees_of_freedom: r.degrees_of_freedom,
                sigma_ratio: r.sigma_ratio,
                lack_of_fit: r.lack_of_fit,
                critical: r.critical,
                passed: r.passed(),
            }),
            residual_length: verdict.residual_length,
            residual_angle: verdict.residual_angle,
            configurations: verdict.configurations,
            distinct_configurations: verdict.distinct_configurations,
            copies: verdict.copies,
            implausible: verdict
                .implausible
                .iter()
                .map(|p| ImplausibleJson {
                    name: p.name.clone(),
                    why: p.why.clone(),
                    cause: p.cause.clone(),
                })
                .collect(),
            coverage: CoverageJson {
                still_joints: verdict.coverage.still_joints.clone(),
                not_excited: verdict.coverage.not_excited.clone(),
                equations: verdict.coverage.equations,
                unknowns: verdict.coverage.unknowns,
                low_redundancy: verdict.coverage.low_redundancy(),
                scale: verdict.coverage.scale.map(|scale| UnobservedScaleJson {
                    std: scale.std,
                    base_set_scale: scale.base_set_scale,
                }),
                tool_observed: verdict.coverage.tool_observed,
                base_observed: verdict.coverage.base_observed,
            },
            changes: verdict.changes.iter().map(Into::into).collect(),
            sets: verdict
                .sets
                .iter()
                .map(|set| SetFitJson {
                    label: set.label.clone(),
                    sigma_ratio: set.sigma_ratio,
                })
                .collect(),
            disagreement: verdict.disagreement.as_ref().map(|d| DisagreementJson {
                set: d.set,
                label: d.label.clone(),
                rest_ratio: d.rest_ratio,
                whole_ratio: d.whole_ratio,
                error: d.error,
            }),
            shifted_join: verdict.shifted_join.as_ref().map(|join| ShiftedJoinJson {
                set: join.set,
                label: join.label.clone(),
                shift: join.shift,
                rms_as_read: join.rms_as_read,
                rms_shifted: join.rms_shifted,
            }),
            region: verdict.region.as_ref().map(|region| {
                let ranges = |region: &gecaro_core::JointRegion| {
                    region.ranges().iter().map(|(a, b)| vec![*a, *b]).collect()
                };
                RegionJson {
                    measured: ranges(&region.measured),
                    work: ranges(&region.work),
                    work_is_limits: region.work_is_limits,
                    predicted_inside: region.inside,
                    predicted_work: region.work_rms,
                    predicted_work_max: region.work_max,
                    noise_floor: region.floor,
                    narrow_joints: region.narrow_joints(),
                    holds_everywhere: region.holds_everywhere,
                }
            }),
        }
    }
}
