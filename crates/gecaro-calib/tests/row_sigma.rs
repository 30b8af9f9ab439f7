//! Rows weighted by the σ their instrument states for each (issue 74): a
//! tracker's points measured far away or through a poor line of sight
//! count less, the verdict tests each row against its own σ, and the
//! calibration is judged on the real robot at held-out configurations.

use crate::util::{simulated, stanford};
use gecaro_calib::identification::{IdentificationOptions, Outcome, evaluate, identify};
use gecaro_calib::methods::{MethodOptions, method};
use gecaro_calib::simulation::{Sampler, perturbed_robot};
use gecaro_calib::study::{MeasurementSet, RowSigma, Sample, Samples, Study};
use gecaro_calib::{Error, Quiet};
use gecaro_core::Robot;

/// The real robot, its exact positions at 120 configurations and the same
/// measured with a σ of each row's own, drawn log-uniformly between 5 µm
/// and 0.5 mm (a tracker near and far, clear and grazing), each row
/// stating its σ; and 200 held-out configurations of the real robot.
fn measured() -> (Robot, Vec<Sample>, Study) {
    let mut sampler = Sampler::new(74);
    let real = perturbed_robot(&stanford(), 1.0, &mut sampler).expect("real robot");
    let position = method("position", &MethodOptions::default()).expect("method");
    let exact = simulated(&real, position.as_ref(), 120, 0.0, &mut sampler);
    let rows: Vec<Sample> = exact
        .iter()
        .map(|sample| {
            let sigma = 5e-6 * 100f64.powf(sampler.uniform(0.0, 1.0));
            let mut row = sample.clone();
            row.position = row.position.map(|p| p + sampler.gaussian_vector(sigma));
            row.sigma = Some(Box::new(RowSigma {
                length: Some(sigma),
                angle: None,
            }));
            row
        })
        .collect();
    let held_out = simulated(&real, position.as_ref(), 200, 0.0, &mut Sampler::new(740));
    (real, rows, Study::single(position, held_out, "held out"))
}

/// The study of `rows` by the position method, with the set's σ `sigma`.
fn study(rows: Vec<Sample>, sigma: Option<f64>) -> Study {
    let mut study = Study::single(
        method("position", &MethodOptions::default()).expect("method"),
        rows,
        "tracker.csv",
    );
    study.sets[0].sigma = sigma;
    study
}

/// Weighted by each row's σ, the calibration is several times closer to
/// the real robot than with one σ for all (the RMS of the rows' σ, which
/// the same residuals fit as well), and its verdict tests each row against
/// its own σ: the noise fits, σ̂/σ near 1. Without any σ stated, the rows'
/// own make the verdict tested.
#[test]
fn rows_count_by_their_own_sigma_and_the_verdict_tests_them_so() {
    let (_, rows, held_out) = measured();
    let sigmas: Vec<f64> = rows
        .iter()
        .map(|row| row.sigma.as_ref().and_then(|s| s.length).expect("σ"))
        .collect();
    let rms_sigma = (sigmas.iter().map(|s| s * s).sum::<f64>() / sigmas.len() as f64).sqrt();
    let options = IdentificationOptions::default();

    let weighted = identify(
        &stanford(),
        &study(rows.clone(), None),
        &options,
        &mut Quiet,
    )
    .expect("weighted by rows");
    assert_eq!(
        weighted.verdict.outcome,
        Outcome::FitsNoise,
        "{:?}",
        weighted.verdict
    );
    let test = weighted
        .verdict
        .noise_test
        .expect("tested against the rows' σ");
    assert!(
        (0.8..1.2).contains(&test.sigma_ratio),
        "σ̂/σ {}",
        test.sigma_ratio
    );

    let plain: Vec<Sample> = rows
        .iter()
        .map(|row| Sample {
            sigma: None,
            ..row.clone()
        })
        .collect();
    let single = identify(
        &stanford(),
        &study(plain, Some(rms_sigma)),
        &options,
        &mut Quiet,
    )
    .expect("one σ");
    let weighted_error = evaluate(&weighted.calibrated, &held_out)
        .expect("held out")
        .rms;
    let single_error = evaluate(&single.calibrated, &held_out)
        .expect("held out")
        .rms;
    println!(
        "held out: {:.1} µm by the rows' σ, {:.1} µm by one σ of {:.1} µm",
        weighted_error * 1e6,
        single_error * 1e6,
        rms_sigma * 1e6
    );
    assert!(
        weighted_error * 2.0 < single_error,
        "{weighted_error} against {single_error}"
    );
    // The rows' σ stand for the set's where the set states one too.
    let both = identify(
        &stanford(),
        &study(rows, Some(rms_sigma)),
        &options,
        &mut Quiet,
    )
    .expect("both");
    for (one, other) in both.parameters.iter().zip(&weighted.parameters) {
        assert_eq!(one.identified, other.identified, "{}", one.name);
    }
}

/// A σ too small for a row's residual shows in the verdict: rows claiming
/// ten times better than they are exceed the noise.
#[test]
fn rows_overstating_their_precision_exceed_the_noise() {
    let (_, rows, _) = measured();
    let boasting: Vec<Sample> = rows
        .into_iter()
        .map(|mut row| {
            let sigma = row.sigma.as_mut().expect("σ");
            sigma.length = sigma.length.map(|s| s / 10.0);
            row
        })
        .collect();
    let result = identify(
        &stanford(),
        &study(boasting, None),
        &IdentificationOptions::default(),
        &mut Quiet,
    )
    .expect("identification");
    assert_eq!(result.verdict.outcome, Outcome::ExceedsNoise);
}

/// A σ per row where a method's equations join configurations (a point
/// reached by several), or one that is no standard deviation, is refused
/// naming the set and line.
#[test]
fn a_sigma_per_row_is_refused_where_it_means_nothing() {
    let robot = stanford();
    let link = method("point-link", &MethodOptions::default()).expect("method");
    let mut rows = simulated(&robot, link.as_ref(), 12, 0.0, &mut Sampler::new(3));
    rows[4].sigma = Some(Box::new(RowSigma {
        length: Some(1e-5),
        angle: None,
    }));
    let links = Study::single(link, rows, "links.csv");
    let error = identify(
        &robot,
        &links,
        &IdentificationOptions::default(),
        &mut Quiet,
    )
    .expect_err("refused");
    assert!(
        error.to_string().contains("links.csv") && error.to_string().contains("σ per row"),
        "{error}"
    );

    let (_, mut rows, _) = measured();
    rows[7].line = Some(9);
    rows[7].sigma = Some(Box::new(RowSigma {
        length: Some(-1e-5),
        angle: None,
    }));
    let error = identify(
        &robot,
        &study(rows, None),
        &IdentificationOptions::default(),
        &mut Quiet,
    )
    .expect_err("refused");
    assert!(matches!(error, Error::InvalidData { .. }));
    assert!(error.to_string().contains("tracker.csv:9"), "{error}");
}

/// A set's samples keep their σ through the column form, a gather and the
/// rows ([`Samples`]), and a set with σ per row says it states its σ.
#[test]
fn the_rows_sigma_is_kept_by_the_samples() {
    let (_, rows, _) = measured();
    let samples = Samples::from(rows.clone());
    assert_eq!(samples.to_rows(), rows);
    assert_eq!(
        samples.gather(&[3, 1]).to_rows(),
        vec![rows[3].clone(), rows[1].clone()]
    );
    let set = MeasurementSet {
        sigma: None,
        ..study(rows, None).sets.remove(0)
    };
    assert!(set.states_sigma());
    assert_eq!(set.observation_sensors().len(), 120);
}
