//! The results as JSON documents: what `gecaro … --json` prints and what the
//! web API answers, built from the library's result types so that both speak
//! the same shapes (documented in `docs/api.md`).
//!
//! Units: metres and radians everywhere, as in the robot model.

use gecaro_calib::{
    curve::CurvePoint,
    frames::NamedFrame,
    identifiability::{Classified, Identifiability, RankReport},
    identification::{
        ErrorSummary, Identification, IdentifiedParameter, NOISE_TEST_LEVEL, SIGMA_MARGIN,
        StopReason, Verdict,
    },
    observability::Observability,
    planning::{Criterion, DesignQuality, Plan},
    prediction::{MonteCarlo, PoseErrors, Prediction},
    study::Study,
};
use gecaro_core::Robot;
use serde::Serialize;

/// One parameter's identifiability.
#[derive(Clone, Debug, Serialize)]
pub struct StatusJson {
    /// `theta0`, `alpha3`, `K2`, or an auxiliary unknown (`a`, `b`, …).
    pub name: String,
    /// Its priority (column order of the QR).
    pub priority: u32,
    /// `identifiable`, `regrouped`, `no_effect` or `excluded`.
    pub status: &'static str,
}

impl From<&Classified> for StatusJson {
    fn from(classified: &Classified) -> Self {
        StatusJson {
            name: classified.name.clone(),
            priority: classified.priority,
            status: classified.status.as_str(),
        }
    }
}

/// The rows of a matrix as lists (serde writes fixed-size arrays as tuples,
/// which Python would see as tuples rather than the lists JSON gives).
fn rows_as_lists<S: serde::Serializer>(
    rows: &[[u32; 6]],
    serializer: S,
) -> Result<S::Ok, S::Error> {
    serializer.collect_seq(rows.iter().map(|row| row.as_slice()))
}

/// A parameter absorbed by a base parameter, with its coefficient.
#[derive(Clone, Debug, Serialize)]
pub struct AbsorbedJson {
    /// The absorbed parameter.
    pub name: String,
    /// Its coefficient β in eq. 32.
    pub coefficient: f64,
}

/// A regrouping relation: `base_b = base + Σ coefficient·absorbed` (eq. 32).
#[derive(Clone, Debug, Serialize)]
pub struct RelationJson {
    /// The base parameter.
    pub base: String,
    /// What it absorbs.
    pub absorbed: Vec<AbsorbedJson>,
}

/// The observability indices of W_b, its columns scaled to 1 cm, 1°, 1 %
/// (see [`gecaro_calib::observability::Observability`]; larger is better for all five).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct ObservabilityJson {
    /// (σ1⋯σL)^(1/L)/√m (Borm & Menq).
    pub o1: f64,
    /// σL/σ1 (Driels & Pathre).
    pub o2: f64,
    /// σL (Nahvi & Hollerbach).
    pub o3: f64,
    /// σL²/σ1, the noise amplification index (Nahvi & Hollerbach).
    pub o4: f64,
    /// 1/Σ(1/σi) (Sun & Hollerbach).
    pub o5: f64,
}

impl From<Observability> for ObservabilityJson {
    fn from(indices: Observability) -> Self {
        ObservabilityJson {
            o1: indices.o1,
            o2: indices.o2,
            o3: indices.o3,
            o4: indices.o4,
            o5: indices.o5,
        }
    }
}

/// The excitation check of measured data (§4).
#[derive(Clone, Debug, Serialize)]
pub struct ExcitationJson {
    /// Whether the data excite every structural base parameter.
    pub same_base_set: bool,
    /// Structural base parameters the data do not excite.
    pub not_excited: Vec<String>,
    /// Condition number of W_b built from the data (at the nominal parameters).
    pub condition_number: f64,
}

/// The "Identifiable parameters" function's result.
#[derive(Clone, Debug, Serialize)]
pub struct IdentifiableJson {
    /// The study's methods, joined with `+`.
    pub method: String,
    /// The robot's name.
    pub robot: String,
    /// What the rank test ran on.
    pub source: String,
    /// Configurations of that data.
    pub configurations: usize,
    /// Number of identifiable robot parameters.
    pub count: usize,
    /// Condition number of W_b.
    pub condition_number: f64,
    /// Rows of W.
    pub rows: usize,
    /// Independent equations.
    pub equations: usize,
    /// The numerical zero τ.
    pub tolerance: f64,
    /// Smallest |R_ii| kept.
    pub smallest_kept: f64,
    /// Largest |R_ii| rejected.
    pub largest_rejected: f64,
    /// How well the regrouping relations hold.
    pub relation_residual: f64,
    /// Every robot parameter, in vocabulary order.
    pub parameters: Vec<StatusJson>,
    /// The method's own unknowns (plane coefficients).
    pub auxiliary: Vec<StatusJson>,
    /// Regrouping relations.
    pub regrouping: Vec<RelationJson>,
    /// The new priority matrix ((n+2) rows of α, d, θ, r, β, K; 0 = not identified).
    #[serde(serialize_with = "rows_as_lists")]
    pub priority_matrix: Vec<[u32; 6]>,
    /// Observability indices of W_b: of the measured data when given, else of
    /// the random configurations.
    pub observability: ObservabilityJson,
    /// For measured data: the excitation check.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub excitation: Option<ExcitationJson>,
    /// What the set-up keeps from being identified (a measured point on a
    /// joint's axis), before any data are taken.
    pub warnings: Vec<String>,
}

