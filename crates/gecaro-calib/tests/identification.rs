//! Identification against known simulated truth (paper §3–§4): every method,
//! noise-free and noisy data, large errors, and the reported precision.

use crate::util::{simulated, stanford};
use gecaro_calib::identification::Warning;
use gecaro_calib::study::Samples;
use gecaro_calib::{
    Progress, Quiet,
    identifiability::ParameterStatus,
    identification::{IdentificationOptions, Prior, Route, StopReason, evaluate, identify},
    methods::{CalibrationMethod, MethodOptions, Plane, method},
    simulation::{Sampler, perturbed_robot},
    study::{MeasurementSet, Sample, Study},
    table2::{STANFORD_PLANE_POINT, TABLE2_PLANE_NORMAL},
};
use gecaro_core::Robot;
use nalgebra::Vector3;
use std::ops::ControlFlow;

fn options(plane_unknown: bool) -> MethodOptions {
    MethodOptions {
        plane: Some(
            Plane::new(
                Vector3::from(TABLE2_PLANE_NORMAL),
                Vector3::from(STANFORD_PLANE_POINT),
            )
            .expect("plane"),
        ),
        plane_unknown,
        ..MethodOptions::default()
    }
}

/// (method, plane unknown, configurations) for every column of Table 2.
const VARIANTS: [(&str, bool, usize); 9] = [
    ("position", false, 50),
    ("frame", false, 30),
    ("point-link", false, 80),
    ("frame-link", false, 60),
    ("plane1", false, 120),
    ("plane1", true, 120),
    ("plane2", false, 120),
    ("plane2", true, 120),
    ("distance", false, 200),
];

/// The real robot and its measurements by one method.
fn simulate(
    level: f64,
    noise: f64,
    seed: u64,
    name: &str,
    unknown: bool,
    count: usize,
) -> (Robot, Study) {
    let mut sampler = Sampler::new(seed);
    let real = perturbed_robot(&stanford(), level, &mut sampler).expect("real robot");
    let chosen = method(name, &options(unknown)).expect("method");
    let samples = simulated(&real, chosen.as_ref(), count, noise, &mut sampler);
    (real, Study::single(chosen, samples, name))
}

/// Fresh data of the same method on the same real robot (other configurations).
fn held_out(real: &Robot, name: &str, unknown: bool, count: usize, seed: u64) -> Study {
    let chosen = method(name, &options(unknown)).expect("method");
    let samples = simulated(real, chosen.as_ref(), count, 0.0, &mut Sampler::new(seed));
    Study::single(chosen, samples, "held out")
}

#[test]
fn noise_free_data_are_reproduced_to_rounding_by_every_method() {
    for (name, unknown, count) in VARIANTS {
        let (real, study) = simulate(1.0, 0.0, 21, name, unknown, count);
        let result = identify(
            &stanford(),
            &study,
            &IdentificationOptions::default(),
            &mut Quiet,
        )
        .expect("identification");
        assert_eq!(result.stop_reason, StopReason::Converged, "{name}");
        // The structural report (relations and conditioning computed on
        // first read): every regrouped parameter is absorbed by a relation
        // that holds, and the random W_b is well conditioned.
        let rank = &result.rank;
        for regrouped in rank
            .parameters
            .iter()
            .filter(|p| p.status == ParameterStatus::Regrouped)
        {
            assert!(
                rank.relations()
                    .iter()
                    .any(|relation| relation.absorbed.iter().any(|(n, _)| *n == regrouped.name)),
                "{name}: {} is in no relation",
                regrouped.name
            );
        }
        assert!(rank.relation_residual() < 1e-9, "{name}");
        let condition = rank.condition_number();
        assert!((1.0..1e4).contains(&condition), "{name}: {condition}");
        assert!(
            result.before.rms > 1e-3,
            "{name}: the errors are visible before ({})",
            result.before.rms
        );
        assert!(
            result.after.rms < 1e-10,
            "{name}: after {:e}",
            result.after.rms
        );
        // The calibrated robot also predicts the real robot on configurations it never saw.
        let fresh = held_out(&real, name, unknown, count, 99);
        let nominal_error = evaluate(&stanford(), &fresh).expect("nominal").rms;
        let calibrated_error = evaluate(&result.calibrated, &fresh)
            .expect("calibrated")
            .rms;
        assert!(nominal_error > 1e-3, "{name}");
        assert!(
            calibrated_error < 1e-9,
            "{name}: held-out {calibrated_error:e}"
        );
    }
}

