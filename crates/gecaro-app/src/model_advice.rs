//! Another model that would do better, said with its figures: the elastic
//! model where the robot file has masses and the rigid fit fails the global
//! test, and, on request, the next smaller model when it predicts the ends
//! of the measured range better (docs/methods.md, "The model that
//! generalises").
//!
//! - **Elastic joints.** A robot whose joints sag under its links' weight
//!   leaves the rigid model 5× the noise; the verdict used to say so and
//!   no more. When the fit exceeds the stated noise, the robot file states
//!   masses and the model is rigid, the elastic model is identified too (one
//!   identification, on failure only) and suggested when it fits the noise,
//!   with both models' error held out by region ([`Folds::Regions`]).
//! - **A smaller model** (`check_model`). The full model fits its own data
//!   best by construction; a parameter that only interpolates (a gain seen
//!   over a narrow range) may predict worse where the data were not taken.
//!   On request, the model identified and the next smaller one (without the
//!   gains, or without the Hayati angles) are compared by region folds, and
//!   the smaller one is suggested when its held-out error is below
//!   [`BETTER`] of the model's. It costs two region cross-validations (two
//!   folds a joint each): 5–10× the identification's own time, hence not by
//!   default.

use gecaro_calib::identification::{Identification, IdentificationOptions, identify};
use gecaro_calib::study::Study;
use gecaro_calib::validation::{Folds, Model, compare_models};
use gecaro_calib::{Observer, Quiet};
use gecaro_core::PriorityMatrix;

use crate::error::{AppError, Part};
use crate::measurements::{Loaded, Note};

/// A smaller model is suggested when its held-out error is below this part
/// of the model's.
pub const BETTER: f64 = 0.9;

/// The size of data (equations) up to which `identify` compares its model
/// with its neighbours unasked: a few hundred measurements, where the two or
/// three region cross-validations take a fraction of a second.
pub const CHEAP_EQUATIONS: usize = 1_500;

/// The parts of each joint's range the region folds hold out (a fifth at
/// each end).
const REGION_PARTS: usize = 5;

/// Another model, with the figures that recommend it (the JSON documents'
/// `model_advice`, as it stands).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ModelAdvice {
    /// The model suggested (`elastic`, `no-gains`, …).
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

impl ModelAdvice {
    /// The advice as a note, in each front end's words.
    pub(crate) fn note(&self) -> Note {
        let ratios = match (self.sigma_ratio, self.instead_ratio) {
            (Some(suggested), Some(instead)) => {
                format!("σ̂/σ {suggested:.2} against {instead:.2}; ")
            }
            _ => String::new(),
        };
        Note::warning_parts(vec![
            Part::Text(format!(
                "the {} model predicts better than the {} one ({ratios}held out by region, the ends \
                 of each joint's range: {:.4} mm against {:.4} mm): identify with ",
                self.model,
                self.instead_of,
                self.held_out * 1e3,
                self.instead_held_out * 1e3,
            )),
            Part::SettingValue("model".into(), self.model.clone()),
        ])
    }
}

/// The elastic model, when the rigid fit `result` of `loaded` exceeds the
/// stated noise, the robot file has masses, and the elastic model fits
/// (module docs).
///
/// # Errors
/// An interruption.
pub(crate) fn elastic_advice(
    loaded: &Loaded,
    options: &IdentificationOptions,
    result: &Identification,
    observer: &mut dyn Observer,
) -> Result<Option<ModelAdvice>, AppError> {
    let exceeded = result
        .verdict
        .noise_test
        .is_some_and(|test| test.exceeded());
    if !exceeded || loaded.robot.robot.is_elastic() || loaded.robot.masses.is_empty() {
        return Ok(None);
    }
    let mut elastic = loaded.clone();
    if elastic.make_elastic().is_err() {
        return Ok(None);
    }
    let robot = &elastic.robot.robot;
    let elastic_options = IdentificationOptions {
        priority: Some(Model::Elastic.priority(robot, options.priority.as_ref())),
        masses: Some(elastic.robot.masses.clone()),
        ..options.clone()
    };
    let Ok(fitted) = identify(robot, &elastic.study, &elastic_options, &mut Quiet) else {
        return Ok(None);
    };
    let fits = fitted
        .verdict
        .noise_test
        .is_some_and(|test| !test.exceeded());
    if !fits {
        return Ok(None);
    }
    let folds = Folds::Regions {
        count: REGION_PARTS,
    };
    let held_out =
        |loaded: &Loaded, options: &IdentificationOptions, observer: &mut dyn Observer| {
            compare_models(
                &loaded.robot.robot,
                &loaded.study,
                options,
                &[Model::Matrix(
                    "model".into(),
                    options
                        .priority
                        .clone()
                        .unwrap_or_else(|| loaded.robot.robot.priority()),
                )],
                folds,
                observer,
            )
            .map(|scores| scores.first().map(|score| score.validation.rms))
        };
    let (Some(elastic_held_out), Some(rigid_held_out)) = (
        held_out(&elastic, &elastic_options, observer)?,
        held_out(loaded, options, observer)?,
    ) else {
        return Ok(None);
    };
    Ok(Some(ModelAdvice {
        model: "elastic".into(),
        instead_of: "rigid".into(),
        sigma_ratio: fitted.verdict.noise_test.map(|test| test.sigma_ratio),
        instead_ratio: result.verdict.noise_test.map(|test| test.sigma_ratio),
        held_out: elastic_held_out,
        instead_held_out: rigid_held_out,
    }))
}