impl IdentifiableJson {
    /// The document of an identifiability analysis of `robot`.
    pub fn new(robot: &Robot, analysis: &Identifiability) -> Self {
        let report: &RankReport = &analysis.report;
        IdentifiableJson {
            method: report.method.clone(),
            robot: robot.name().to_owned(),
            source: analysis.source.clone(),
            configurations: analysis.configurations,
            count: report.count(),
            condition_number: report.condition_number(),
            rows: report.rows,
            equations: report.equations,
            tolerance: report.tolerance,
            smallest_kept: report.smallest_kept,
            largest_rejected: report.largest_rejected,
            relation_residual: report.relation_residual(),
            parameters: report.parameters.iter().map(StatusJson::from).collect(),
            auxiliary: report.auxiliary.iter().map(StatusJson::from).collect(),
            regrouping: report
                .relations()
                .iter()
                .map(|relation| RelationJson {
                    base: relation.base.clone(),
                    absorbed: relation
                        .absorbed
                        .iter()
                        .map(|(name, coefficient)| AbsorbedJson {
                            name: name.clone(),
                            coefficient: *coefficient,
                        })
                        .collect(),
                })
                .collect(),
            priority_matrix: report.priority.rows().to_vec(),
            observability: analysis
                .excitation
                .as_ref()
                .map_or(report, |checked| &checked.report)
                .observability()
                .into(),
            excitation: analysis.excitation.as_ref().map(|checked| ExcitationJson {
                same_base_set: checked.not_excited.is_empty(),
                not_excited: checked.not_excited.clone(),
                condition_number: checked.report.condition_number(),
            }),
            warnings: report.set_up_warnings(robot),
        }
    }
}

/// How a compared robot (the calibrated one) fares against the robot (the
/// nominal, or the table's) on the same measurements: the verdict of an
/// evaluation on held-out data.
#[derive(Clone, Debug, Serialize)]
pub struct ComparisonJson {
    /// `better`, `worse`, or `same` (RMS within 5 % of the robot's).
    pub outcome: &'static str,
    /// The compared robot's RMS over the robot's (position-like errors).
    pub rms_ratio: f64,
    /// In words, with both RMS values in millimetres.
    pub summary: String,
}

impl ComparisonJson {
    /// RMS ratios within this of 1 are `same`.
    const SAME: f64 = 0.05;

    /// The comparison of the compared robot's errors `compared` with the
    /// robot's `robot` (position-like RMS, metres).
    pub fn of(robot: &ErrorSummary, compared: &ErrorSummary) -> Self {
        let ratio = compared.rms / robot.rms;
        let (outcome, words) = if !ratio.is_finite() {
            (
                if compared.rms < robot.rms {
                    "better"
                } else {
                    "same"
                },
                "exact on these data".to_owned(),
            )
        } else if (ratio - 1.0).abs() <= Self::SAME {
            ("same", "as accurate as the robot compared with".to_owned())
        } else if ratio < 1.0 {
            (
                "better",
                format!("{}× smaller errors", three_digits(1.0 / ratio)),
            )
        } else {
            (
                "worse",
                format!("WORSE: {}× larger errors", three_digits(ratio)),
            )
        };
        ComparisonJson {
            outcome,
            rms_ratio: ratio,
            summary: format!(
                "{words} (RMS {:.4} mm against {:.4} mm)",
                compared.rms * 1e3,
                robot.rms * 1e3
            ),
        }
    }
}

/// A factor with three significant digits: 673, 10.3, 1.29.
fn three_digits(factor: f64) -> String {
    match factor {
        f if f >= 100.0 => format!("{f:.0}"),
        f if f >= 10.0 => format!("{f:.1}"),
        f => format!("{f:.2}"),
    }
}

/// Error statistics over observations (metres; radians for orientations).
#[derive(Clone, Debug, Serialize)]
pub struct SummaryJson {
    /// Root mean square.
    pub rms: f64,
    /// Mean.
    pub mean: f64,
    /// Largest.
    pub max: f64,
    /// Number of observations.
    pub count: usize,
    /// RMS of the orientation errors, for methods that measure orientation.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rms_rotation: Option<f64>,
    /// Largest orientation error.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_rotation: Option<f64>,
}

impl From<&ErrorSummary> for SummaryJson {
    fn from(summary: &ErrorSummary) -> Self {
        SummaryJson {
            rms: summary.rms,
            mean: summary.mean,
            max: summary.max,
            count: summary.count,
            rms_rotation: summary.rms_rotation,
            max_rotation: summary.max_rotation,
        }
    }
}

