//! Held-out error as the judge: K-fold cross-validation of an
//! identification, and the choice of the model by it.
//!
//! **Folds** ([`Folds`]). The unit held out is a configuration, or a whole
//! link set or distance pair, so that a set is never split. Each fold
//! identifies on the units it keeps and measures the calibrated robot's
//! errors on those it holds out with [`crate::identification::evaluate`]
//! (the distance to the measured point, the scatter of a held-out link set
//! about its own mean, the distance to a held-out plane, the distance error
//! of a pair). The overall held-out RMS pools every held-out observation.
//!
//! - **Random** folds ([`Folds::Random`]): the units of each set are
//!   shuffled (seeded) and dealt to K folds in turn, so that each fold holds
//!   about 1/K of every set. Every held-out unit has measured neighbours:
//!   this tests *interpolation*, and ranks first whatever fits the measured
//!   region best.
//! - **Regions** ([`Folds::Regions`]): a calibration is used in a workspace
//!   it was not measured in, and a parameter that only interpolates (a gain
//!   over a narrow range of its joint) fits the region and misleads beyond
//!   it. So each fold holds out one end of one joint's measured range: the
//!   units whose joint value lies in the lowest, or the highest, 1/K of the
//!   range the data cover (each unit judged at its first configuration's
//!   joint variables, eq. 4 of the nominal robot), two folds per joint that
//!   moved. A unit may be held out by several folds (a corner of the
//!   workspace) or by none (its middle): the score is the RMS over every
//!   held-out error, as for random folds.
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
use crate::identification::{Identification, IdentificationOptions, evaluate, identify_fit};
use crate::methods::units;
use crate::progress::{Observer, Progress, Quiet, report};
use crate::sampler::Sampler;
use crate::study::Study;

/// How observations are held out (see the module docs).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Folds {
    /// `count` folds of units dealt at random, seeded: interpolation.
    Random {
        /// The number of folds.
        count: usize,
        /// The seed of the deal.
        seed: u64,
    },
    /// The ends of each joint's measured range, 1/`count` of it at each
    /// end, one fold per end: extrapolation.
    Regions {
        /// The range's parts: each end holds out 1/`count` of it.
        count: usize,
    },
}

impl Folds {
    /// The names users give the two kinds: `regions`, `random`.
    pub const NAMES: [&'static str; 2] = ["regions", "random"];

    /// The folds of kind `name` ([`NAMES`](Self::NAMES)) with `count`
    /// parts and `seed` (random folds only).
    pub fn from_name(name: &str, count: usize, seed: u64) -> Option<Self> {
        match name {
            "regions" => Some(Folds::Regions { count }),
            "random" => Some(Folds::Random { count, seed }),
            _ => None,
        }
    }

    /// `regions` or `random`.
    pub fn name(self) -> &'static str {
        match self {
            Folds::Regions { .. } => "regions",
            Folds::Random { .. } => "random",
        }
    }

    /// The number of folds, or of parts of a range.
    pub fn count(self) -> usize {
        match self {
            Folds::Regions { count } | Folds::Random { count, .. } => count,
        }
    }
}

/// The held-out errors of one fold.
#[derive(Clone, Debug, PartialEq)]
pub struct Fold {
    /// What the fold holds out: `fold 3`, or `q1 ≥ 1.82 rad`.
    pub label: String,
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
    /// How the observations were held out.
    pub folds_by: Folds,
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
    cross_validate_by(
        robot,
        study,
        options,
        Folds::Random { count: folds, seed },
        observer,
    )
}