#[test]
fn with_sensor_noise_the_residual_settles_at_the_noise_level() {
    let sigma = 1e-4;
    // Methods that measure a length observe the scale on their own; link and
    // plane methods are stacked with a distance set (weights 1/σ), as a real
    // setup would be: the weighted residual σ is then ≈ 1.
    for (name, unknown, count) in VARIANTS {
        let (real, mut study) = simulate(1.0, sigma, 22, name, unknown, count);
        let standalone = study.observes_scale();
        if !standalone {
            let distance = method("distance", &MethodOptions::default()).expect("method");
            let pairs = simulated(&real, distance.as_ref(), 120, sigma, &mut Sampler::new(5));
            study.sets.push(MeasurementSet {
                method: distance,
                samples: pairs.into(),
                sigma: Some(sigma),
                sigma_rotation: None,
                sigma_source: None,
                label: "pairs".into(),
                tool: None,
                station: None,
            });
            study.sets[0].sigma = Some(sigma);
        }
        let result = identify(
            &stanford(),
            &study,
            &IdentificationOptions::default(),
            &mut Quiet,
        )
        .expect("identification");
        assert_eq!(result.stop_reason, StopReason::Converged, "{name}");
        let ratio = if standalone {
            result.residual_sigma / sigma
        } else {
            result.residual_sigma
        };
        assert!(
            (0.75..1.3).contains(&ratio),
            "{name}: residual σ ratio {ratio}"
        );
        // The fit is at least as good as the truth's (least squares), and no better than noise allows.
        let truth = evaluate(&real, &study).expect("truth").rms;
        let fitted = result.after.rms;
        assert!(
            fitted <= truth * 1.02 && fitted > truth * 0.6,
            "{name}: {fitted:e} vs truth {truth:e}"
        );
    }
}

#[test]
fn link_and_plane_methods_alone_warn_that_they_cannot_see_the_scale() {
    let (_, study) = simulate(1.0, 1e-4, 22, "point-link", false, 80);
    let result = identify(
        &stanford(),
        &study,
        &IdentificationOptions::default(),
        &mut Quiet,
    )
    .expect("identification");
    assert!(
        result
            .warnings
            .iter()
            .any(|w| matches!(w, Warning::ScaleNotMeasured { .. })),
        "{:?}",
        result.warnings
    );
    let (_, study) = simulate(1.0, 1e-4, 22, "position", false, 50);
    let result = identify(
        &stanford(),
        &study,
        &IdentificationOptions::default(),
        &mut Quiet,
    )
    .expect("identification");
    // Position data observe the scale: no such warning (r0–r1 and θ0–θ1
    // are named as correlated, z0 and z1 being 0.1 rad apart).
    assert!(
        !result
            .warnings
            .iter()
            .any(|w| matches!(w, Warning::ScaleNotMeasured { .. })),
        "{:?}",
        result.warnings
    );
}

#[test]
fn position_and_frame_converge_from_half_metre_errors_in_at_most_six_plain_iterations() {
    for seed in 1..=6 {
        for (name, count) in [("position", 60), ("frame", 40)] {
            let (_, study) = simulate(10.0, 0.0, seed, name, false, count);
            let result = identify(
                &stanford(),
                &study,
                &IdentificationOptions::default(),
                &mut Quiet,
            )
            .expect("identification");
            assert!(
                result.before.max > 0.3,
                "level 10 moves the terminal point by 0.3–0.8 m: {}",
                result.before.max
            );
            assert_eq!(result.stop_reason, StopReason::Converged);
            assert_eq!(
                result.route,
                Route::GaussNewton,
                "{name}, seed {seed}: the paper's plain scheme"
            );
            assert!(
                result.iterations() <= 6,
                "{name}, seed {seed}: {} iterations",
                result.iterations()
            );
            assert!(result.after.rms < 1e-10);
        }
    }
}

