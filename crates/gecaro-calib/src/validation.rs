//! Held-out error as the judge: K-fold cross-validation of an
//! identification, and the choice of the model by it.
//!
//! **Folds.** The units of each measurement set — a configuration, or a
//! whole link set or distance pair, so that a set is never split — are
//! shuffled (seeded) and dealt to K folds in turn, one set after the other,
//! so that each fold holds about 1/K of every set. Fold k identifies on the
//! other K − 1 folds and measures the calibrated robot's errors on fold k
//! with [`crate::identification::evaluate`] (the distance to the measured point, the scatter
//! of a held-out link set about its own mean, the distance to a held-out
//! plane, the distance error of a pair). The overall held-out RMS pools every
//! held-out observation.
//!
//! **Models.** A model is a priority matrix: which parameters may be
//! identified at all ([`Model`]). The full model fits the training data best
//! by construction; cross-validation tells whether what a bigger model adds
//! (gains, Hayati angles) generalises or fits noise and unmodelled effects
//! (joint play, compliance).

use std::fmt;
use std::ops::ControlFlow;
use std::str::FromStr;

use gecaro_core::{ParameterKind, PriorityMatrix, Robot};

use crate::Error;
use crate::error::Setting;
use crate::identification::{Identification, IdentificationOptions, evaluate, identify};
use crate::methods::units;
use crate::progress::{Observer, Progress, Quiet, report};
use crate::sampler::Sampler;
use crate::study::Study;

/// The held-out errors of one fold.
#[derive(Clone, Debug, PartialEq)]
pub struct Fold {
    /// Observations held out (configurations, or pairs).
    pub held_out: usize,
    /// Training residual: RMS position-like error of the training observations (m).
    pub training_rms: f64,
    /// Held-out RMS position-like error (m).
    pub rms: f64,
    /// Held-out RMS orientation error (rad), for data with orientations.
    pub rms_rotation: Option<f64>,
}

/// The result of [`cross_validate`].
#[derive(Clone, Debug, PartialEq)]
pub struct CrossValidation {
    /// Per fold.
    pub folds: Vec<Fold>,
    /// Held-out RMS over every held-out observation (m).
    pub rms: f64,
    /// Held-out RMS orientation error over every held-out observation (rad).
    pub rms_rotation: Option<f64>,
    /// Identified parameters of the first fold's fit (the model's size).
    pub parameters: Vec<String>,
}

/// K-fold cross-validation of `identify(robot, study, options)`; see the
/// module docs. Each finished fold is reported to `observer`
/// ([`Progress::Step`]).
///
/// # Errors
/// [`Error::InvalidOption`] for K < 2 or more folds than units; the errors of
/// a fold's identification or evaluation, naming the fold;
/// [`Error::Interrupted`] when the observer stops the work.
pub fn cross_validate(
    robot: &Robot,
    study: &Study,
    options: &IdentificationOptions,
    folds: usize,
    seed: u64,
    observer: &mut dyn Observer,
) -> Result<CrossValidation, Error> {
    let assignment = fold_assignment(study, folds, seed)?;
    let mut results = Vec::with_capacity(folds);
    let mut parameters = Vec::new();
    let (mut squares, mut rotation_squares, mut count) = (0.0, 0.0, 0);
    for fold in 0..folds {
        let in_fold = |set: usize, sample: usize| assignment[set][sample] == fold;
        let dropped: Vec<Vec<usize>> = study
            .sets
            .iter()
            .enumerate()
            .map(|(set, measurement)| {
                (0..measurement.samples.len())
                    .filter(|sample| in_fold(set, *sample))
                    .collect()
            })
            .collect();
        let training = study.without_samples(&dropped);
        let held_out = Study {
            sets: study
                .sets
                .iter()
                .zip(&dropped)
                .filter(|(_, kept)| !kept.is_empty())
                .map(|(set, kept)| set.with_samples(set.samples.gather(kept)))
                .collect(),
            frames: study.frames.clone(),
        };
        let context = |error: Error| Error::Numerical {
            message: format!("cross-validation fold {} of {folds}: {error}", fold + 1),
        };
        let fitted: Identification =
            identify(robot, &training, options, &mut Quiet).map_err(context)?;
        let errors = evaluate(
            &fitted.calibrated,
            &held_out.with_frames(fitted.frames.clone()),
        )
        .map_err(context)?;
        if fold == 0 {
            parameters = fitted.parameters.iter().map(|p| p.name.clone()).collect();
        }
        squares += errors.rms * errors.rms * errors.count as f64;
        rotation_squares += errors.rms_rotation.unwrap_or(0.0).powi(2) * errors.count as f64;
        count += errors.count;
        results.push(Fold {
            held_out: errors.count,
            training_rms: fitted.after.rms,
            rms: errors.rms,
            rms_rotation: errors.rms_rotation,
        });
        report(
            observer,
            Progress::Step {
                done: fold + 1,
                total: folds,
            },
        )?;
    }
    let pooled = |sum: f64| (sum / count.max(1) as f64).sqrt();
    let has_rotation = results.iter().any(|fold| fold.rms_rotation.is_some());
    Ok(CrossValidation {
        folds: results,
        rms: pooled(squares),
        rms_rotation: has_rotation.then(|| pooled(rotation_squares)),
        parameters,
    })
}