/// Cross-validation of `identify(robot, study, options)` with the `folds`
/// asked for (see the module docs); each finished fold is reported to
/// `observer` ([`Progress::Step`]).
///
/// # Errors
/// As [`cross_validate`]; region folds on data whose joints did not move.
pub fn cross_validate_by(
    robot: &Robot,
    study: &Study,
    options: &IdentificationOptions,
    folds: Folds,
    observer: &mut dyn Observer,
) -> Result<CrossValidation, Error> {
    let held_out_by = match folds {
        Folds::Random { count, seed } => {
            let assignment = fold_assignment(study, count, seed)?;
            (0..count)
                .map(|fold| {
                    let dropped = study
                        .sets
                        .iter()
                        .enumerate()
                        .map(|(set, measurement)| {
                            (0..measurement.samples.len())
                                .filter(|sample| assignment[set][*sample] == fold)
                                .collect()
                        })
                        .collect();
                    (format!("fold {}", fold + 1), dropped)
                })
                .collect()
        }
        Folds::Regions { count } => region_folds(robot, study, count)?,
    };
    let total = held_out_by.len();
    let mut results = Vec::with_capacity(total);
    let mut parameters = Vec::new();
    let (mut squares, mut rotation_squares, mut count) = (0.0, 0.0, 0);
    for (fold, (label, dropped)) in held_out_by.into_iter().enumerate() {
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
            message: format!(
                "cross-validation fold {} of {total} ({label}): {error}",
                fold + 1
            ),
        };
        let fitted: Identification =
            identify_fit(robot, &training, options, &mut Quiet).map_err(context)?;
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
            label,
            held_out: errors.count,
            training_rms: fitted.after.rms,
            rms: errors.rms,
            rms_rotation: errors.rms_rotation,
        });
        report(
            observer,
            Progress::Step {
                done: fold + 1,
                total,
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
        folds_by: folds,
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

/// A fold: its label, and the samples it holds out, per set.
type HeldOut = (String, Vec<Vec<usize>>);

/// The region folds of `study` (module docs): per joint that moved, the
/// units whose joint value lies in the lowest and in the highest
/// 1/`parts` of the range the data cover, each fold with its label and its
/// held-out samples per set.
///
/// # Errors
/// Fewer than 2 parts, or data whose joints did not move.
fn region_folds(robot: &Robot, study: &Study, parts: usize) -> Result<Vec<HeldOut>, Error> {
    if parts < 2 {
        return Err(Error::InvalidOption {
            setting: Setting::Folds,
            message: format!("{parts} parts: region folds hold out 1/K of each end, K ≥ 2"),
        });
    }
    // Every unit with its joint variables (at its first configuration).
    let mut joints = vec![0.0; robot.joint_count()];
    let mut located: Vec<(usize, Vec<usize>, Vec<f64>)> = Vec::new();
    for (index, set) in study.sets.iter().enumerate() {
        for unit in units(set.method.as_ref(), set.samples.as_slice()) {
            let Some(first) = unit.first() else { continue };
            robot.joint_positions_into(set.samples.get(*first).motor_positions(), &mut joints)?;
            located.push((index, unit, joints.clone()));
        }
    }
    let mut folds = Vec::new();
    for joint in 0..robot.joint_count() {
        let values = located.iter().map(|(_, _, q)| q[joint]);
        let (min, max) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), q| {
            (a.min(q), b.max(q))
        });
        let width = max - min;
        if width.is_nan() || width <= crate::identification::STILL_RANGE {
            continue;
        }
        let unit = if robot.frames()[joint + 1].frame_type == gecaro_core::FrameType::Prismatic {
            (" mm", 1e3)
        } else {
            ("°", 180.0 / std::f64::consts::PI)
        };
        let part = width / parts as f64;
        for (low, bound) in [(true, min + part), (false, max - part)] {
            let held = |q: f64| if low { q <= bound } else { q >= bound };
            let mut dropped = vec![Vec::new(); study.sets.len()];
            let mut held_units = 0;
            for (set, unit_samples, q) in &located {
                if held(q[joint]) {
                    dropped[*set].extend(unit_samples);
                    held_units += 1;
                }
            }
            if held_units == 0 || held_units == located.len() {
                continue;
            }
            let label = format!(
                "q{} {} {:.1}{}",
                joint + 1,
                if low { "≤" } else { "≥" },
                bound * unit.1,
                unit.0
            );
            folds.push((label, dropped));
        }
    }
    if folds.is_empty() {
        return Err(Error::InvalidOption {
            setting: Setting::Folds,
            message: "region folds need joints that moved in the data".into(),
        });
    }
    Ok(folds)
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
/// RMS) first; every finished fold of every model is reported to
/// `observer`. Region folds ([`Folds::Regions`]) rank the model that
/// generalises to where the data were not taken; random folds, the one that
/// interpolates best.
///
/// # Errors
/// As [`cross_validate`], naming the model.
pub fn compare_models(
    robot: &Robot,
    study: &Study,
    options: &IdentificationOptions,
    models: &[Model],
    folds: Folds,
    observer: &mut dyn Observer,
) -> Result<Vec<ModelScore>, Error> {
    let mut scores = Vec::with_capacity(models.len());
    // Each model's folds are counted as one of the first model's.
    let per_model = match folds {
        Folds::Random { count, .. } => count,
        Folds::Regions { count } => region_folds(robot, study, count)?.len(),
    };
    let total = models.len() * per_model;
    for (index, model) in models.iter().enumerate() {
        let options = IdentificationOptions {
            priority: Some(model.priority(robot, options.priority.as_ref())),
            ..options.clone()
        };
        let mut folds_of_all = |progress: Progress<'_>| match progress {
            Progress::Step { done, .. } => observer.observe(Progress::Step {
                done: index * per_model + done,
                total,
            }),
            // Each model's folds are one count of all models' folds.
            Progress::Iteration(_) | Progress::Phase(_) => ControlFlow::Continue(()),
        };
        let validation = cross_validate_by(robot, study, &options, folds, &mut folds_of_all)
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