#[test]
fn link_and_plane_methods_converge_from_level_three() {
    for seed in 1..=5 {
        for (name, unknown, count) in [
            ("point-link", false, 80),
            ("frame-link", false, 60),
            ("plane1", false, 120),
            ("plane1", true, 120),
            ("plane2", false, 120),
            ("plane2", true, 120),
        ] {
            let (real, study) = simulate(3.0, 0.0, seed, name, unknown, count);
            let result = identify(
                &stanford(),
                &study,
                &IdentificationOptions::default(),
                &mut Quiet,
            )
            .expect("identification");
            assert_eq!(
                result.stop_reason,
                StopReason::Converged,
                "{name}, seed {seed}"
            );
            assert!(
                result.after.rms < 1e-10,
                "{name}, seed {seed}: {:e}",
                result.after.rms
            );
            let fresh = held_out(&real, name, unknown, count, 7);
            assert!(
                evaluate(&result.calibrated, &fresh).expect("held out").rms < 1e-9,
                "{name}, seed {seed}"
            );
        }
    }
}

/// Per parameter, the spread of the identified values over 80 runs with
/// fresh noise (σ 0.2 mm, one real robot drawn at `level`, 40
/// configurations) over the mean reported σ and over the mean reported noise
/// σ, identified with `prior`.
fn spread_over_reported(level: f64, prior: Option<Prior>) -> Vec<(String, f64, f64)> {
    let sigma = 2e-4;
    let (_, exact) = simulate(level, 0.0, 5, "position", false, 40);
    let samples = exact.sets[0].samples.clone();
    let runs = 80;
    let mut values: Vec<Vec<f64>> = Vec::new();
    // The reported σ of each run scatters too (σ̂ from 89 degrees of freedom): average them.
    let mut reported: Vec<(f64, f64)> = Vec::new();
    let mut names = Vec::new();
    let mut noise = Sampler::new(1234);
    for _ in 0..runs {
        let noisy: Vec<Sample> = samples
            .iter()
            .map(|sample| Sample {
                position: sample.position().map(|p| p + noise.gaussian_vector(sigma)),
                ..sample.to_sample()
            })
            .collect();
        let study = Study::single(
            method("position", &MethodOptions::default()).expect("method"),
            noisy,
            "run",
        );
        let options = IdentificationOptions {
            prior: prior.clone(),
            ..IdentificationOptions::default()
        };
        let result = identify(&stanford(), &study, &options, &mut Quiet).expect("identification");
        if reported.is_empty() {
            reported = vec![(0.0, 0.0); result.parameters.len()];
            values = vec![Vec::new(); reported.len()];
            names = result.parameters.iter().map(|p| p.name.clone()).collect();
        }
        for (column, parameter) in result.parameters.iter().enumerate() {
            values[column].push(parameter.identified);
            reported[column].0 += parameter.std / runs as f64;
            reported[column].1 += parameter.noise_std / runs as f64;
        }
    }
    values
        .iter()
        .zip(&reported)
        .zip(names)
        .map(|((spread, (std, noise_std)), name)| {
            let mean = spread.iter().sum::<f64>() / runs as f64;
            let sample_std =
                (spread.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (runs - 1) as f64).sqrt();
            (name, sample_std / std, sample_std / noise_std)
        })
        .collect()
}

/// Whether `ratios` are those of an honest σ: with 80 runs a sample standard
/// deviation is within ±16 % (2σ) of the truth.
fn honest(ratios: &[f64]) -> bool {
    let within = ratios.iter().filter(|r| (0.75..1.3).contains(*r)).count();
    let mut sorted = ratios.to_vec();
    sorted.sort_by(f64::total_cmp);
    let median = sorted[sorted.len() / 2];
    within as f64 >= 0.9 * ratios.len() as f64 && (0.9..1.1).contains(&median)
}

#[test]
fn reported_standard_deviations_match_a_monte_carlo_spread() {
    let plain = spread_over_reported(1.0, None);
    // Without a prior the noise makes all of σ.
    for (name, std, noise) in &plain {
        assert!((std / noise - 1.0).abs() < 1e-9, "{name}");
    }
    let ratios: Vec<f64> = plain.iter().map(|r| r.1).collect();
    assert!(honest(&ratios), "{plain:?}");
}

#[test]
fn a_prior_adds_its_uncertainty_to_sigma_and_the_noise_sigma_is_the_spread() {
    // A real robot within ±0.1 mm, ±0.01°, ±0.01 % of the nominal one, and a
    // prior that says so, as tight as the data: the estimate moves less
    // with the noise than σ, which also says how far the prior may be from
    // the true robot; the noise σ is the spread.
    let prior = Prior::new(1e-4, 0.01_f64.to_radians(), 1e-4).expect("prior");
    let held = spread_over_reported(0.01, Some(prior));
    let noise: Vec<f64> = held.iter().map(|r| r.2).collect();
    assert!(honest(&noise), "{held:?}");
    let whole: Vec<f64> = held.iter().map(|r| r.1).collect();
    assert!(!honest(&whole), "σ alone would have matched: {held:?}");
}

