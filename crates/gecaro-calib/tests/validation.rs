//! Held-out error as the judge: K-fold cross-validation and model choice,
//! against known simulated truth.
use gecaro_calib::{
    Quiet,
    identification::{IdentificationOptions, evaluate, identify},
    methods::{MethodOptions, method},
    simulation::{Sampler, perturbed_robot, simulate_measurements},
    study::Study,
    validation::{Model, compare_models, cross_validate},
};
use gecaro_core::Robot;

fn stanford() -> Robot {
    gecaro_io::load_robot("stanford")
        .expect("ready robot")
        .robot
}

fn simulate(real: &Robot, name: &str, count: usize, noise: f64, seed: u64) -> Study {
    let chosen = method(name, &MethodOptions::default()).expect("method");
    let samples = simulate_measurements(
        real,
        chosen.as_ref(),
        count,
        noise,
        &mut Sampler::new(seed),
        &mut Quiet,
    )
    .expect("data");
    Study::single(chosen, samples, format!("{name}.csv"))
}

#[test]
fn folds_keep_sets_whole_cover_every_observation_and_are_seeded() {
    let real = perturbed_robot(&stanford(), 0.5, &mut Sampler::new(3)).expect("real robot");
    let study = simulate(&real, "point-link", 120, 1e-4, 4);
    let options = IdentificationOptions::default();
    let first =
        cross_validate(&stanford(), &study, &options, 5, 9, &mut Quiet).expect("cross-validation");
    assert_eq!(first.folds.len(), 5);
    // Every configuration is held out once; sets of 4 are never split, so
    // each fold holds whole sets.
    assert_eq!(first.folds.iter().map(|f| f.held_out).sum::<usize>(), 120);
    assert!(
        first.folds.iter().all(|f| f.held_out % 4 == 0),
        "{:?}",
        first.folds
    );
    let again =
        cross_validate(&stanford(), &study, &options, 5, 9, &mut Quiet).expect("cross-validation");
    assert_eq!(first, again);
    let other =
        cross_validate(&stanford(), &study, &options, 5, 10, &mut Quiet).expect("cross-validation");
    assert_ne!(first.folds, other.folds);
    // Too many or too few folds.
    for folds in [1, 31] {
        let error =
            cross_validate(&stanford(), &study, &options, folds, 9, &mut Quiet).expect_err("folds");
        assert!(error.to_string().starts_with("folds:"), "{error}");
    }
}

#[test]
fn the_cross_validated_error_predicts_the_error_on_new_data() {
    let real = perturbed_robot(&stanford(), 1.0, &mut Sampler::new(5)).expect("real robot");
    let noise = 2e-4;
    let study = simulate(&real, "position", 40, noise, 6);
    let options = IdentificationOptions::default();
    let validation =
        cross_validate(&stanford(), &study, &options, 5, 1, &mut Quiet).expect("cross-validation");
    // The error of the calibrated robot on fresh measurements of the real one.
    let fitted = identify(&stanford(), &study, &options, &mut Quiet).expect("identification");
    let fresh = simulate(&real, "position", 400, noise, 7);
    let new_data = evaluate(&fitted.calibrated, &fresh)
        .expect("evaluation")
        .rms;
    let ratio = validation.rms / new_data;
    // Trained on 4/5 of the data, the folds' robots are a little worse.
    assert!(
        (0.9..1.6).contains(&ratio),
        "cross-validated {} vs new data {new_data}",
        validation.rms
    );
    // Above the training residual, which flatters the fit.
    assert!(validation.rms > fitted.after.rms);
}

#[test]
fn models_are_ranked_by_held_out_error() {
    // The real robot's gains are off by up to 1 %: a model without them
    // cannot describe it, and the offsets alone even less.
    let real = perturbed_robot(&stanford(), 1.0, &mut Sampler::new(8)).expect("real robot");
    let study = simulate(&real, "position", 60, 1e-4, 9);
    let models = [Model::Offsets, Model::Kinematic, Model::Full];
    let scores = compare_models(
        &stanford(),
        &study,
        &IdentificationOptions::default(),
        &models,
        4,
        1,
        &mut Quiet,
    )
    .expect("comparison");
    let order: Vec<&str> = scores.iter().map(|s| s.model.name()).collect();
    assert_eq!(order, ["full", "kinematic", "offsets"]);
    assert!(
        scores[0].validation.rms < 0.2 * scores[1].validation.rms,
        "{:?}",
        scores.iter().map(|s| s.validation.rms).collect::<Vec<_>>()
    );
    // The kinematic model identifies no gain.
    assert!(
        scores[1]
            .validation
            .parameters
            .iter()
            .all(|name| !name.starts_with('K'))
    );
    assert!(
        scores[0]
            .validation
            .parameters
            .iter()
            .any(|name| name.starts_with('K'))
    );
}
