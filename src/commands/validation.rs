//! `gecaro identify --cv K` and `gecaro compare-models`: held-out error as
//! the judge of an identification and of the model (docs/methods.md).

use gecaro_app::{CompareModelsRequest, LocalFiles};
use gecaro_calib::validation::{CrossValidation, Folds};

use super::options::{fit_settings, measurements, one_data_file, print_notes};
use super::progress::with_steps;
use crate::cli::CompareModelsArgs;
use crate::failure::Failure;
use crate::format::table;

fn millimetres(metres: f64) -> String {
    format!("{:.3}", metres * 1e3)
}

fn degrees(radians: Option<f64>) -> String {
    radians.map_or("–".into(), |r| format!("{:.4}", r.to_degrees()))
}

/// How `folds` (`count` of them) held the observations out, in words.
fn folds_words(folds: Folds, count: usize) -> String {
    match folds {
        Folds::Random { count, seed } => format!(
            "{count}-fold cross-validation by random rows (seed {seed}; interpolation: every \
             held-out pose has measured neighbours)"
        ),
        Folds::Regions { count: parts } => format!(
            "{count} folds by region (the lowest and the highest 1/{parts} of each joint's \
             measured range held out in turn: extrapolation)"
        ),
    }
}

/// The per-fold table and the pooled held-out error.
pub(super) fn print_cross_validation(validation: &CrossValidation) {
    let rotation = validation.rms_rotation.is_some();
    let mut header = vec!["fold", "held out", "training RMS (mm)", "held-out RMS (mm)"];
    if rotation {
        header.push("held-out RMS (°)");
    }
    let mut rows = table(&header, 1);
    for fold in &validation.folds {
        let mut row = vec![
            fold.label.clone(),
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
        "Cross-validation, {} (sets and pairs kept whole):\n{rows}",
        folds_words(validation.folds_by, validation.folds.len())
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

pub(crate) fn compare(args: &CompareModelsArgs) -> Result<(), Failure> {
    super::options::no_measuring_leg(&args.run.leg, args.run.source.method.as_deref())?;
    let mut request = CompareModelsRequest::new(
        measurements(&args.run.source, one_data_file(&args.run.data)?)?,
        args.models.split(',').map(str::to_owned).collect(),
        args.cv,
    );
    // A --model other than full is refused by the comparison itself.
    request.settings = fit_settings(&args.run);
    request.seed = Some(args.seed);
    request.folds_by = Some(args.folds_by.clone());
    let comparison = with_steps("comparing models (folds)", |observer| {
        request.run(&LocalFiles, observer)
    });
    let comparison = comparison?;
    print_notes(&comparison.loaded.notes);
    if args.json {
        return super::output::print_json(&comparison.documents());
    }
    let scores = &comparison.scores;
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
    for (rank, (score, adds)) in scores.iter().zip(&comparison.adds).enumerate() {
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
        "Models of {} on {} ({} method), {}, best first:\n{rows}",
        comparison.loaded.robot.robot.name(),
        comparison.loaded.label,
        comparison.loaded.study.method_names(),
        folds_words(
            comparison.folds,
            scores.first().map_or(0, |s| s.validation.folds.len())
        ),
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