/// A ready robot, the `name` method, and `count` exact measurements of a
/// real robot drawn from it at `level` with `seed` (the measurements drawn
/// next from the same sampler).
fn exact_measurements(
    robot: &str,
    name: &str,
    (level, seed): (f64, u64),
    count: usize,
) -> (Robot, Box<dyn CalibrationMethod>, Vec<Sample>) {
    let nominal = gecaro_io::load_robot(robot).expect("ready robot").robot;
    let measure = method(name, &MethodOptions::default()).expect("method");
    let mut sampler = Sampler::new(seed);
    let real = perturbed_robot(&nominal, level, &mut sampler).expect("real robot");
    let exact = simulated(&real, measure.as_ref(), count, 0.0, &mut sampler);
    (nominal, measure, exact)
}

/// Per parameter of a ready robot's identification from `name` data (one
/// real robot at level 1, `count` configurations measured 40 times with
/// fresh noise, σ 0.01 mm and 0.01 mrad stated): the spread of what its σ
/// is about (the value, or its combination `Δη_b + Σ β_j Δη_j` with what it
/// still absorbs) over its mean noise σ; and the parameters joined.
fn spread_over_noise_sigma(
    robot: &str,
    name: &str,
    count: usize,
) -> (Vec<(String, f64)>, Vec<String>) {
    let sigma = 1e-5;
    let (nominal, measure, exact) = exact_measurements(robot, name, (1.0, 7), count);
    let mut noise = Sampler::new(1007);
    let runs = 40;
    let mut values: Vec<Vec<f64>> = Vec::new();
    let mut reported: Vec<f64> = Vec::new();
    let mut names: Vec<String> = Vec::new();
    let mut joined = Vec::new();
    for _ in 0..runs {
        let noisy: Vec<Sample> = exact
            .iter()
            .map(|sample| Sample {
                position: sample.position.map(|p| p + noise.gaussian_vector(sigma)),
                orientation: sample.orientation.map(|q| {
                    q * nalgebra::UnitQuaternion::from_rotation_matrix(
                        &noise.gaussian_rotation(sigma),
                    )
                }),
                ..sample.clone()
            })
            .collect();
        let mut study = Study::single(measure.clone_method(), noisy, "run");
        study.sets[0].sigma = Some(sigma);
        let result = identify(
            &nominal,
            &study,
            &IdentificationOptions::default(),
            &mut Quiet,
        )
        .expect("identification");
        assert_eq!(result.stop_reason, StopReason::Converged);
        let current: Vec<String> = result.parameters.iter().map(|p| p.name.clone()).collect();
        if names.is_empty() {
            names = current.clone();
            reported = vec![0.0; names.len()];
            values = vec![Vec::new(); names.len()];
            joined = result.joined.clone();
        }
        assert_eq!(current, names, "the same parameters in every run");
        // Nothing a base parameter absorbs is left moved by the route.
        for parameter in &result.parameters {
            for (absorbed, _) in &parameter.absorbs {
                assert!(
                    result.moved.iter().all(|m| &m.name != absorbed),
                    "{} absorbs {absorbed}, moved",
                    parameter.name
                );
            }
        }
        let deviation = |name: &str| {
            nominal
                .parameters()
                .ids()
                .iter()
                .find(|id| id.to_string() == name)
                .map_or(0.0, |id| {
                    result.calibrated.parameter(*id) - nominal.parameter(*id)
                })
        };
        for (column, parameter) in result.parameters.iter().enumerate() {
            let absorbed: f64 = parameter
                .absorbs
                .iter()
                .map(|(name, beta)| beta * deviation(name))
                .sum();
            values[column].push(parameter.identified + absorbed);
            reported[column] += parameter.noise_std / runs as f64;
        }
    }
    let ratios = values
        .iter()
        .zip(&reported)
        .zip(names)
        .map(|((spread, noise_std), name)| {
            let mean = spread.iter().sum::<f64>() / runs as f64;
            let sample_std =
                (spread.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (runs - 1) as f64).sqrt();
            (name, sample_std / noise_std)
        })
        .collect();
    (ratios, joined)
}

