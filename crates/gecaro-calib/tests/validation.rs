//! Held-out error as the judge: K-fold cross-validation and model choice,
//! against known simulated truth.
use crate::util::{simulated, stanford};
use gecaro_calib::{
    Quiet,
    identification::{IdentificationOptions, evaluate, identify},
    methods::{MethodOptions, method},
    simulation::{Sampler, perturbed_robot},
    study::Study,
    validation::{Folds, Model, compare_models, cross_validate},
};
use gecaro_core::Robot;

fn simulate(real: &Robot, name: &str, count: usize, noise: f64, seed: u64) -> Study {
    let chosen = method(name, &MethodOptions::default()).expect("method");
    let samples = simulated(real, chosen.as_ref(), count, noise, &mut Sampler::new(seed));
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
        Folds::Random { count: 4, seed: 1 },
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

/// Random folds test interpolation, region folds extrapolation: joint 1
/// measured over [0, 2.4] rad only, its transmission off by a smooth bump
/// a·sin(π q1/2.4) that a gain can only follow in the middle of the range
/// (the real robot's gains are exact). Random folds cannot tell the model
/// with gains from the one without (within 5 %); region folds, which hold
/// out the ends of each joint's range, rank the one without gains first by
/// 10 % or more, four seeds out of four.
#[test]
fn region_folds_rank_the_model_that_generalises() {
    use gecaro_calib::simulation::simulate_at;
    use gecaro_calib::study::{Sample, Samples};
    use gecaro_core::{ParameterId, ParameterKind};
    const NOISE: f64 = 2e-5;
    const AMPLITUDE: f64 = 2e-3;
    let nominal = gecaro_io::load_robot("industrial6").expect("ready").robot;
    let position = method("position", &MethodOptions::default()).expect("method");
    // The joint-1 angle the robot turns to for an encoder reading q1.
    let turned = |q1: f64| q1 + AMPLITUDE * (q1 * std::f64::consts::PI / 2.4).sin();
    for seed in 17..21 {
        let mut sampler = Sampler::new(seed);
        let mut real = perturbed_robot(&nominal, 1.0, &mut sampler).expect("real");
        for joint in 1..=6 {
            real.set_parameter(ParameterId::new(ParameterKind::Gain, joint), 1.0)
                .expect("gain");
        }
        let read: Vec<Vec<f64>> = (0..300)
            .map(|_| {
                let mut q = sampler.configuration(&nominal);
                q[0] = sampler.uniform(0.0, 2.4);
                q
            })
            .collect();
        let moved: Samples = read
            .iter()
            .map(|q| {
                let mut q = q.clone();
                q[0] = turned(q[0]);
                Sample::new(q)
            })
            .collect();
        let mut samples = simulate_at(
            &real,
            position.as_ref(),
            moved.as_slice(),
            NOISE,
            &mut sampler,
            &mut Quiet,
        )
        .expect("measured");
        for (sample, q) in samples.iter_mut().zip(&read) {
            sample.motor_positions = q.as_slice().into();
        }
        let mut study = Study::single(position.clone_method(), samples, "day1.csv");
        study.sets[0].sigma = Some(NOISE);
        let options = IdentificationOptions::default();
        let models = [Model::NoGains, Model::Full];
        let held_out = |folds: Folds| -> (f64, f64) {
            let scores = compare_models(&nominal, &study, &options, &models, folds, &mut Quiet)
                .expect("comparison");
            let rms = |name: &str| {
                scores
                    .iter()
                    .find(|score| score.model.name() == name)
                    .expect("scored")
                    .validation
                    .rms
            };
            (rms("no-gains"), rms("full"))
        };
        let (no_gains, full) = held_out(Folds::Random { count: 5, seed: 1 });
        assert!(
            (no_gains / full - 1.0).abs() < 0.05,
            "random: {no_gains} against {full}"
        );
        let (no_gains, full) = held_out(Folds::Regions { count: 5 });
        assert!(no_gains < 0.9 * full, "regions: {no_gains} against {full}");
    }
}

#[test]
fn region_folds_hold_out_the_ends_of_every_joint_that_moved() {
    use gecaro_calib::validation::cross_validate_by;
    let real = perturbed_robot(&stanford(), 0.5, &mut Sampler::new(3)).expect("real robot");
    let study = simulate(&real, "point-link", 120, 1e-4, 4);
    let options = IdentificationOptions::default();
    let validation = cross_validate_by(
        &stanford(),
        &study,
        &options,
        Folds::Regions { count: 4 },
        &mut Quiet,
    )
    .expect("cross-validation");
    // Two folds per joint, labelled with the bound, sets of 4 kept whole.
    assert_eq!(validation.folds.len(), 12);
    assert!(
        validation.folds[0].label.starts_with("q1 ≤ "),
        "{}",
        validation.folds[0].label
    );
    assert!(
        validation.folds[5].label.starts_with("q3 ≥ "),
        "{}",
        validation.folds[5].label
    );
    assert!(
        validation.folds[5].label.ends_with(" mm"),
        "{}",
        validation.folds[5].label
    );
    assert!(
        validation
            .folds
            .iter()
            .all(|f| f.held_out % 4 == 0 && f.held_out > 0)
    );
    assert_eq!(validation.folds_by, Folds::Regions { count: 4 });
    let again = cross_validate_by(
        &stanford(),
        &study,
        &options,
        Folds::Regions { count: 4 },
        &mut Quiet,
    )
    .expect("cross-validation");
    assert_eq!(validation, again);
}
