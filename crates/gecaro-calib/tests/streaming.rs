//! Streamed systems (issue 36): rows folded into the normal equations or a
//! triangular factor as they are written give the identification of the
//! held W, to floating-point order, for every kind of data that streams.

use crate::util::{simulated, stanford};
use gecaro_calib::study::Samples;
use gecaro_calib::{
    Quiet,
    identification::{Identification, IdentificationOptions, Loss, Prior, identify},
    methods::{MethodOptions, method},
    simulation::{Sampler, perturbed_robot, simulate_at},
    study::{MeasurementSet, Study},
};
use gecaro_core::Robot;
use nalgebra::Vector3;

/// Data of `name` on a Stanford arm with level-`level` errors.
fn measured(real: &Robot, name: &str, count: usize, seed: u64) -> MeasurementSet {
    let chosen = method(name, &MethodOptions::default()).expect("method");
    let samples = simulated(real, chosen.as_ref(), count, 1e-5, &mut Sampler::new(seed));
    let mut set = Study::single(chosen, samples, name).sets.remove(0);
    set.sigma = Some(1e-5);
    set
}

/// The identification with every system held, and with every system streamed.
fn both_routes(study: &Study, options: &IdentificationOptions) -> (Identification, Identification) {
    let route = |streamed_rows| {
        identify(
            &stanford(),
            study,
            &IdentificationOptions {
                streamed_rows,
                ..options.clone()
            },
            &mut Quiet,
        )
        .expect("identification")
    };
    (route(usize::MAX), route(0))
}

/// The same result, but for the order of floating-point sums.
pub(crate) fn assert_same(held: &Identification, streamed: &Identification, case: &str) {
    assert_eq!(held.stop_reason, streamed.stop_reason, "{case}");
    assert_eq!(held.route, streamed.route, "{case}");
    assert_eq!(
        held.verdict.outcome, streamed.verdict.outcome,
        "{case}: {} / {}",
        held.verdict.summary, streamed.verdict.summary
    );
    assert_eq!(held.second_pass, streamed.second_pass, "{case}");
    assert_eq!(held.parameters.len(), streamed.parameters.len(), "{case}");
    // Iterations stop at a tolerance: the two routes stop a rounding apart.
    let close = |a: f64, b: f64, scale: f64| (a - b).abs() <= 1e-5 * scale;
    for (a, b) in held.parameters.iter().zip(&streamed.parameters) {
        assert_eq!(a.name, b.name, "{case}");
        assert!(
            close(a.identified, b.identified, a.std),
            "{case}: {} {} vs {} (σ {})",
            a.name,
            a.identified,
            b.identified,
            a.std
        );
        assert!(
            close(a.std, b.std, a.std),
            "{case}: σ of {} {} vs {}",
            a.name,
            a.std,
            b.std
        );
        // Where G is nearly singular the noise σ reads the residuals'
        // curvature at the solution (`identification::curvature`), which
        // the two routes' stopping points, a rounding apart along the
        // near-null direction, move (PUMA 560, level 0.1: r7 by 1e-3, r6
        // by 6e-5): three digits of a standard deviation.
        assert!(
            (a.noise_std - b.noise_std).abs() <= 2e-3 * a.noise_std,
            "{case}: noise σ of {} {} vs {}",
            a.name,
            a.noise_std,
            b.noise_std
        );
    }
    assert!(
        close(held.after.rms, streamed.after.rms, held.after.rms),
        "{case}: rms {} vs {}",
        held.after.rms,
        streamed.after.rms
    );
    assert!(
        close(
            held.residual_sigma,
            streamed.residual_sigma,
            held.residual_sigma
        ),
        "{case}"
    );
    assert!(
        close(
            held.condition_number,
            streamed.condition_number,
            held.condition_number
        ),
        "{case}: κ {} vs {}",
        held.condition_number,
        streamed.condition_number
    );
    assert_eq!(held.outliers.len(), streamed.outliers.len(), "{case}");
    assert_eq!(held.not_excited, streamed.not_excited, "{case}");
}