/// The median and the range of `ratios`.
fn median_and_range(ratios: &[(String, f64)]) -> (f64, f64, f64) {
    let mut sorted: Vec<f64> = ratios.iter().map(|r| r.1).collect();
    sorted.sort_by(f64::total_cmp);
    (
        sorted[sorted.len() / 2],
        sorted[0],
        sorted[sorted.len() - 1],
    )
}

#[test]
fn parameters_the_data_set_outside_the_base_set_are_joined_and_every_sigma_is_the_spread() {
    // PUMA 560 frame data: the closed-form start fits the tool frame, β7 of a
    // flange parallel to axis 6 with it, and θ6, r6, r7, α7, d7, θ7 absorb β7
    // with coefficients of hundreds. Held where the start put it, their σ
    // was from 0.01 to 82 times the spread; joined, every parameter's noise σ
    // is its spread.
    let (ratios, joined) = spread_over_noise_sigma("puma560", "frame", 40);
    assert!(joined.contains(&"beta7".to_owned()), "{joined:?}");
    let (median, low, high) = median_and_range(&ratios);
    assert!((0.8..1.25).contains(&median), "{ratios:?}");
    assert!(low > 0.5 && high < 2.0, "{ratios:?}");
    // Position data: α7 and d7 of the tool point, absorbed with coefficients
    // of thousands. r7, which only the real robot's deviations let the data
    // see (the second pass adds it, held by its prior), spread 1.8 times the
    // noise σ of Gauss–Newton's G; with the residuals' curvature (the
    // Newton Hessian, `identification::curvature`) its noise σ is its spread.
    let (ratios, joined) = spread_over_noise_sigma("puma560", "position", 60);
    assert!(!joined.is_empty(), "{joined:?}");
    let (median, low, high) = median_and_range(&ratios);
    assert!((0.8..1.25).contains(&median), "{ratios:?}");
    assert!(low > 0.5 && high < 1.5, "{ratios:?}");
    // industrial6 (issue 33's other robot): its r7 too spread up to 2.1 times
    // Gauss–Newton's noise σ.
    for name in ["position", "frame"] {
        let (ratios, _) = spread_over_noise_sigma("industrial6", name, 60);
        let (median, low, high) = median_and_range(&ratios);
        assert!((0.8..1.25).contains(&median), "{name}: {ratios:?}");
        assert!(low > 0.5 && high < 1.5, "{name}: {ratios:?}");
    }
}

/// The noise σ against an independent route: the identification's own
/// sensitivity to its data, by finite differences (each of the 180
/// measured coordinates moved by 1e-7 m and the whole identification run
/// again), `σ √Σₖ (∂θ̂/∂yₖ)²`. Linear in the noise, so it is what the noise σ
/// claims to be, draw for draw, without Monte Carlo's ±11 %. PUMA 560
/// position data at error levels 1 and 2: r7, held by the second pass's
/// prior and seen only through the real robot's deviations, moves twice as
/// much as Gauss–Newton's `G⁻¹DᵀDG⁻¹` says; the Newton Hessian's sandwich
/// is right for every parameter to 3 % (measured: 1 %).
#[test]
fn the_noise_sigma_is_the_identifications_sensitivity_to_its_data() {
    // Level 2, seed 8: the near-null direction's own curvature is 4e-8 of
    // G's diagonal; differences of the gradients `Wᵀr` did not resolve it
    // (r7 at 2×), the moved rows against the residuals do.
    for (level, seed) in [(1.0, 7), (2.0, 8)] {
        noise_sigma_against_sensitivity(level, seed);
    }
}