/// An identified parameter.
#[derive(Clone, Debug, Serialize)]
pub struct ParameterJson {
    /// Its name.
    pub name: String,
    /// Its nominal value.
    pub nominal: f64,
    /// Its identified value.
    pub identified: f64,
    /// Its standard deviation (eq. 11; posterior with a prior); `null` for a
    /// parameter moved outside the base set, which has none.
    pub std: Option<f64>,
    /// The part of `std` the measurement noise makes: the spread over
    /// repeated measurements of the same robot (below `std` where a prior,
    /// or the gauge of an unmeasured scale, holds the parameter).
    pub noise_std: Option<f64>,
    /// Its prior standard deviation, with a prior (regrouping included).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub prior_std: Option<f64>,
    /// The parameters it absorbs with their coefficients (a regrouped base
    /// parameter: its deviation is that combination, not a physical value);
    /// empty for a physical parameter.
    pub absorbs: Vec<AbsorbedJson>,
    /// The combination its deviation stands for (`theta2 + theta3`), when regrouped.
    pub combination: Option<String>,
}

/// The loss an identification minimised.
#[derive(Clone, Debug, Serialize)]
pub struct LossJson {
    /// `l2`, `huber`, `cauchy` or `tukey`.
    pub kind: &'static str,
    /// Its scale k in robust σ̂ (none for l2).
    pub scale: Option<f64>,
}

/// A prior's standard deviations per kind (metres, radians, fraction of the gain).
#[derive(Clone, Debug, Serialize)]
pub struct PriorJson {
    /// σ of lengths (m).
    pub length: f64,
    /// σ of angles (rad).
    pub angle: f64,
    /// σ of gains (fraction).
    pub gain: f64,
    /// Per-parameter σ (units of the parameter's kind).
    pub parameters: std::collections::BTreeMap<String, f64>,
}

/// An observation beyond the outlier threshold.
#[derive(Clone, Debug, Serialize)]
pub struct OutlierJson {
    /// Index of its measurement set in the study (0-based).
    pub set: usize,
    /// The set's data file.
    pub file: String,
    /// `configuration` or `pair`.
    pub kind: &'static str,
    /// Its number in the set (1-based, as the text output says it).
    pub observation: usize,
    /// The data-file lines of its samples.
    pub lines: Vec<usize>,
    /// Its position-like error at the solution (m).
    pub error: f64,
    /// Its orientation error (rad), for data with orientations.
    pub rotation_error: Option<f64>,
    /// Its residual in robust σ̂.
    pub residual_sigmas: f64,
    /// Its weight in the final fit.
    pub weight: f64,
}

impl OutlierJson {
    /// The documents of the first [`MAX_LISTED_OUTLIERS`](crate::limits::MAX_LISTED_OUTLIERS)
    /// of `outliers` (worst first, as the identification sorts them).
    pub fn worst(outliers: &[gecaro_calib::identification::Outlier]) -> Vec<OutlierJson> {
        Self::list(&outliers[..outliers.len().min(crate::limits::MAX_LISTED_OUTLIERS)])
    }

    /// The documents of `outliers`, in their order.
    pub fn list(outliers: &[gecaro_calib::identification::Outlier]) -> Vec<OutlierJson> {
        outliers
            .iter()
            .map(|o| OutlierJson {
                set: o.location.set,
                file: o.location.label.clone(),
                kind: o.location.kind,
                observation: o.location.observation + 1,
                lines: o.location.lines.clone(),
                error: o.error,
                rotation_error: o.rotation_error,
                residual_sigmas: o.standardized,
                weight: o.weight,
            })
            .collect()
    }
}

fn parameters(parameters: &[IdentifiedParameter]) -> Vec<ParameterJson> {
    parameters
        .iter()
        .map(|p| ParameterJson {
            name: p.name.clone(),
            nominal: p.nominal,
            identified: p.identified,
            std: p.std.is_finite().then_some(p.std),
            noise_std: p.noise_std.is_finite().then_some(p.noise_std),
            prior_std: p.prior_std,
            absorbs: p
                .absorbs
                .iter()
                .map(|(name, coefficient)| AbsorbedJson {
                    name: name.clone(),
                    coefficient: *coefficient,
                })
                .collect(),
            combination: p.combination(),
        })
        .collect()
}

/// A named tool or station's pose, as a study file states it (metres and
/// radians; `rpy` about the fixed x, y, z axes, as URDF).
#[derive(Clone, Debug, Serialize)]
pub struct FrameJson {
    /// Its name in the study.
    pub name: String,
    /// `tool` (in the robot's tool frame n+1) or `station` (in the world frame).
    pub role: &'static str,
    /// Its origin (m), three numbers (a list, not a tuple, in Python).
    pub position: Vec<f64>,
    /// Roll, pitch, yaw (rad).
    pub rpy: Vec<f64>,
    /// The same orientation as a unit quaternion `[w, x, y, z]`.
    pub quaternion: Vec<f64>,
}

