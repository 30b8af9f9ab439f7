//! The coarse start of large data (issue 36): the first iterations on a
//! spread subsample, then all the data from its solution, end where the
//! descent on all the data from the nominal robot does.

use crate::util::{simulated, stanford};
use gecaro_calib::identification::Warning;
use gecaro_calib::study::Samples;
use gecaro_calib::{
    Quiet,
    identification::{Identification, IdentificationOptions, identify},
    methods::{MethodOptions, method},
    simulation::{Sampler, perturbed_robot, simulate_at, simulate_measurements},
    study::Study,
};

use super::streaming::assert_same;

/// Position data of the Stanford arm with errors of a centimetre and a
/// degree, σ = 0.01 mm, on `configurations` (or `count` random ones).
fn position_study(configurations: Option<&[gecaro_calib::study::Sample]>, count: usize) -> Study {
    let real = perturbed_robot(&stanford(), 1.0, &mut Sampler::new(5)).expect("real robot");
    let measure = method("position", &MethodOptions::default()).expect("method");
    let samples = match configurations {
        None => simulate_measurements(
            &real,
            measure.as_ref(),
            count,
            1e-5,
            &mut Sampler::new(1),
            &mut Quiet,
        ),
        Some(planned) => simulate_at(
            &real,
            measure.as_ref(),
            Samples::from(planned).as_slice(),
            1e-5,
            &mut Sampler::new(2),
            &mut Quiet,
        ),
    }
    .expect("data");
    let mut study = Study::single(measure, samples, "simulated");
    study.sets[0].sigma = Some(1e-5);
    study
}

/// The identification without a coarse start, and with one from `coarse_from`.
fn without_and_with(study: &Study, coarse_from: usize) -> (Identification, Identification) {
    let identified = |coarse_from| {
        identify(
            &stanford(),
            study,
            &IdentificationOptions {
                coarse_from,
                ..IdentificationOptions::default()
            },
            &mut Quiet,
        )
        .expect("identification")
    };
    (identified(usize::MAX), identified(coarse_from))
}

fn note(result: &Identification) -> Option<&String> {
    result.warnings.iter().find_map(|w| match w {
        Warning::CoarseStart(words) => Some(words),
        _ => None,
    })
}

#[test]
fn a_coarse_start_ends_where_all_the_data_from_the_nominal_do() {
    let study = position_study(None, 3000);
    let (whole, coarse) = without_and_with(&study, 1000);
    assert_same(&whole, &coarse, "coarse start");
    assert!(whole.verdict.outcome.trusted(), "{}", whole.verdict.summary);
    assert!(note(&whole).is_none());
    let said = note(&coarse).expect("the coarse start is named");
    assert!(said.contains("200 of the 3000"), "{said}");
    // Iteration 0 is the nominal robot on all the data, as without it; the
    // jump lands where the last iterations are within 1 % of the solution.
    let (first, jump) = (&coarse.history[0], &coarse.history[1]);
    assert!((first.rms - whole.history[0].rms).abs() <= 1e-12 * first.rms);
    assert!(first.rms > 100.0 * jump.rms, "{first:?} {jump:?}");
    assert!(jump.rms < 1.01 * coarse.after.rms / 1e-5, "{jump:?}");
    assert!(jump.step > 0.0);
    assert!(coarse.history.len() < whole.history.len());
    assert_eq!(coarse.before.rms, whole.before.rms);
    // Below the threshold, no coarse start.
    let (_, small) = without_and_with(&study, 3000);
    assert!(note(&small).is_none());
}

#[test]
fn a_coarse_start_on_repeated_cycles_reads_every_pose() {
    // 40 repeats of a cycle of 50 poses: a subsample of every 15th
    // configuration would hold 10 poses, which do not determine the
    // robot; the spread subsample holds all of them.
    let cycle = position_study(None, 50);
    let planned: Vec<_> = (0..40)
        .flat_map(|_| cycle.sets[0].samples.to_rows())
        .collect();
    let study = position_study(Some(&planned), 0);
    let (whole, coarse) = without_and_with(&study, 1000);
    assert!(note(&coarse).is_some(), "{:?}", coarse.warnings);
    assert_same(&whole, &coarse, "repeated cycles");
    assert!(
        coarse.verdict.outcome.trusted(),
        "{}",
        coarse.verdict.summary
    );
}

#[test]
fn a_study_that_does_not_observe_the_scale_starts_from_its_robot() {
    let real = perturbed_robot(&stanford(), 0.3, &mut Sampler::new(5)).expect("real robot");
    let link = method("point-link", &MethodOptions::default()).expect("method");
    let samples = simulated(&real, link.as_ref(), 120, 1e-5, &mut Sampler::new(1));
    let study = Study::single(link, samples, "point link");
    let (whole, coarse) = without_and_with(&study, 50);
    assert!(note(&coarse).is_none(), "{:?}", coarse.warnings);
    assert_eq!(whole.history.len(), coarse.history.len());
}