/// The fold of every sample, per set (see the module docs).
fn fold_assignment(study: &Study, folds: usize, seed: u64) -> Result<Vec<Vec<usize>>, Error> {
    let unit_lists: Vec<Vec<Vec<usize>>> = study
        .sets
        .iter()
        .map(|set| units(set.method.as_ref(), set.samples.as_slice()))
        .collect();
    let total: usize = unit_lists.iter().map(Vec::len).sum();
    if folds < 2 || folds > total {
        return Err(Error::InvalidOption {
            setting: Setting::Folds,
            message: format!(
                "{folds} folds: give between 2 and the number of configurations, sets and pairs ({total})"
            ),
        });
    }
    let mut sampler = Sampler::new(seed);
    let mut next = 0;
    Ok(study
        .sets
        .iter()
        .zip(&unit_lists)
        .map(|(set, set_units)| {
            let mut fold_of = vec![0; set.samples.len()];
            for position in sampler.subset(set_units.len(), set_units.len()) {
                for sample in &set_units[position] {
                    fold_of[*sample] = next % folds;
                }
                next += 1;
            }
            fold_of
        })
        .collect())
}

/// Which parameters a model may identify; see the module docs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Model {
    /// The priority matrix as given (the robot's, or `--priority`).
    Full,
    /// Without the transmission gains K.
    NoGains,
    /// Without the Hayati angles β.
    NoBeta,
    /// Neither gains nor Hayati angles: Khalil–Kleinfinger parameters only.
    Kinematic,
    /// The joint offsets only (θ of revolute, r of prismatic joints).
    Offsets,
    /// The full model and every joint's compliance (issue 38), after the
    /// geometry in the priority order: the robot must be elastic
    /// ([`gecaro_core::Robot::set_compliances`]) and its samples loaded
    /// ([`crate::elastic::load_samples`]).
    Elastic,
    /// The elastic model and the direction of gravity: its two tilts
    /// (`tilt1`, `tilt2`, [`gecaro_core::MassModel::tilted`]) after the
    /// compliances, for a measurement frame that is not levelled. Seen only
    /// through the compliances, they are identified in a second pass.
    ElasticGravity,
    /// A priority matrix read from a file (named by it).
    Matrix(String, PriorityMatrix),
}

impl Model {
    /// The models that need no file, smallest first.
    pub const NAMED: [&'static str; 7] = [
        "offsets",
        "kinematic",
        "no-gains",
        "no-beta",
        "full",
        "elastic",
        "elastic-gravity",
    ];

    /// Whether it identifies compliances (its robot must be elastic).
    pub fn is_elastic(&self) -> bool {
        matches!(self, Model::Elastic | Model::ElasticGravity)
    }

    /// Its name: `full`, `no-gains`, …, or the file's.
    pub fn name(&self) -> &str {
        match self {
            Model::Full => "full",
            Model::NoGains => "no-gains",
            Model::NoBeta => "no-beta",
            Model::Kinematic => "kinematic",
            Model::Offsets => "offsets",
            Model::Elastic => "elastic",
            Model::ElasticGravity => "elastic-gravity",
            Model::Matrix(name, _) => name,
        }
    }