impl From<&NamedFrame> for FrameJson {
    fn from(frame: &NamedFrame) -> Self {
        let t = frame.pose.translation.vector;
        let (roll, pitch, yaw) = frame.pose.rotation.euler_angles();
        let q = nalgebra::UnitQuaternion::from_rotation_matrix(&frame.pose.rotation);
        FrameJson {
            name: frame.name.clone(),
            role: frame.role.as_str(),
            position: vec![t.x, t.y, t.z],
            rpy: vec![roll, pitch, yaw],
            quaternion: vec![q.w, q.i, q.j, q.k],
        }
    }
}

/// The "Identification" function's result.
#[derive(Clone, Debug, Serialize)]
pub struct IdentificationJson {
    /// The study's methods, joined with `+`.
    pub method: String,
    /// Whether the result can be trusted, and why.
    pub verdict: VerdictJson,
    /// Parameters the second pass added to the nominal base set.
    pub second_pass: Vec<String>,
    /// Parameters outside the base set that the data set and base
    /// parameters absorb, identified beside it under a weak prior.
    pub joined: Vec<String>,
    /// Strongly correlated pairs of identified parameters, strongest first.
    pub correlated: Vec<CorrelatedJson>,
    /// Whether the iteration converged.
    pub converged: bool,
    /// Iterations done.
    pub iterations: usize,
    /// Residual RMS of every iterate, from the nominal robot on.
    pub rms_history: Vec<f64>,
    /// Residual RMS at the nominal robot.
    pub rms_before: f64,
    /// Residual RMS at the identified robot.
    pub rms_after: f64,
    /// Condition number of W_b at the solution.
    pub condition_number: f64,
    /// Observability indices of the data's W_b at the nominal robot.
    pub observability: ObservabilityJson,
    /// The identified base parameters.
    pub parameters: Vec<ParameterJson>,
    /// The identified auxiliary unknowns (named frames' first).
    pub auxiliary: Vec<ParameterJson>,
    /// The study's named tools and stations at their identified poses.
    pub frames: Vec<FrameJson>,
    /// `converged`, `iteration_limit` or `diverged`.
    pub stop_reason: &'static str,
    /// Standard deviation of the residual (eq. 11).
    pub residual_sigma: f64,
    /// Errors at the nominal robot.
    pub before: SummaryJson,
    /// Errors at the identified robot.
    pub after: SummaryJson,
    /// The same without the outliers (none when nothing is an outlier).
    pub after_inliers: Option<SummaryJson>,
    /// Structural base parameters that the data do not excite.
    pub not_excited: Vec<String>,
    /// Number of structurally identifiable parameters.
    pub identifiable: usize,
    /// The step rule that produced the result.
    pub route: &'static str,
    /// Parameters outside the base set that had to move.
    pub moved: Vec<ParameterJson>,
    /// What the user should know about the result.
    pub warnings: Vec<String>,
    /// The loss minimised.
    pub loss: LossJson,
    /// Outer iterations of the reweighted phase (0 for plain least squares).
    pub reweightings: usize,
    /// The robust σ̂ of the residuals (units of the sensor σ).
    pub robust_sigma: f64,
    /// The outlier threshold (robust σ̂).
    pub outlier_threshold: f64,
    /// Observations beyond the threshold at the solution, worst first: the
    /// worst [`MAX_LISTED_OUTLIERS`](crate::limits::MAX_LISTED_OUTLIERS).
    pub outliers: Vec<OutlierJson>,
    /// How many observations are beyond the threshold (listed or not).
    pub outlier_count: usize,
    /// Observations rejected before this fit (`--reject`), worst first, as
    /// many as `outliers` lists.
    pub rejected: Vec<OutlierJson>,
    /// How many observations were rejected before this fit.
    pub rejected_count: usize,
    /// The prior, if one was given.
    pub prior: Option<PriorJson>,
    /// The K-fold cross-validation, when asked for (`--cv K`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cross_validation: Option<CrossValidationJson>,
    /// Where the calibrated robot puts the measurement frame and the tool,
    /// against the robot file (the registration a cell's user reads first).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub registration: Option<RegistrationJson>,
    /// Other models that would do better, with their figures (the elastic
    /// model where the robot file has masses and the rigid fit exceeds the
    /// noise; with `check_model`, the next smaller model).
    pub model_advice: Vec<ModelAdviceJson>,
    /// A study's errors set by set (none for one set).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub sets: Vec<crate::set_errors::GroupErrorsJson>,
    /// The same station by station (none for one station).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub stations: Vec<crate::set_errors::GroupErrorsJson>,
}

/// Another model that would do better (see [`crate::ModelAdvice`]).
#[derive(Clone, Debug, Serialize)]
pub struct ModelAdviceJson {
    /// The model suggested.
    pub model: String,
    /// The model identified.
    pub instead_of: String,
    /// The suggested model's σ̂/σ, when σ was stated.
    pub sigma_ratio: Option<f64>,
    /// The identified model's σ̂/σ.
    pub instead_ratio: Option<f64>,
    /// The suggested model's error held out by region (m).
    pub held_out: f64,
    /// The identified model's (m).
    pub instead_held_out: f64,
}