#[test]
fn streamed_and_held_systems_identify_alike() {
    let real = perturbed_robot(&stanford(), 1.0, &mut Sampler::new(5)).expect("real robot");
    let position = measured(&real, "position", 300, 1);
    let frame = measured(&real, "frame", 150, 2);
    let single = |set: &MeasurementSet| Study {
        sets: vec![set.clone()],
        ..Study::default()
    };
    let plain = IdentificationOptions::default();
    let (held, streamed) = both_routes(&single(&position), &plain);
    assert_same(&held, &streamed, "position");
    assert!(held.verdict.outcome.trusted(), "{}", held.verdict.summary);
    let (held, streamed) = both_routes(&single(&frame), &plain);
    assert_same(&held, &streamed, "frame");
    // Two sets: their folded rows are merged in order.
    let both = Study {
        sets: vec![position.clone(), frame],
        ..Study::default()
    };
    let (held, streamed) = both_routes(&both, &plain);
    assert_same(&held, &streamed, "position and frame");
    // A prior's rows are appended to the folded ones.
    let prior = IdentificationOptions {
        prior: Some(Prior::new(0.01, 1f64.to_radians(), 0.01).expect("prior")),
        ..IdentificationOptions::default()
    };
    let (held, streamed) = both_routes(&single(&position), &prior);
    assert_same(&held, &streamed, "with a prior");
    // Gross errors under a robust loss: every reweighting streams.
    let mut gross = position;
    let mut rows = gross.samples.to_rows();
    for sample in rows.iter_mut().step_by(25) {
        sample.position = sample.position.map(|p| p + Vector3::new(0.02, 0.0, 0.0));
    }
    gross.samples = rows.into();
    let robust = IdentificationOptions {
        loss: Loss::new("tukey".parse().expect("loss")),
        ..IdentificationOptions::default()
    };
    let (held, streamed) = both_routes(&single(&gross), &robust);
    assert_same(&held, &streamed, "tukey");
    assert_eq!(held.outliers.len(), 12);
}

#[test]
fn a_joint_that_never_moved_is_found_by_the_streamed_excitation_check() {
    // The normal equations of data where joint 2 never moved are singular:
    // the streamed excitation check writes the rows again into the R of a
    // QR, whose rank decisions are those of the held W.
    let real = perturbed_robot(&stanford(), 1.0, &mut Sampler::new(5)).expect("real robot");
    let measure = method("position", &MethodOptions::default()).expect("method");
    let mut planned = simulated(&real, measure.as_ref(), 300, 0.0, &mut Sampler::new(3));
    for sample in &mut planned {
        sample.motor_positions[1] = 0.4;
    }
    let samples = simulate_at(
        &real,
        measure.as_ref(),
        Samples::from(planned.as_slice()).as_slice(),
        1e-5,
        &mut Sampler::new(4),
        &mut Quiet,
    )
    .expect("data");
    let mut study = Study::single(measure, samples, "joint 2 still");
    study.sets[0].sigma = Some(1e-5);
    let (held, streamed) = both_routes(&study, &IdentificationOptions::default());
    assert!(!held.not_excited.is_empty(), "every parameter excited");
    assert!(!held.verdict.outcome.trusted(), "{}", held.verdict.summary);
    assert_same(&held, &streamed, "joint 2 still");
}

#[test]
fn an_ill_conditioned_pass_streams_into_a_triangular_factor() {
    // PUMA 560 at level 0.1: the second pass's W_b has an equilibrated
    // condition number of 2.8e5, beyond what the normal equations solve
    // accurately, so its systems fold into the R of a QR of [W | r].
    let nominal = gecaro_io::load_robot("puma560").expect("ready robot").robot;
    let mut sampler = Sampler::new(7);
    let real = perturbed_robot(&nominal, 0.1, &mut sampler).expect("real robot");
    let measure = method("position", &MethodOptions::default()).expect("method");
    let samples = simulated(&real, measure.as_ref(), 200, 1e-5, &mut sampler);
    let study = Study::single(measure, samples, "simulated");
    let route = |streamed_rows| {
        identify(
            &nominal,
            &study,
            &IdentificationOptions {
                streamed_rows,
                ..IdentificationOptions::default()
            },
            &mut Quiet,
        )
        .expect("identification")
    };
    let (held, streamed) = (route(usize::MAX), route(0));
    assert!(!held.second_pass.is_empty(), "no second pass");
    assert_same(&held, &streamed, "PUMA 560, level 0.1");
}