/// [`the_noise_sigma_is_the_identifications_sensitivity_to_its_data`] for
/// one real robot (PUMA 560 at `level`, drawn with `seed`).
fn noise_sigma_against_sensitivity(level: f64, seed: u64) {
    let sigma = 1e-5;
    let (nominal, measure, exact) = exact_measurements("puma560", "position", (level, seed), 60);
    let mut noise = Sampler::new(seed + 1000);
    let noisy: Vec<Sample> = exact
        .iter()
        .map(|sample| Sample {
            position: sample.position.map(|p| p + noise.gaussian_vector(sigma)),
            ..sample.clone()
        })
        .collect();
    let run = |samples: &[Sample]| {
        let mut study = Study::single(measure.clone_method(), samples.to_vec(), "run");
        study.sets[0].sigma = Some(sigma);
        identify(
            &nominal,
            &study,
            &IdentificationOptions::default(),
            &mut Quiet,
        )
        .expect("identification")
    };
    let base = run(&noisy);
    assert!(!base.second_pass.is_empty() && !base.joined.is_empty());
    let delta = 1e-7;
    let mut squares = vec![0.0; base.parameters.len()];
    for k in 0..noisy.len() {
        for axis in 0..3 {
            let mut moved = noisy.clone();
            if let Some(position) = moved[k].position.as_mut() {
                position[axis] += delta;
            }
            let result = run(&moved);
            for ((square, after), before) in squares
                .iter_mut()
                .zip(&result.parameters)
                .zip(&base.parameters)
            {
                assert_eq!(after.name, before.name, "the same route");
                *square += ((after.identified - before.identified) / delta).powi(2);
            }
        }
    }
    // The noise σ is scaled by σ̂/σ: every ratio is σ/σ̂ alike.
    let ratios: Vec<(String, f64)> = base
        .parameters
        .iter()
        .zip(&squares)
        .map(|(parameter, square)| {
            (
                parameter.name.clone(),
                sigma * square.sqrt() / parameter.noise_std,
            )
        })
        .collect();
    let (median, low, high) = median_and_range(&ratios);
    assert!(
        low > 0.97 * median && high < 1.03 * median,
        "level {level}, seed {seed}: {median} {ratios:?}"
    );
    let r7 = ratios
        .iter()
        .find(|(name, _)| name == "r7")
        .expect("r7 added");
    assert!((r7.1 / median - 1.0).abs() < 0.03, "{r7:?}");
}

#[test]
fn failures_are_reported_not_hidden() {
    // An iteration limit is a stop reason with the best iterate, not silence.
    let (_, study) = simulate(10.0, 0.0, 3, "position", false, 60);
    let options = IdentificationOptions {
        max_iterations: 2,
        ..IdentificationOptions::default()
    };
    let result = identify(&stanford(), &study, &options, &mut Quiet).expect("identification");
    assert_ne!(result.stop_reason, StopReason::Converged);
    assert!(result.rms_after() < result.rms_before());
    // Fewer equations than unknowns is an error.
    let (_, mut study) = simulate(1.0, 0.0, 3, "position", false, 60);
    study.sets[0].samples = study.sets[0].samples.slice(0..8).to_samples();
    let error = identify(
        &stanford(),
        &study,
        &IdentificationOptions::default(),
        &mut Quiet,
    )
    .expect_err("too few");
    assert!(error.to_string().contains("too few equations"), "{error}");
}

#[test]
fn a_progress_hook_can_stop_an_identification() {
    // Level 10 takes several iterations: stop after the second record.
    let (_, study) = simulate(10.0, 0.0, 3, "position", false, 60);
    let mut records = 0;
    let error = identify(
        &stanford(),
        &study,
        &IdentificationOptions::default(),
        &mut |_: Progress<'_>| {
            records += 1;
            if records == 2 {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        },
    )
    .expect_err("interrupted");
    assert_eq!(error, gecaro_calib::Error::Interrupted);
    assert_eq!(records, 2, "no record after the stop");
}

/// Points generation and measurements at planned configurations report their
/// progress for every method, up to the count asked for, and stop when the
/// observer says so (a closed page, Ctrl-C) with nothing returned.
#[test]
fn every_sensor_reports_its_progress_and_can_be_stopped() {
    let robot = stanford();
    for info in gecaro_calib::methods::METHODS {
        let chosen = method(info.name, &options(false)).expect("method");
        let sensor = chosen.sensor();
        let mut seen = Vec::new();
        let samples = sensor
            .generate(
                &robot,
                12,
                0.0,
                &mut Sampler::new(3),
                &mut |progress: Progress<'_>| {
                    if let Progress::Step { done, total } = progress {
                        seen.push((done, total));
                    }
                    ControlFlow::Continue(())
                },
            )
            .expect("generated");
        assert_eq!(samples.len(), 12, "{}", info.name);
        assert!(
            seen.len() >= 2
                && seen.windows(2).all(|pair| pair[0].0 < pair[1].0)
                && seen.iter().all(|&(done, total)| total == 12 && done < 12),
            "{}: {seen:?}",
            info.name
        );
        let samples = Samples::from(samples);
        for planned in [None, Some(samples.as_slice())] {
            let mut calls = 0;
            let mut stop_at_second = |_: Progress<'_>| {
                calls += 1;
                if calls == 2 {
                    ControlFlow::Break(())
                } else {
                    ControlFlow::Continue(())
                }
            };
            let stopped = match planned {
                None => sensor.generate(&robot, 12, 0.0, &mut Sampler::new(3), &mut stop_at_second),
                Some(planned) => sensor.measure_at(
                    &robot,
                    planned,
                    0.0,
                    &mut Sampler::new(3),
                    &mut stop_at_second,
                ),
            };
            assert_eq!(
                stopped.expect_err("stopped"),
                gecaro_calib::Error::Interrupted,
                "{}",
                info.name
            );
            assert_eq!(calls, 2, "{}: no step after the stop", info.name);
        }
    }
}