impl From<&crate::ModelAdvice> for ModelAdviceJson {
    fn from(advice: &crate::ModelAdvice) -> Self {
        ModelAdviceJson {
            model: advice.model.clone(),
            instead_of: advice.instead_of.clone(),
            sigma_ratio: advice.sigma_ratio,
            instead_ratio: advice.instead_ratio,
            held_out: advice.held_out,
            instead_held_out: advice.instead_held_out,
        }
    }
}

/// A pose: origin (m) and roll, pitch, yaw (rad).
#[derive(Clone, Debug, Serialize)]
pub struct PoseJson {
    /// Origin (m).
    pub position: Vec<f64>,
    /// Roll, pitch, yaw (rad), `R = Rz(yaw) Ry(pitch) Rx(roll)`.
    pub rpy: Vec<f64>,
}

impl From<&nalgebra::IsometryMatrix3<f64>> for PoseJson {
    fn from(pose: &nalgebra::IsometryMatrix3<f64>) -> Self {
        let t = pose.translation.vector;
        let (roll, pitch, yaw) = pose.rotation.euler_angles();
        PoseJson {
            position: vec![t.x, t.y, t.z],
            rpy: vec![roll, pitch, yaw],
        }
    }
}

/// The registration of the base and the tool that an identification found
/// (frames 0 and n+1 of the calibrated robot, read against the nominal).
#[derive(Clone, Debug, Serialize)]
pub struct RegistrationJson {
    /// The robot's base (frame 1 with joint 1 at zero) in the measurement
    /// frame, as calibrated.
    pub base: PoseJson,
    /// How far it is from where the robot file puts it: distance (m) and
    /// angle (rad) (a list, not a tuple, in Python).
    pub base_moved: Vec<f64>,
    /// The tool frame n+1 in the flange (joint n's frame at the robot
    /// file's θn and rn: a change of those is the tool's, as `robot
    /// reframe` writes a new tool), as calibrated.
    pub tool: PoseJson,
    /// How far it is from the robot file's: distance (m) and angle (rad).
    pub tool_moved: Vec<f64>,
}

impl RegistrationJson {
    /// The registration of `calibrated` against `nominal` (robots of the
    /// same joints).
    pub fn of(nominal: &gecaro_core::Robot, calibrated: &gecaro_core::Robot) -> Self {
        use gecaro_core::{ParameterId, ParameterKind};
        let (distance, angle) = nominal.base_offset(calibrated);
        let last = nominal.frames().len() - 2;
        let along_z = |robot: &gecaro_core::Robot, kind| {
            let id = ParameterId::new(kind, last);
            robot.parameter(id) - nominal.parameter(id)
        };
        let tool_of = |robot: &gecaro_core::Robot| {
            // θn and rn beyond the robot file's: a turn and a shift along
            // z_n, which commute with joint n's own.
            let beyond = nalgebra::IsometryMatrix3::from_parts(
                nalgebra::Translation3::new(0.0, 0.0, along_z(robot, ParameterKind::R)),
                nalgebra::Rotation3::from_axis_angle(
                    &nalgebra::Vector3::z_axis(),
                    along_z(robot, ParameterKind::Theta),
                ),
            );
            beyond * gecaro_core::frame_transform(&robot.frames()[last + 1], 0.0)
        };
        let (nominal_tool, tool) = (tool_of(nominal), tool_of(calibrated));
        let change = nominal_tool.inverse() * tool;
        RegistrationJson {
            base: (&calibrated.base_pose()).into(),
            base_moved: vec![distance, angle],
            tool: (&tool).into(),
            tool_moved: vec![change.translation.vector.norm(), change.rotation.angle()],
        }
    }
}

/// One fold of a cross-validation.
#[derive(Clone, Debug, Serialize)]
pub struct FoldJson {
    /// What the fold holds out: `fold 3`, or `q1 ≥ 101.5°`.
    pub label: String,
    /// Observations held out.
    pub held_out: usize,
    /// RMS position-like error of the training observations (m).
    pub training_rms: f64,
    /// Held-out RMS position-like error (m).
    pub rms: f64,
    /// Held-out RMS orientation error (rad), for data with orientations.
    pub rms_rotation: Option<f64>,
}

/// A K-fold cross-validation (docs/methods.md).
#[derive(Clone, Debug, Serialize)]
pub struct CrossValidationJson {
    /// How the observations were held out: `regions` (the ends of each
    /// joint's measured range: extrapolation) or `random` (interpolation).
    pub by: &'static str,
    /// Number of folds.
    pub folds: usize,
    /// The seed of random folds.
    pub seed: Option<u64>,
    /// Held-out RMS over every held-out observation (m).
    pub rms: f64,
    /// Held-out RMS orientation error (rad), for data with orientations.
    pub rms_rotation: Option<f64>,
    /// Per fold.
    pub per_fold: Vec<FoldJson>,
}

