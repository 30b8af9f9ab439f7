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
use gecaro_calib::validation::{Folds, Model, compare_models};
use gecaro_calib::{Observer, Quiet};

use crate::error::{AppError, Part};
use crate::measurements::{Loaded, Note};

/// A smaller model is suggested when its held-out error is below this part
/// of the model's.
pub const BETTER: f64 = 0.9;

/// The parts of each joint's range the region folds hold out (a fifth at
/// each end).
const REGION_PARTS: usize = 5;

/// Another model, with the figures that recommend it.
#[derive(Clone, Debug, PartialEq)]
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

/// The next smaller model than `name`'s, when region folds say it
/// predicts better (module docs).
///
/// # Errors
/// A fold that cannot be identified; an interruption.
pub(crate) fn smaller_model_advice(
    loaded: &Loaded,
    options: &IdentificationOptions,
    name: &str,
    observer: &mut dyn Observer,
) -> Result<Option<ModelAdvice>, AppError> {
    let smaller = match name {
        "full" => Model::NoGains,
        "no-gains" | "no-beta" => Model::Kinematic,
        "kinematic" => Model::Offsets,
        _ => return Ok(None),
    };
    let robot = &loaded.robot.robot;
    // The model identified is the options' priority matrix as it stands.
    let current = Model::Matrix(
        name.to_owned(),
        options.priority.clone().unwrap_or_else(|| robot.priority()),
    );
    let candidates = [
        current,
        Model::Matrix(
            smaller.name().to_owned(),
            smaller.priority(robot, options.priority.as_ref()),
        ),
    ];
    let scores = compare_models(
        robot,
        &loaded.study,
        options,
        &candidates,
        Folds::Regions {
            count: REGION_PARTS,
        },
        observer,
    )?;
    let held_out = |model: &str| {
        scores
            .iter()
            .find(|score| score.model.name() == model)
            .map(|score| score.validation.rms)
    };
    let (Some(small), Some(current)) = (held_out(smaller.name()), held_out(name)) else {
        return Ok(None);
    };
    Ok((small < BETTER * current).then(|| ModelAdvice {
        model: smaller.name().to_owned(),
        instead_of: name.to_owned(),
        sigma_ratio: None,
        instead_ratio: None,
        held_out: small,
        instead_held_out: current,
    }))
}
