//! The predicted accuracy of a whole cell as a job ([`PredictStudyRequest`]):
//! a study's sets — each with its method, sensor σ, reflector and station —
//! judged together, before measuring, by eq. 11
//! ([`gecaro_calib::prediction::predict_study`]). The sets' data files need
//! only their configurations (a plan per set), measured or not.

use gecaro_calib::prediction::{Prediction, predict_study};
use serde::{Deserialize, Serialize};

use crate::documents::{PoseErrorsJson, SigmaJson};
use crate::error::AppError;
use crate::files::Files;
use crate::measurements::{Data, Loaded, Measurements, StudySource, Unknown};
use crate::plan::TestPoses;
use crate::sources::RobotSource;

/// A cell's prediction; see the module docs.
#[derive(Clone, Debug, Deserialize)]
pub struct PredictStudyRequest {
    /// The study (its robot, sets, σ, named frames).
    pub study: StudySource,
    /// The robot of a stated study that names none (the web page's table).
    pub robot: Option<RobotSource>,
    /// Where the calibrated robot's accuracy is judged.
    #[serde(flatten)]
    pub test_poses: TestPoses,
    /// Seed of random test poses (default 1).
    pub seed: Option<u64>,
    #[serde(flatten)]
    unknown: Unknown,
}

/// A cell's predicted precision.
#[derive(Clone, Debug)]
pub struct PredictedStudy {
    /// The robot and the study (configurations of every set).
    pub loaded: Loaded,
    /// Test poses used.
    pub test_poses: usize,
    /// The predicted precision.
    pub prediction: Prediction,
}

/// One set of a predicted study.
#[derive(Clone, Debug, Serialize)]
pub struct PredictedSetJson {
    /// Its data file.
    pub data: String,
    /// Its method.
    pub method: &'static str,
    /// Its configurations.
    pub configurations: usize,
    /// Its sensor's σ (m).
    pub sigma: Option<f64>,
    /// Its named tool, if any.
    pub tool: Option<String>,
    /// Its station, if any.
    pub station: Option<String>,
}

/// `gecaro predict --study --json`.
#[derive(Clone, Debug, Serialize)]
pub struct PredictStudyJson {
    /// The study's methods, joined with `+`.
    pub method: String,
    /// Every set.
    pub sets: Vec<PredictedSetJson>,
    /// Test poses.
    pub test_poses: usize,
    /// Every base parameter's predicted σ (named frames' unknowns first).
    pub parameters: Vec<SigmaJson>,
    /// The predicted errors at the test poses (the robot's own frame n+1).
    pub predicted: PoseErrorsJson,
}

impl PredictStudyRequest {
    /// A prediction of `study`, at random test poses.
    pub fn new(study: StudySource) -> Self {
        PredictStudyRequest {
            study,
            robot: None,
            test_poses: TestPoses::default(),
            seed: None,
            unknown: Unknown::default(),
        }
    }

    /// Reads the study's configurations and predicts.
    ///
    /// # Errors
    /// Files that cannot be read, a set without σ, configurations that do
    /// not determine the identifiable parameters.
    pub fn run(&self, files: &dyn Files) -> Result<PredictedStudy, AppError> {
        self.unknown.check()?;
        let measurements = Measurements {
            robot: self.robot.clone(),
            study: Some(self.study.clone()),
            ..Measurements::default()
        };
        let loaded = measurements.load(files, Data::Configurations)?;
        let robot = &loaded.robot.robot;
        let format = crate::sources::DataFormatSpec::default().format()?;
        let poses = self.test_poses.load(
            robot,
            self.seed.unwrap_or(gecaro_calib::simulation::DEFAULT_SEED),
            &format,
            files,
        )?;
        let priority = loaded.priority.clone().unwrap_or_else(|| robot.priority());
        let prediction = predict_study(robot, &loaded.study, &poses, &priority)?;
        Ok(PredictedStudy {
            loaded,
            test_poses: poses.len(),
            prediction,
        })
    }
}

impl PredictedStudy {
    /// The JSON document (`gecaro predict --study --json`).
    pub fn document(&self) -> PredictStudyJson {
        let study = &self.loaded.study;
        let frame = |index: Option<usize>| index.map(|i| study.frames[i].name.clone());
        PredictStudyJson {
            method: study.method_names(),
            sets: study
                .sets
                .iter()
                .map(|set| PredictedSetJson {
                    data: set.label.clone(),
                    method: set.method.name(),
                    configurations: set.samples.len(),
                    sigma: set.sigma,
                    tool: frame(set.tool),
                    station: frame(set.station),
                })
                .collect(),
            test_poses: self.test_poses,
            parameters: SigmaJson::list(&self.prediction.parameters),
            predicted: self.prediction.errors.into(),
        }
    }
}