impl CrossValidationJson {
    /// The document of `validation`.
    pub fn new(validation: &gecaro_calib::validation::CrossValidation) -> Self {
        CrossValidationJson {
            by: validation.folds_by.name(),
            folds: validation.folds.len(),
            seed: match validation.folds_by {
                gecaro_calib::validation::Folds::Random { seed, .. } => Some(seed),
                gecaro_calib::validation::Folds::Regions { .. } => None,
            },
            rms: validation.rms,
            rms_rotation: validation.rms_rotation,
            per_fold: validation
                .folds
                .iter()
                .map(|fold| FoldJson {
                    label: fold.label.clone(),
                    held_out: fold.held_out,
                    training_rms: fold.training_rms,
                    rms: fold.rms,
                    rms_rotation: fold.rms_rotation,
                })
                .collect(),
        }
    }
}

/// One candidate of `compare-models`.
#[derive(Clone, Debug, Serialize)]
pub struct ModelScoreJson {
    /// Its name (or priority-matrix file).
    pub model: String,
    /// Parameters it identifies (on the first fold's training data).
    pub parameters: Vec<String>,
    /// What it identifies beyond the next smaller candidate.
    pub adds: Vec<String>,
    /// Its cross-validation.
    pub cross_validation: CrossValidationJson,
}

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
            changes: verdict
                .changes
                .iter()
                .map(|change| CellChangeJson {
                    set: change.set,
                    label: change.label.clone(),
                    observations: vec![change.first + 1, change.last + 1],
                    lines: change.lines.map(|(first, last)| vec![first, last]),
                    to_end: change.to_end(),
                    outliers_inside: change.outliers_inside,
                    outliers_elsewhere: change.outliers_elsewhere,
                    chance: change.chance,
                })
                .collect(),
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

impl IdentificationJson {
    /// The document of an identification on `study`.
    pub fn new(study: &Study, result: &Identification) -> Self {
        let (sets, stations) = crate::set_errors::group_errors(study, result);
        IdentificationJson {
            method: study.method_names(),
            verdict: (&result.verdict).into(),
            second_pass: result.second_pass.clone(),
            joined: result.joined.clone(),
            correlated: result
                .correlated
                .iter()
                .map(|(a, b, rho)| CorrelatedJson {
                    a: a.clone(),
                    b: b.clone(),
                    rho: *rho,
                })
                .collect(),
            converged: result.stop_reason == StopReason::Converged,
            iterations: result.iterations(),
            rms_history: result.history.iter().map(|h| h.rms).collect(),
            rms_before: result.rms_before(),
            rms_after: result.rms_after(),
            condition_number: result.condition_number,
            observability: result.observability().into(),
            parameters: parameters(&result.parameters),
            auxiliary: parameters(&result.auxiliary),
            frames: result.frames.iter().map(FrameJson::from).collect(),
            stop_reason: result.stop_reason.as_str(),
            residual_sigma: result.residual_sigma,
            before: (&result.before).into(),
            after: (&result.after).into(),
            after_inliers: result.after_inliers().as_ref().map(Into::into),
            not_excited: result.not_excited.clone(),
            identifiable: result.rank.count(),
            route: result.route.as_str(),
            moved: parameters(&result.moved),
            warnings: result.warnings.iter().map(ToString::to_string).collect(),
            loss: LossJson {
                kind: result.loss.kind.as_str(),
                scale: (!result.loss.is_l2()).then_some(result.loss.scale),
            },
            reweightings: result.reweightings,
            robust_sigma: result.robust_sigma,
            outlier_threshold: result.outlier_threshold,
            outliers: OutlierJson::worst(&result.outliers),
            outlier_count: result.outliers.len(),
            rejected: OutlierJson::worst(&result.rejected),
            rejected_count: result.rejected.len(),
            prior: result.prior.as_ref().map(|prior| PriorJson {
                length: prior.length,
                angle: prior.angle,
                gain: prior.gain,
                parameters: prior
                    .overrides
                    .iter()
                    .map(|(id, sigma)| (id.to_string(), *sigma))
                    .collect(),
            }),
            cross_validation: None,
            registration: None,
            model_advice: Vec::new(),
            sets,
            stations,
        }
    }
}

/// The document of a plan (`gecaro plan --json`, the page's Plan function).
#[derive(Clone, Debug, Serialize)]
pub struct PlanJson {
    /// The method's name.
    pub method: &'static str,
    /// The criterion's name (d, a, e, o4, o5, test).
    pub criterion: &'static str,
    /// What `value` is.
    pub criterion_meaning: &'static str,
    /// The criterion's value for the plan.
    pub value: f64,
    /// The same for a random choice of as many units from the same pool.
    pub random_value: f64,
    /// Configurations of the plan (kept ones included).
    pub configurations: usize,
    /// Units chosen (configurations, sets or pairs).
    pub units: usize,
    /// Configurations in the pool.
    pub pool: usize,
    /// Configurations kept.
    pub kept: usize,
    /// log det(W_bᵀW_b) of the plan (scaled columns).
    pub log_det: f64,
    /// The same for the random choice.
    pub random_log_det: f64,
    /// The plan's observability indices.
    pub observability: ObservabilityJson,
    /// Exchanges made after the greedy pass.
    pub exchanges: usize,
    /// The base parameters judged (auxiliary unknowns first).
    pub columns: Vec<String>,
}

