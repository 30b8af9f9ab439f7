//! The "Identification" function's document: the parameters with their
//! precision, the loss and prior, outliers, named frames, the registration,
//! cross-validation and other models.

use super::errors::SummaryJson;
use super::identifiable::{AbsorbedJson, ObservabilityJson};
use super::verdict::{CorrelatedJson, VerdictJson};
use gecaro_calib::{
    frames::NamedFrame,
    identification::{Identification, IdentifiedParameter, StopReason},
    study::Study,
};
use serde::Serialize;

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

/// Another model that would do better: [`crate::ModelAdvice`] itself,
/// serialised as it stands.
pub type ModelAdviceJson = crate::ModelAdvice;

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