    /// The priority matrix of this model for `robot`, from `full` (the full
    /// model's; the robot's own when `None`).
    pub fn priority(&self, robot: &Robot, full: Option<&PriorityMatrix>) -> PriorityMatrix {
        let mut matrix = match self {
            Model::Matrix(_, matrix) => return matrix.clone(),
            // The compliances come last: geometry first in the base set.
            Model::Elastic | Model::ElasticGravity => {
                let tilt = u32::from(*self == Model::ElasticGravity);
                return full
                    .cloned()
                    .unwrap_or_else(|| robot.priority())
                    .with_compliances(1)
                    .with_gravity_tilt(tilt);
            }
            _ => full.cloned().unwrap_or_else(|| robot.priority()),
        };
        for id in robot.parameters().ids() {
            let keep = match self {
                Model::Full | Model::Matrix(..) | Model::Elastic | Model::ElasticGravity => true,
                Model::NoGains => id.kind != ParameterKind::Gain,
                Model::NoBeta => id.kind != ParameterKind::Beta,
                Model::Kinematic => !matches!(id.kind, ParameterKind::Gain | ParameterKind::Beta),
                Model::Offsets => {
                    (1..=robot.joint_count()).contains(&id.frame)
                        && match robot.frames()[id.frame].frame_type {
                            gecaro_core::FrameType::Prismatic => id.kind == ParameterKind::R,
                            _ => id.kind == ParameterKind::Theta,
                        }
                }
            };
            if !keep {
                matrix.set(*id, 0);
            }
        }
        matrix
    }
}

impl fmt::Display for Model {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Model {
    type Err = Error;

    /// A named model (`full`, `no-gains`, `no-beta`, `kinematic`, `offsets`).
    fn from_str(name: &str) -> Result<Self, Error> {
        Ok(match name.trim() {
            "full" => Model::Full,
            "no-gains" => Model::NoGains,
            "no-beta" => Model::NoBeta,
            "kinematic" => Model::Kinematic,
            "offsets" => Model::Offsets,
            "elastic" => Model::Elastic,
            "elastic-gravity" => Model::ElasticGravity,
            other => {
                return Err(Error::InvalidOption {
                    setting: Setting::Model,
                    message: format!(
                        "unknown model '{other}' (expected {}, or a priority-matrix file)",
                        Model::NAMED.join(", ")
                    ),
                });
            }
        })
    }
}

/// One model's cross-validated result.
#[derive(Clone, Debug)]
pub struct ModelScore {
    /// The model.
    pub model: Model,
    /// Its cross-validation.
    pub validation: CrossValidation,
}

/// Cross-validates each model (same folds for all), best (lowest held-out
/// RMS) first; every finished fold of every model is reported to `observer`.
///
/// # Errors
/// As [`cross_validate`], naming the model.
pub fn compare_models(
    robot: &Robot,
    study: &Study,
    options: &IdentificationOptions,
    models: &[Model],
    folds: usize,
    seed: u64,
    observer: &mut dyn Observer,
) -> Result<Vec<ModelScore>, Error> {
    let mut scores = Vec::with_capacity(models.len());
    let total = models.len() * folds;
    for (index, model) in models.iter().enumerate() {
        let options = IdentificationOptions {
            priority: Some(model.priority(robot, options.priority.as_ref())),
            ..options.clone()
        };
        let mut folds_of_all = |progress: Progress<'_>| match progress {
            Progress::Step { done, .. } => observer.observe(Progress::Step {
                done: index * folds + done,
                total,
            }),
            // Each model's folds are one count of all models' folds.
            Progress::Iteration(_) | Progress::Phase(_) => ControlFlow::Continue(()),
        };
        let validation = cross_validate(robot, study, &options, folds, seed, &mut folds_of_all)
            .map_err(|error| match error {
                Error::Interrupted => Error::Interrupted,
                error => Error::Numerical {
                    message: format!("model {model}: {error}"),
                },
            })?;
        scores.push(ModelScore {
            model: model.clone(),
            validation,
        });
    }
    scores.sort_by(|a, b| a.validation.rms.total_cmp(&b.validation.rms));
    Ok(scores)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn models_keep_what_they_say() {
        let robot = Robot::template("arm", "RRPRRR").expect("template");
        let full = robot.priority();
        let count = |model: Model, kind: ParameterKind| {
            let matrix = model.priority(&robot, Some(&full));
            robot
                .parameters()
                .ids()
                .iter()
                .filter(|id| id.kind == kind && matrix.get(**id) > 0)
                .count()
        };
        assert!(count(Model::Full, ParameterKind::Gain) > 0);
        assert_eq!(count(Model::NoGains, ParameterKind::Gain), 0);
        assert_eq!(count(Model::Kinematic, ParameterKind::Beta), 0);
        assert_eq!(count(Model::Offsets, ParameterKind::D), 0);
        assert_eq!(count(Model::Offsets, ParameterKind::Theta), 5);
        assert_eq!(count(Model::Offsets, ParameterKind::R), 1);
        assert!("no-gain".parse::<Model>().is_err());
        assert_eq!("kinematic".parse::<Model>().ok(), Some(Model::Kinematic));
    }
}