impl PlanJson {
    /// The document of `plan` by `criterion` for `method`, against the
    /// `random` choice, from a pool of `pool` configurations with `kept` kept.
    pub fn new(
        method: &'static str,
        criterion: &Criterion,
        plan: &Plan,
        random: &DesignQuality,
        pool: usize,
        kept: usize,
    ) -> Self {
        PlanJson {
            method,
            criterion: criterion.name(),
            criterion_meaning: criterion.meaning(),
            value: plan.quality.value,
            random_value: random.value,
            configurations: plan.samples.len(),
            units: plan.chosen.len(),
            pool,
            kept,
            log_det: plan.quality.log_det,
            random_log_det: random.log_det,
            observability: plan.quality.observability.into(),
            exchanges: plan.exchanges,
            columns: plan.columns.clone(),
        }
    }
}

/// One count of an accuracy curve ([`gecaro_calib::curve::accuracy_curve`]).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct CurvePointJson {
    /// Configurations measured.
    pub configurations: usize,
    /// Predicted RMS position error of the planned design (m); null when it
    /// determines nothing.
    pub planned: Option<f64>,
    /// The mean over random designs (m); null likewise.
    pub random: Option<f64>,
}

impl From<&CurvePoint> for CurvePointJson {
    fn from(point: &CurvePoint) -> Self {
        CurvePointJson {
            configurations: point.count,
            planned: point.planned,
            random: point.random,
        }
    }
}

/// An accuracy curve (`gecaro plan --curve --json`, the page's Plan function).
#[derive(Clone, Debug, Serialize)]
pub struct CurveJson {
    /// The method's name.
    pub method: &'static str,
    /// The criterion of the plans.
    pub criterion: &'static str,
    /// The sensor's σ (m).
    pub noise: f64,
    /// Candidates in the pool.
    pub pool: usize,
    /// Test poses the errors are predicted at.
    pub test_poses: usize,
    /// Random designs averaged per count.
    pub random_draws: usize,
    /// Predicted RMS position error (metres) per count.
    pub points: Vec<CurvePointJson>,
}

/// Errors at test poses (m, rad).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct PoseErrorsJson {
    /// RMS position error.
    pub position_rms: f64,
    /// Largest position error.
    pub position_max: f64,
    /// RMS orientation error, for methods that measure orientation.
    pub rotation_rms: Option<f64>,
    /// Largest orientation error.
    pub rotation_max: Option<f64>,
}

impl From<PoseErrors> for PoseErrorsJson {
    fn from(errors: PoseErrors) -> Self {
        PoseErrorsJson {
            position_rms: errors.position_rms,
            position_max: errors.position_max,
            rotation_rms: errors.rotation_rms,
            rotation_max: errors.rotation_max,
        }
    }
}

/// A parameter's predicted σ.
#[derive(Clone, Debug, Serialize)]
pub struct SigmaJson {
    /// Its name.
    pub name: String,
    /// Its predicted standard deviation.
    pub sigma: f64,
}

impl SigmaJson {
    /// Every (name, σ) of a prediction.
    pub fn list(parameters: &[(String, f64)]) -> Vec<SigmaJson> {
        parameters
            .iter()
            .map(|(name, sigma)| SigmaJson {
                name: name.clone(),
                sigma: *sigma,
            })
            .collect()
    }
}

/// Simulated calibrations.
#[derive(Clone, Debug, Serialize)]
pub struct MonteCarloJson {
    /// Calibrations run.
    pub runs: usize,
    /// Those that did not converge.
    pub not_converged: usize,
    /// The real robots' error level.
    pub error_level: f64,
    /// The errors measured at the test poses.
    pub measured: PoseErrorsJson,
    /// Measured / predicted RMS position error.
    pub position_ratio: f64,
}

/// A prediction (`gecaro predict --json`).
#[derive(Clone, Debug, Serialize)]
pub struct PredictJson {
    /// The method's name.
    pub method: &'static str,
    /// Configurations of the plan.
    pub configurations: usize,
    /// The sensor's σ.
    pub noise: f64,
    /// Test poses.
    pub test_poses: usize,
    /// Every base parameter's predicted σ.
    pub parameters: Vec<SigmaJson>,
    /// The predicted errors at the test poses.
    pub predicted: PoseErrorsJson,
    /// The simulated calibrations, if run.
    pub monte_carlo: Option<MonteCarloJson>,
}

impl PredictJson {
    /// The document of a prediction for `method` from `configurations`
    /// with σ `noise` at `test_poses` poses, and of the simulated
    /// calibrations at their error level, if run.
    pub fn new(
        method: &'static str,
        configurations: usize,
        noise: f64,
        test_poses: usize,
        prediction: &Prediction,
        measured: Option<(&MonteCarlo, f64)>,
    ) -> Self {
        let predicted = prediction.errors;
        PredictJson {
            method,
            configurations,
            noise,
            test_poses,
            parameters: SigmaJson::list(&prediction.parameters),
            predicted: predicted.into(),
            monte_carlo: measured.map(|(measured, error_level)| MonteCarloJson {
                runs: measured.runs,
                not_converged: measured.not_converged,
                error_level,
                measured: measured.errors.into(),
                position_ratio: measured.errors.position_rms / predicted.position_rms,
            }),
        }
    }
}