/// Held-out RMS of the identified robot over that of the real robot itself
/// (the noise floor), for position data of a ready robot with errors at
/// `level` (200 configurations to identify from, 200 to check on, σ 0.01 mm),
/// and the parameters the second pass added.
fn held_out_over_floor(robot: &str, level: f64, seed: u64) -> (f64, Vec<String>) {
    held_out_over_floor_of(robot, "position", level, seed)
}

/// [`held_out_over_floor`] for the measure method `name`.
fn held_out_over_floor_of(robot: &str, name: &str, level: f64, seed: u64) -> (f64, Vec<String>) {
    let nominal = gecaro_io::load_robot(robot).expect("ready robot").robot;
    let measure = method(name, &MethodOptions::default()).expect("method");
    let mut sampler = Sampler::new(seed);
    let real = perturbed_robot(&nominal, level, &mut sampler).expect("real robot");
    let mut measure = || {
        let samples = simulated(&real, measure.as_ref(), 200, 1e-5, &mut sampler);
        Study::single(measure.clone_method(), samples, "simulated")
    };
    let (train, check) = (measure(), measure());
    let result = identify(
        &nominal,
        &train,
        &IdentificationOptions::default(),
        &mut Quiet,
    )
    .expect("fit");
    assert_eq!(result.stop_reason, StopReason::Converged);
    let floor = evaluate(&real, &check).expect("floor").rms;
    let held_out = evaluate(&result.calibrated, &check).expect("held out").rms;
    (held_out / floor, result.second_pass)
}

#[test]
fn errors_of_a_centimetre_are_identified_to_the_noise_floor() {
    // Parallel axes (PUMA 2–3, industrial6 2–3) and a tool point on the last
    // axis (Panda): the nominal structure's base set holds only to first
    // order, and the paper's pass alone stops at 2.5× (Panda), 18× (PUMA)
    // and 15× (industrial6) the floor at level 1, 10–67× at level 2. The
    // second pass identifies what the structure at the calibrated robot
    // adds; the damped descent over every parameter what is left (PUMA at
    // level 2 stopped at 3.0× without it, industrial6 at 1.6×).
    for robot in ["panda", "puma560", "industrial6"] {
        for level in [1.0, 2.0] {
            let (ratio, added) = held_out_over_floor(robot, level, 7);
            assert!(!added.is_empty(), "{robot} at {level}: no second pass");
            assert!(
                ratio < 1.2,
                "{robot} at {level}: held-out RMS {ratio:.2}× the floor"
            );
        }
    }
    // Errors of 3 cm and 3°: the first pass's misfit makes 11 of the 200
    // frames "outliers" (beyond 3 σ̂); the tests behind the passes read the
    // inliers, which still show the structure (18× the floor when outliers
    // stopped the passes).
    let (ratio, added) = held_out_over_floor_of("industrial6", "frame", 3.0, 7);
    assert!(
        !added.is_empty() && ratio < 1.2,
        "level 3: {ratio:.2}× the floor"
    );
    // Small errors: the floor either way (at 0.1 the F test may still find
    // the second-order terms, ~2e-6 m, among 600 equations); at 0.01 they
    // are far below the noise and the paper's pass stays alone.
    let (ratio, _) = held_out_over_floor("puma560", 0.1, 7);
    assert!(ratio < 1.1, "level 0.1: {ratio:.2}× the floor");
    for seed in 1..4 {
        let (ratio, added) = held_out_over_floor("puma560", 0.01, seed);
        assert!(ratio < 1.1, "level 0.01: {ratio:.2}× the floor");
        assert!(
            added.is_empty(),
            "level 0.01: a second pass added {added:?}"
        );
    }
}

