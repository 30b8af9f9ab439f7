//! The settings of an identification as a user gives them: solver,
//! iterations, priority matrix, model, loss, prior, outliers; parsed and
//! checked here, once, into the library's
//! [`IdentificationOptions`].

use gecaro_calib::identification::{
    DEFAULT_OUTLIER_THRESHOLD, IdentificationOptions, Loss, LossKind, Prior, Solver,
};
use gecaro_calib::validation::Model;
use gecaro_core::{PriorityMatrix, Robot};
use serde::Deserialize;

use crate::error::AppError;
use crate::files::Files;
use crate::limits::MAX_ITERATIONS;
use crate::measurements::Loaded;
use crate::method::parse_name;

/// A priority matrix given by a user.
#[derive(Clone, Debug, Deserialize)]
#[serde(untagged)]
pub enum PrioritySource {
    /// A priority file: `matrix = [[alpha, d, theta, r, beta, K], ...]`.
    File(String),
    /// A matrix given already (Python arrays).
    #[serde(skip)]
    Matrix(PriorityMatrix),
}

impl PrioritySource {
    /// The matrix, checked against `robot`.
    ///
    /// # Errors
    /// A file that cannot be read or a matrix that does not fit the robot.
    pub fn load(&self, robot: &Robot, files: &dyn Files) -> Result<PriorityMatrix, AppError> {
        match self {
            PrioritySource::File(name) => {
                let (path, text) = files.read_text(name, &["toml"])?;
                Ok(gecaro_io::parse_priority_file(&text, &path, robot)?)
            }
            PrioritySource::Matrix(matrix) => {
                matrix.validate(robot.parameters())?;
                Ok(matrix.clone())
            }
        }
    }
}

/// How to identify; every field is optional (see [`IdentificationOptions`]
/// for the defaults).
#[derive(Clone, Debug, Default, Deserialize)]
pub struct FitSettings {
    /// The priority matrix; default the study file's, else the robot's.
    pub priority: Option<PrioritySource>,
    /// Which parameters may be identified: `full` (default), `no-gains`,
    /// `no-beta`, `kinematic`, `offsets`, or a priority file.
    pub model: Option<String>,
    /// `gauss-newton` (default, the paper) or `lm`.
    pub solver: Option<String>,
    /// Iteration limit (default [`DEFAULT_MAX_ITERATIONS`](gecaro_calib::identification::DEFAULT_MAX_ITERATIONS), at most [`MAX_ITERATIONS`]).
    pub max_iterations: Option<usize>,
    /// `l2` (default), `huber`, `cauchy` or `tukey`.
    pub loss: Option<String>,
    /// Scale of a robust loss, in robust σ.
    pub loss_scale: Option<f64>,
    /// A Gaussian prior: `5mm,0.5deg,1%` (σ of lengths, angles, gains).
    pub prior: Option<String>,
    /// Observations beyond this many robust σ are outliers (default 3).
    pub outlier_threshold: Option<f64>,
    /// Drop the outliers and identify again, once.
    #[serde(default)]
    pub reject: bool,
    /// The region the calibrated robot will be used in, over which the
    /// verdict predicts its error: joint ranges with their units,
    /// `q1=-90..90deg,q3=0..120deg` (default: the joint limits).
    pub work_region: Option<String>,
}

impl FitSettings {
    /// The priority matrix before the model restricts it: the one given,
    /// else the study file's (`None`: the robot's own).
    ///
    /// # Errors
    /// A priority file that cannot be read.
    pub fn given_priority(
        &self,
        loaded: &Loaded,
        files: &dyn Files,
    ) -> Result<Option<PriorityMatrix>, AppError> {
        Ok(match &self.priority {
            Some(source) => Some(source.load(&loaded.robot.robot, files)?),
            None => loaded.priority.clone(),
        })
    }