/// One corrected target.
#[derive(Clone, Debug, Serialize)]
pub struct CompensatedJson {
    /// Its line in the program file (or its row, 0-based).
    pub line: usize,
    /// `reached`, `outside-limits` or `not-reached`.
    pub status: &'static str,
    /// The corrected motor variables.
    pub motor_positions: Vec<f64>,
    /// The calibrated robot's remaining position error there (m).
    pub position_error: f64,
    /// Its orientation error (rad), for pose targets.
    pub rotation_error: Option<f64>,
    /// The tool's turn a position match left (rad), for joint targets
    /// matched by position.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tool_turn: Option<f64>,
}

/// The largest change of a joint between a program and its correction.
#[derive(Copy, Clone, Debug, PartialEq, Serialize)]
pub struct LargestCorrection {
    /// The change, in the program file's unit.
    pub value: f64,
    /// That unit's name.
    pub unit: &'static str,
    /// The joint (1-based).
    pub joint: usize,
    /// The target's line.
    pub line: usize,
}

/// A corrected program (`gecaro compensate --json`).
#[derive(Clone, Debug, Serialize)]
pub struct CompensationJson {
    /// Targets in the program.
    pub targets: usize,
    /// Targets reached within the limits in the program's configuration.
    pub reached: usize,
    /// Lines of the targets reached within the limits in another
    /// configuration (a joint moved by more than a radian).
    pub reconfigured: Vec<usize>,
    /// Lines of the targets reached outside the joint ranges the
    /// calibration's data covered (a calibrated robot that holds there only).
    pub outside_region: Vec<usize>,
    /// Lines of the targets reached only beyond a joint limit.
    pub outside_limits: Vec<usize>,
    /// Lines of the targets not reached.
    pub not_reached: Vec<usize>,
    /// The largest residual of a reached target (m).
    pub largest_position_error: f64,
    /// The largest joint correction, in the program's unit.
    pub largest_correction: f64,
    /// The same with its unit, joint and line (`0.9360 rad (joint 5, line
    /// 7)`); absent for targets given as arrays.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub largest_correction_at: Option<LargestCorrection>,
    /// The largest turn of the tool a position match left (rad); absent for
    /// a pose match.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub largest_tool_turn: Option<f64>,
    /// Lines of the targets a position match reached with the tool turned
    /// beyond the tolerance (`max_tool_turn`).
    pub turned: Vec<usize>,
    /// The corrected program file, when written.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub output: Option<String>,
    /// Every target (none listed for a program corrected as it was read:
    /// they are in its file).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub points: Vec<CompensatedJson>,
    /// The owner's base registered by points, when they were given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub registration: Option<crate::base_frame::BaseRegistrationJson>,
}

#[cfg(test)]
mod tests {
    use super::RegistrationJson;
    use nalgebra::{IsometryMatrix3, Rotation3, Translation3, Vector3};

    #[test]
    fn the_registration_is_the_robot_moved_in_the_world_and_its_tool_in_the_flange() {
        let nominal = gecaro_io::load_robot("stanford").expect("ready").robot;
        // The same robot seen from a frame 100 mm and 10° away, its tool
        // frame moved 20 mm along the flange's z and turned 5° about x.
        let world = IsometryMatrix3::from_parts(
            Translation3::new(0.06, 0.08, 0.0),
            Rotation3::from_axis_angle(&Vector3::z_axis(), 10f64.to_radians()),
        );
        let tool = IsometryMatrix3::from_parts(
            Translation3::new(0.0, 0.0, 0.02),
            Rotation3::from_axis_angle(&Vector3::x_axis(), 5f64.to_radians()),
        );
        let moved = nominal.reframed(&world, &tool).expect("reframed");
        let registration = RegistrationJson::of(&nominal, &moved);
        let [distance, angle] = registration.base_moved[..] else {
            panic!("two numbers");
        };
        // Joint 1's frame stands on the z axis of the world (500 mm up): the
        // new world moved it by the translation's 100 mm (its rotation is
        // about that axis).
        assert!((angle - 10f64.to_radians()).abs() < 1e-9, "{angle}");
        assert!((distance - 0.1).abs() < 1e-9, "{distance}");
        assert!((registration.tool_moved[0] - 0.02).abs() < 1e-9);
        assert!((registration.tool_moved[1] - 5f64.to_radians()).abs() < 1e-9);
        let same = RegistrationJson::of(&nominal, &nominal);
        assert_eq!(same.base_moved, vec![0.0, 0.0]);
        assert_eq!(same.tool_moved, vec![0.0, 0.0]);
    }
}