/// A comparison of the model identified with its neighbours, prepared.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelCheck {
    /// The model identified (`full`, `no-gains`, …).
    pub model: String,
    /// The priority matrix before the model restricted it (`None`: the
    /// robot's), from which the next larger model is drawn.
    pub given: Option<PriorityMatrix>,
    /// Whether the user asked for it (an error of a fold is then reported);
    /// otherwise it runs because the data are small (`is_cheap`) and a
    /// fold that cannot be identified only skips it.
    pub asked: bool,
}

/// Whether comparing models costs little beside the identification: at
/// most [`CHEAP_EQUATIONS`] equations.
pub(crate) fn is_cheap(study: &Study) -> bool {
    study.equation_count() <= CHEAP_EQUATIONS
}

/// The model one step smaller than `name` (full → no-gains → kinematic →
/// offsets; no-beta → kinematic).
fn smaller(name: &str) -> Option<Model> {
    match name {
        "full" => Some(Model::NoGains),
        "no-gains" | "no-beta" => Some(Model::Kinematic),
        "kinematic" => Some(Model::Offsets),
        _ => None,
    }
}

/// The larger model `name` is compared with: the kinematic one for the
/// offsets, the full one (the priority matrix given) for any model between.
fn larger(name: &str) -> Option<Model> {
    match name {
        "offsets" => Some(Model::Kinematic),
        "kinematic" | "no-gains" | "no-beta" => Some(Model::Full),
        _ => None,
    }
}

/// The neighbour of the model identified (one step smaller or larger) that
/// region folds say predicts better, by at least [`BETTER`] (module docs).
///
/// # Errors
/// An interruption; a fold that cannot be identified when the check was
/// asked for.
pub(crate) fn neighbour_advice(
    loaded: &Loaded,
    options: &IdentificationOptions,
    check: &ModelCheck,
    observer: &mut dyn Observer,
) -> Result<Option<ModelAdvice>, AppError> {
    let robot = &loaded.robot.robot;
    let name = check.model.as_str();
    // The model identified is the options' priority matrix as it stands.
    let current = options.priority.clone().unwrap_or_else(|| robot.priority());
    let neighbours = [
        smaller(name).map(|model| (model.priority(robot, Some(&current)), model)),
        larger(name).map(|model| (model.priority(robot, check.given.as_ref()), model)),
    ];
    let mut candidates = vec![Model::Matrix(name.to_owned(), current.clone())];
    let mut matrices = vec![current];
    // A neighbour that identifies the same parameters is no alternative.
    for (matrix, model) in neighbours.into_iter().flatten() {
        if !matrices.contains(&matrix) {
            candidates.push(Model::Matrix(model.name().to_owned(), matrix.clone()));
            matrices.push(matrix);
        }
    }
    if candidates.len() < 2 {
        return Ok(None);
    }
    let folds = Folds::Regions {
        count: REGION_PARTS,
    };
    let scores = match compare_models(robot, &loaded.study, options, &candidates, folds, observer) {
        Ok(scores) => scores,
        Err(error) if check.asked || matches!(error, gecaro_calib::Error::Interrupted) => {
            return Err(error.into());
        }
        Err(_) => return Ok(None),
    };
    let held_out = |model: &str| {
        scores
            .iter()
            .find(|score| score.model.name() == model)
            .map(|score| score.validation.rms)
    };
    let Some(current) = held_out(name) else {
        return Ok(None);
    };
    let best = scores
        .iter()
        .filter(|score| score.model.name() != name)
        .map(|score| (score.model.name(), score.validation.rms))
        .min_by(|a, b| a.1.total_cmp(&b.1));
    Ok(best
        .filter(|&(_, rms)| rms < BETTER * current)
        .map(|(model, rms)| ModelAdvice {
            model: model.to_owned(),
            instead_of: name.to_owned(),
            sigma_ratio: None,
            instead_ratio: None,
            held_out: rms,
            instead_held_out: current,
        }))
}