    /// The library's options for the robot and study of `loaded`: the priority
    /// matrix given, else the study's, restricted by the model; the prior
    /// given (its σ per kind replacing the study file's, whose per-parameter
    /// σ stay), else the study's.
    ///
    /// # Errors
    /// A bad value of any setting, naming it.
    pub fn options(
        &self,
        loaded: &Loaded,
        files: &dyn Files,
    ) -> Result<IdentificationOptions, AppError> {
        let robot = &loaded.robot.robot;
        let given = self.given_priority(loaded, files)?;
        let name = loaded.model(self.model.as_deref()).unwrap_or("full");
        let model = model(name, robot, files)?;
        let max_iterations = self
            .max_iterations
            .unwrap_or(gecaro_calib::identification::DEFAULT_MAX_ITERATIONS);
        if !(1..=MAX_ITERATIONS).contains(&max_iterations) {
            return Err(AppError::setting_value(
                "max_iterations",
                max_iterations,
                format!("between 1 and {MAX_ITERATIONS}"),
            ));
        }
        let kind: LossKind = self.loss.as_deref().unwrap_or("l2").parse()?;
        Ok(IdentificationOptions {
            solver: parse_name(
                "solver",
                self.solver.as_deref(),
                &Solver::NAMES,
                Solver::from_name,
            )?
            .unwrap_or_default(),
            max_iterations,
            priority: Some(model.priority(robot, given.as_ref())),
            loss: Loss::from_parts(kind, self.loss_scale)?,
            prior: prior(self.prior.as_deref(), loaded.prior.clone())?,
            outlier_threshold: self.outlier_threshold.unwrap_or(DEFAULT_OUTLIER_THRESHOLD),
            reject: self.reject,
            // An elastic robot's loads follow the calibrated geometry.
            masses: robot.is_elastic().then(|| loaded.robot.masses.clone()),
            work_region: self
                .work_region
                .as_deref()
                .map(|text| {
                    gecaro_io::parse_work_region(text, robot).map_err(|message| {
                        AppError::setting("work_region", message).with_help(vec![
                            crate::error::Part::Text(
                                "for example: q1=-90..90deg,q2=-45..45deg".into(),
                            ),
                        ])
                    })
                })
                .transpose()?,
            ..IdentificationOptions::default()
        })
    }
}

/// Whether `name` names an elastic model (`elastic`, `elastic-gravity`),
/// whose robot is made elastic (and its samples loaded) before the model's
/// priorities are drawn.
pub(crate) fn names_elastic(name: Option<&str>) -> bool {
    name.and_then(|name| name.trim().parse::<Model>().ok())
        .is_some_and(|model| model.is_elastic())
}

/// A model by name, or a priority-matrix file.
///
/// # Errors
/// An unknown name, or a file that cannot be read.
pub(crate) fn model(name: &str, robot: &Robot, files: &dyn Files) -> Result<Model, AppError> {
    let name = name.trim();
    let looks_like_file = std::path::Path::new(name)
        .extension()
        .is_some_and(|e| e == "toml");
    if looks_like_file || files.is_file(name) {
        let matrix = PrioritySource::File(name.to_owned()).load(robot, files)?;
        return Ok(Model::Matrix(name.to_owned(), matrix));
    }
    Ok(name.parse::<Model>()?)
}

/// The prior of `text` (σ per kind), keeping the per-parameter σ of the
/// study's; the study's alone without `text`.
///
/// # Errors
/// Text that is not a prior, naming the setting.
pub(crate) fn prior(text: Option<&str>, study: Option<Prior>) -> Result<Option<Prior>, AppError> {
    match text.map(str::trim) {
        None | Some("") => Ok(study),
        Some(text) => {
            let mut prior = gecaro_io::parse_prior(text).map_err(|message| {
                AppError::setting("prior", message).with_help(vec![crate::error::Part::Text(
                    "for example: 5mm,0.5deg,1%".into(),
                )])
            })?;
            prior.overrides = study.map(|p| p.overrides).unwrap_or_default();
            Ok(Some(prior))
        }
    }
}