#[test]
fn a_repeatability_study_of_many_cycles_converges() {
    // 500 repeats of the same 50 poses (a drift or repeatability study):
    // the start, the score tests and the scale read a bounded subsample, and
    // an evenly spaced one read a single pose 500 times. Before: "not
    // converged", 32 → 460 mm (the command line, 0.01 mm noise).
    let (_, exact) = simulate(1.0, 0.0, 4, "position", false, 50);
    let mut noise = Sampler::new(77);
    let samples: Vec<Sample> = (0..500)
        .flat_map(|_| {
            exact.sets[0]
                .samples
                .iter()
                .map(|sample| sample.to_sample())
        })
        .map(|sample| Sample {
            position: sample.position.map(|p| p + noise.gaussian_vector(1e-5)),
            ..sample
        })
        .collect();
    let mut study = Study::single(
        method("position", &MethodOptions::default()).expect("method"),
        samples,
        "cycles",
    );
    study.sets[0].sigma = Some(1e-5);
    let result = identify(
        &stanford(),
        &study,
        &IdentificationOptions::default(),
        &mut Quiet,
    )
    .expect("identification");
    assert_eq!(result.stop_reason, StopReason::Converged);
    // From the closed-form start, as with 50 distinct configurations: three
    // iterations (eleven from the start an evenly spaced subsample gave
    // here; from the command line's data it never converged).
    assert!(
        result.history.len() <= 5,
        "{} iterates",
        result.history.len()
    );
    assert!(
        result.verdict.outcome.trusted(),
        "{}",
        result.verdict.summary
    );
    assert!(result.after.rms < 2e-5, "{}", result.after.rms);
}

/// Where the descent's steps contract by orders of magnitude, its last step
/// is applied without W evaluated at its end (the linear model's residuals;
/// a folded system's measured residuals evaluated at the new parameters):
/// the result is that of a descent made to evaluate W until its step is
/// negligible, with W held and folded alike.
#[test]
fn a_last_step_left_unevaluated_gives_the_evaluated_descents_result() {
    let (_, mut study) = simulate(1.0, 1e-5, 31, "position", false, 2000);
    study.sets[0].sigma = Some(1e-5);
    for streamed_rows in [usize::MAX, 0] {
        let run = |step_tolerance| {
            identify(
                &stanford(),
                &study,
                &IdentificationOptions {
                    streamed_rows,
                    step_tolerance,
                    ..IdentificationOptions::default()
                },
                &mut Quiet,
            )
            .expect("identification")
        };
        // At 1e-15 what the contraction leaves is not negligible: W is
        // evaluated at the end of the last step.
        let (last, evaluated) = (run(1e-8), run(1e-15));
        assert_eq!(last.stop_reason, StopReason::Converged);
        assert_eq!(evaluated.stop_reason, StopReason::Converged);
        let steps: Vec<f64> = last.history.iter().map(|record| record.step).collect();
        let n = steps.len();
        assert!(
            n >= 3 && steps[n - 1] < 0.1 * steps[n - 2] && steps[n - 1] > 1e-9,
            "{streamed_rows}: steps {steps:?}"
        );
        // The same steps; the last one's end evaluated in one run only,
        // where the precision reads W there (a relative 1e-6 or so apart).
        let evaluated_steps: Vec<f64> = evaluated.history.iter().map(|r| r.step).collect();
        assert_eq!(steps, evaluated_steps, "{streamed_rows}");
        assert!(
            last.parameters
                .iter()
                .zip(&evaluated.parameters)
                .any(|(a, b)| a.std != b.std),
            "{streamed_rows}: W read at the same point"
        );
        for (a, b) in last.parameters.iter().zip(&evaluated.parameters) {
            assert_eq!(a.name, b.name);
            assert!(
                (a.identified - b.identified).abs() <= 1e-3 * b.std,
                "{streamed_rows}: {} {} against {} (σ {})",
                a.name,
                a.identified,
                b.identified,
                b.std
            );
            assert!(
                (a.std - b.std).abs() <= 1e-4 * b.std,
                "{streamed_rows}: σ of {} {} against {}",
                a.name,
                a.std,
                b.std
            );
        }
        let worst = last
            .errors_after
            .lengths
            .iter()
            .zip(&evaluated.errors_after.lengths)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-10, "{streamed_rows}: errors {worst:e} m apart");
        assert!(
            (last.residual_sigma - evaluated.residual_sigma).abs()
                < 1e-9 * evaluated.residual_sigma
        );
    }
}
