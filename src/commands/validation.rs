//! `gecaro identify --cv K` and `gecaro compare-models`: held-out error as
//! the judge of an identification and of the model (docs/methods.md).
use gecaro_calib::{
    each_step,
    identification::IdentificationOptions,
    study::Study,
    validation::{CrossValidation, Model, ModelScore, compare_models, cross_validate},
};
use gecaro_core::Robot;
use gecaro_report::json::{CrossValidationJson, ModelScoreJson};
use indicatif::ProgressBar;

use super::calibration::{Prepared, model, prepare};
use crate::cli::CompareModelsArgs;
use crate::failure::Failure;
use crate::format::table;

/// A bar over `total` fold identifications.
fn fold_bar(what: &str, total: usize) -> ProgressBar {
    let bar = super::progress_bar(what);
    bar.set_length(total as u64);
    bar
}

/// K-fold cross-validation of an identification with a progress bar.
pub(super) fn cross_validation(
    robot: &Robot,
    study: &Study,
    options: &IdentificationOptions,
    folds: usize,
    seed: u64,
) -> Result<CrossValidation, Failure> {
    let bar = fold_bar("cross-validating", folds);
    let result = cross_validate(
        robot,
        study,
        options,
        folds,
        seed,
        &mut each_step(|done, _| bar.set_position(done as u64)),
    );
    bar.finish_and_clear();
    Ok(result?)
}

fn millimetres(metres: f64) -> String {
    format!("{:.3}", metres * 1e3)
}

fn degrees(radians: Option<f64>) -> String {
    radians.map_or("–".into(), |r| format!("{:.4}", r.to_degrees()))
}

/// The per-fold table and the pooled held-out error.
pub(super) fn print_cross_validation(validation: &CrossValidation, seed: u64) {
    let rotation = validation.rms_rotation.is_some();
    let mut header = vec!["fold", "held out", "training RMS (mm)", "held-out RMS (mm)"];
    if rotation {
        header.push("held-out RMS (°)");
    }
    let mut rows = table(&header, 1);
    for (index, fold) in validation.folds.iter().enumerate() {
        let mut row = vec![
            (index + 1).to_string(),
            fold.held_out.to_string(),
            millimetres(fold.training_rms),
            millimetres(fold.rms),
        ];
        if rotation {
            row.push(degrees(fold.rms_rotation));
        }
        rows.add_row(row);
    }
    println!(
        "Cross-validation, {} folds (seed {seed}; sets and pairs kept whole):\n{rows}",
        validation.folds.len()
    );
    println!(
        "Held-out RMS over every fold: {} mm{}",
        millimetres(validation.rms),
        if rotation {
            format!(", {}°", degrees(validation.rms_rotation))
        } else {
            String::new()
        }
    );
}

/// What each model identifies beyond the next smaller one (by parameter
/// count), or which model it identifies the same parameters as.
fn additions(scores: &[ModelScore]) -> Vec<Vec<String>> {
    let parameters = |index: usize| &scores[index].validation.parameters;
    let mut by_size: Vec<usize> = (0..scores.len()).collect();
    by_size.sort_by_key(|index| parameters(*index).len());
    let mut adds = vec![Vec::new(); scores.len()];
    for (position, &index) in by_size.iter().enumerate() {
        let earlier = &by_size[..position];
        if let Some(same) = earlier.iter().find(|other| {
            parameters(**other).len() == parameters(index).len()
                && parameters(index)
                    .iter()
                    .all(|name| parameters(**other).contains(name))
        }) {
            adds[index] = vec![format!("(the same parameters as {})", scores[*same].model)];
        } else if let Some(smaller) = earlier
            .iter()
            .rev()
            .find(|other| parameters(**other).len() < parameters(index).len())
        {
            adds[index] = parameters(index)
                .iter()
                .filter(|name| !parameters(*smaller).contains(name))
                .cloned()
                .collect();
        }
    }
    adds
}

pub(crate) fn compare(args: &CompareModelsArgs) -> Result<(), Failure> {
    if args.run.model != "full" {
        return Err(Failure::usage(
            "compare-models takes its candidates from --models, not --model",
            Some("for example: --models kinematic,no-gains,full".to_owned()),
        ));
    }
    let Prepared {
        file,
        study,
        options,
        data_label,
    } = prepare(&args.run)?;
    let robot = &file.robot;
    let models = args
        .models
        .split(',')
        .filter(|name| !name.trim().is_empty())
        .map(|name| model(name.trim(), robot))
        .collect::<Result<Vec<Model>, Failure>>()?;
    if models.is_empty() {
        return Err(Failure::usage("--models lists no model", None));
    }
    let bar = fold_bar("comparing models (folds)", models.len() * args.cv);
    let scores = compare_models(
        robot,
        &study,
        &options,
        &models,
        args.cv,
        args.seed,
        &mut each_step(|done, _| bar.set_position(done as u64)),
    );
    bar.finish_and_clear();
    let scores = scores?;
    let adds = additions(&scores);
    if args.json {
        let documents: Vec<ModelScoreJson> = scores
            .iter()
            .zip(&adds)
            .map(|(score, adds)| ModelScoreJson {
                model: score.model.to_string(),
                parameters: score.validation.parameters.clone(),
                adds: adds.clone(),
                cross_validation: CrossValidationJson::new(&score.validation, args.seed),
            })
            .collect();
        return super::print_json(&documents);
    }
    let rotation = scores.iter().any(|s| s.validation.rms_rotation.is_some());
    let mut header = vec![
        "rank",
        "model",
        "adds to the next smaller model",
        "parameters",
        "held-out RMS (mm)",
    ];
    if rotation {
        header.push("held-out RMS (°)");
    }
    header.push("training RMS (mm)");
    let mut rows = table(&header, 3);
    for (rank, (score, adds)) in scores.iter().zip(&adds).enumerate() {
        let training = score
            .validation
            .folds
            .iter()
            .map(|fold| fold.training_rms)
            .sum::<f64>()
            / score.validation.folds.len().max(1) as f64;
        let mut row = vec![
            (rank + 1).to_string(),
            score.model.to_string(),
            if adds.is_empty() {
                "–".into()
            } else {
                adds.join(" ")
            },
            score.validation.parameters.len().to_string(),
            millimetres(score.validation.rms),
        ];
        if rotation {
            row.push(degrees(score.validation.rms_rotation));
        }
        row.push(millimetres(training));
        rows.add_row(row);
    }
    println!(
        "Models of {} on {} ({} method), {}-fold cross-validation (seed {}), best first:\n{rows}",
        robot.name(),
        data_label.display(),
        study.method_names(),
        args.cv,
        args.seed
    );
    if let Some(best) = scores.first() {
        println!(
            "Best on held-out data: {} ({} mm). A bigger model that fits the training data better \
             but does worse held out fits noise or effects the model does not describe.",
            best.model,
            millimetres(best.validation.rms)
        );
    }
    Ok(())
}
